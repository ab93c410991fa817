//! A bounded glTF 2.0 reader: a `.gltf` file (its buffers and images embedded as
//! `data:` URIs or in files beside it) or a `.glb` file, read into a neutral,
//! fully resolved description in world space ([`Imported`]): one triangle mesh
//! per (node, mesh primitive) of the scene, the materials those meshes use, the
//! encoded images of their base colour textures, the perspective cameras and the
//! punctual lights the nodes carry, and a warning for everything left out.
//!
//! # What is read
//!
//! - The scene: the default one (`scene`), else scene 0, else every root node
//!   (a node no other node names as a child). Node transforms (a `matrix` or
//!   translation, rotation and scale) are composed down the tree (parent ×
//!   child), in `f64`, column-major as glTF stores them. A node reached twice by
//!   the hierarchy (a cycle, or a node with two parents) is an error.
//! - Every primitive of mode `TRIANGLES`, `TRIANGLE_STRIP` or `TRIANGLE_FAN`
//!   (strips and fans are turned into triangles), indexed (8, 16 or 32-bit
//!   indices) or not: `POSITION` and `NORMAL` (`f32`), `TEXCOORD_0` (`f32`, or
//!   normalized 8 or 16-bit integers), sparse accessors included. Positions are
//!   moved into world space, normals by the inverse transpose and made unit
//!   length; a world matrix of negative determinant (a mirror) has the winding
//!   of its triangles reversed, so that they keep facing the way the file means.
//!   Texture coordinates are kept as stored (glTF's convention: `v` grows down
//!   from the image's top row). Only the vertices the triangles use are kept;
//!   triangles with a repeated vertex (a strip's restarts) are left out.
//!   Points and lines are left out, with a warning.
//! - Materials (metallic-roughness): base colour factor and texture (with its
//!   sampler's magnification filter and wrap modes), metallic and roughness
//!   factors, `KHR_materials_transmission`, `KHR_materials_ior`, the emissive
//!   factor times `KHR_materials_emissive_strength`, `doubleSided`.
//! - Images: the encoded bytes (PNG or JPEG, checked by their signature) of the
//!   base colour textures, from a buffer view, a `data:` URI or a file. They are
//!   not decoded here.
//! - Perspective cameras and `KHR_lights_punctual` lights, in world space.
//! - Animations ([`read_animated`], what a whole glTF scene plays; [`read`]
//!   leaves them out with a warning, as a scene file's `[[mesh]]` takes a
//!   file's triangles as posed): the file's first animation, its channels
//!   that move a node's `translation`, `rotation` or `scale`. Each node they
//!   move that draws meshes (itself or the nodes below it) is an anchor: its
//!   meshes and its descendants' are read in its own space (the descendants'
//!   transforms relative to it applied) and [`Imported::animation`] gives
//!   its rest placement and its tracks in world space
//!   ([`AnimatedNode`]): the node's parent's world matrix `P` must be a
//!   similarity (a rotation `R`, a uniform scale `s`, possibly negative for a
//!   mirror, and a translation; checked in `f64` within a relative 1e-6), and
//!   is composed into each keyframe: translations moved by `P`, rotations
//!   `R q`, scales times `s`; a channel not animated takes the node's own
//!   TRS composed the same way. Times come from the sampler's input accessor
//!   (seconds, at least 0, strictly increasing), values from its output
//!   (rotations of `FLOAT` or normalized integers, made unit length);
//!   `LINEAR` stays linear (spherical for rotations), `STEP` step, and
//!   `CUBICSPLINE` is read as linear through the keyframes' values, its
//!   tangents dropped, with a warning naming the animation and the channel.
//!   Nodes not animated stay in world space.
//!
//! # What is not, and what it costs
//!
//! Each of these is a warning naming the item (`node 'Arm': skin ignored: ...`),
//! or an error where the picture would be wrong:
//!
//! | feature | outcome |
//! | --- | --- |
//! | skins and joints | warning per node: drawn as stored (the bind pose) |
//! | morph targets, weights | warning per mesh: the base shape is drawn |
//! | animations other than the first | warning naming them |
//! | animations, read by [`read`] (a `[[mesh]]` file) | warning: not read for a `[[mesh]]` file, the triangles as posed |
//! | a `weights` channel (morph targets) | warning naming the animation, the channel and the node: left still |
//! | a channel moving a node that draws no mesh (a camera, a light, a joint, an empty node) | warning naming the node: left still |
//! | an animated node whose parent's world matrix shears or scales unevenly | warning naming the node: drawn still at its rest pose |
//! | an animated node below another animated node | warning naming both: only the outermost's animation is read, the inner one stays at its rest pose within it |
//! | an animated node given by a `matrix` (glTF forbids it) | warning naming the node: drawn still |
//! | `CUBICSPLINE` interpolation | warning naming the animation and the channel: linear through the keyframes' values |
//! | keyframes: times not finite, negative or not strictly increasing, a count of values that is not one (three for `CUBICSPLINE`) a time, a value not finite, a rotation of length 0, an accessor of the wrong type; two channels moving one property of a node; a channel naming a sampler or a node the file lacks | error naming the animation, the channel and the sampler |
//! | `KHR_draco_mesh_compression`, `EXT_meshopt_compression` | error if in `extensionsRequired`; otherwise a warning and the uncompressed data is read, or an error if there is none |
//! | `KHR_texture_basisu` (KTX2) | error if required; otherwise a warning naming the texture (its PNG/JPEG fallback is read); a base colour texture whose image is KTX2 is an error naming the image |
//! | `KHR_mesh_quantization`, any other unknown `extensionsRequired` entry | error naming it |
//! | an `extensionsUsed` entry not read | warning naming it |
//! | `KHR_texture_transform` on the base colour texture | warning naming the material (drawn untransformed) |
//! | base colour texture on `TEXCOORD_1` or another set | warning naming the material; the texture is dropped (only `TEXCOORD_0` is read) |
//! | normal, occlusion, emissive, metallic-roughness, transmission textures | warning naming the material and the textures |
//! | `alphaMode` `MASK` or `BLEND` | warning naming the material (drawn opaque) |
//! | `COLOR_0` and other vertex colours | warning naming the mesh and primitive |
//! | attributes not named by glTF (custom `_NAME` ones) | warning naming the mesh and primitive |
//! | spot lights | read as point lights, with a warning that the cone is ignored |
//! | orthographic cameras | warning, skipped |
//! | points and lines | warning, skipped |
//! | a node whose world matrix cannot be inverted (a zero scale) | warning, its mesh, camera or light is skipped |
//! | a mesh, camera or light moved past the range of `f64` | error naming it |
//!
//! # Bounds
//!
//! Nothing is read without a bound ([`Limits`]), and no input makes it panic:
//!
//! - The file's size is checked from its metadata before it is read, and the read
//!   itself stops one byte past [`Limits::max_file_bytes`] (only regular files
//!   are opened, as scene files are: see [`crate::file`]).
//! - External buffers and images are resolved relative to the `.gltf`'s folder.
//!   A URI is refused if it has a scheme other than `data:` (`http:`, `file:`, a
//!   Windows drive `C:`), if it is absolute (`/etc/...`), if it has a `..`
//!   component or a backslash: a model's files are in its folder or below it, so
//!   that a downloaded model cannot make the reader take (and a firmware bake
//!   carry) some other file of the machine. URIs are percent-decoded first.
//! - Only the buffers that the read meshes and images use are resolved. Their
//!   declared sizes together are bounded by [`Limits::max_buffer_bytes`] before
//!   any is read; a buffer declared larger than its file (or its `data:` URI, or
//!   the `.glb`'s binary chunk) is an error naming the buffer; an external one is
//!   read up to its declared size and no further.
//! - The triangles of the scene (every instance of every primitive) are counted
//!   from the accessors' counts and bounded by [`Limits::max_triangles`] before
//!   any vertex is read. An accessor's count times its element size must fit in
//!   [`Limits::max_buffer_bytes`] too (a sparse accessor needs no buffer bytes
//!   for its count).
//! - Every accessor read is checked before the reader sees it: its type is the
//!   one the glTF specification allows for its use, its count is at least 1, its
//!   stride at least its element size, and its last element lies within its
//!   buffer view, which lies within its buffer (sparse indices and values too),
//!   all in checked arithmetic. Index values must be below the vertex count;
//!   positions, normals and texture coordinates must be finite.
//! - The images' bytes together are bounded by [`Limits::max_image_bytes`].
//! - The keyframes read, every channel together, are bounded by
//!   [`Limits::max_keyframes`], checked from each input accessor's count
//!   before it is read; their accessors are checked as the meshes' are.
//! - Each warning is given once; past [`MAX_WARNINGS`] they are counted, not
//!   kept. Every primitive instance counts as at least one triangle against
//!   [`Limits::max_triangles`] (points and lines too), so that the work of a
//!   file of many empty instances is bounded like the rest.
//! - A `.glb` is checked chunk by chunk: a file shorter than its header says
//!   (a truncated download) is an error naming the file and the chunk.
//!
//! Errors are `Result<_, String>` messages naming the file and the item:
//! `model.glb: buffer 2: ...`, `model.gltf: mesh 'Cube', primitive 0: POSITION:
//! accessor 3: ...`. Names from the file are escaped as [`crate::escape`] does.
//!
//! # Why not `gltf::Gltf::from_slice` as is
//!
//! The `gltf` crate is used for its JSON types, its validation and its accessor
//! reader (`Primitive::reader`, fed with the buffers resolved here), but the
//! file is split and the JSON validated in steps of this module's own, because
//! `gltf` 1.4 panics on some inputs before its own checks reach them: a `.glb`
//! header declaring fewer than 12 bytes (a subtraction that overflows), a
//! primitive whose `POSITION` names an accessor that does not exist (its
//! validation indexes the accessor list), and, in its wrappers, cameras, images
//! and accessors whose JSON validation lets through what the wrapper unwraps.
//! So the `.glb` container is split here (checked), the JSON parsed with
//! `gltf::json`, those cases checked first, then validated by
//! `gltf::Document::from_json`; the plain JSON is read for everything but the
//! accessors, which go through `gltf`'s reader only after the checks above.
//!
//! # Refinements of the planned types
//!
//! - [`ImportedMesh`] also says which node, mesh and primitive it comes from.
//! - [`Imported::materials`] holds only the materials the read meshes use, in
//!   order of first use ([`ImportedMaterial::index`] is the file's index), and
//!   [`Imported::images`] only the images their base colour textures use
//!   ([`ImportedImage::index`] likewise): an image nothing draws is not read.
//! - [`ImportedCamera::node`] names the node a camera hangs on.
//! - [`ImportedMesh::anchor`] says which animated node's space a mesh is in;
//!   cameras and lights hang at their rest pose, animated or not.

