//! The scene description: what a scene file says, in `f64`, before it becomes a core
//! scene (in `f32`, fixed capacities) or a reference scene (in `f64`, plain `Vec`s).
//!
//! Both renderers are built from this one description, so a comparison measures
//! what `f32`, the math backend and the core's shortcuts cost, nothing else.

use crate::arr3::{add, cross, sub};
pub use crate::kinds::{BoxDesc, PlaneDesc, SphereDesc, TriangleDesc};
use crate::kinds::{HostKind, Listed, each_kind};
use serde::Deserialize;
use std::fmt;
use tessera_core::Geometry;
use tessera_core::kind::{KINDS, Kind};
use tessera_core::{
    Camera, Color, Sampler, Scene, Vec3, geometry::Triangle, light::Light, material::Material,
    material::MaterialId, texture::Texture,
};
use tessera_core::{error::Field, error::List};

/// How many spheres the host scene holds.
pub const MAX_SPHERES: usize = 1024;
/// How many planes the host scene holds.
pub const MAX_PLANES: usize = 64;
/// How many triangles the host scene holds.
pub const MAX_TRIANGLES: usize = 8192;
/// How many boxes the host scene holds (as every geometry kind not named in
/// [`HostCaps`]).
pub const MAX_BOXES: usize = 1024;
/// How many materials the host scene holds.
pub const MAX_MATERIALS: usize = 256;
/// How many lights the host scene holds.
pub const MAX_LIGHTS: usize = 64;

/// The host's scene capacities: 1,024 of each geometry kind but the planes and
/// the triangles.
pub type HostCaps = tessera_core::capacities!(
    planes: MAX_PLANES,
    triangles: MAX_TRIANGLES,
    materials: MAX_MATERIALS,
    lights: MAX_LIGHTS,
    ..MAX_SPHERES
);

/// The host's core scene, of capacities [`HostCaps`].
pub type CoreScene = Scene<HostCaps>;

const _: () = assert!(MAX_BOXES == MAX_SPHERES);

/// A BVH for the host scene's triangles (`2 T` nodes: always enough).
pub type HostBvh = tessera_core::bvh::Bvh<{ 2 * MAX_TRIANGLES }, MAX_TRIANGLES>;

/// A BVH for the host scene's spheres.
pub type HostSphereBvh = tessera_core::bvh::Bvh<{ 2 * MAX_SPHERES }, MAX_SPHERES>;

/// A scene file's core scene: its lists ([`CoreScene`]) and its meshes, indexed
/// (shared vertices, `u16` faces, vertex normals when smooth) with a BVH each.
/// Render it through [`HostScene::with_view`].
pub struct HostScene {
    scene: Box<CoreScene>,
    meshes: Vec<HostMesh>,
    /// The meshes' instances, each `[[instance]]` one per part of its mesh.
    instances: Vec<tessera_core::instance::Instance>,
}

/// The most instances a host scene holds (each part of a mesh split by its
/// file's materials counts).
pub const MAX_INSTANCES: usize = 1024;

/// The host's instances of a view's meshes (in RAM, boxed: 200 bytes each).
type HostInstances<'a> = tessera_core::instance::Instances<'a, MAX_INSTANCES>;

/// A mesh of a [`HostScene`]: what a [`tessera_core::mesh::Mesh`] of it borrows.
#[derive(Clone, Copy)]
pub struct MeshParts<'a> {
    /// The distinct vertices.
    pub vertices: &'a [[f32; 3]],
    /// The faces.
    pub faces: &'a [[u16; 3]],
    /// The vertex normals (empty: flat).
    pub normals: &'a [[f32; 3]],
    /// The vertex texture coordinates (empty: the faces' barycentrics).
    pub uvs: &'a [[f32; 2]],
    /// The material.
    pub material: MaterialId,
    /// The BVH over the faces.
    pub bvh: &'a HostBvh,
}

impl<'a> MeshParts<'a> {
    /// The core's mesh of these parts.
    #[must_use]
    pub fn mesh(&self) -> tessera_core::mesh::Mesh<'a> {
        let bvh =
            tessera_core::bvh::BakedBvh::new(self.bvh.nodes(), self.bvh.order(), self.bvh.reach());
        tessera_core::mesh::Mesh::new(self.vertices, self.faces, self.normals, self.material, bvh)
            .with_uvs(self.uvs)
    }
}

/// A mesh's data, which a [`tessera_core::mesh::Mesh`] borrows.
struct HostMesh {
    vertices: Vec<[f32; 3]>,
    faces: Vec<[u16; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    material: MaterialId,
    bvh: Box<HostBvh>,
}

impl fmt::Debug for HostScene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HostScene")
            .field("scene", &self.scene)
            .field("meshes", &self.meshes.len())
            .finish()
    }
}

impl HostScene {
    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &Camera {
        self.scene.camera()
    }

    /// The lists (spheres, planes, triangles, boxes, materials, lights), without
    /// the meshes.
    #[must_use]
    pub fn lists(&self) -> &CoreScene {
        &self.scene
    }

    /// How many meshes.
    #[must_use]
    pub fn mesh_count(&self) -> usize {
        self.meshes.len()
    }

    /// Each mesh's data.
    pub fn mesh_parts(&self) -> impl Iterator<Item = MeshParts<'_>> {
        self.meshes.iter().map(|m| MeshParts {
            vertices: &m.vertices,
            faces: &m.faces,
            normals: &m.normals,
            uvs: &m.uvs,
            material: m.material,
            bvh: &m.bvh,
        })
    }

    /// Runs `f` with the view of the lists and the meshes where they lie.
    fn with_meshes_view<R>(&self, f: impl FnOnce(&tessera_core::SceneView<'_>) -> R) -> R {
        let meshes: Vec<tessera_core::mesh::Mesh<'_>> =
            self.mesh_parts().map(|m| m.mesh()).collect();
        let view = self.scene.view();
        // Checked when the scene was made: cannot fail (if it did, the meshes
        // would be missing from the image, which every test would see).
        let view = if meshes.is_empty() {
            view
        } else {
            view.with_meshes(&meshes).unwrap_or(view)
        };
        f(&view)
    }

    /// The meshes' instances (each `[[instance]]` one per part of its mesh,
    /// in the file's order).
    #[must_use]
    pub fn instances(&self) -> &[tessera_core::instance::Instance] {
        &self.instances
    }

    /// Runs `f` with the scene's view: its meshes (where their instances
    /// place them), and its triangles through a BVH when there are enough of
    /// them for it to pay ([`tessera_core::SceneView::with_bvh`]).
    pub fn with_view<R>(&self, f: impl FnOnce(&tessera_core::SceneView<'_>) -> R) -> R {
        self.with_meshes_view(|view| self.with_placed_view(*view, f))
    }

    /// [`HostScene::with_view`] from the view with the meshes where they lie.
    fn with_placed_view<R>(
        &self,
        view: tessera_core::SceneView<'_>,
        f: impl FnOnce(&tessera_core::SceneView<'_>) -> R,
    ) -> R {
        let mut placed = (!self.instances.is_empty()).then(|| Box::new(HostInstances::new(&view)));
        // As the meshes: placed when the scene was made.
        let view = match &mut placed {
            Some(p) => match p.place_all(&self.instances) {
                Ok(()) => view.with_instances(p).unwrap_or(view),
                Err(_) => view,
            },
            None => view,
        };
        // Built only where it pays; as below, it cannot fail, and the flat list
        // renders the same image.
        let spheres = (view.spheres().len() >= tessera_core::bvh::SPHERE_CROSSOVER)
            .then(|| {
                let mut b = Box::new(HostSphereBvh::new());
                b.build(view.spheres()).ok().map(|()| b)
            })
            .flatten();
        let view = match &spheres {
            Some(b) => view.with_sphere_bvh(b).unwrap_or(view),
            None => view,
        };
        if view.triangles().len() < tessera_core::bvh::CROSSOVER {
            return f(&view);
        }
        let mut bvh = Box::new(HostBvh::new());
        // Cannot fail: the capacities are the scene's, and 2 T nodes always
        // suffice; if it did, the flat lists render the same image.
        match bvh
            .build(view.triangles())
            .and_then(|()| view.with_bvh(&bvh))
        {
            Ok(v) => f(&v),
            Err(_) => f(&view),
        }
    }
}

/// A mesh welded: its distinct vertices (in the order they first appear), its
/// faces as indices into them, each vertex's normal when the mesh is shaded
/// smooth (the file's, or else the normalised sum of its faces' `(p1 - p0) x
/// (p2 - p0)`, so weighted by area) and each vertex's texture coordinate when
/// the file gives them. A vertex is one where its position, normal and uv are
/// the same numbers: a hard edge of the file (two normals at one position) or
/// a uv seam stays two vertices.
#[derive(Clone, Debug, PartialEq)]
pub struct Welded {
    /// The distinct vertices.
    pub positions: Vec<[f64; 3]>,
    /// The faces.
    pub faces: Vec<[usize; 3]>,
    /// One unit normal per vertex (smooth), or none (flat).
    pub normals: Vec<[f64; 3]>,
    /// One texture coordinate per vertex, or none.
    pub uvs: Vec<[f64; 2]>,
}

impl MeshDesc {
    /// A mesh of the file `obj` and `material` (`None`: the file's own) as the
    /// file gives it: no scale, turn or move, shaded as the file says, its
    /// faces not read yet.
    #[must_use]
    pub fn unplaced(obj: impl Into<String>, material: Option<String>) -> Self {
        Self {
            obj: obj.into(),
            material,
            scale: 1.0,
            rotate: None,
            quaternion: None,
            translate: [0.0; 3],
            smooth: None,
            name: None,
            faces: Vec::new(),
            degenerate: 0,
            normals: Vec::new(),
            uvs: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// The faces welded where their vertices are the same numbers (see
    /// [`Welded`]).
    #[must_use]
    pub fn welded(&self) -> Welded {
        // Welded by the f32 numbers the core gets (-0 as 0): vertices that differ
        // in f64 but not once rounded are one vertex, so a smooth mesh has no seam.
        let same = |x: f64| {
            let y = x as f32;
            if y == 0.0 { 0 } else { y.to_bits() }
        };
        let given = self.given_normals();
        let uvs_given = self.uvs.len() == self.faces.len() && !self.uvs.is_empty();
        let mut index: std::collections::HashMap<[u32; 8], usize> = Default::default();
        let (mut positions, mut normals, mut uvs) = (Vec::new(), Vec::new(), Vec::new());
        let mut faces = Vec::with_capacity(self.faces.len());
        for (j, f) in self.faces.iter().enumerate() {
            let mut face = [0; 3];
            for (k, (slot, p)) in face.iter_mut().zip(f).enumerate() {
                let n = given.then(|| unit(self.normals[j][k]));
                let uv = uvs_given.then(|| self.uvs[j][k]);
                let [x, y, z] = p.map(same);
                let [nx, ny, nz] = n.map_or([0; 3], |n| n.map(same));
                let [u, v] = uv.map_or([0; 2], |uv| uv.map(same));
                *slot = *index.entry([x, y, z, nx, ny, nz, u, v]).or_insert_with(|| {
                    positions.push(*p);
                    normals.extend(n);
                    uvs.extend(uv);
                    positions.len() - 1
                });
            }
            faces.push(face);
        }
        if !given && self.smooth == Some(true) {
            let mut sum = vec![[0.0f64; 3]; positions.len()];
            for (f, p) in faces.iter().zip(&self.faces) {
                let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
                for &i in f {
                    sum[i] = add(sum[i], n);
                }
            }
            normals = sum.into_iter().map(unit).collect();
        }
        Welded {
            positions,
            faces,
            normals,
            uvs,
        }
    }

    /// True when the mesh is shaded with the file's own vertex normals: it has
    /// one for every corner of every face, and `smooth` is not `false`.
    #[must_use]
    pub fn given_normals(&self) -> bool {
        self.smooth != Some(false)
            && !self.normals.is_empty()
            && self.normals.len() == self.faces.len()
    }
}

/// `n` normalised, each component subnormal in `f32` read as zero (as every
/// number of a scene is: the core refuses a baked normal that is not); a normal
/// that does not normalise (faces cancelling out at a vertex, never on a closed
/// surface seen from outside; a file's zero normal) is an up normal, which the
/// shading turns to the face's side.
fn unit(n: [f64; 3]) -> [f64; 3] {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        n.map(|x| flush(x / len))
    } else {
        [0.0, 1.0, 0.0]
    }
}

/// The lists of a scene file, by the name of their `[[...]]` sections, with their
/// capacity and the core's name for them: the materials, the lights, then each
/// geometry kind's, in the core's order.
pub const LISTS: [(&str, usize, List); 2 + KINDS] = {
    let mut out = [("material", MAX_MATERIALS, List::Materials); 2 + KINDS];
    out[1] = ("light", MAX_LIGHTS, List::Lights);
    let capacities = <HostCaps as tessera_core::Capacities>::COUNTS.kinds();
    let mut i = 0;
    while i < KINDS {
        let kind = Kind::ALL[i];
        out[2 + i] = (kind.name(), capacities[i], kind.list());
        i += 1;
    }
    out
};

/// The message for item number `count + 1` of a list that holds `capacity`:
/// `too many spheres: the scene holds at most 1024` (the core's words).
pub fn too_many(list: List, capacity: usize) -> String {
    tessera_core::Error::CapacityExceeded { list, capacity }.to_string()
}

/// `SceneDesc`, with one list per geometry kind of the core's list.
macro_rules! scene_desc {
    ([] $( ($K:ident, $f:ident, $L:ident, $T:ty, $name:literal) ),* $(,)?) => {
        /// A whole scene file.
        #[derive(Clone, Debug, Deserialize, PartialEq)]
        #[serde(deny_unknown_fields)]
        pub struct SceneDesc {
            /// Ambient light (linear RGB, `>= 0`).
            #[serde(default)]
            pub ambient: [f64; 3],
            /// Colour of rays that hit nothing.
            #[serde(default)]
            pub background: [f64; 3],
            /// The camera.
            pub camera: CameraDesc,
            /// Render settings (all optional).
            #[serde(default)]
            pub render: RenderDesc,
            /// Materials, referred to by name.
            #[serde(default, rename = "material")]
            pub materials: Vec<MaterialDesc>,
            /// Point lights.
            #[serde(default, rename = "light")]
            pub lights: Vec<LightDesc>,
            $(
                #[doc = concat!("The ", stringify!($f), " (`[[", $name, "]]`).")]
                #[serde(default, rename = $name)]
                pub $f: Vec<<$T as HostKind>::Desc>,
            )*
            /// Triangle meshes read from OBJ files: their faces are triangles of the scene,
            /// after the file's own `[[triangle]]`s.
            #[serde(default, rename = "mesh")]
            pub meshes: Vec<MeshDesc>,
            /// Instances of the meshes (`[[instance]]`): a mesh an instance
            /// names is drawn at each of its instances, not where it lies.
            #[serde(default, rename = "instance")]
            pub instances: Vec<InstanceDesc>,
            /// Keyframe tracks of the instances (`[[keyframes]]`): the
            /// scene's animation (module [`crate::animation`]).
            #[serde(default, rename = "keyframes")]
            pub keyframes: Vec<KeyframesDesc>,
            /// The numbers [`SceneDesc::flush_subnormals`] read as zero, the first
            /// [`FLUSHED_KEPT`] of them: never written in a file.
            #[serde(skip)]
            pub flushed: Vec<Flushed>,
            /// How many numbers [`SceneDesc::flush_subnormals`] read as zero in all.
            #[serde(skip)]
            pub flushed_count: usize,
            /// What reading the scene's files (images, glTF, MTL) left out or
            /// changed, each a sentence naming it: never written in a file.
            #[serde(skip)]
            pub warnings: Vec<String>,
            /// Encoded images (PNG, JPEG) that files of the scene carry inside
            /// them (a `.glb`'s), by the name an image texture's `file` gives
            /// them (`model.glb#image0`): read as files are.
            #[serde(skip)]
            pub embedded: Vec<(String, Vec<u8>)>,
        }

        impl SceneDesc {
            /// A scene seen by `camera` with nothing in it (no ambient light, a
            /// black background, the default render settings).
            #[must_use]
            pub fn new(camera: CameraDesc) -> Self {
                Self {
                    ambient: [0.0; 3],
                    background: [0.0; 3],
                    camera,
                    render: RenderDesc::default(),
                    materials: Vec::new(),
                    lights: Vec::new(),
                    $($f: Vec::new(),)*
                    meshes: Vec::new(),
                    instances: Vec::new(),
                    keyframes: Vec::new(),
                    flushed: Vec::new(),
                    flushed_count: 0,
                    warnings: Vec::new(),
                    embedded: Vec::new(),
                }
            }
        }

        $(
            impl Listed for $T {
                fn descs(s: &SceneDesc) -> &[Self::Desc] {
                    &s.$f
                }
                fn descs_mut(s: &mut SceneDesc) -> &mut Vec<Self::Desc> {
                    &mut s.$f
                }
            }
        )*
    };
}

tessera_core::__kinds!({ scene_desc });

/// How many of the numbers read as zero a description remembers by name (an OBJ
/// file may hold millions; the loader shows a few and counts the rest).
pub const FLUSHED_KEPT: usize = 64;

/// A number of a scene file read as zero by the rule for subnormal numbers
/// ([`SceneDesc::flush_subnormals`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Flushed {
    /// The item, as messages name it (`sphere 2`, `camera`).
    pub item: String,
    /// The key (`center`, `texture scale`).
    pub key: String,
    /// The number as written.
    pub value: f64,
}

impl fmt::Display for Flushed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {} {} is below the smallest normal f32 number (1.18e-38 in magnitude) \
             and is read as 0 (tessera reads every subnormal number of a scene as 0, so \
             that the f32 core, the chip and the f64 reference agree)",
            self.item,
            self.key,
            num(self.value)
        )
    }
}

