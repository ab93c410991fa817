//! Built-in scenes, usable by firmware with no files: the chapter's two pictures, the
//! interference screen, and a showcase of every geometry and material kind.
//!
//! Each scene type has exactly the capacities it uses.

use crate::camera::Camera;
use crate::error::Error;
use crate::kind::Capacities;
use crate::sample::Sampler;
use crate::scene::Scene;
use crate::tile::RenderSettings;
use crate::view::SceneView;

/// The chapter's pictures: four spheres on a floor, one light.
pub type ChapterScene = Scene<crate::capacities!(spheres: 4, planes: 1, materials: 5, lights: 1)>;
/// The interference screen: one plane, one material, no light.
pub type InterferenceScene = Scene<crate::capacities!(planes: 1, materials: 1)>;
/// The showcase: every geometry and material kind.
pub type ShowcaseScene = Scene<
    crate::capacities!(spheres: 3, planes: 2, triangles: 4, boxes: 2, materials: 8, lights: 2),
>;
/// The teapot's scene in RAM: the floor, two materials and two lights; its mesh
/// and the mesh's BVH are baked data in flash ([`teapot`]).
#[cfg(feature = "teapot")]
pub type TeapotScene = Scene<crate::capacities!(planes: 1, materials: 2, lights: 2)>;

/// The built-in scenes as `static` data (flash on a chip), baked by the host
/// from their scene files (`scenes/<name>.toml`; a test of the host checks
/// that each file here is what it bakes today): each module's `SCENE` is a
/// [`crate::BakedScene`] at the scene's own size and settings, with a constant
/// per material and the tile loops it needs (`SceneLoops`).
/// [`Builtin::baked`] gives any of them, checked.
pub mod baked {
    /// `scenes/chapter-direct.toml`.
    #[rustfmt::skip]
    pub mod chapter_direct; /// `scenes/chapter-reflect.toml`.
    #[rustfmt::skip]
    pub mod chapter_reflect; /// `scenes/interference.toml`.
    #[rustfmt::skip]
    pub mod interference; /// `scenes/showcase.toml`.
    #[rustfmt::skip]
    pub mod showcase; /// `scenes/teapot.toml` (feature `teapot`).
    #[cfg(feature = "teapot")]
    #[rustfmt::skip]
    pub mod teapot;
}

/// The teapot's mesh (baked `static` data: flash on a chip), to give to a view of
/// [`teapot`] with [`SceneView::with_meshes`]:
///
/// ```
/// # fn main() -> Result<(), tessera_core::Error> {
/// let scene = tessera_core::builtin::teapot()?;
/// let view = scene.view().with_meshes(&tessera_core::builtin::TEAPOT_MESHES)?;
/// assert_eq!(view.meshes()[0].faces().len(), 1088);
/// # Ok(())
/// # }
/// ```
#[cfg(feature = "teapot")]
pub static TEAPOT_MESHES: &[crate::mesh::Mesh<'static>] = &baked::teapot::MESHES;

/// The built-in scenes, by name. Non-exhaustive: the feature `teapot` adds one,
/// so that code written without it still compiles with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Builtin {
    /// The chapter's first picture: direct light only.
    ChapterDirect,
    /// The chapter's second picture: one level of mirror reflection (the default).
    ChapterReflect,
    /// Young's interference fringes on a screen.
    Interference,
    /// Every geometry and material kind.
    Showcase,
    /// A smooth teapot of 1,088 faces on a checkered floor, two lights: its
    /// mesh and BVH are baked `static` data (flash on a chip); feature `teapot`.
    #[cfg(feature = "teapot")]
    Teapot,
}