use std::collections::HashSet;
use std::path::Path;

mod animation;
pub mod desc;
mod material;
mod primitive;
mod scene;
mod source;
#[cfg(test)]
mod tests;

/// What a glTF file holds that tessera can draw, resolved and in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    /// One mesh per (node, mesh primitive) of triangles, in the scene's order.
    pub meshes: Vec<ImportedMesh>,
    /// The materials the meshes use, in order of first use.
    pub materials: Vec<ImportedMaterial>,
    /// The images of the materials' base colour textures (encoded, not decoded).
    pub images: Vec<ImportedImage>,
    /// Every perspective camera a node of the scene carries, in world space.
    pub cameras: Vec<ImportedCamera>,
    /// Every `KHR_lights_punctual` light a node of the scene carries, in world
    /// space.
    pub lights: Vec<ImportedLight>,
    /// The file's first animation, as the nodes it moves that draw meshes
    /// ([`read_animated`]; `None` from [`read`], or when it moves no such node).
    pub animation: Option<ImportedAnimation>,
    /// Everything left out or changed, by name (`node 'Foo': skin ignored: ...`).
    pub warnings: Vec<String>,
}

/// A triangle mesh: one primitive of one node's mesh, in world space (or in
/// its animated anchor's own space).
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedMesh {
    /// The node's name, else the mesh's, else `node N`.
    pub name: String,
    /// The node's index in the file.
    pub node: usize,
    /// The animated node ([`AnimatedNode::node`]) whose own space the
    /// positions and normals are in (the node itself or an ancestor), or
    /// `None`: world space.
    pub anchor: Option<usize>,
    /// The mesh's index in the file.
    pub mesh: usize,
    /// The primitive's index in its mesh.
    pub primitive: usize,
    /// The vertices the triangles use, in world space.
    pub positions: Vec<[f64; 3]>,
    /// The vertex normals (world space, unit length), if the file has them.
    pub normals: Option<Vec<[f64; 3]>>,
    /// `TEXCOORD_0` as stored (glTF's convention: `v` grows down from the
    /// image's top), if the file has them.
    pub uvs: Option<Vec<[f64; 2]>>,
    /// Indices into `positions` (and `normals`, `uvs`), counter-clockwise seen
    /// from the front.
    pub triangles: Vec<[u32; 3]>,
    /// Index into [`Imported::materials`]; `None`: glTF's default material.
    pub material: Option<usize>,
}