/// `x` read by the rule for subnormal numbers: a zero of its sign when it is not
/// zero but its `f32` is below `2^-126` in magnitude (subnormal, or rounded to 0),
/// as the core reads its `f32` (`tessera`'s validation flushes subnormal numbers).
#[must_use]
pub fn flush(x: f64) -> f64 {
    if x != 0.0 && (x as f32).abs() < f32::MIN_POSITIVE {
        0f64.copysign(x)
    } else {
        x
    }
}

/// The camera: `forward` or `look_at` (exactly one).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Position `r_cam`.
    pub position: [f64; 3],
    /// Forward direction `c_a` (any non-zero length).
    pub forward: Option<[f64; 3]>,
    /// A point to look at (forward = look_at - position, computed in `f32`).
    pub look_at: Option<[f64; 3]>,
    /// Up direction `c_h`.
    #[serde(default = "default_up")]
    pub up: [f64; 3],
    /// Vertical opening angle, degrees.
    #[serde(default = "default_fovy")]
    pub fovy: f64,
    /// Near distance.
    pub near: f64,
    /// Far distance.
    pub far: f64,
}

fn default_up() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}
fn default_fovy() -> f64 {
    60.0
}

/// Render settings; every field has a default.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct RenderDesc {
    /// Width `N_L`, pixels.
    pub width: u16,
    /// Height `N_H`, pixels.
    pub height: u16,
    /// `corner`, `centre`, `offset:X,Y`, `stratified:K` or `random:N`.
    pub sampler: String,
    /// Reflection/refraction depth.
    pub depth: u8,
    /// Seed of the random samplers.
    pub seed: u32,
    /// Tile size: 8, 16 or 32.
    pub tile: usize,
    /// How the pixels become 8 bits: `srgb` (the default) or `linear`.
    pub encoding: String,
    /// The texel format of image textures: `srgb8` (3 bytes a texel, the
    /// default) or `rgb565` (2 bytes).
    pub texture_format: String,
    /// The bytes all image textures may take together (in flash, once baked):
    /// each image is resized to its share, in proportion to its own texels.
    pub texture_budget: usize,
    /// Frames a second of the scene's animation: frame `n` is the time
    /// `n / fps` (`tessera render --frame N`).
    pub fps: f64,
}

/// The default [`RenderDesc::texture_budget`]: 64 KiB.
pub const TEXTURE_BUDGET: usize = 64 << 10;

impl Default for RenderDesc {
    fn default() -> Self {
        Self {
            width: 320,
            height: 240,
            sampler: "centre".into(),
            depth: 3,
            seed: 0,
            tile: 16,
            encoding: "srgb".into(),
            texture_format: "srgb8".into(),
            texture_budget: TEXTURE_BUDGET,
            fps: 30.0,
        }
    }
}

/// A material; every weight has the default of [`Material::matte`].
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaterialDesc {
    /// The name primitives use to refer to it.
    pub name: String,
    /// Colour (ignored when a texture is given).
    #[serde(default = "white")]
    pub color: [f64; 3],
    /// A uv texture instead of the colour.
    pub texture: Option<TextureDesc>,
    /// Ambient weight.
    #[serde(default = "one")]
    pub ambient: f64,
    /// Diffuse weight.
    #[serde(default = "one")]
    pub diffuse: f64,
    /// Specular weight.
    #[serde(default)]
    pub specular: f64,
    /// Blinn-Phong exponent.
    #[serde(default = "one")]
    pub shininess: f64,
    /// Mirror reflectivity.
    #[serde(default)]
    pub reflectivity: f64,
    /// Transparency.
    #[serde(default)]
    pub transparency: f64,
    /// Index of refraction.
    #[serde(default = "one")]
    pub ior: f64,
}

impl MaterialDesc {
    /// A matte material of `color` named `name`: every weight at the default a
    /// scene file gives it ([`Material::matte`]'s).
    #[must_use]
    pub fn matte(name: impl Into<String>, color: [f64; 3]) -> Self {
        Self {
            name: name.into(),
            color,
            texture: None,
            ambient: 1.0,
            diffuse: 1.0,
            specular: 0.0,
            shininess: 1.0,
            reflectivity: 0.0,
            transparency: 0.0,
            ior: 1.0,
        }
    }
}

fn white() -> [f64; 3] {
    [1.0; 3]
}
fn one() -> f64 {
    1.0
}

/// A texture: procedural, or an image file.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum TextureDesc {
    /// Checker of colours `a` and `b`, `scale` squares per uv unit.
    Checker {
        /// First colour.
        a: [f64; 3],
        /// Second colour.
        b: [f64; 3],
        /// Squares per uv unit.
        scale: f64,
    },
    /// Young's fringes from the slit distance `d`, the `wavelength` and the screen
    /// `distance` (spacing = wavelength * distance / d, in uv units).
    Young {
        /// Bright fringe colour.
        color: [f64; 3],
        /// Slit distance.
        d: f64,
        /// Wavelength.
        wavelength: f64,
        /// Slits-to-screen distance.
        distance: f64,
    },
    /// Fringes of a given spacing.
    Fringes {
        /// Bright fringe colour.
        color: [f64; 3],
        /// Spacing between bright fringes, uv units.
        spacing: f64,
    },
    /// An image file (PNG or JPEG), sampled at the surface's uv (`v` down from
    /// the image's top, as glTF has it; OBJ's `vt` are turned so when read).
    Image {
        /// The file, relative to the scene file's folder.
        file: String,
        /// `bilinear` (the default) or `nearest`.
        #[serde(default)]
        filter: FilterDesc,
        /// How `u` and `v` beyond `[0, 1]` wrap: `repeat` (the default),
        /// `mirror` or `clamp`, each axis its own.
        #[serde(default)]
        wrap: [WrapDesc; 2],
        /// Multiplies the image's linear colour (a glTF base colour factor, an
        /// MTL file's `Kd`): applied to the texels when they are read.
        #[serde(default = "white")]
        tint: [f64; 3],
        /// The texels, read when the scene file is loaded (never written in it).
        #[serde(skip)]
        image: Option<tessera_core::image::Image>,
    },
}

/// An image texture's filter.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(rename_all = "lowercase")]
pub enum FilterDesc {
    /// The four texels around the point, weighted.
    #[default]
    Bilinear,
    /// The texel under the point.
    Nearest,
}

/// An image texture's wrap mode along one axis.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(rename_all = "lowercase")]
pub enum WrapDesc {
    /// The image again.
    #[default]
    Repeat,
    /// The image mirrored every other time.
    Mirror,
    /// The edge texels.
    Clamp,
}

impl FilterDesc {
    /// The core's filter.
    #[must_use]
    pub fn core(self) -> tessera_core::image::Filter {
        match self {
            Self::Bilinear => tessera_core::image::Filter::Bilinear,
            Self::Nearest => tessera_core::image::Filter::Nearest,
        }
    }
}

impl WrapDesc {
    /// The core's wrap mode.
    #[must_use]
    pub fn core(self) -> tessera_core::image::Wrap {
        match self {
            Self::Repeat => tessera_core::image::Wrap::Repeat,
            Self::Mirror => tessera_core::image::Wrap::MirroredRepeat,
            Self::Clamp => tessera_core::image::Wrap::ClampToEdge,
        }
    }
}