impl Builtin {
    /// Every built-in scene (a slice: its length depends on the features).
    pub const ALL: &'static [Self] = &[
        Self::ChapterDirect,
        Self::ChapterReflect,
        Self::Interference,
        Self::Showcase,
        #[cfg(feature = "teapot")]
        Self::Teapot,
    ];

    /// The default scene (the chapter's second picture).
    pub const DEFAULT: Self = Self::ChapterReflect;

    /// The scene's name (`chapter-direct`, `chapter-reflect`, `interference`,
    /// `showcase`, `teapot`).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::ChapterDirect => "chapter-direct",
            Self::ChapterReflect => "chapter-reflect",
            Self::Interference => "interference",
            Self::Showcase => "showcase",
            #[cfg(feature = "teapot")]
            Self::Teapot => "teapot",
        }
    }

    /// The scene called `name`, if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|b| b.name() == name)
    }

    /// The settings the scene is meant to be rendered with.
    #[must_use]
    pub fn settings(self) -> RenderSettings {
        let (sampler, max_depth) = match self {
            Self::ChapterDirect => (Sampler::Centre, 0),
            Self::ChapterReflect => (Sampler::Centre, 1),
            Self::Interference => (Sampler::Centre, 0),
            Self::Showcase => (Sampler::Centre, 5),
            #[cfg(feature = "teapot")]
            Self::Teapot => (Sampler::Centre, 0),
        };
        RenderSettings {
            sampler,
            max_depth,
            seed: 0,
            encoding: crate::Encoding::Srgb,
        }
    }

    /// The scene's `static` data ([`baked`]), checked: its view (which reads
    /// the tables where they lie, in flash on a chip) and its frame at the
    /// scene's own size and [settings](Builtin::settings). The same pixels as
    /// [`Builtin::with_scene`], with no scene in RAM.
    ///
    /// ```
    /// use tessera_core::{builtin::Builtin, Tile, TileCoord};
    /// let (view, renderer) = Builtin::Showcase.baked()?;
    /// let mut tile = Tile::<16>::new();
    /// renderer.render_tile(&view, TileCoord::new(0, 0), &mut tile, &mut ())?;
    /// # Ok::<(), tessera_core::Error>(())
    /// ```
    ///
    /// # Errors
    /// As [`crate::BakedScene::view`] and [`crate::BakedScene::renderer`] (none
    /// for data the host baked).
    pub fn baked(self) -> Result<(SceneView<'static>, crate::Renderer), Error> {
        self.with_baked_scene(|view, camera| {
            let renderer = crate::Renderer::try_new(camera, baked_viewport(self), self.settings())?;
            Ok((*view, renderer))
        })?
    }

    /// [`Builtin::with_scene`] from the scene's `static` data ([`baked`]): its
    /// checked view, which reads the tables where they lie, and its camera.
    ///
    /// # Errors
    /// As [`crate::BakedScene::view`] and its camera's check (none for data the
    /// host baked).
    pub fn with_baked_scene<R>(
        self,
        f: impl FnOnce(&SceneView<'static>, &Camera) -> R,
    ) -> Result<R, Error> {
        fn hand<C: Capacities, R>(
            s: &'static crate::BakedScene<'static, C>,
            f: impl FnOnce(&SceneView<'static>, &Camera) -> R,
        ) -> Result<R, Error> {
            Ok(f(&s.view()?, &s.camera().camera()?))
        }
        match self {
            Self::ChapterDirect => hand(&baked::chapter_direct::SCENE, f),
            Self::ChapterReflect => hand(&baked::chapter_reflect::SCENE, f),
            Self::Interference => hand(&baked::interference::SCENE, f),
            Self::Showcase => hand(&baked::showcase::SCENE, f),
            #[cfg(feature = "teapot")]
            Self::Teapot => hand(&baked::teapot::SCENE, f),
        }
    }

    /// The text of the scene file the built-in scene is baked from
    /// (`scenes/<name>.toml` of the repository, which `tessera bake` turns into
    /// the scene's `static` tables, this text among them): not linked unless
    /// called.
    #[must_use]
    pub fn source(self) -> &'static str {
        match self {
            Self::ChapterDirect => baked::chapter_direct::SOURCE,
            Self::ChapterReflect => baked::chapter_reflect::SOURCE,
            Self::Interference => baked::interference::SOURCE,
            Self::Showcase => baked::showcase::SOURCE,
            #[cfg(feature = "teapot")]
            Self::Teapot => baked::teapot::SOURCE,
        }
    }

    /// Builds the scene (on the stack) and hands its view and camera to `f`.
    pub fn with_scene<R>(self, f: impl FnOnce(&SceneView<'_>, &Camera) -> R) -> Result<R, Error> {
        self.build(0, f)
    }

    /// [`Builtin::with_scene`] with the scene scaled by `2^k` (see
    /// [`Scene::scaled_pow2`]): a test hook, with the feature `testing`.
    #[cfg(feature = "testing")]
    pub(crate) fn with_scaled_scene_hook<R>(
        self,
        k: i32,
        f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
    ) -> Result<R, Error> {
        self.build(k, f)
    }

    /// Builds the scene, scaled by `2^k` unless `k` is 0, and hands it to `f`.
    fn build<R>(self, k: i32, f: impl FnOnce(&SceneView<'_>, &Camera) -> R) -> Result<R, Error> {
        match self {
            Self::ChapterDirect => hand(chapter_direct()?, k, f),
            Self::ChapterReflect => hand(chapter_reflect()?, k, f),
            Self::Interference => hand(interference()?, k, f),
            Self::Showcase => hand(showcase()?, k, f),
            #[cfg(feature = "teapot")]
            Self::Teapot => hand_teapot(k, f),
        }
    }
}

/// The size a built-in scene's file gives (each is 320x240).
fn baked_viewport(b: Builtin) -> crate::Viewport {
    match b {
        Builtin::ChapterDirect => baked::chapter_direct::SCENE.viewport(),
        Builtin::ChapterReflect => baked::chapter_reflect::SCENE.viewport(),
        Builtin::Interference => baked::interference::SCENE.viewport(),
        Builtin::Showcase => baked::showcase::SCENE.viewport(),
        #[cfg(feature = "teapot")]
        Builtin::Teapot => baked::teapot::SCENE.viewport(),
    }
}

/// `f` of the scene's view and camera, the scene scaled by `2^k` first unless `k`
/// is 0 (scaling is a test hook: without the feature `testing`, `k` is always 0).
fn hand<C: Capacities, R>(
    scene: Scene<C>,
    k: i32,
    f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
) -> Result<R, Error> {
    #[cfg(feature = "testing")]
    let scene = if k == 0 {
        scene
    } else {
        scene.scaled_pow2_hook(k)?
    };
    #[cfg(not(feature = "testing"))]
    let _ = k;
    Ok(f(&scene.view(), scene.camera()))
}

/// `f` of the teapot scene's view (its baked mesh in flash, see
/// [`SceneView::with_meshes`]) and camera; scaled by `2^k` (a test hook), the
/// mesh's vertices are copied into RAM, scaled, and given a BVH built there.
#[cfg(feature = "teapot")]
fn hand_teapot<R>(k: i32, f: impl FnOnce(&SceneView<'_>, &Camera) -> R) -> Result<R, Error> {
    let scene = teapot()?;
    if k == 0 {
        let view = scene.view().with_meshes(TEAPOT_MESHES)?;
        return Ok(f(&view, scene.camera()));
    }
    #[cfg(feature = "testing")]
    {
        let [mesh] = &baked::teapot::MESHES;
        scaled_teapot(&scene, k, &baked::teapot::MESH0_VERTICES, mesh, f)
    }
    #[cfg(not(feature = "testing"))]
    Err(Error::BvhMismatch)
}

/// The teapot scaled by `2^k`, in RAM (a test hook: its triangles and their BVH on
/// the stack, in its own frame: never inlined, so that the unscaled scenes do not
/// reserve it).
/// `vertices` are `mesh`'s.
#[cfg(all(feature = "teapot", feature = "testing"))]
#[inline(never)]
fn scaled_teapot<const V: usize, R>(
    scene: &TeapotScene,
    k: i32,
    vertices: &[[f32; 3]; V],
    mesh: &crate::mesh::Mesh<'_>,
    f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
) -> Result<R, Error> {
    use crate::geometry::Triangle;
    use crate::primitive::Primitive;
    use crate::vec::Vec3;
    let scene = scene.scaled_pow2_hook(k)?;
    let s = libm::ldexpf(1.0, k.clamp(-200, 200));
    let moved = vertices.map(|[x, y, z]| [x * s, y * s, z * s]);
    let at = |i: u16| {
        let [x, y, z] = moved.get(usize::from(i)).copied().unwrap_or([0.0; 3]);
        Vec3::new(x, y, z)
    };
    let mut triangles: heapless::Vec<Primitive<Triangle>, 2048> = heapless::Vec::new();
    for &[a, b, c] in mesh.faces() {
        let t = Primitive {
            geometry: Triangle::try_new(at(a), at(b), at(c))?,
            material: mesh.material(),
        };
        triangles.push(t).map_err(|_| Error::CapacityExceeded {
            list: crate::error::List::Triangles,
            capacity: 2048,
        })?;
    }
    let mut bvh: crate::bvh::Bvh<4096, 2048> = crate::bvh::Bvh::new();
    bvh.build(&triangles)?;
    let scaled = [crate::mesh::Mesh::new(
        &moved,
        mesh.faces(),
        mesh.normals(),
        mesh.material(),
        crate::bvh::BakedBvh::new(bvh.nodes(), bvh.order(), bvh.reach()),
    )];
    let view = scene.view().with_meshes(&scaled)?;
    Ok(f(&view, scene.camera()))
}

/// The scene of `baked` in RAM ([`Scene::from_view`]): the built-in scenes are
/// written once, as scene files, and baked; the scenes in RAM are copies of
/// their lists (a mesh stays in flash and is checked where a view is given it).
fn copied<C: Capacities, B: Capacities>(
    baked: &'static crate::BakedScene<'static, B>,
) -> Result<Scene<C>, Error> {
    Scene::from_view(baked.camera().camera()?, &baked.lists_only().view()?)
}

/// The teapot's scene without its mesh (a copy of [`baked::teapot`]'s tables):
/// a checkered floor, the teapot's glazed red, a warm key light and a cool fill
/// light.
#[cfg(feature = "teapot")]
pub fn teapot() -> Result<TeapotScene, Error> {
    copied(&baked::teapot::SCENE)
}

/// The chapter's first picture (a copy of [`baked::chapter_direct`]'s tables):
/// direct illumination only, a white light above the blue sphere.
pub fn chapter_direct() -> Result<ChapterScene, Error> {
    copied(&baked::chapter_direct::SCENE)
}

/// The chapter's second picture (a copy of [`baked::chapter_reflect`]'s
/// tables): direct and one level of indirect illumination, with a slightly
/// (red) and a very (green) mirror-like sphere.
pub fn chapter_reflect() -> Result<ChapterScene, Error> {
    copied(&baked::chapter_reflect::SCENE)
}

/// The chapter's interference example (a copy of [`baked::interference`]'s
/// tables): Young's fringes (`d` = 2 mm, `lambda` = 500 nm, `L` = 3 m, spacing
/// 0.75 mm) on a screen 7 mm high, seen head on. The texture is emitted as is
/// (ambient light 1, no diffuse), so a pixel's value is the texture's, which
/// makes the sampling error measurable.
pub fn interference() -> Result<InterferenceScene, Error> {
    copied(&baked::interference::SCENE)
}

/// Every geometry kind (plane, sphere, triangle, box) and material kind (matte,
/// specular, mirror, glass, checker and fringe textures) in one scene (a copy of
/// [`baked::showcase`]'s tables).
pub fn showcase() -> Result<ShowcaseScene, Error> {
    copied(&baked::showcase::SCENE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::Texture;

    /// The baked teapot's named items are its scene file's: the constants
    /// index the tables at the items the file names.
    #[cfg(feature = "teapot")]
    #[test]
    fn the_baked_teapots_names_index_its_tables() {
        use baked::teapot as t;
        assert_eq!(
            t::LIGHTS[t::LIGHT_KEY].position(),
            crate::Vec3::new(-2.0, 5.0, 3.0)
        );
        assert_eq!(
            t::LIGHTS[t::LIGHT_FILL].position(),
            crate::Vec3::new(4.0, 3.0, -1.0)
        );
        assert_eq!(t::PLANES[t::PLANE_FLOOR].material, t::MAT_FLOOR);
        assert_eq!(t::MESHES.len(), 1);
        assert_eq!(t::MESH_TEAPOT, 0);
    }

    #[test]
    fn every_builtin_builds_and_is_named() {
        for &b in Builtin::ALL {
            assert_eq!(Builtin::from_name(b.name()), Some(b));
            assert!(b.with_scene(|_, _| ()).is_ok());
            assert!(b.settings().validate().is_ok());
        }
        assert_eq!(Builtin::from_name("nope"), None);
    }

    /// Every tile of `frame` over `view`, as bytes.
    fn pixels(view: &SceneView<'_>, renderer: &crate::Renderer) -> [u8; 3 * 80 * 60] {
        let mut out = [0; 3 * 80 * 60];
        let mut tile = crate::Tile::<16>::new();
        for ty in 0..4 {
            for tx in 0..5 {
                let coord = crate::TileCoord::new(tx, ty);
                renderer
                    .render_tile(view, coord, &mut tile, &mut ())
                    .unwrap();
                for (y, row) in tile.rows().enumerate() {
                    for (x, p) in row.iter().enumerate() {
                        let i = 3 * ((usize::from(ty) * 16 + y) * 80 + usize::from(tx) * 16 + x);
                        out[i..i + 3].copy_from_slice(&[p.r, p.g, p.b]);
                    }
                }
            }
        }
        out
    }

    /// A built-in scene's static data renders the scene the core builds, byte
    /// for byte, at the scene's own settings; its size is the scene file's.
    #[test]
    fn every_builtin_baked_renders_like_the_built_scene() {
        let vp = crate::Viewport::new(80, 60);
        for &b in Builtin::ALL {
            let (view, renderer) = b.baked().unwrap();
            assert_eq!(*renderer.settings(), b.settings(), "{}", b.name());
            assert_eq!(renderer.viewport(), crate::Viewport::new(320, 240));
            let baked = b
                .with_baked_scene(|v, cam| {
                    let f = crate::Renderer::try_new(cam, vp, b.settings()).unwrap();
                    pixels(v, &f)
                })
                .unwrap();
            // Read where they lie.
            assert!(
                core::ptr::eq(view.materials(), baked_materials(b)),
                "{}",
                b.name()
            );
            let built = b
                .with_scene(|v, cam| {
                    let f = crate::Renderer::try_new(cam, vp, b.settings()).unwrap();
                    pixels(v, &f)
                })
                .unwrap();
            assert!(baked == built, "{}", b.name());
            assert!(baked.iter().any(|&x| x > 40), "{}: a black image", b.name());
        }
    }

    /// The baked scene's material table, where it lies.
    fn baked_materials(b: Builtin) -> &'static [crate::material::Material] {
        match b {
            Builtin::ChapterDirect => &baked::chapter_direct::MATERIALS,
            Builtin::ChapterReflect => &baked::chapter_reflect::MATERIALS,
            Builtin::Interference => &baked::interference::MATERIALS,
            Builtin::Showcase => &baked::showcase::MATERIALS,
            #[cfg(feature = "teapot")]
            Builtin::Teapot => &baked::teapot::MATERIALS,
        }
    }

    #[test]
    fn showcase_uses_every_kind() {
        let s = showcase().unwrap();
        let v = s.view();
        assert!(!v.spheres().is_empty() && !v.planes().is_empty());
        assert!(!v.triangles().is_empty() && !v.boxes().is_empty());
        let m = v.materials();
        assert!(m.iter().any(|m| m.transparency() > 0.0));
        assert!(m.iter().any(|m| m.reflectivity() > 0.5));
        assert!(m.iter().any(|m| m.specular() > 0.0));
        assert!(
            m.iter()
                .any(|m| matches!(m.texture(), Texture::Checker { .. }))
        );
        assert!(
            m.iter()
                .any(|m| matches!(m.texture(), Texture::Fringes { .. }))
        );
    }
}