/// A metallic-roughness material.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedMaterial {
    /// The material's name, else `material N`.
    pub name: String,
    /// The material's index in the file.
    pub index: usize,
    /// The base colour factor (linear RGBA).
    pub base_color: [f64; 4],
    /// The base colour texture, multiplied by `base_color`.
    pub base_color_texture: Option<TextureRef>,
    /// The metallic factor.
    pub metallic: f64,
    /// The roughness factor.
    pub roughness: f64,
    /// `KHR_materials_transmission`'s factor (0 without it).
    pub transmission: f64,
    /// `KHR_materials_ior`'s index of refraction (1.5 without it).
    pub ior: f64,
    /// The emissive factor times `KHR_materials_emissive_strength`.
    pub emissive: [f64; 3],
    /// Whether back faces are drawn lit as front faces.
    pub double_sided: bool,
}

/// A texture: an image and how it is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureRef {
    /// Index into [`Imported::images`].
    pub image: usize,
    /// The magnification filter is `NEAREST` (else linear, glTF's default).
    pub mag_nearest: bool,
    /// How `u` wraps.
    pub wrap_s: Wrap,
    /// How `v` wraps.
    pub wrap_t: Wrap,
}

/// A texture's wrap mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// Repeats (glTF's default).
    Repeat,
    /// Repeats, every other copy mirrored.
    MirroredRepeat,
    /// Clamps to the edge texels.
    ClampToEdge,
}