/// A light: a point light (`position`) or a directional light, a sun
/// (`direction`: the way its rays travel); a scene file gives one of the two.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(try_from = "LightFields")]
pub struct LightDesc {
    /// A point light's position (unused for a sun).
    pub position: [f64; 3],
    /// A sun's direction, the way its rays travel (`None`: a point light).
    pub direction: Option<[f64; 3]>,
    /// Colour.
    pub color: [f64; 3],
    /// Intensity: a point light's irradiance at distance 1, a sun's everywhere.
    pub intensity: f64,
    /// Its name, unique among the scene's objects and lights: the baker's
    /// constant for it, the host's lookup ([`SceneDesc::find`]).
    pub name: Option<String>,
}

/// A `[[light]]` table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightFields {
    position: Option<[f64; 3]>,
    direction: Option<[f64; 3]>,
    #[serde(default = "white")]
    color: [f64; 3],
    intensity: f64,
    #[serde(default)]
    name: Option<String>,
}

impl TryFrom<LightFields> for LightDesc {
    type Error = String;

    fn try_from(l: LightFields) -> Result<Self, String> {
        let (position, direction) = match (l.position, l.direction) {
            (Some(p), None) => (p, None),
            (None, Some(d)) => ([0.0; 3], Some(d)),
            (Some(_), Some(_)) => {
                return Err("a light has a position (a point light) or a direction \
                            (a directional light, a sun), not both"
                    .into());
            }
            (None, None) => {
                return Err("a light needs a position (a point light) or a direction \
                            (a directional light, a sun: the way its rays travel)"
                    .into());
            }
        };
        Ok(Self {
            position,
            direction,
            color: l.color,
            intensity: l.intensity,
            name: l.name,
        })
    }
}

impl LightDesc {
    /// A point light.
    #[must_use]
    pub fn point(position: [f64; 3], color: [f64; 3], intensity: f64) -> Self {
        Self {
            position,
            direction: None,
            color,
            intensity,
            name: None,
        }
    }

    /// A directional light whose rays travel along `direction`.
    #[must_use]
    pub fn sun(direction: [f64; 3], color: [f64; 3], intensity: f64) -> Self {
        Self {
            position: [0.0; 3],
            direction: Some(direction),
            color,
            intensity,
            name: None,
        }
    }
}

/// What is wrong with an item's `name`, if anything: empty (or blank), or
/// holding a control character.
#[must_use]
pub fn name_fault(name: &str) -> Option<String> {
    if name.trim().is_empty() {
        Some("its name is empty: give it one, or leave the key out".into())
    } else if name.chars().any(char::is_control) {
        Some(format!("its name {name:?} holds a control character"))
    } else {
        None
    }
}

/// A named item of a scene ([`SceneDesc::find`]): its list and its place in
/// it (from 0), which is its place in that list's table in a baked scene
/// (`SPHERES`, `MESHES`, `LIGHTS`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Object {
    /// A primitive of a geometry kind (`[[sphere]]`, `[[box]]`, ...).
    Primitive(Kind, usize),
    /// A mesh (`[[mesh]]`, a turned box, a part of a mesh split by its
    /// file's materials).
    Mesh(usize),
    /// A light.
    Light(usize),
    /// An instance of a mesh (`[[instance]]`; its place in the baked
    /// `INSTANCES` table is that of its first part).
    Instance(usize),
}

impl fmt::Display for Object {
    /// As messages name the item: `sphere 2`, `mesh 1`, `light 3` (from 1).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Primitive(kind, i) => write!(f, "{} {}", kind.name(), i + 1),
            Self::Mesh(i) => write!(f, "mesh {}", i + 1),
            Self::Light(i) => write!(f, "light {}", i + 1),
            Self::Instance(i) => write!(f, "instance {}", i + 1),
        }
    }
}

/// A triangle's three vertices.
pub type Face = [[f64; 3]; 3];

/// A triangle mesh from a Wavefront OBJ file: each face (a polygon is split into a
/// fan of triangles) becomes a triangle of the scene with the mesh's material,
/// its vertices scaled by `scale` about the origin, turned by `rotate` or
/// `quaternion`, then moved by `translate`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MeshDesc {
    /// The mesh's file (OBJ, glTF `.gltf` or `.glb`), relative to the scene
    /// file's folder (to the current folder for a scene given as text).
    #[serde(alias = "file")]
    pub obj: String,
    /// Material name; `None` (the key left out): the file's own materials (an
    /// OBJ's MTL file, a glTF file's), the mesh split into one a material when
    /// the scene file is read.
    #[serde(default)]
    pub material: Option<String>,
    /// Uniform scale (finite, `> 0`).
    #[serde(default = "one")]
    pub scale: f64,
    /// Rotation after the scale, before the translation: degrees about the
    /// fixed X axis, then Y, then Z (`[0, 90, 0]` turns +X to -Z).
    #[serde(default)]
    pub rotate: Option<[f64; 3]>,
    /// Rotation as a quaternion `[x, y, z, w]` (glTF's order; normalised), in
    /// place of `rotate`.
    #[serde(default)]
    pub quaternion: Option<[f64; 4]>,
    /// Translation, after the scale and the rotation.
    #[serde(default)]
    pub translate: [f64; 3],
    /// Shading normals. Unset: the file's vertex normals when it has them (a
    /// hard edge stays hard: its faces' normals differ), else flat. `true`: the
    /// file's, or else computed from the faces (weighted by area). `false`: flat,
    /// whatever the file says.
    #[serde(default)]
    pub smooth: Option<bool>,
    /// Its name (`name = "teapot"`), unique among the scene's objects and
    /// lights: the baker's constant for it, the host's lookup
    /// ([`SceneDesc::find`]). A mesh split by its file's materials names each
    /// part `<name>/<material>`.
    #[serde(default)]
    pub name: Option<String>,
    /// The faces read from the file, scaled and moved: filled when the scene file
    /// is loaded ([`crate::file`]), never written in it.
    #[serde(skip)]
    pub faces: Vec<Face>,
    /// Faces of the file left out because their vertices are collinear once in
    /// `f32` (zero area: no ray can hit them).
    #[serde(skip)]
    pub degenerate: usize,
    /// The file's normal at each corner of each face (turned as the vertices
    /// are), or none: filled when the scene file is loaded.
    #[serde(skip)]
    pub normals: Vec<[[f64; 3]; 3]>,
    /// The file's texture coordinate at each corner of each face (glTF's
    /// convention: `v` down from the image's top), or none.
    #[serde(skip)]
    pub uvs: Vec<[[f64; 2]; 3]>,
    /// What the file has that the mesh does not use, each a sentence naming it
    /// (shown as warnings when the scene is read).
    #[serde(skip)]
    pub warnings: Vec<String>,
}

/// A scale: one number for every axis, or one per axis.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum ScaleDesc {
    /// The same on every axis.
    Uniform(f64),
    /// `[x, y, z]`.
    Axes([f64; 3]),
}

impl ScaleDesc {
    /// Per axis.
    #[must_use]
    pub fn axes(self) -> [f64; 3] {
        match self {
            Self::Uniform(s) => [s; 3],
            Self::Axes(a) => a,
        }
    }
}

fn unit_scale() -> ScaleDesc {
    ScaleDesc::Uniform(1.0)
}

/// An instance of a mesh (`[[instance]]`): the mesh named `mesh` (every part
/// of a mesh split by its file's materials) drawn scaled (per axis: a mirror
/// allowed), turned by `rotate` or `quaternion`, then moved by `translate`,
/// from the mesh's own place (its own `scale`, `rotate` and `translate` make
/// its space). The mesh is then drawn only where its instances are.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InstanceDesc {
    /// The name of a `[[mesh]]`.
    pub mesh: String,
    /// Its own name, unique among the scene's objects and lights.
    #[serde(default)]
    pub name: Option<String>,
    /// Scale: a number, or `[x, y, z]` (each finite, not 0, at most `2^20`
    /// and at least `2^-20` in magnitude).
    #[serde(default = "unit_scale")]
    pub scale: ScaleDesc,
    /// Degrees about the fixed X axis, then Y, then Z.
    #[serde(default)]
    pub rotate: Option<[f64; 3]>,
    /// A quaternion `[x, y, z, w]` (normalised), in place of `rotate`.
    #[serde(default)]
    pub quaternion: Option<[f64; 4]>,
    /// Translation, after the scale and the rotation.
    #[serde(default)]
    pub translate: [f64; 3],
}

/// What a keyframe track moves (`channel`).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ChannelDesc {
    /// `values` are translations `[x, y, z]`.
    Translation,
    /// `values` are quaternions `[x, y, z, w]` (each normalised).
    Rotation,
    /// `values` are rotations in degrees `[x, y, z]`, as an instance's
    /// `rotate` (turned into quaternions).
    Rotate,
    /// `values` are scales `[x, y, z]` (or one number each).
    Scale,
}

/// How a track goes between keyframes (`interpolation`).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum InterpolationDesc {
    /// The earlier keyframe's value until the next one's time.
    Step,
    /// Straight between keyframes; spherical (constant angular speed) for
    /// rotations. The default.
    #[default]
    Linear,
}

/// A keyframe track (`[[keyframes]]`): the instance named `target` moved on
/// `channel` through `values` at `times` (seconds, strictly increasing).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KeyframesDesc {
    /// The name of an `[[instance]]`.
    pub target: String,
    /// What it moves.
    pub channel: ChannelDesc,
    /// How it goes between keyframes.
    #[serde(default)]
    pub interpolation: InterpolationDesc,
    /// The keyframes' times, in seconds.
    pub times: Vec<f64>,
    /// The keyframes' values, one per time (see [`ChannelDesc`]).
    pub values: Vec<Vec<f64>>,
}

/// What is wrong with a description: the item (`sphere 3`, `camera`, `render`) and
/// the message.
#[derive(Clone, Debug, PartialEq)]
pub struct DescError {
    /// The item at fault, e.g. `sphere 3` (1-based, in file order).
    pub item: String,
    /// What is wrong, e.g. `sphere radius must be > 0, got -1`.
    pub message: String,
}

impl fmt::Display for DescError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {}",
            crate::escape(&self.item),
            crate::escape(&self.message)
        )
    }
}

impl std::error::Error for DescError {}