/// An encoded image (PNG or JPEG), not decoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImportedImage {
    /// The image's name, else its file's name, else `image N`.
    pub name: String,
    /// The image's index in the file.
    pub index: usize,
    /// `image/png` or `image/jpeg`, as the bytes' signature says.
    pub mime: String,
    /// The encoded bytes.
    pub bytes: Vec<u8>,
}

/// A perspective camera in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedCamera {
    /// The camera's name, else its node's, else `camera N`.
    pub name: String,
    /// The index of the node that carries it.
    pub node: usize,
    /// Where it is.
    pub position: [f64; 3],
    /// Where it looks (its node's -Z), unit length.
    pub forward: [f64; 3],
    /// Its up (its node's +Y, made perpendicular to `forward`), unit length.
    pub up: [f64; 3],
    /// The vertical field of view, in degrees.
    pub yfov_degrees: f64,
    /// Width over height, if the file fixes it.
    pub aspect: Option<f64>,
    /// The near plane's distance.
    pub znear: f64,
    /// The far plane's distance; `None`: infinite.
    pub zfar: Option<f64>,
}

/// What kind of light, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ImportedLightKind {
    /// A light infinitely far away.
    Directional {
        /// The way the light travels (its node's -Z), unit length.
        direction: [f64; 3],
    },
    /// A light at a point (also a spot light, its cone ignored).
    Point {
        /// Where it is.
        position: [f64; 3],
        /// Beyond this distance it is off; `None`: no limit.
        range: Option<f64>,
    },
}

/// A `KHR_lights_punctual` light.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedLight {
    /// The light's name, else its node's, else `light N`.
    pub name: String,
    /// What kind, where.
    pub kind: ImportedLightKind,
    /// Linear RGB.
    pub color: [f64; 3],
    /// As the file gives it: candela for a point light, lux for a directional one.
    pub intensity: f64,
}