/// Formats a number of a scene file for a message: the shortest digits that read
/// back to the same `f64` (`-1`, `0.002`, `NaN`, `inf`), with an exponent when the
/// magnitude is `1e6` or more, or below `1e-6` (`1e39`, `-1e-45`, `1.5e-7`).
pub fn num(x: f64) -> String {
    let a = x.abs();
    if x.is_finite() && a != 0.0 && !(1e-6..1e6).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Formats a value for a message: numbers as [`num`], vectors as `[x, y, z]`.
pub(crate) fn show(a: &[f64]) -> String {
    if let [x] = a {
        return num(*x);
    }
    let parts: Vec<String> = a.iter().map(|&x| num(x)).collect();
    format!("[{}]", parts.join(", "))
}

/// The message for a number of a scene file beyond the `f32` range.
fn too_large(what: &str, value: &str) -> String {
    format!("{what} is too large for f32 (largest 3.4e38), got {value}")
}

/// `x` in `f32` (a subnormal result read as a zero of its sign), or `None` when
/// `x` is finite but beyond the `f32` range (the cast would round it to
/// infinity). NaN and infinities pass unchanged, for the core to refuse with its
/// own message.
fn to_f32(x: f64) -> Option<f32> {
    let y = x as f32;
    // The rule for subnormal numbers ([`flush`]), also for a description built
    // in code, which the loader's [`SceneDesc::flush_subnormals`] did not read.
    let y = if y.is_subnormal() {
        0f32.copysign(y)
    } else {
        y
    };
    (y.is_finite() || !x.is_finite()).then_some(y)
}

/// The number `x` of `what` (`sphere radius`) in `f32`, or why it does not fit.
fn f1(x: f64, what: &str) -> Result<f32, String> {
    to_f32(x).ok_or_else(|| too_large(what, &num(x)))
}

/// The three numbers `a` of `what` in `f32`, or why they do not fit (showing all
/// three).
fn f3(a: [f64; 3], what: &str) -> Result<[f32; 3], String> {
    match a.map(to_f32) {
        [Some(x), Some(y), Some(z)] => Ok([x, y, z]),
        _ => Err(too_large(what, &show(&a))),
    }
}

/// A vector of the file in `f32` (see [`f3`]).
fn v3(a: [f64; 3], what: &str) -> Result<Vec3, String> {
    f3(a, what).map(|[x, y, z]| Vec3::new(x, y, z))
}

/// A colour of the file in `f32` (see [`f3`]).
fn c3(a: [f64; 3], what: &str) -> Result<Color, String> {
    f3(a, what).map(|[r, g, b]| Color::new(r, g, b))
}

/// The message of a core error, with the offending value appended when known.
fn describe(e: tessera_core::Error, value: Option<String>) -> String {
    match value {
        Some(v) => format!("{e}, got {v}"),
        None => e.to_string(),
    }
}

/// A core error about `item`, with the offending value appended when known.
fn err(item: String, e: tessera_core::Error, value: Option<String>) -> DescError {
    DescError {
        item,
        message: describe(e, value),
    }
}

/// The field a core error is about, if it names one.
fn field_of(e: tessera_core::Error) -> Option<Field> {
    match e {
        tessera_core::Error::NotFinite(f)
        | tessera_core::Error::ZeroLength(f)
        | tessera_core::Error::NotPositive(f)
        | tessera_core::Error::OutOfRange { field: f, .. } => Some(f),
        _ => None,
    }
}

impl SceneDesc {
    /// Reads every number of the scene by the rule for subnormal numbers
    /// ([`flush`]), as the core and the reference then both see them, and records
    /// each one changed in [`SceneDesc::flushed`] (the loader warns about them, and
    /// an item refused because of one says so).
    pub fn flush_subnormals(&mut self) {
        let (mut out, mut count) = (Vec::new(), 0);
        let mut at = |item: &str, key: &str, xs: &mut [f64]| {
            for x in xs {
                let y = flush(*x);
                if y.to_bits() != x.to_bits() {
                    if out.len() < FLUSHED_KEPT {
                        out.push(Flushed {
                            item: item.to_string(),
                            key: key.to_string(),
                            value: *x,
                        });
                    }
                    count += 1;
                    *x = y;
                }
            }
        };
        at("ambient", "ambient", &mut self.ambient);
        at("background", "background", &mut self.background);
        let c = &mut self.camera;
        at("camera", "position", &mut c.position);
        if let Some(f) = &mut c.forward {
            at("camera", "forward", f);
        }
        if let Some(l) = &mut c.look_at {
            at("camera", "look_at", l);
        }
        at("camera", "up", &mut c.up);
        for (key, x) in [
            ("fovy", &mut c.fovy),
            ("near", &mut c.near),
            ("far", &mut c.far),
        ] {
            at("camera", key, std::slice::from_mut(x));
        }
        for (i, m) in self.materials.iter_mut().enumerate() {
            let item = format!("material {} ({:?})", i + 1, m.name);
            at(&item, "color", &mut m.color);
            for (key, x) in [
                ("ambient", &mut m.ambient),
                ("diffuse", &mut m.diffuse),
                ("specular", &mut m.specular),
                ("shininess", &mut m.shininess),
                ("reflectivity", &mut m.reflectivity),
                ("transparency", &mut m.transparency),
                ("ior", &mut m.ior),
            ] {
                at(&item, key, std::slice::from_mut(x));
            }
            match &mut m.texture {
                None => {}
                Some(TextureDesc::Checker { a, b, scale }) => {
                    at(&item, "texture a", a);
                    at(&item, "texture b", b);
                    at(&item, "texture scale", std::slice::from_mut(scale));
                }
                Some(TextureDesc::Fringes { color, spacing }) => {
                    at(&item, "texture color", color);
                    at(&item, "texture spacing", std::slice::from_mut(spacing));
                }
                Some(TextureDesc::Young {
                    color,
                    d,
                    wavelength,
                    distance,
                }) => {
                    at(&item, "texture color", color);
                    at(&item, "texture d", std::slice::from_mut(d));
                    at(
                        &item,
                        "texture wavelength",
                        std::slice::from_mut(wavelength),
                    );
                    at(&item, "texture distance", std::slice::from_mut(distance));
                }
                Some(TextureDesc::Image { tint, .. }) => at(&item, "texture tint", tint),
            }
        }
        for (i, l) in self.lights.iter_mut().enumerate() {
            let item = format!("light {}", i + 1);
            match &mut l.direction {
                Some(d) => at(&item, "direction", d),
                None => at(&item, "position", &mut l.position),
            }
            at(&item, "color", &mut l.color);
            at(&item, "intensity", std::slice::from_mut(&mut l.intensity));
        }
        each_kind!(|G| {
            for (i, d) in G::descs_mut(self).iter_mut().enumerate() {
                let item = format!("{} {}", G::KIND.name(), i + 1);
                G::numbers(d, &mut |key, _, xs| at(&item, key, xs));
            }
        });
        for (i, m) in self.meshes.iter_mut().enumerate() {
            let item = format!("mesh {}", i + 1);
            at(&item, "scale", std::slice::from_mut(&mut m.scale));
            at(&item, "translate", &mut m.translate);
            if let Some(r) = &mut m.rotate {
                at(&item, "rotate", r);
            }
            if let Some(q) = &mut m.quaternion {
                at(&item, "quaternion", q);
            }
            for (j, f) in m.faces.iter_mut().enumerate() {
                for v in f {
                    at(&item, &format!("face {} vertex", j + 1), v);
                }
            }
        }
        for (i, k) in self.keyframes.iter_mut().enumerate() {
            let item = format!("keyframes {}", i + 1);
            at(&item, "times", &mut k.times);
            for v in &mut k.values {
                at(&item, "values", v);
            }
        }
        for (i, d) in self.instances.iter_mut().enumerate() {
            let item = format!("instance {}", i + 1);
            match &mut d.scale {
                ScaleDesc::Uniform(x) => at(&item, "scale", std::slice::from_mut(x)),
                ScaleDesc::Axes(a) => at(&item, "scale", a),
            }
            at(&item, "translate", &mut d.translate);
            if let Some(r) = &mut d.rotate {
                at(&item, "rotate", r);
            }
            if let Some(q) = &mut d.quaternion {
                at(&item, "quaternion", q);
            }
        }
        self.flushed = out;
        self.flushed_count = count;
    }

    /// The sampler named by `render.sampler`.
    pub fn sampler(&self) -> Result<Sampler, DescError> {
        let text = &self.render.sampler;
        text.parse().map_err(|e| DescError {
            item: "render".into(),
            message: format!("sampler {text:?}: {e}"),
        })
    }

    /// The render settings of the file.
    pub fn settings(&self) -> Result<tessera_core::RenderSettings, DescError> {
        let s = tessera_core::RenderSettings {
            sampler: self.sampler()?,
            max_depth: self.render.depth,
            seed: self.render.seed,
            encoding: self.render.encoding.parse().map_err(|e| DescError {
                item: "render".into(),
                message: format!("encoding {:?}: {e}", self.render.encoding),
            })?,
        };
        s.validate().map_err(|e| err("render".into(), e, None))?;
        self.fps()?;
        if !tessera_tile_ok(self.render.tile) {
            return Err(DescError {
                item: "render".into(),
                message: format!("tile must be 8, 16 or 32, got {}", self.render.tile),
            });
        }
        Ok(s)
    }

    /// The viewport of the file.
    pub fn viewport(&self) -> tessera_core::Viewport {
        tessera_core::Viewport::new(self.render.width, self.render.height)
    }

    /// The index of the material called `name`.
    pub fn material_index(&self, name: &str) -> Option<usize> {
        self.materials.iter().position(|m| m.name == name)
    }

    /// The camera's numbers in `f32`, as the core's [`Camera::try_new`] takes
    /// them (`look_at` made a direction), not yet checked by it: what a baked
    /// scene keeps ([`tessera_core::BakedCamera`]).
    pub fn camera_numbers(&self) -> Result<tessera_core::BakedCamera, DescError> {
        let c = &self.camera;
        let item = Item::new("camera");
        let position = item.v3(c.position, Field::CameraPosition)?;
        let up = item.v3(c.up, Field::CameraUp)?;
        let fovy = item.f1(c.fovy, Field::FieldOfView)?;
        let near = item.f1(c.near, Field::Near)?;
        let far = item.f1(c.far, Field::Far)?;
        let forward = match (c.forward, c.look_at) {
            (Some(f), None) => item.v3(f, Field::CameraForward)?,
            (None, Some(t)) => v3(t, "camera look_at").map_err(|m| item.fail(m))? - position,
            _ => return Err(item.fail("give exactly one of `forward` and `look_at`".into())),
        };
        Ok(tessera_core::BakedCamera {
            position: position.to_array(),
            forward: forward.to_array(),
            up: up.to_array(),
            fovy_degrees: fovy,
            near,
            far,
        })
    }

    /// The core camera (checked).
    pub fn core_camera(&self) -> Result<Camera, DescError> {
        let c = &self.camera;
        let item = Item::new("camera");
        let n = self.camera_numbers()?;
        n.camera().map_err(|e| {
            let value = match e {
                tessera_core::Error::NotPositive(_) => Some(show(&[c.near])),
                tessera_core::Error::NearNotBeforeFar => {
                    Some(format!("near {} far {}", num(c.near), num(c.far)))
                }
                _ => match field_of(e) {
                    Some(Field::CameraPosition) => Some(show(&c.position)),
                    Some(Field::CameraForward) => c.forward.or(c.look_at).map(|v| show(&v)),
                    Some(Field::CameraUp) => Some(show(&c.up)),
                    Some(Field::FieldOfView) => Some(show(&[c.fovy])),
                    Some(Field::Near) => Some(show(&[c.near])),
                    Some(Field::Far) => Some(show(&[c.far])),
                    _ => None,
                },
            };
            err(item.0.clone(), e, value)
        })
    }

    /// Every named item of the scene, with its name: the lights, then each
    /// geometry kind's items in the core's order, then the meshes (each in its
    /// list's order, which is its table's in a baked scene).
    #[must_use]
    pub fn named(&self) -> Vec<(&str, Object)> {
        let mut out: Vec<(&str, Object)> = self
            .lights
            .iter()
            .enumerate()
            .filter_map(|(i, l)| Some((l.name.as_deref()?, Object::Light(i))))
            .collect();
        each_kind!(|G| {
            for (i, d) in G::descs(self).iter().enumerate() {
                if let Some(name) = G::name(d) {
                    out.push((name, Object::Primitive(G::KIND, i)));
                }
            }
        });
        for (i, m) in self.meshes.iter().enumerate() {
            if let Some(name) = m.name.as_deref() {
                out.push((name, Object::Mesh(i)));
            }
        }
        for (i, d) in self.instances.iter().enumerate() {
            if let Some(name) = d.name.as_deref() {
                out.push((name, Object::Instance(i)));
            }
        }
        out
    }

    /// The item named `name` (names are unique among a scene's objects and
    /// lights: [`SceneDesc::to_core`] refuses two alike).
    #[must_use]
    pub fn find(&self, name: &str) -> Option<Object> {
        self.named()
            .into_iter()
            .find_map(|(n, o)| (n == name).then_some(o))
    }

    /// Refuses a name [`name_fault`] finds fault with, and a name that an
    /// earlier item has, naming both items.
    fn check_names(&self) -> Result<(), DescError> {
        let mut seen = std::collections::HashMap::new();
        for (name, object) in self.named() {
            let fail = |message: String| DescError {
                item: object.to_string(),
                message,
            };
            if let Some(fault) = name_fault(name) {
                return Err(fail(fault));
            }
            if let Some(first) = seen.insert(name, object) {
                return Err(fail(format!(
                    "{first} has the name {name:?} too: a name is unique among the \
                     scene's objects and lights"
                )));
            }
        }
        Ok(())
    }

    /// Refuses a list longer than the host scene holds, before any item is
    /// converted; the item named is the first one too many (`sphere 1025`).
    fn check_counts(&self) -> Result<(), DescError> {
        let mut lens = vec![self.materials.len(), self.lights.len()];
        each_kind!(|G| {
            let mut len = G::descs(self).len();
            if G::KIND == Kind::Triangle {
                len += self.meshes.iter().map(|m| m.faces.len()).sum::<usize>();
            }
            lens.push(len);
        });
        for ((kind, capacity, list), len) in LISTS.into_iter().zip(lens) {
            if len > capacity {
                let mut item = format!("{kind} {}", capacity + 1);
                if kind == "material" {
                    item += &format!(" ({:?})", self.materials[capacity].name);
                }
                if kind == "triangle" && self.triangles.len() <= capacity {
                    return Err(self.meshes_too_large(capacity));
                }
                return Err(DescError {
                    item,
                    message: too_many(list, capacity),
                });
            }
        }
        Ok(())
    }

    /// The error for meshes whose faces do not fit in the triangle list: the first
    /// mesh that overflows it, with the counts.
    fn meshes_too_large(&self, capacity: usize) -> DescError {
        let mut total = self.triangles.len();
        for (i, m) in self.meshes.iter().enumerate() {
            if total + m.faces.len() > capacity {
                return DescError {
                    item: format!("mesh {} ({:?})", i + 1, m.obj),
                    message: format!(
                        "{}: its {} faces come after {total} triangles",
                        too_many(List::Triangles, capacity),
                        m.faces.len()
                    ),
                };
            }
            total += m.faces.len();
        }
        DescError {
            item: "mesh".into(),
            message: too_many(List::Triangles, capacity),
        }
    }

    /// The core scene (every value checked, capacities enforced).
    pub fn to_core(&self) -> Result<HostScene, DescError> {
        self.check_counts()?;
        self.check_names()?;
        let mut s = Box::new(CoreScene::new(self.core_camera()?));
        let item = Item::new("ambient");
        s.set_ambient(item.c3(self.ambient, Field::AmbientLight)?)
            .map_err(|e| item.core(e, show(&self.ambient)))?;
        let item = Item::new("background");
        s.set_background(item.c3(self.background, Field::Background)?)
            .map_err(|e| item.core(e, show(&self.background)))?;
        for (i, m) in self.materials.iter().enumerate() {
            let item = Item(format!("material {} ({:?})", i + 1, m.name));
            if self.materials[..i].iter().any(|o| o.name == m.name) {
                return Err(item.fail("a material of the same name comes earlier".into()));
            }
            let mat = core_material(m).map_err(|message| item.fail(message))?;
            s.add_material(mat).map_err(|e| item.refused(e))?;
        }
        for (i, l) in self.lights.iter().enumerate() {
            let item = Item(format!("light {}", i + 1));
            s.add_light(core_light(&item, l)?)
                .map_err(|e| item.refused(e))?;
        }
        each_kind!(|G| {
            for (i, d) in G::descs(self).iter().enumerate() {
                let item = Item(format!("{} {}", G::KIND.name(), i + 1));
                let geometry = G::core(&item, d)?;
                s.add(geometry, self.material_id(&item, G::material(d))?)
                    .map_err(|e| item.refused(e))?;
            }
        });
        if self.meshes.len() > tessera_core::mesh::MAX_MESHES {
            let item = Item(format!("mesh {}", tessera_core::mesh::MAX_MESHES + 1));
            return Err(item.fail(too_many(List::Meshes, tessera_core::mesh::MAX_MESHES)));
        }
        let mut meshes = Vec::with_capacity(self.meshes.len());
        for (i, m) in self.meshes.iter().enumerate() {
            let item = Item(format!("mesh {} ({:?})", i + 1, m.obj));
            meshes.push(self.core_mesh(&item, m)?);
        }
        let mut scene = HostScene {
            scene: s,
            meshes,
            instances: Vec::new(),
        };
        // Each mesh's own checks (the view's), named by its item: every fault
        // should have been caught above.
        for (i, (m, d)) in scene.mesh_parts().zip(&self.meshes).enumerate() {
            let mesh = [m.mesh()];
            let item = Item(format!("mesh {} ({:?})", i + 1, d.obj));
            scene
                .scene
                .view()
                .with_meshes(&mesh)
                .map_err(|e| item.fail(e.to_string()))?;
        }
        scene.instances = self.core_instances(&scene)?;
        Ok(scene)
    }

    /// The mesh parts that the instance of the mesh named `name` draws: the
    /// mesh of that name, or else every part of it split by its file's
    /// materials (`<name>/<material>`).
    pub fn instance_parts(&self, name: &str) -> Vec<usize> {
        if let Some(i) = self
            .meshes
            .iter()
            .position(|m| m.name.as_deref() == Some(name))
        {
            return vec![i];
        }
        let prefix = format!("{name}/");
        self.meshes
            .iter()
            .enumerate()
            .filter(|(_, m)| {
                m.name
                    .as_deref()
                    .is_some_and(|n| n == name || n.starts_with(&prefix))
            })
            .map(|(i, _)| i)
            .collect()
    }

    /// Where each `[[instance]]` starts in the scene's instances (one per part
    /// of its mesh: the baked `INSTANCES` table's order).
    pub fn instance_starts(&self) -> Vec<usize> {
        let mut at = 0;
        self.instances
            .iter()
            .map(|d| {
                let start = at;
                at += self.instance_parts(&d.mesh).len();
                start
            })
            .collect()
    }

    /// The placement of instance `d` (`item`), its rotation from `rotate`
    /// (degrees, about X, then Y, then Z) or `quaternion`, in `f32`.
    fn placement(
        item: &Item,
        d: &InstanceDesc,
    ) -> Result<tessera_core::instance::Placement, DescError> {
        let q = match (d.rotate, d.quaternion) {
            (Some(_), Some(_)) => {
                return Err(item.fail(
                    "an instance is rotated by `rotate` (degrees) or `quaternion`, not both".into(),
                ));
            }
            (Some(r), None) => {
                if !r.iter().all(|x| x.is_finite()) {
                    return Err(
                        item.fail(format!("instance rotate must be finite, got {}", show(&r)))
                    );
                }
                crate::mesh::euler_quaternion(r)
            }
            (None, Some(q)) => match crate::mesh::unit_quaternion(q) {
                // A unit quaternion of `f32` numbers already (an animation's
                // frame: what the tracks give a firmware) goes to the core as
                // it is, which normalises it in `f32` as a firmware's
                // `Instances::set` does: the same placement to the bit.
                Some(_)
                    if q.iter().all(|&x| f64::from(x as f32) == x)
                        && (q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-5 =>
                {
                    q
                }
                Some(unit) => unit,
                None => {
                    let field = Field::InstanceRotation;
                    let e = if q.iter().all(|x| x.is_finite()) {
                        tessera_core::Error::ZeroLength(field)
                    } else {
                        tessera_core::Error::NotFinite(field)
                    };
                    return Err(item.core(e, show(&q)));
                }
            },
            (None, None) => [0.0, 0.0, 0.0, 1.0],
        };
        let rotation = q.map(|x| to_f32(x).unwrap_or(if x > 0.0 { f32::MAX } else { f32::MIN }));
        let scale = d.scale.axes();
        let scale = f3(scale, Field::InstanceScale.name()).map_err(|m| item.fail(m))?;
        let translation =
            f3(d.translate, Field::InstanceTranslation.name()).map_err(|m| item.fail(m))?;
        Ok(tessera_core::instance::Placement::new(
            rotation,
            scale,
            translation,
        ))
    }

    /// The core's instances of the file's `[[instance]]`s, each checked (as
    /// placed over the scene's meshes) and named in its error.
    fn core_instances(
        &self,
        scene: &HostScene,
    ) -> Result<Vec<tessera_core::instance::Instance>, DescError> {
        let mut out = Vec::new();
        for (i, d) in self.instances.iter().enumerate() {
            let item = Item(match &d.name {
                Some(n) => format!("instance {} ({n:?})", i + 1),
                None => format!("instance {}", i + 1),
            });
            let parts = self.instance_parts(&d.mesh);
            if parts.is_empty() {
                return Err(item.fail(format!(
                    "no mesh is named {:?}: an instance names a [[mesh]] by its `name`",
                    d.mesh
                )));
            }
            let placement = Self::placement(&item, d)?;
            let first = out.len();
            for part in parts {
                let mesh = u16::try_from(part).map_err(|_| item.fail("too many meshes".into()))?;
                out.push(tessera_core::instance::Instance::new(mesh, placement));
            }
            if out.len() > MAX_INSTANCES {
                return Err(item.fail(format!(
                    "too many instances: the scene holds at most {MAX_INSTANCES} (each part of a \
                     mesh split by its file's materials counts)"
                )));
            }
            // Checked as the view will place it, named by this item.
            let value = format!(
                "scale {}, rotation {}, translate {}",
                show(&d.scale.axes()),
                show(&placement.rotation.map(f64::from)),
                show(&d.translate)
            );
            // Each part (its own box, its own extent).
            scene.with_meshes_view(|view| {
                for inst in &out[first..] {
                    let mut one: tessera_core::instance::Instances<'_, 1> =
                        tessera_core::instance::Instances::new(view);
                    one.push(*inst).map_err(|e| item.core(e, value.clone()))?;
                }
                Ok(())
            })?;
        }
        Ok(out)
    }

    /// The core data of mesh `m`: welded, in `f32`, with its BVH.
    fn core_mesh(&self, item: &Item, m: &MeshDesc) -> Result<HostMesh, DescError> {
        let Some(name) = &m.material else {
            return Err(item.fail("no material: the mesh's file was not read".into()));
        };
        let material = self.material_id(item, name)?;
        let w = m.welded();
        // As `core_triangle` rounds them (a vertex it refuses fails its face).
        let f32s = |p: &[f64; 3]| p.map(|x| to_f32(x).unwrap_or(f32::NAN));
        let vertices: Vec<[f32; 3]> = w.positions.iter().map(f32s).collect();
        let normals: Vec<[f32; 3]> = w.normals.iter().map(f32s).collect();
        let uvs: Vec<[f32; 2]> = w
            .uvs
            .iter()
            .map(|p| p.map(|x| to_f32(x).unwrap_or(f32::NAN)))
            .collect();
        if uvs.iter().flatten().any(|x| !x.is_finite()) {
            return Err(item.fail("a texture coordinate is beyond the range of f32".into()));
        }
        let too_many = || item.fail(format!("more than {} vertices", 1 << 16));
        let mut faces = Vec::with_capacity(w.faces.len());
        let mut triangles = Vec::with_capacity(w.faces.len());
        for (j, f) in w.faces.iter().enumerate() {
            let face = f.map(|i| u16::try_from(i).map_err(|_| too_many()));
            let [a, b, c] = face;
            faces.push([a?, b?, c?]);
            let face_item = Item(format!("{} face {}", item.0, j + 1));
            let t = core_triangle(&face_item, &f.map(|i| w.positions[i]))?;
            triangles.push(tessera_core::Primitive {
                geometry: t,
                material,
            });
        }
        let mut bvh = Box::new(HostBvh::new());
        bvh.build(&triangles)
            .map_err(|e| item.fail(format!("its BVH cannot be built: {e}")))?;
        Ok(HostMesh {
            vertices,
            faces,
            normals,
            uvs,
            material,
            bvh,
        })
    }

    /// The id of the material called `name`, which `item` uses.
    fn material_id(&self, item: &Item, name: &str) -> Result<MaterialId, DescError> {
        self.material_index(name)
            .and_then(|i| u16::try_from(i).ok())
            .map(MaterialId)
            .ok_or_else(|| item.fail(format!("unknown material {name:?}")))
    }
}

/// An item of the file (`sphere 3`, `camera`), named in every message about it.
pub struct Item(String);

impl Item {
    pub(crate) fn new(name: &str) -> Self {
        Self(name.to_string())
    }

    /// `message` about this item.
    pub(crate) fn fail(&self, message: String) -> DescError {
        DescError {
            item: self.0.clone(),
            message,
        }
    }

    /// The core refused this item; the offending value is `value`.
    pub(crate) fn core(&self, e: tessera_core::Error, value: String) -> DescError {
        err(self.0.clone(), e, Some(value))
    }

    /// The core refused this item, with no value to show (a full list, ...).
    pub(crate) fn refused(&self, e: tessera_core::Error) -> DescError {
        err(self.0.clone(), e, None)
    }

    /// The number `x` of `field` in `f32` (see [`f1`]).
    pub(crate) fn f1(&self, x: f64, field: Field) -> Result<f32, DescError> {
        f1(x, field.name()).map_err(|m| self.fail(m))
    }

    /// The vector `a` of `field` in `f32` (see [`v3`]).
    pub(crate) fn v3(&self, a: [f64; 3], field: Field) -> Result<Vec3, DescError> {
        v3(a, field.name()).map_err(|m| self.fail(m))
    }

    /// The colour `a` of `field` in `f32` (see [`c3`]).
    pub(crate) fn c3(&self, a: [f64; 3], field: Field) -> Result<Color, DescError> {
        c3(a, field.name()).map_err(|m| self.fail(m))
    }
}

/// The value of the field a core error `e` names among `fields`, or `other` (the
/// value shown with the message).
pub(crate) fn value_for(
    e: tessera_core::Error,
    fields: &[(Field, &[f64])],
    other: &[f64],
) -> String {
    let f = field_of(e);
    let v = fields
        .iter()
        .find(|(x, _)| Some(*x) == f)
        .map_or(other, |(_, v)| v);
    show(v)
}

fn core_light(item: &Item, l: &LightDesc) -> Result<Light, DescError> {
    let color = item.c3(l.color, Field::LightColor)?;
    let intensity = item.f1(l.intensity, Field::LightIntensity)?;
    let (made, field, at) = match &l.direction {
        Some(d) => {
            let direction = item.v3(*d, Field::LightDirection)?;
            (
                Light::directional(direction, color, intensity),
                Field::LightDirection,
                &d[..],
            )
        }
        None => {
            let position = item.v3(l.position, Field::LightPosition)?;
            (
                Light::point(position, color, intensity),
                Field::LightPosition,
                &l.position[..],
            )
        }
    };
    made.map_err(|e| {
        let fields = [(field, at), (Field::LightColor, &l.color[..])];
        item.core(e, value_for(e, &fields, &[l.intensity]))
    })
}

/// The core's triangle of `vertices`; refused as the core refuses it.
pub fn core_triangle_of(vertices: &[[f64; 3]; 3]) -> Result<Triangle, tessera_core::Error> {
    match vertices.map(|p| f3(p, "")) {
        [Ok(pa), Ok(pb), Ok(pc)] => {
            let [pa, pb, pc] = [pa, pb, pc].map(|[x, y, z]| Vec3::new(x, y, z));
            Triangle::try_new(pa, pb, pc)
        }
        _ => Err(tessera_core::Error::NotFinite(Field::TriangleVertex)),
    }
}

pub(crate) fn core_triangle(item: &Item, vertices: &[[f64; 3]; 3]) -> Result<Triangle, DescError> {
    let [a, b, c] = *vertices;
    let shown = || format!("{}, {}, {}", show(&a), show(&b), show(&c));
    match vertices.map(|p| f3(p, "")) {
        [Ok(pa), Ok(pb), Ok(pc)] => {
            let [pa, pb, pc] = [pa, pb, pc].map(|[x, y, z]| Vec3::new(x, y, z));
            Triangle::try_new(pa, pb, pc).map_err(|e| item.core(e, shown()))
        }
        _ => Err(item.fail(too_large(Field::TriangleVertex.name(), &shown()))),
    }
}

fn tessera_tile_ok(n: usize) -> bool {
    crate::TILE_SIZES.contains(&n)
}

/// The core texture of a description (not yet validated), or the message.
fn core_texture(m: &MaterialDesc) -> Result<Texture, String> {
    Ok(match &m.texture {
        None => Texture::Solid(c3(m.color, Field::Color.name())?),
        Some(TextureDesc::Checker { a, b, scale }) => Texture::Checker {
            a: c3(*a, "texture a")?,
            b: c3(*b, "texture b")?,
            scale: f1(*scale, "texture scale")?,
        },
        Some(TextureDesc::Fringes { color, spacing }) => Texture::Fringes {
            color: c3(*color, "texture color")?,
            spacing: f1(*spacing, "texture spacing")?,
        },
        Some(TextureDesc::Young {
            color,
            d,
            wavelength,
            distance,
        }) => {
            let c = c3(*color, "texture color")?;
            let (fd, fw, fl) = (
                f1(*d, "texture d")?,
                f1(*wavelength, "texture wavelength")?,
                f1(*distance, "texture distance")?,
            );
            Texture::young(c, fd, fw, fl).map_err(|e| describe(e, Some(texture_value(m, e))))?
        }
        Some(TextureDesc::Image { image, file, .. }) => {
            Texture::Image(image.ok_or_else(|| format!("texture image {file:?} was not read"))?)
        }
    })
}

/// The value of the texture key a core error `e` is about: `color [0.1, -1, 0]`
/// for a Young texture's colour, `d 0 wavelength 5e-7 distance 3` for its
/// spacing, the material's `color` when there is no texture.
fn texture_value(m: &MaterialDesc, e: tessera_core::Error) -> String {
    let is_color = field_of(e) == Some(Field::TextureColor);
    match &m.texture {
        None => show(&m.color),
        Some(TextureDesc::Checker { a, b, .. }) if is_color => {
            format!("a {} b {}", show(a), show(b))
        }
        Some(TextureDesc::Checker { scale, .. }) => format!("scale {}", num(*scale)),
        Some(TextureDesc::Fringes { color, .. } | TextureDesc::Young { color, .. }) if is_color => {
            format!("color {}", show(color))
        }
        Some(TextureDesc::Fringes { spacing, .. }) => format!("spacing {}", num(*spacing)),
        Some(TextureDesc::Image { file, .. }) => format!("file {file:?}"),
        Some(TextureDesc::Young {
            d,
            wavelength,
            distance,
            ..
        }) => format!(
            "d {} wavelength {} distance {}",
            num(*d),
            num(*wavelength),
            num(*distance)
        ),
    }
}

/// The core material of a description, or the message (with the offending value).
fn core_material(m: &MaterialDesc) -> Result<Material, String> {
    let one = |x: f64| Some(show(&[x]));
    let both = || {
        Some(format!(
            "reflectivity {} transparency {}",
            num(m.reflectivity),
            num(m.transparency)
        ))
    };
    let texture = core_texture(m)?;
    let weight = |x: f64, field: Field| f1(x, field.name());
    let (ambient, diffuse) = (
        weight(m.ambient, Field::Ambient)?,
        weight(m.diffuse, Field::Diffuse)?,
    );
    let (specular, shininess) = (
        weight(m.specular, Field::Specular)?,
        weight(m.shininess, Field::Shininess)?,
    );
    let reflectivity = weight(m.reflectivity, Field::Reflectivity)?;
    let (transparency, ior) = (
        weight(m.transparency, Field::Transparency)?,
        weight(m.ior, Field::RefractiveIndex)?,
    );
    Material::matte(Color::WHITE)
        .with_texture(texture)
        .map_err(|e| describe(e, Some(texture_value(m, e))))?
        .with_ambient(ambient)
        .map_err(|e| describe(e, one(m.ambient)))?
        .with_diffuse(diffuse)
        .map_err(|e| describe(e, one(m.diffuse)))?
        .with_specular(specular, shininess)
        .map_err(|e| {
            let v = if field_of(e) == Some(Field::Shininess) {
                m.shininess
            } else {
                m.specular
            };
            describe(e, one(v))
        })?
        .with_reflectivity(reflectivity)
        .map_err(|e| match field_of(e) {
            Some(_) => describe(e, one(m.reflectivity)),
            None => describe(e, both()),
        })?
        .with_transparency(transparency, ior)
        .map_err(|e| match field_of(e) {
            Some(Field::RefractiveIndex) => describe(e, one(m.ior)),
            Some(_) => describe(e, one(m.transparency)),
            None => describe(e, both()),
        })
}

/// A scene of named items, for the tests of names: two lights (one named),
/// four spheres (one unnamed, two names of one stem, one without a letter), a
/// box and a turned box (a mesh).
#[cfg(test)]
pub(crate) const NAMED_SCENE: &str = r#"
    [camera]
    position = [0, 0, 5]
    look_at = [0, 0, 0]
    near = 0.1
    far = 100
    [[material]]
    name = "m"
    color = [1, 1, 1]
    [[light]]
    position = [0, 4, 4]
    intensity = 10
    [[light]]
    direction = [0, -1, 0]
    intensity = 1
    name = "sun"
    [[sphere]]
    center = [0, 0, 0]
    radius = 1
    material = "m"
    [[sphere]]
    center = [2, 0, 0]
    radius = 1
    material = "m"
    name = "red ball"
    [[sphere]]
    center = [4, 0, 0]
    radius = 1
    material = "m"
    name = "Red-Ball"
    [[sphere]]
    center = [6, 0, 0]
    radius = 1
    material = "m"
    name = "!"
    [[box]]
    min = [-1, -1, -1]
    max = [1, 1, 1]
    material = "m"
    name = "crate"
    [[box]]
    min = [-1, -1, -1]
    max = [1, 1, 1]
    material = "m"
    rotate = [0, 45, 0]
    name = "turned crate"
"#;

#[cfg(test)]
mod tests {
    use super::*;

    /// Each named item is found by its name in its list, at its place there
    /// (a turned box among the meshes); an unknown name is none.
    #[test]
    fn named_items_are_found_in_their_lists() {
        let d = crate::file::parse(NAMED_SCENE, "named.toml").unwrap();
        assert_eq!(d.find("sun"), Some(Object::Light(1)));
        assert_eq!(d.find("red ball"), Some(Object::Primitive(Kind::Sphere, 1)));
        assert_eq!(d.find("crate"), Some(Object::Primitive(Kind::Box, 0)));
        assert_eq!(d.find("turned crate"), Some(Object::Mesh(0)));
        assert_eq!(d.find("Red ball"), None);
        assert_eq!(d.named().len(), 6);
        assert_eq!(Object::Primitive(Kind::Sphere, 1).to_string(), "sphere 2");
        assert_eq!(Object::Mesh(0).to_string(), "mesh 1");
        d.to_core().unwrap();
    }

    /// A name used twice (across lists too), an empty name and one with a
    /// control character are refused, naming the item and the earlier one.
    #[test]
    fn names_are_unique_and_not_empty() {
        let refused = |from: &str, to: &str| {
            let text = NAMED_SCENE.replacen(from, to, 1);
            let d = crate::file::parse(&text, "named.toml");
            let e = match d {
                Ok(d) => d.to_core().map(|_| ()).unwrap_err(),
                Err(e) => return e.to_string(),
            };
            e.to_string()
        };
        let e = refused("name = \"crate\"", "name = \"sun\"");
        assert!(
            e.contains("box 1") && e.contains("light 2 has the name \"sun\" too"),
            "{e}"
        );
        let e = refused("name = \"crate\"", "name = \" \"");
        assert!(
            e.contains("box 1") && e.contains("its name is empty"),
            "{e}"
        );
        let e = refused("name = \"crate\"", "name = \"a\\nb\"");
        assert!(e.contains("control character"), "{e}");
    }

    /// A named mesh that its file's materials split names each part by its
    /// material; a turned box keeps its name as a mesh.
    #[test]
    fn a_named_mesh_split_by_material_names_its_parts() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/blender");
        // The OBJ files named by absolute paths: the text is parsed from here.
        let at = |f: &str| format!("file = {:?}", dir.join(f).to_str().unwrap());
        let text = std::fs::read_to_string(dir.join("mtl.toml"))
            .unwrap()
            .replace("file = \"happy-cube.obj\"", &at("happy-cube.obj"))
            .replace(
                "file = \"box_stack.obj\"",
                &format!("{}\nname = \"stack\"", at("box_stack.obj")),
            );
        let d = crate::file::parse(&text, "named-stack.toml").unwrap();
        let parts: Vec<&str> = d.named().into_iter().map(|(n, _)| n).collect();
        assert!(parts.len() > 1, "{parts:?}");
        for (p, m) in parts
            .iter()
            .zip(d.meshes.iter().filter(|m| m.name.is_some()))
        {
            assert_eq!(
                *p,
                format!("stack/{}", m.material.as_deref().unwrap()),
                "{parts:?}"
            );
        }
        d.to_core().unwrap();
    }

    #[test]
    fn the_subnormal_rule_reads_f32_subnormals_as_signed_zeros() {
        for x in [1e-45, -1e-45, 1e-40, 1.1e-38, -1e-300, 1e-50] {
            assert_eq!(flush(x).to_bits(), 0f64.copysign(x).to_bits(), "{x}");
        }
        // Normal in f32 (the last rounds up to f32's smallest normal), or zero.
        let smallest = f64::from(f32::MIN_POSITIVE);
        for x in [
            0.0,
            -0.0,
            1.0,
            smallest,
            -smallest,
            smallest * (1.0 - 1e-9),
            1e300,
        ] {
            assert_eq!(flush(x).to_bits(), x.to_bits(), "{x}");
        }
    }

    /// A scene file's subnormal numbers are read as zeros and warned about, each
    /// named by its item, key and value; a length refused because of it says why.
    #[test]
    fn the_loader_reads_subnormals_as_zero_and_says_so() {
        let scene = |sphere: &str| {
            format!(
                "[camera]\nposition = [0, 2, 1e-45]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\
                 [[material]]\nname = \"m\"\ncolor = [0.5, -1e-40, 0.2]\n\
                 [[light]]\nposition = [1, 4, 2]\nintensity = 20\n{sphere}"
            )
        };
        let d = crate::file::parse(
            &scene("[[sphere]]\ncenter = [0, -1, 0]\nradius = 1\nmaterial = \"m\"\n"),
            "s.toml",
        )
        .unwrap();
        assert_eq!(d.camera.position[2].to_bits(), 0f64.to_bits());
        assert_eq!(d.materials[0].color[1].to_bits(), (-0f64).to_bits());
        let w = crate::file::warnings(&d);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].starts_with("camera: position 1e-45 is below the smallest normal f32 number"),
            "{w:?}"
        );
        assert!(
            w[1].starts_with("material 1 (\"m\"): color -1e-40 is below"),
            "{w:?}"
        );
        let e = crate::file::parse(
            &scene("[[sphere]]\ncenter = [0, -1, 0]\nradius = 1e-40\nmaterial = \"m\"\n"),
            "s.toml",
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "s.toml:12: sphere 1: sphere radius must be > 0, got 0: the file's radius 1e-40 \
             is subnormal in f32 and reads as 0"
        );
    }

    /// A smooth mesh whose computed vertex normals have a component subnormal in
    /// f32 (every number of the file normal): read as zero, so the core takes the
    /// mesh (it refuses a subnormal normal) and the reference shades the same.
    #[test]
    fn computed_normals_follow_the_subnormal_rule() {
        let mesh = MeshDesc {
            smooth: Some(true),
            faces: vec![[[0.0, 0.0, 0.0], [1000.0, 0.0, 0.0], [0.0, 2e-38, 1000.0]]],
            ..MeshDesc::unplaced("f.obj", Some("m".into()))
        };
        let n = mesh.welded().normals;
        assert!(
            n.iter()
                .flatten()
                .all(|x| flush(*x).to_bits() == x.to_bits()),
            "{n:?}"
        );
        assert_eq!(n[0][2].to_bits(), 0f64.to_bits(), "{n:?}");
        let mut d = crate::file::parse(
            "[camera]\nposition = [0, 2, 5]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\
             [[material]]\nname = \"m\"\n[[light]]\nposition = [1, 4, 2]\nintensity = 20\n",
            "m.toml",
        )
        .unwrap();
        d.meshes.push(mesh);
        assert!(d.to_core().is_ok());
    }

    #[test]
    fn numbers_print_in_the_shortest_form() {
        let cases = [
            (-1.0, "-1"),
            (0.002, "0.002"),
            (0.0, "0"),
            (-0.0, "-0"),
            (123_456.5, "123456.5"),
            (999_999.0, "999999"),
            (1e6, "1e6"),
            (1e-6, "0.000001"),
            (9e-7, "9e-7"),
            (-1e-45, "-1e-45"),
            (f64::from(f32::from_bits(1)), "1.401298464324817e-45"),
            (1e39, "1e39"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (x, shown) in cases {
            assert_eq!(num(x), shown, "{x:?}");
        }
        assert_eq!(show(&[0.1, f64::NAN, 0.0]), "[0.1, NaN, 0]");
    }

    #[test]
    fn only_numbers_beyond_f32_are_too_large() {
        let max = f64::from(f32::MAX);
        assert_eq!(to_f32(max), Some(f32::MAX));
        // 3.4028235e38 (the largest f32 as printed) rounds to it.
        assert_eq!(to_f32(3.402_823_5e38), Some(f32::MAX));
        assert_eq!(to_f32(-3.402_823_5e38), Some(f32::MIN));
        assert_eq!(to_f32(3.5e38), None);
        assert_eq!(to_f32(-1e300), None);
        assert_eq!(to_f32(f64::INFINITY), Some(f32::INFINITY));
        assert!(to_f32(f64::NAN).unwrap().is_nan());
        assert_eq!(to_f32(1e-50), Some(0.0));
        assert_eq!(
            f3([0.0, 0.0, 1e39], "sphere center").unwrap_err(),
            "sphere center is too large for f32 (largest 3.4e38), got [0, 0, 1e39]"
        );
    }

    fn small_scene() -> SceneDesc {
        crate::file::parse(
            "[camera]\nposition = [0, 1, 5]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\
             [[material]]\nname = \"red\"\n",
            "t.toml",
        )
        .unwrap()
    }

    /// A list beyond its capacity is refused before any item is converted: what is
    /// reported is the list's length, not the first sphere's bad radius (which
    /// converting first would report, after converting 1024 items for nothing).
    #[test]
    fn lists_beyond_capacity_are_refused_before_conversion() {
        let mut d = small_scene();
        let sphere = SphereDesc {
            name: None,
            center: [0.0; 3],
            radius: -1.0,
            material: "red".into(),
        };
        d.spheres = vec![sphere; MAX_SPHERES];
        assert_eq!(d.to_core().unwrap_err().item, "sphere 1");
        d.spheres.push(d.spheres[0].clone());
        assert_eq!(
            d.to_core().unwrap_err(),
            DescError {
                item: "sphere 1025".into(),
                message: "too many spheres: the scene holds at most 1024".into(),
            }
        );
        let mut d = small_scene();
        d.materials = (0..=MAX_MATERIALS)
            .map(|i| MaterialDesc {
                name: format!("m{i}"),
                ..d.materials[0].clone()
            })
            .collect();
        d.camera.fovy = -1.0;
        assert_eq!(
            d.to_core().unwrap_err().to_string(),
            "material 257 (\"m256\"): too many materials: the scene holds at most 256"
        );
    }

    /// A scene with a sphere named "ball" and the built-in teapot as the mesh
    /// named "teapot" (mesh 1), before its `[[instance]]`s.
    const INSTANCE_HEAD: &str = r#"
[camera]
position = [0, 2, 8]
look_at = [0, 0, 0]
near = 0.1
far = 100
[[material]]
name = "m"
[[light]]
position = [0, 5, 5]
intensity = 20
[[sphere]]
center = [0, -101, 0]
radius = 100
material = "m"
name = "ball"
[[mesh]]
obj = "builtin:teapot"
material = "m"
name = "teapot"
"#;

    /// A folder of its own under the system's temp folder, removed (with what
    /// it holds) when dropped, also when the test fails.
    struct Scratch(std::path::PathBuf);

    impl Scratch {
        fn new(tag: &str) -> Self {
            use std::sync::atomic::{AtomicUsize, Ordering};
            static N: AtomicUsize = AtomicUsize::new(0);
            let n = N.fetch_add(1, Ordering::Relaxed);
            let dir =
                std::env::temp_dir().join(format!("tessera-desc-{tag}-{}-{n}", std::process::id()));
            std::fs::create_dir_all(&dir).unwrap();
            Self(dir)
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// An OBJ file of two faces of two materials of its MTL file (`red` and
    /// `blue`) in `dir`: a mesh its file's materials split into two parts.
    /// The `[[mesh]]` line naming it (by its absolute path).
    fn two_part_obj(dir: &std::path::Path) -> String {
        std::fs::write(
            dir.join("pair.mtl"),
            "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("pair.obj"),
            "mtllib pair.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
             usemtl red\nf 1 2 3\nusemtl blue\nf 1 2 4\n",
        )
        .unwrap();
        format!("file = {:?}", dir.join("pair.obj").to_str().unwrap())
    }

    /// The error of the instance scene with `instances` after its head.
    fn instance_refusal(instances: &str) -> crate::file::FileError {
        let text = format!("{INSTANCE_HEAD}{instances}");
        match crate::file::parse(&text, "inst.toml") {
            Ok(d) => panic!("accepted: {instances}\n{:?}", d.instances),
            Err(e) => e,
        }
    }

    /// Every bad `[[instance]]` is refused with a message naming the
    /// instance (by its place and its name) at its header's line, and what is
    /// wrong with it; nothing panics.
    #[test]
    fn bad_instances_are_refused_naming_the_instance_and_the_fault() {
        // (the instance's keys, the item, words of the message).
        let cases: &[(&str, &str, &[&str])] = &[
            (
                "mesh = \"kettle\"\nname = \"k\"",
                "instance 1 (\"k\")",
                &["no mesh is named \"kettle\"", "[[mesh]]", "`name`"],
            ),
            (
                "mesh = \"teapot\"\nrotate = [0, 90, 0]\nquaternion = [0, 0, 0, 1]",
                "instance 1",
                &["`rotate`", "`quaternion`", "not both"],
            ),
            (
                "mesh = \"teapot\"\nquaternion = [0, 0, 0, 0]",
                "instance 1",
                &["instance rotation", "zero length"],
            ),
            (
                "mesh = \"teapot\"\nquaternion = [0, inf, 0, 1]",
                "instance 1",
                &["instance rotation", "NaN or infinite"],
            ),
            (
                "mesh = \"teapot\"\nrotate = [0, nan, 0]",
                "instance 1",
                &["rotate", "finite", "NaN"],
            ),
            (
                "mesh = \"teapot\"\nname = \"flat\"\nscale = 0",
                "instance 1 (\"flat\")",
                &[
                    "instance scale",
                    "[2^-20, 2^20]",
                    "not 0",
                    "scale [0, 0, 0]",
                ],
            ),
            (
                "mesh = \"teapot\"\nscale = [1, 0, 1]",
                "instance 1",
                &["instance scale", "[2^-20, 2^20]", "scale [1, 0, 1]"],
            ),
            (
                "mesh = \"teapot\"\nscale = [1, nan, 1]",
                "instance 1",
                &["instance scale", "NaN or infinite"],
            ),
            (
                "mesh = \"teapot\"\nscale = 2097152",
                "instance 1",
                &[
                    "instance scale",
                    "[2^-20, 2^20]",
                    "got scale [2.097152e6, 2.097152e6, 2.097152e6]",
                ],
            ),
            (
                "mesh = \"teapot\"\nscale = [1, 1, -1048577]",
                "instance 1",
                &[
                    "instance scale",
                    "[2^-20, 2^20]",
                    "got scale [1, 1, -1.048577e6]",
                ],
            ),
            (
                "mesh = \"teapot\"\nscale = 9.5e-7",
                "instance 1",
                &[
                    "instance scale",
                    "[2^-20, 2^20]",
                    "got scale [9.5e-7, 9.5e-7, 9.5e-7]",
                ],
            ),
            (
                "mesh = \"teapot\"\nscale = 1e39",
                "instance 1",
                &["instance scale", "too large for f32", "1e39"],
            ),
            (
                "mesh = \"teapot\"\ntranslate = [nan, 0, 0]",
                "instance 1",
                &[
                    "instance translation",
                    "NaN or infinite",
                    "translate [NaN, 0, 0]",
                ],
            ),
            (
                "mesh = \"teapot\"\ntranslate = [0, -inf, 0]",
                "instance 1",
                &[
                    "instance translation",
                    "NaN or infinite",
                    "translate [0, -inf, 0]",
                ],
            ),
            (
                "mesh = \"teapot\"\nname = \"ball\"",
                "instance 1",
                &["sphere 1 has the name \"ball\" too", "unique"],
            ),
        ];
        let header = INSTANCE_HEAD.lines().count() + 1;
        for (keys, item, words) in cases {
            let e = instance_refusal(&format!("[[instance]]\n{keys}\n"));
            assert_eq!(e.item.as_deref(), Some(*item), "{keys}: {e}");
            for w in *words {
                assert!(e.message.contains(w), "{keys}: {w:?} in {e}");
            }
            assert_eq!(e.line, Some(header), "{keys}: {e}");
            assert!(!e.message.contains("panick"), "{keys}: {e}");
        }
        // The second instance is the one named (the first is good), by its
        // place among the instances.
        let e = instance_refusal(
            "[[instance]]\nmesh = \"teapot\"\n[[instance]]\nmesh = \"teapot\"\nname = \"two\"\n\
             scale = [1, 0, 1]\n",
        );
        assert_eq!(e.item.as_deref(), Some("instance 2 (\"two\")"), "{e}");
        assert_eq!(e.line, Some(header + 2), "{e}");
    }

    /// An unknown key of an `[[instance]]` is a TOML error at its line and
    /// column, naming the key and the keys an instance has.
    #[test]
    fn an_unknown_key_of_an_instance_is_refused_by_name() {
        let e = instance_refusal("[[instance]]\nmesh = \"teapot\"\nrotation = [0, 90, 0]\n");
        assert_eq!(e.kind, crate::file::ErrorKind::Toml, "{e}");
        assert_eq!(e.item, None, "{e}");
        assert_eq!(e.line, Some(INSTANCE_HEAD.lines().count() + 3), "{e}");
        assert_eq!(e.column, Some(1), "{e}");
        for w in [
            "unknown field `rotation`",
            "`mesh`",
            "`name`",
            "`scale`",
            "`rotate`",
            "`quaternion`",
            "`translate`",
        ] {
            assert!(e.message.contains(w), "{w:?} in {e}");
        }
    }

    /// The scale's bounds are inclusive: `2^20` and `2^-20` (and their
    /// mirrors) are taken as written.
    #[test]
    fn instance_scales_of_the_bounds_are_taken() {
        for scale in [
            "1048576",
            "-1048576",
            "9.5367431640625e-7",
            "[1, -9.5367431640625e-7, 1]",
        ] {
            let text = format!("{INSTANCE_HEAD}[[instance]]\nmesh = \"teapot\"\nscale = {scale}\n");
            let d =
                crate::file::parse(&text, "inst.toml").unwrap_or_else(|e| panic!("{scale}: {e}"));
            let s = d.to_core().unwrap();
            let want: f64 = scale
                .trim_matches(['[', ']'])
                .split(", ")
                .map(|x| x.parse::<f64>().unwrap())
                .find(|x| *x != 1.0)
                .unwrap();
            let got = s.instances()[0].placement.scale;
            assert!(got.contains(&(want as f32)), "{scale}: {got:?}");
        }
    }

    /// `to_core` of a description changed in code names the instance as the
    /// file does, and leaves the scene's own items alone.
    #[test]
    fn to_core_names_the_instance_it_refuses() {
        let text = format!("{INSTANCE_HEAD}[[instance]]\nmesh = \"teapot\"\nname = \"t\"\n");
        let mut d = crate::file::parse(&text, "inst.toml").unwrap();
        d.to_core().unwrap();
        d.instances[0].scale = ScaleDesc::Axes([1.0, 0.0, 1.0]);
        let e = d.to_core().unwrap_err();
        assert_eq!(e.item, "instance 1 (\"t\")");
        assert!(
            e.message
                .starts_with("instance scale must be in [2^-20, 2^20]"),
            "{e}"
        );
        d.instances[0].scale = ScaleDesc::Uniform(1.0);
        d.instances[0].quaternion = Some([0.0; 4]);
        let e = d.to_core().unwrap_err();
        assert_eq!(e.item, "instance 1 (\"t\")");
        assert!(
            e.message.starts_with("instance rotation has zero length"),
            "{e}"
        );
        d.instances[0].quaternion = None;
        d.instances[0].mesh = "nothing".into();
        let e = d.to_core().unwrap_err();
        assert_eq!(
            e.to_string(),
            "instance 1 (\"t\"): no mesh is named \"nothing\": an instance names a [[mesh]] by its `name`"
        );
    }

    fn assert_close(got: &[f32], want: &[f64], tolerance: f64, what: &str) {
        assert_eq!(got.len(), want.len(), "{what}");
        for (g, w) in got.iter().zip(want) {
            assert!(
                (f64::from(*g) - w).abs() <= tolerance,
                "{what}: {got:?}, want {want:?}"
            );
        }
    }

    /// A quaternion of `f32` numbers far from unit length (here 2^100, exact
    /// in `f32`, whose squares `f32` cannot hold) is normalised in `f64`
    /// before the core sees it, as a file's quaternions are; only a unit one
    /// (an animation's frame) goes to the core as it is.
    #[test]
    fn a_huge_quaternion_of_f32_numbers_is_normalised_first() {
        let dir = Scratch::new("huge-quaternion");
        let big = 2f64.powi(100);
        let text = format!(
            "{INSTANCE_HEAD}[[mesh]]\n{}\nname = \"pair\"\n\
             [[instance]]\nmesh = \"pair\"\nquaternion = [0, 0, {big:e}, {big:e}]\n",
            two_part_obj(&dir.0)
        );
        let d = crate::file::parse(&text, "inst.toml").unwrap();
        let s = d.to_core().unwrap();
        let h = 0.5f64.sqrt();
        for i in s.instances() {
            assert_close(&i.placement.rotation, &[0.0, 0.0, h, h], 1e-7, "rotation");
        }
    }

    /// A good scene of instances: each named instance is found by its name;
    /// the core scene has one instance a part of its mesh, in the file's
    /// order, of the mesh's index, with its placement (rotation as a
    /// quaternion, a uniform scale on every axis).
    #[test]
    fn instances_are_found_and_placed_one_per_part() {
        let dir = Scratch::new("instances");
        let text = format!(
            "{INSTANCE_HEAD}[[mesh]]\n{}\nname = \"pair\"\n\
             [[instance]]\nmesh = \"teapot\"\nname = \"front\"\nrotate = [0, 90, 0]\nscale = 2\n\
             translate = [1, 2, 3]\n\
             [[instance]]\nmesh = \"pair\"\nquaternion = [0, 0, 1, 1]\nscale = [1, -2, 0.5]\n\
             [[instance]]\nmesh = \"teapot\"\nname = \"mirror\"\nscale = [-1, 0.5, 1]\n\
             translate = [-1, 0, 0]\n",
            two_part_obj(&dir.0)
        );
        let d = crate::file::parse(&text, "inst.toml").unwrap();
        assert_eq!(d.meshes.len(), 3, "the teapot and the pair's two parts");
        assert_eq!(d.find("front"), Some(Object::Instance(0)));
        assert_eq!(d.find("mirror"), Some(Object::Instance(2)));
        assert_eq!(d.find("teapot"), Some(Object::Mesh(0)));
        assert_eq!(Object::Instance(2).to_string(), "instance 3");
        assert_eq!(d.instance_parts("teapot"), [0]);
        assert_eq!(d.instance_parts("pair"), [1, 2]);
        assert_eq!(d.instance_parts("pai"), Vec::<usize>::new());
        assert_eq!(d.instance_starts(), [0, 1, 3]);
        let s = d.to_core().unwrap();
        let inst = s.instances();
        assert_eq!(
            inst.iter().map(|i| i.mesh).collect::<Vec<_>>(),
            [0, 1, 2, 0]
        );
        let h = 0.5f64.sqrt();
        let p = inst[0].placement;
        assert_close(&p.rotation, &[0.0, h, 0.0, h], 1e-7, "front rotation");
        assert_eq!(p.scale, [2.0; 3]);
        assert_eq!(p.translation, [1.0, 2.0, 3.0]);
        for p in [inst[1].placement, inst[2].placement] {
            // As written or normalised: the same turn.
            let q = p.rotation.map(f64::from);
            let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            let unit: Vec<f32> = q.iter().map(|x| (x / len) as f32).collect();
            assert_close(&unit, &[0.0, 0.0, h, h], 1e-7, "pair rotation");
            assert_eq!(p.scale, [1.0, -2.0, 0.5]);
            assert_eq!(p.translation, [0.0; 3]);
        }
        let p = inst[3].placement;
        assert_close(&p.rotation, &[0.0, 0.0, 0.0, 1.0], 0.0, "mirror rotation");
        assert_eq!(p.scale, [-1.0, 0.5, 1.0]);
        assert_eq!(p.translation, [-1.0, 0.0, 0.0]);
        assert_eq!(s.with_view(|v| v.instance_count()), 4);
        // Each mesh (part) is baked once, however many its instances.
        assert_eq!(s.mesh_count(), 3);
    }

    /// Two instances of a mesh split into two parts start at 0 and 2 of the
    /// scene's four instances, each part of the mesh once an instance.
    #[test]
    fn instances_of_a_split_mesh_start_a_part_count_apart() {
        let dir = Scratch::new("starts");
        let text = format!(
            "{INSTANCE_HEAD}[[mesh]]\n{}\nname = \"pair\"\n\
             [[instance]]\nmesh = \"pair\"\n\
             [[instance]]\nmesh = \"pair\"\nname = \"second\"\ntranslate = [2, 0, 0]\n",
            two_part_obj(&dir.0)
        );
        let d = crate::file::parse(&text, "inst.toml").unwrap();
        assert_eq!(d.instance_starts(), [0, 2]);
        assert_eq!(d.find("second"), Some(Object::Instance(1)));
        let s = d.to_core().unwrap();
        let got: Vec<(u16, [f32; 3])> = s
            .instances()
            .iter()
            .map(|i| (i.mesh, i.placement.translation))
            .collect();
        assert_eq!(
            got,
            [
                (1, [0.0; 3]),
                (2, [0.0; 3]),
                (1, [2.0, 0.0, 0.0]),
                (2, [2.0, 0.0, 0.0])
            ]
        );
        // One part alone, by its own name.
        let part = d.meshes[1].name.clone().unwrap();
        assert!(part.starts_with("pair/"), "{part}");
        assert_eq!(d.instance_parts(&part), [1]);
    }

    /// `euler_quaternion` is the turn of `euler_xyz` (about X, then Y, then Z):
    /// its matrix is that rotation, for quarter turns and any angles; it is of
    /// length 1; and a few turns are the quaternions worked out by hand.
    #[test]
    fn euler_quaternion_turns_as_euler_xyz() {
        use crate::mesh::{euler_quaternion, euler_xyz, quaternion_matrix};
        let angles = [
            [0.0, 0.0, 0.0],
            [90.0, 0.0, 0.0],
            [0.0, 90.0, 0.0],
            [0.0, 0.0, -90.0],
            [180.0, 270.0, 90.0],
            [90.0, 90.0, 90.0],
            [-450.0, 720.0, 45.0],
            [30.0, 45.0, 60.0],
            [-12.5, 100.25, 359.0],
            [123.456, -78.9, 10.11],
            [0.001, -179.999, 33.3],
            [1000.5, -3.0, 7.0],
        ];
        for a in angles {
            let q = euler_quaternion(a);
            let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!((len - 1.0).abs() <= 1e-12, "{a:?}: {q:?}");
            let (m, r) = (quaternion_matrix(q), euler_xyz(a));
            for (mr, rr) in m.iter().zip(&r) {
                for (x, y) in mr.iter().zip(rr) {
                    assert!((x - y).abs() <= 1e-12, "{a:?}: {m:?} != {r:?}");
                }
            }
        }
        // By hand: a quarter turn about Y, a half turn about Z, and about X
        // then Y a quarter turn each (qy qx).
        let h = 0.5f64.sqrt();
        let same = |a: [f64; 3], want: [f64; 4]| {
            let q = euler_quaternion(a);
            let sign = if q.iter().zip(&want).map(|(x, y)| x * y).sum::<f64>() < 0.0 {
                -1.0
            } else {
                1.0
            };
            for (x, y) in q.iter().zip(want) {
                assert!((sign * x - y).abs() <= 1e-15, "{a:?}: {q:?}, want {want:?}");
            }
        };
        same([0.0, 90.0, 0.0], [0.0, h, 0.0, h]);
        same([0.0, 0.0, 180.0], [0.0, 0.0, 1.0, 0.0]);
        same([90.0, 90.0, 0.0], [0.5, 0.5, -0.5, 0.5]);
        // [0, 90, 0] turns +X to -Z, as `rotate` is documented.
        let r = euler_xyz([0.0, 90.0, 0.0]);
        assert_eq!([r[0][0], r[1][0], r[2][0]], [0.0, 0.0, -1.0]);
    }

    /// Every part of a split mesh is checked where an instance places it: a
    /// first part carried beyond the scene's extent is refused as the last
    /// would be (not accepted, then left out of the view with every other
    /// instance).
    #[test]
    fn every_part_of_an_instance_is_checked() {
        let dir = Scratch::new("extent");
        std::fs::write(
            dir.0.join("big.mtl"),
            "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n",
        )
        .unwrap();
        // The first part (red) 1e13 wide, the last (blue) 1: at a scale of
        // 2^20 the first reaches 1e19, beyond 2^60.
        std::fs::write(
            dir.0.join("big.obj"),
            "mtllib big.mtl\nv 0 0 0\nv 1e13 0 0\nv 0 1e13 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
             usemtl red\nf 1 2 3\nusemtl blue\nf 4 5 6\n",
        )
        .unwrap();
        let text = format!(
            "{INSTANCE_HEAD}[[mesh]]\nfile = {:?}\nname = \"big\"\n\
             [[instance]]\nmesh = \"big\"\nscale = 1048576\n",
            dir.0.join("big.obj").to_str().unwrap()
        );
        match crate::file::parse(&text, "inst.toml") {
            Ok(d) => {
                let s = d.to_core().unwrap();
                panic!(
                    "accepted: {} instances, {} in the view",
                    s.instances().len(),
                    s.with_view(|v| v.instance_count())
                );
            }
            Err(e) => {
                assert_eq!(e.item.as_deref(), Some("instance 1"), "{e}");
                assert!(
                    e.message
                        .contains("instance translation must be in the scene's extent"),
                    "{e}"
                );
            }
        }
    }
}