/// The animation read: the file's first, as the nodes it moves that draw
/// meshes (each an anchor: its meshes and its descendants' are in its own
/// space), their tracks in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedAnimation {
    /// The animation's name (empty when it has none).
    pub name: String,
    /// Its index in the file.
    pub index: usize,
    /// The nodes it moves that draw meshes, in the order the scene visits
    /// them.
    pub nodes: Vec<AnimatedNode>,
}

/// A node an animation moves, which draws meshes (itself or below it), placed
/// in world space: its own translation, rotation and scale composed with its
/// parent's world matrix (a similarity: a uniform scale `s` and a rotation
/// `P`): translations moved by the parent's matrix, rotations `P q`, scales
/// times `s`.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimatedNode {
    /// The node's index in the file.
    pub node: usize,
    /// The node's name, else its mesh's, else `node N`.
    pub name: String,
    /// Its translation at rest (the file's pose), in world space.
    pub translation: [f64; 3],
    /// Its rotation at rest, a unit quaternion `x, y, z, w`, in world space.
    pub rotation: [f64; 4],
    /// Its scale at rest, per axis, in world space.
    pub scale: [f64; 3],
    /// Its world matrix at rest (column-major): where its meshes' positions go.
    pub world: [[f64; 4]; 4],
    /// The channels moving it, each in world space.
    pub tracks: Vec<ImportedTrack>,
}

/// One channel of an animated node: keyframe `k` is `values[k]` at
/// `times[k]` (seconds, at least 0, strictly increasing).
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedTrack {
    /// The channel's index in its animation.
    pub channel: usize,
    /// What it moves.
    pub path: tessera_core::animation::Channel,
    /// How (`CUBICSPLINE` is read as linear through the values).
    pub interpolation: tessera_core::animation::Interpolation,
    /// The keyframes' times, in seconds.
    pub times: Vec<f64>,
    /// The values, in world space: a translation or a scale in the first
    /// three numbers, a unit quaternion in all four.
    pub values: Vec<[f64; 4]>,
}

/// How much a glTF file may make the reader read and hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// The largest `.gltf` or `.glb` file.
    pub max_file_bytes: usize,
    /// The most buffer bytes, all the buffers the meshes and images use
    /// together (as declared by their `byteLength`); also the most bytes an
    /// accessor's count and element size may span.
    pub max_buffer_bytes: usize,
    /// The most triangles, every instance of every primitive together.
    pub max_triangles: usize,
    /// The most image bytes, all the images read together.
    pub max_image_bytes: usize,
    /// The most animation keyframes, every channel read together (a
    /// `CUBICSPLINE` keyframe counts once).
    pub max_keyframes: usize,
}

/// 64 MiB of file and of buffers: about 2.8 million triangles of indexed,
/// normalled, textured vertices (a vertex of 32 bytes, two triangles a vertex),
/// far beyond the host scene's [`crate::desc::MAX_TRIANGLES`] triangles, which
/// bound the triangles by default; 32 MiB of images; [`MAX_KEYFRAMES`]
/// keyframes.
impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_file_bytes: 64 << 20,
            max_buffer_bytes: 64 << 20,
            max_triangles: crate::desc::MAX_TRIANGLES,
            max_image_bytes: 32 << 20,
            max_keyframes: MAX_KEYFRAMES,
        }
    }
}

/// The most keyframes read by default, every channel together: an hour of
/// three channels at 30 keyframes a second would be 324,000; a scene's
/// description holds each as about 100 bytes, 10 MB at most.
pub const MAX_KEYFRAMES: usize = 100_000;

/// Reads the glTF file at `path` (`.gltf` or `.glb`, told apart by the `.glb`
/// signature, not the name), its external buffers and images relative to its
/// folder, within `limits`, as posed: its animations are left out, with a
/// warning (what a scene file's `[[mesh]]` takes). Errors name the file as
/// `path` shows and the item at fault.
pub fn read(path: &Path, limits: &Limits) -> Result<Imported, String> {
    read_with(path, limits, false)
}

/// [`read`], and the file's first animation: the meshes of each node it
/// moves (and of the nodes below it) in that node's own space, its tracks
/// in [`Imported::animation`] (what a whole glTF scene plays).
pub fn read_animated(path: &Path, limits: &Limits) -> Result<Imported, String> {
    read_with(path, limits, true)
}

/// [`read`] or [`read_animated`].
fn read_with(path: &Path, limits: &Limits, animated: bool) -> Result<Imported, String> {
    let shown = crate::escape_path(path);
    let bytes = crate::file::read_bytes(path, limits.max_file_bytes, "glTF file")
        .map_err(|e| format!("{shown}: {e}"))?;
    let base = path.parent().unwrap_or(Path::new(""));
    let mut cx = Cx {
        file: shown,
        base,
        limits,
        warnings: Vec::new(),
        seen: HashSet::new(),
        unshown: 0,
    };
    import(&bytes, animated, &mut cx)
}

/// What every step needs: the file as messages name it, its folder, the
/// limits, the warnings so far.
struct Cx<'a> {
    file: String,
    base: &'a Path,
    limits: &'a Limits,
    warnings: Vec<String>,
    /// The warnings given so far (each is given once).
    seen: HashSet<String>,
    /// Warnings past [`MAX_WARNINGS`], counted.
    unshown: usize,
}

/// The most warnings kept; past them one more says how many were left out.
pub const MAX_WARNINGS: usize = 256;

impl Cx<'_> {
    /// `message` about the file: `file: message`.
    fn err(&self, message: impl std::fmt::Display) -> String {
        format!("{}: {message}", self.file)
    }

    /// Adds a warning (about the file: the caller shows its name once), unless
    /// it was given already; past [`MAX_WARNINGS`] only counts it.
    fn warn(&mut self, message: String) {
        if self.seen.contains(&message) {
            return;
        }
        if self.warnings.len() < MAX_WARNINGS {
            self.seen.insert(message.clone());
            self.warnings.push(message);
        } else {
            self.seen.insert(message);
            self.unshown += 1;
        }
    }

    /// The warnings, with the count of those left out.
    fn take_warnings(&mut self) -> Vec<String> {
        let mut out = std::mem::take(&mut self.warnings);
        if self.unshown > 0 {
            out.push(format!("and {} more warnings", self.unshown));
        }
        out
    }
}

/// `kind 'name'` (escaped) if the item has a name, else `kind N`.
fn named(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(n) if !n.is_empty() => format!("{kind} '{}'", crate::escape(n)),
        _ => format!("{kind} {index}"),
    }
}

/// The whole import of the file's `bytes` (its first animation too when
/// `animated`).
fn import(bytes: &[u8], animated: bool, cx: &mut Cx) -> Result<Imported, String> {
    let (json, bin) = source::split(bytes, cx)?;
    let root = source::parse_json(json, cx)?;
    let document = source::validate(root, cx)?;
    let root = document.as_json();
    let targets = animation::targets(root, animated, cx)?;
    let visit = scene::visit(root, &targets.animated(), &targets.name, cx)?;
    let mut plan = primitive::plan(&document, &visit.placed, cx)?;
    let (materials, image_indices) = material::materials(root, &plan.materials, cx)?;
    let mut needed = primitive::needed_buffers(&document, &plan, &image_indices);
    needed.extend(animation::needed_buffers(root, &targets, &visit));
    needed.sort_unstable();
    needed.dedup();
    let buffers = source::buffers(root, bin, &needed, cx)?;
    let images = source::images(root, &image_indices, &buffers, cx)?;
    let meshes = primitive::meshes(&document, &visit.placed, &mut plan, &buffers, cx)?;
    let animation = animation::read(&document, &targets, &visit, &meshes, &buffers, cx)?;
    let cameras = scene::cameras(root, &visit.placed, cx)?;
    let lights = scene::lights(root, &visit.placed, cx)?;
    Ok(Imported {
        meshes,
        materials,
        images,
        cameras,
        lights,
        animation,
        warnings: cx.take_warnings(),
    })
}
