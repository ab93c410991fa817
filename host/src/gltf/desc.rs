//! A glTF file made into tessera's scene description: its triangles as the
//! faces of a mesh file ([`mesh_file`], what a `[[mesh]]` of a scene file takes
//! from a `.gltf` or `.glb`), or the whole file as a scene ([`scene`], what
//! `tessera render model.glb` shows). The file is read by [`super::read`] with
//! the default [`super::Limits`]; every warning of the reader is kept.
//!
//! # What each part becomes
//!
//! - **Triangles**: every triangle of every mesh primitive the scene draws, in
//!   the file's world space (node transforms applied by the reader), then placed
//!   as a `[[mesh]]` places an OBJ file's ([`crate::mesh::Placement`]). A
//!   primitive's vertex normals (`NORMAL`) and texture coordinates
//!   (`TEXCOORD_0`, kept as stored: glTF's `v` runs down from the image's top,
//!   as tessera's does) go with each of its faces. Faces the core refuses as
//!   degenerate (collinear once in `f32`) are left out and counted, as for OBJ
//!   files.
//! - **Materials**: each material the triangles use becomes a
//!   [`crate::desc::MaterialDesc`] by the rule of [`crate::material_rule`]
//!   ([`crate::material_rule::from_pbr`]: base colour, metallic, roughness,
//!   transmission, ior; what it cannot model is a warning), named
//!   `FILE/NAME` (`FILE` the file as the caller names it, `NAME` the
//!   material's name in the file, `material N` for an unnamed one; a name
//!   already taken gets ` (material N)` after it). A primitive without a
//!   material takes glTF's default material, white, metallic 1 and roughness 1
//!   (by the same rule: no diffuse term, lit by the ambient light alone), named
//!   `FILE/default material`.
//! - **Images**: the encoded bytes of each base colour texture's image, named
//!   `FILE#imageN` (`N` its index in the file), are handed over in
//!   [`crate::desc::SceneDesc::embedded`]; the material's image texture names
//!   them (decoded later, by the scene loader), with the sampler's
//!   magnification filter (`NEAREST`: nearest, else bilinear) and wrap modes.
//! - **Meshes** ([`scene`]): one [`crate::desc::MeshDesc`] per material (the
//!   core's meshes have one material each), in the order of the materials
//!   (and one per material of each animated node: see below);
//!   at most [`tessera_core::mesh::MAX_MESHES`] of them: a file whose
//!   triangles use more materials is refused. A mesh has the vertex normals of
//!   its faces (or texture coordinates) only when every one of its faces has
//!   them; otherwise it is shaded flat (or untextured), with a warning.
//!
//! # Animation
//!
//! [`scene`] reads the file's first animation ([`super::read_animated`]).
//! Each node it moves that draws meshes becomes an `[[instance]]` named after
//! the node (its name, else its mesh's, else `node N`; when that name is
//! taken, `NAME (node N)`, else `node N`, with a warning) of its own meshes,
//! one per material in the node's own space, named `NAME/MATERIAL`; the
//! instance stands at the node's rest placement in world space, and each
//! channel is a `[[keyframes]]` track of it (`translation`, `rotation` as
//! quaternions, `scale`; `LINEAR` linear, `STEP` step, `CUBICSPLINE` linear
//! through its values). The scene renders at the default 30 frames a second
//! (`tessera render model.glb --frame N`, `tessera simulate --animate`); a
//! render without `--frame` shows the file's rest pose. The still nodes'
//! meshes are drawn in world space as before. The still meshes and the
//! animated nodes' together are at most [`tessera_core::mesh::MAX_MESHES`]:
//! more is an error (so at most that many instances, and three tracks each).
//! The default camera frames the meshes at rest. [`mesh_file`] leaves the
//! animations out, with a warning.
//!
//! # Camera
//!
//! [`scene`] takes the perspective camera named by its caller (an error listing
//! the file's cameras when there is none of that name), else the file's first
//! one: its position, forward (its node's -Z) and up (its node's +Y), `yfov` in
//! degrees, `znear` as the near distance, `zfar` as the far distance. An
//! infinite `zfar` (none given) becomes 100 times the diagonal of the meshes'
//! bounding box plus the camera's distance to the box's centre (at least twice
//! `znear`), with a warning. A camera's `aspectRatio` sets the render size:
//! 240 pixels high, `round(240 aspect)` wide (within `[1, 65535]`, a warning
//! when cut); without one, the default size (320 x 240).
//!
//! Without a perspective camera in the file, a camera looks at the centre of
//! the meshes' bounding box from the front (+Z, up +Y), with a 45-degree field
//! of view, as far as the box's bounding sphere (radius half its diagonal `r`)
//! fills it: at the distance `d = r / sin 22.5°` from the centre; near `(d -
//! r) / 2`, far `2 (d + r)`. A warning says so.
//!
//! # Lights
//!
//! Each `KHR_lights_punctual` light becomes a light: a point light (a spot
//! light too, its cone ignored by the reader) a [`crate::desc::LightDesc::point`],
//! a directional light a [`crate::desc::LightDesc::sun`] along its direction,
//! with its colour. The intensity is the file's: tessera's light intensity is
//! the irradiance a light gives at distance 1 (a point light's falls off as
//! `1 / d^2` from there; a sun's is the same everywhere), so a point light of
//! `I` candela (lumens per steradian, glTF's unit) is taken as intensity `I`,
//! and a sun of `E` lux (glTF's unit) as intensity `E`. A light's `range` is
//! not modelled (the light reaches every distance): a warning names the light.
//!
//! Without a light in the file, a sun shines from above and behind the camera,
//! over its left shoulder (its rays travel along `forward - up + right / 2`,
//! the camera's axes), of intensity 1, and the ambient light is 0.1; a warning
//! says so. The background is a dark grey, `[0.05, 0.05, 0.05]`; every other
//! setting is [`crate::desc::SceneDesc::new`]'s.
//!
//! # Warnings
//!
//! The reader's warnings (which name the item but not the file) are given
//! with the file's name before them, once: `model.glb: node 'Arm': skin
//! ignored: ...`; the material rule's name the material, whose name starts
//! with the file's. [`mesh_file`] puts them in [`crate::mesh::MeshFile::warnings`];
//! [`scene`] in [`crate::desc::SceneDesc::warnings`], with its own (the
//! default camera or light, an infinite far plane, a light's range). What
//! concerns one mesh of a scene (some of its faces without normals) is that
//! mesh's warning ([`crate::desc::MeshDesc::warnings`]).

use super::{Imported, ImportedCamera, ImportedLightKind, ImportedMaterial, ImportedMesh, Limits};
use super::{ImportedImage, Wrap};
use crate::arr3::{cross, dot, length, sub};
use crate::desc::{
    CameraDesc, FilterDesc, LightDesc, MAX_TRIANGLES, MaterialDesc, MeshDesc, SceneDesc, WrapDesc,
    core_triangle_of, num, too_many,
};
use crate::material_rule::{Pbr, from_pbr};
use crate::mesh::{MeshFile, Placement};
use std::path::Path;
use tessera_core::error::List;

/// The height of a render whose camera fixes its aspect ratio, pixels.
pub const CAMERA_HEIGHT: u16 = 240;

/// The vertical field of view of the camera made for a file without one,
/// degrees.
pub const DEFAULT_FOVY: f64 = 45.0;

/// The ambient light of a scene made for a file without a light.
pub const DEFAULT_AMBIENT: f64 = 0.1;

/// The background of a scene made from a glTF file.
pub const BACKGROUND: [f64; 3] = [0.05; 3];

/// The triangles of every mesh primitive of the glTF file at `path` (`shown`:
/// the file as the scene file names it, in names and messages), in the file's
/// world space, placed by `place`; at most `room` faces (the room left in the
/// scene's triangle list). See the module doc for what each part becomes.
///
/// # Errors
/// The reader's errors (naming the file and the item); more than `room` faces
/// that are not degenerate; a file with no face to render.
pub fn mesh_file(
    path: &Path,
    shown: &str,
    place: &Placement,
    room: usize,
) -> Result<MeshFile, String> {
    let imported = super::read(path, &Limits::default())?;
    Ok(convert(imported, shown, place, room)?.file)
}

/// A whole scene from the glTF file at `path`, seen by the file's perspective
/// camera named `camera` (else its first one, else a camera made for it), lit
/// by its lights (else a sun made for it); see the module doc.
///
/// # Errors
/// [`mesh_file`]'s; more materials used than the core's
/// [`tessera_core::mesh::MAX_MESHES`] meshes; no perspective camera named
/// `camera` (the message lists the file's).
pub fn scene(path: &Path, camera: Option<&str>) -> Result<SceneDesc, String> {
    // Named by its file name: its meshes' files are relative to its folder,
    // and messages about the scene name its path already.
    let obj = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let shown = crate::escape(&obj);
    let mut imported = super::read_animated(path, &Limits::default())?;
    let cameras = std::mem::take(&mut imported.cameras);
    let lights = std::mem::take(&mut imported.lights);
    let animated = imported.animation.take().map_or_else(Vec::new, |a| a.nodes);
    let identity = Placement::of(&MeshDesc::unplaced(obj.clone(), None))?;
    let Converted {
        mut file,
        degenerate,
        nodes,
        anchors,
    } = convert(imported, &obj, &identity, MAX_TRIANGLES)?;
    let mut meshes = split(
        &group(&file, &anchors, None),
        &degenerate_of(&degenerate, None),
        &obj,
    )?;
    let mut warnings = std::mem::take(&mut file.warnings);
    name_meshes(&mut meshes, &file, &nodes, &shown, &mut warnings);
    let (lo, hi) = world_bounds(&file.faces, &anchors, &animated);

    let chosen = match camera {
        Some(name) => match cameras.iter().find(|c| c.name == name) {
            Some(c) => Some(c),
            None => {
                let names: Vec<String> = cameras
                    .iter()
                    .map(|c| format!("'{}'", crate::escape(&c.name)))
                    .collect();
                let has = if names.is_empty() {
                    "the file has none".to_string()
                } else {
                    format!("the file's are {}", names.join(", "))
                };
                return Err(format!(
                    "{shown}: no perspective camera named '{}': {has}",
                    crate::escape(name)
                ));
            }
        },
        None => cameras.first(),
    };
    let (camera, size) = match chosen {
        Some(c) => file_camera(c, (lo, hi), &shown, &mut warnings),
        None => {
            let c = front_camera(lo, hi);
            warnings.push(format!(
                "{shown}: the file has no perspective camera: one at [{}] looks at the \
                 centre of the meshes' bounding box from the front (+Z), the whole box \
                 in its {DEFAULT_FOVY}-degree field of view",
                c.position.map(num).join(", ")
            ));
            (c, None)
        }
    };

    let mut desc = SceneDesc::new(camera);
    if let Some((width, height)) = size {
        desc.render.width = width;
        desc.render.height = height;
    }
    desc.background = BACKGROUND;
    for l in &lights {
        let mut light = match l.kind {
            ImportedLightKind::Directional { direction } => {
                LightDesc::sun(direction, l.color, l.intensity)
            }
            ImportedLightKind::Point { position, range } => {
                if let Some(r) = range {
                    warnings.push(format!(
                        "{shown}: light '{}': its range {} is not modelled: the light \
                         reaches every distance, falling off as 1/d^2",
                        crate::escape(&l.name),
                        num(r)
                    ));
                }
                LightDesc::point(position, l.color, l.intensity)
            }
        };
        // Its name (the light's, else its node's) when no earlier light has it:
        // names are unique in a scene.
        if desc
            .lights
            .iter()
            .any(|o| o.name.as_deref() == Some(l.name.as_str()))
        {
            warnings.push(format!(
                "{shown}: light '{}': an earlier light has its name: it is left unnamed",
                crate::escape(&l.name)
            ));
        } else if crate::desc::name_fault(&l.name).is_none() {
            light.name = Some(l.name.clone());
        }
        desc.lights.push(light);
    }
    if lights.is_empty() {
        desc.lights
            .push(LightDesc::sun(shoulder_sun(&desc.camera), [1.0; 3], 1.0));
        desc.ambient = [DEFAULT_AMBIENT; 3];
        warnings.push(format!(
            "{shown}: the file has no light: a sun shines from above and behind the \
             camera (intensity 1), and the ambient light is {DEFAULT_AMBIENT}"
        ));
    }
    // A mesh's name that a light has too is left out: names are unique.
    for m in &mut meshes {
        if let Some(name) = &m.name
            && desc.lights.iter().any(|l| l.name.as_ref() == Some(name))
        {
            warnings.push(format!(
                "{shown}: a mesh and a light would both be named '{}': the mesh is left \
                 unnamed",
                crate::escape(name)
            ));
            m.name = None;
        }
    }
    // The animated nodes: their meshes, an instance of each, its keyframes.
    for a in &animated {
        let parts = split(
            &group(&file, &anchors, Some(a.node)),
            &degenerate_of(&degenerate, Some(a.node)),
            &obj,
        )?;
        if parts.is_empty() {
            continue;
        }
        let name = instance_name(a, &parts, &meshes, &desc);
        if name != a.name {
            warnings.push(format!(
                "{shown}: node '{}': its name is taken (or not a name): its instance is \
                 named '{}'",
                crate::escape(&a.name),
                crate::escape(&name)
            ));
        }
        animate(a, &name, parts, &mut meshes, &mut desc);
    }
    let most = tessera_core::mesh::MAX_MESHES;
    if meshes.len() > most {
        return Err(format!(
            "{shown}: its triangles make {} meshes (one per material of the still nodes, \
             and one per material of each animated node), and tessera draws at most {most}",
            meshes.len()
        ));
    }
    desc.materials = file.materials;
    desc.meshes = meshes;
    desc.embedded = file.embedded;
    desc.warnings = warnings;
    if !desc.keyframes.is_empty() {
        desc.tracks().map_err(|e| format!("{shown}: {e}"))?;
    }
    Ok(desc)
}

/// The faces of `file` that the anchor `anchor` draws (`None`: the still
/// nodes', in world space), with the file's materials.
fn group(file: &MeshFile, anchors: &[Option<usize>], anchor: Option<usize>) -> MeshFile {
    let mut out = MeshFile {
        materials: file.materials.clone(),
        ..MeshFile::default()
    };
    for (j, face) in file.faces.iter().enumerate() {
        if anchors.get(j).copied().flatten() != anchor {
            continue;
        }
        out.faces.push(*face);
        out.normals.push(file.normals.get(j).copied().flatten());
        out.uvs.push(file.uvs.get(j).copied().flatten());
        out.face_materials
            .push(file.face_materials.get(j).copied().flatten());
    }
    out
}

/// The degenerate faces of each material among the faces of `anchor`.
fn degenerate_of(degenerate: &[Vec<(Option<usize>, usize)>], anchor: Option<usize>) -> Vec<usize> {
    degenerate
        .iter()
        .map(|per| {
            per.iter()
                .filter(|(a, _)| *a == anchor)
                .map(|(_, n)| n)
                .sum()
        })
        .collect()
}

/// The smallest and largest coordinates of the faces at rest, in world
/// space: those of an animated node's meshes (`anchors`, by face) moved by
/// its world matrix.
fn world_bounds(
    faces: &[[[f64; 3]; 3]],
    anchors: &[Option<usize>],
    animated: &[super::AnimatedNode],
) -> ([f64; 3], [f64; 3]) {
    let placed: Vec<[[f64; 3]; 3]> = faces
        .iter()
        .enumerate()
        .map(|(j, f)| {
            let world = anchors
                .get(j)
                .copied()
                .flatten()
                .and_then(|n| animated.iter().find(|a| a.node == n));
            match world {
                Some(a) => f.map(|p| super::scene::point(&a.world, p)),
                None => *f,
            }
        })
        .collect();
    bounds(&placed)
}

/// The name of the instance of the animated node `a` (whose meshes are
/// `parts`): the node's name, else `NAME (node N)`, else `node N`, else that
/// with a number: one no mesh, light or instance of `desc` and `meshes` has,
/// that no still mesh's name starts with (followed by `/`), and that makes
/// no part's name (`NAME/MATERIAL`) one taken.
fn instance_name(
    a: &super::AnimatedNode,
    parts: &[MeshDesc],
    meshes: &[MeshDesc],
    desc: &SceneDesc,
) -> String {
    let names = || {
        meshes
            .iter()
            .filter_map(|m| m.name.as_deref())
            .chain(desc.lights.iter().filter_map(|l| l.name.as_deref()))
            .chain(desc.instances.iter().filter_map(|i| i.name.as_deref()))
    };
    let free = |n: &str| {
        let prefix = format!("{n}/");
        crate::desc::name_fault(n).is_none()
            && !names().any(|t| t == n || t.starts_with(&prefix))
            && !parts.iter().any(|p| {
                let own = part_name(n, p);
                names().any(|t| t == own)
            })
    };
    let first = [
        a.name.clone(),
        format!("{} (node {})", a.name, a.node),
        format!("node {}", a.node),
    ];
    first
        .into_iter()
        .chain((2..).map(|k| format!("node {} ({k})", a.node)))
        .find(|n| free(n))
        .unwrap_or_else(|| format!("node {}", a.node))
}

/// The name of the part `p` (a mesh of one material) of the instance `name`:
/// `NAME/MATERIAL`, the material as the file names it.
fn part_name(name: &str, p: &MeshDesc) -> String {
    let material = p.material.as_deref().unwrap_or_default();
    let own = material.split_once('/').map_or(material, |(_, n)| n);
    format!("{name}/{own}")
}

/// Adds the animated node `a` to `desc`: its `parts` (in its own space) as
/// meshes named `NAME/MATERIAL`, an instance `name` of them at its rest
/// placement, and a `[[keyframes]]` track per channel.
fn animate(
    a: &super::AnimatedNode,
    name: &str,
    parts: Vec<MeshDesc>,
    meshes: &mut Vec<MeshDesc>,
    desc: &mut SceneDesc,
) {
    use crate::desc::{ChannelDesc, InstanceDesc, InterpolationDesc, KeyframesDesc, ScaleDesc};
    use tessera_core::animation::{Channel, Interpolation};
    for mut p in parts {
        p.name = Some(part_name(name, &p));
        meshes.push(p);
    }
    desc.instances.push(InstanceDesc {
        mesh: name.to_string(),
        name: Some(name.to_string()),
        scale: ScaleDesc::Axes(a.scale),
        rotate: None,
        quaternion: Some(a.rotation),
        translate: a.translation,
    });
    for t in &a.tracks {
        let (channel, len) = match t.path {
            Channel::Translation => (ChannelDesc::Translation, 3),
            Channel::Rotation => (ChannelDesc::Rotation, 4),
            Channel::Scale => (ChannelDesc::Scale, 3),
        };
        desc.keyframes.push(KeyframesDesc {
            target: name.to_string(),
            channel,
            interpolation: match t.interpolation {
                Interpolation::Step => InterpolationDesc::Step,
                Interpolation::Linear => InterpolationDesc::Linear,
            },
            times: t.times.clone(),
            values: t.values.iter().map(|v| v[..len].to_vec()).collect(),
        });
    }
}

/// What [`convert`] makes of a file: the mesh file, and how many degenerate
/// faces each of its materials lost.
struct Converted {
    file: MeshFile,
    /// By index into `file.materials`: the degenerate faces left out, by the
    /// animated node whose meshes they are in (`None`: a still node's).
    degenerate: Vec<Vec<(Option<usize>, usize)>>,
    /// By index into `file.materials`: the still nodes (index, name) whose
    /// primitives have faces of that material, each once.
    nodes: Vec<Vec<(usize, String)>>,
    /// By face: the animated node whose own space it is in (`None`: world
    /// space).
    anchors: Vec<Option<usize>>,
}

/// The mesh file of what the reader made of a file (see [`mesh_file`]).
fn convert(
    imported: Imported,
    shown: &str,
    place: &Placement,
    room: usize,
) -> Result<Converted, String> {
    let Imported {
        meshes,
        materials,
        images,
        warnings,
        ..
    } = imported;
    let escaped = crate::escape(shown);
    let mut out = MeshFile::default();
    out.warnings
        .extend(warnings.into_iter().map(|w| format!("{escaped}: {w}")));
    let mut degenerate: Vec<Vec<(Option<usize>, usize)>> = Vec::new();
    let mut nodes: Vec<Vec<(usize, String)>> = Vec::new();
    let mut anchors = Vec::new();
    for m in &materials {
        let (desc, notes) = material(m, &images, shown, &out.materials);
        out.materials.push(desc);
        out.warnings.extend(notes);
        degenerate.push(Vec::new());
        nodes.push(Vec::new());
    }
    // Each image once, in the order the reader gives them (of first use).
    for image in images {
        out.embedded.push((image_name(shown, &image), image.bytes));
    }
    let mut default = None;
    for mesh in &meshes {
        let k = match mesh.material {
            Some(k) if k < out.materials.len() => k,
            Some(k) => {
                return Err(format!(
                    "{escaped}: {}: material {k} of the reader's list does not exist",
                    mesh_name(mesh)
                ));
            }
            None => *default.get_or_insert_with(|| {
                let (desc, notes) = default_material(shown, &out.materials);
                out.materials.push(desc);
                out.warnings.extend(notes);
                degenerate.push(Vec::new());
                nodes.push(Vec::new());
                out.materials.len() - 1
            }),
        };
        let mut lost = 0;
        add_faces(mesh, k, place, room, shown, &mut out, &mut lost)?;
        anchors.resize(out.faces.len(), mesh.anchor);
        match degenerate[k].iter_mut().find(|(a, _)| *a == mesh.anchor) {
            Some((_, n)) => *n += lost,
            None => degenerate[k].push((mesh.anchor, lost)),
        }
        if mesh.anchor.is_none()
            && !mesh.triangles.is_empty()
            && !nodes[k].iter().any(|(n, _)| *n == mesh.node)
        {
            nodes[k].push((mesh.node, mesh.name.clone()));
        }
    }
    if out.faces.is_empty() {
        return Err(format!(
            "{escaped}: no face to render ({} degenerate faces left out)",
            out.degenerate
        ));
    }
    Ok(Converted {
        file: out,
        degenerate,
        nodes,
        anchors,
    })
}

/// Adds the faces of `mesh`, of material `k`, placed, to `out` (at most `room`
/// of them in all); counts its degenerate ones in `lost` too.
fn add_faces(
    mesh: &ImportedMesh,
    k: usize,
    place: &Placement,
    room: usize,
    shown: &str,
    out: &mut MeshFile,
    lost: &mut usize,
) -> Result<(), String> {
    let broken = || {
        format!(
            "{}: {}: a triangle's vertex index is beyond its vertices",
            crate::escape(shown),
            mesh_name(mesh)
        )
    };
    let corners = |t: &[u32; 3]| -> Option<[usize; 3]> {
        let [a, b, c] = t.map(|i| {
            usize::try_from(i)
                .ok()
                .filter(|&i| i < mesh.positions.len())
        });
        Some([a?, b?, c?])
    };
    for t in &mesh.triangles {
        let idx = corners(t).ok_or_else(broken)?;
        let face = idx.map(|i| place.point(mesh.positions[i]));
        let normals = match &mesh.normals {
            Some(n) => {
                let [a, b, c] = idx.map(|i| n.get(i).map(|&v| place.normal(v)));
                Some([
                    a.ok_or_else(broken)?,
                    b.ok_or_else(broken)?,
                    c.ok_or_else(broken)?,
                ])
            }
            None => None,
        };
        let uvs = match &mesh.uvs {
            Some(uv) => {
                let [a, b, c] = idx.map(|i| uv.get(i).copied());
                Some([
                    a.ok_or_else(broken)?,
                    b.ok_or_else(broken)?,
                    c.ok_or_else(broken)?,
                ])
            }
            None => None,
        };
        if core_triangle_of(&face) == Err(tessera_core::Error::DegenerateTriangle) {
            out.degenerate += 1;
            *lost += 1;
        } else if out.faces.len() >= room {
            return Err(format!(
                "{}: the faces of {} come after {} triangles",
                too_many(List::Triangles, MAX_TRIANGLES),
                crate::escape(shown),
                MAX_TRIANGLES.saturating_sub(room)
            ));
        } else {
            out.faces.push(face);
            out.normals.push(normals);
            out.uvs.push(uvs);
            out.face_materials.push(Some(k));
        }
    }
    Ok(())
}

/// `mesh 'Cube', primitive 0` (the reader's name for it, escaped).
fn mesh_name(mesh: &ImportedMesh) -> String {
    format!(
        "mesh '{}', primitive {}",
        crate::escape(&mesh.name),
        mesh.primitive
    )
}

/// The name an image of the file `shown` is embedded under.
fn image_name(shown: &str, image: &ImportedImage) -> String {
    format!("{shown}#image{}", image.index)
}

/// `want`, or when a material of `taken` has that name, `want (then)`, or
/// that with a number after it: a name no material of `taken` has.
fn unique(want: String, then: &str, taken: &[MaterialDesc]) -> String {
    let free = |n: &str| !taken.iter().any(|m| m.name == n);
    if free(&want) {
        return want;
    }
    let second = format!("{want} ({then})");
    if free(&second) {
        return second;
    }
    (2..)
        .map(|k| format!("{second} {k}"))
        .find(|n| free(n))
        .unwrap_or(second)
}

/// The material of `m` (its texture's image one of `images`), by the rule.
fn material(
    m: &ImportedMaterial,
    images: &[ImportedImage],
    shown: &str,
    taken: &[MaterialDesc],
) -> (MaterialDesc, Vec<String>) {
    let label = if m.name.is_empty() {
        format!("material {}", m.index)
    } else {
        m.name.clone()
    };
    let name = unique(
        format!("{shown}/{label}"),
        &format!("material {}", m.index),
        taken,
    );
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => WrapDesc::Repeat,
        Wrap::MirroredRepeat => WrapDesc::Mirror,
        Wrap::ClampToEdge => WrapDesc::Clamp,
    };
    let texture = m.base_color_texture.and_then(|t| {
        let image = images.get(t.image)?;
        let filter = if t.mag_nearest {
            FilterDesc::Nearest
        } else {
            FilterDesc::Bilinear
        };
        Some((
            image_name(shown, image),
            filter,
            [wrap(t.wrap_s), wrap(t.wrap_t)],
        ))
    });
    from_pbr(
        &name,
        &Pbr {
            base_color: m.base_color,
            texture,
            metallic: m.metallic,
            roughness: m.roughness,
            transmission: m.transmission,
            ior: m.ior,
            emissive: m.emissive,
        },
    )
}

/// glTF's default material (white, metallic 1, roughness 1), by the rule.
fn default_material(shown: &str, taken: &[MaterialDesc]) -> (MaterialDesc, Vec<String>) {
    let name = unique(format!("{shown}/default material"), "glTF's", taken);
    from_pbr(
        &name,
        &Pbr {
            base_color: [1.0; 4],
            texture: None,
            metallic: 1.0,
            roughness: 1.0,
            transmission: 0.0,
            ior: 1.5,
            emissive: [0.0; 3],
        },
    )
}

/// Names each mesh of a whole glTF scene by its node (the node's name, else
/// its mesh's: [`super::ImportedMesh::name`]) when its faces come from one
/// node; a node whose faces are in several meshes (one a material) names each
/// `NODE/MATERIAL` (the material's name in the file). A mesh of several nodes'
/// faces has no name, and names that two meshes would share are left out, with
/// a warning naming them.
fn name_meshes(
    meshes: &mut [MeshDesc],
    file: &MeshFile,
    nodes: &[Vec<(usize, String)>],
    shown: &str,
    warnings: &mut Vec<String>,
) {
    // The nodes of each mesh, through its material.
    let of = |m: &MeshDesc| {
        let k = file
            .materials
            .iter()
            .position(|d| Some(&d.name) == m.material.as_ref())?;
        nodes.get(k)
    };
    let parts_of = |node: usize| {
        meshes
            .iter()
            .filter(|m| of(m).is_some_and(|n| n.iter().any(|(i, _)| *i == node)))
            .count()
    };
    let names: Vec<Option<String>> = meshes
        .iter()
        .map(|m| {
            let [(node, name)] = of(m)?.as_slice() else {
                return None;
            };
            Some(if parts_of(*node) > 1 {
                // The material as the file names it (`FILE/NAME` less `FILE/`).
                let material = m.material.as_deref().unwrap_or_default();
                let own = material.split_once('/').map_or(material, |(_, n)| n);
                format!("{name}/{own}")
            } else {
                name.clone()
            })
        })
        .collect();
    let mut shared: Vec<&String> = Vec::new();
    for (i, m) in meshes.iter_mut().enumerate() {
        let Some(name) = &names[i] else { continue };
        if names.iter().filter(|n| n.as_ref() == Some(name)).count() > 1 {
            // One warning a name.
            if !shared.contains(&name) {
                shared.push(name);
                warnings.push(format!(
                    "{shown}: several meshes would be named '{}' (nodes of one name): they \
                     are left unnamed",
                    crate::escape(name)
                ));
            }
            continue;
        }
        if crate::desc::name_fault(name).is_none() {
            m.name = Some(name.clone());
        }
    }
}

/// The meshes of `file` (the file `obj`), one per material with faces, with
/// `degenerate[k]` degenerate faces of material `k`.
fn split(file: &MeshFile, degenerate: &[usize], obj: &str) -> Result<Vec<MeshDesc>, String> {
    let mut meshes: Vec<MeshDesc> = file
        .materials
        .iter()
        .zip(degenerate)
        .map(|(m, &lost)| {
            let mut d = MeshDesc::unplaced(obj, Some(m.name.clone()));
            d.degenerate = lost;
            d
        })
        .collect();
    // Per mesh: (faces with normals, faces with uvs).
    let mut with = vec![(0usize, 0usize); meshes.len()];
    let mut normals: Vec<Vec<[[f64; 3]; 3]>> = vec![Vec::new(); meshes.len()];
    let mut uvs: Vec<Vec<[[f64; 2]; 3]>> = vec![Vec::new(); meshes.len()];
    for (j, face) in file.faces.iter().enumerate() {
        let Some(k) = file.face_materials.get(j).copied().flatten() else {
            continue;
        };
        let Some(m) = meshes.get_mut(k) else {
            continue;
        };
        m.faces.push(*face);
        if let Some(n) = file.normals.get(j).copied().flatten() {
            with[k].0 += 1;
            normals[k].push(n);
        }
        if let Some(t) = file.uvs.get(j).copied().flatten() {
            with[k].1 += 1;
            uvs[k].push(t);
        }
    }
    for (k, m) in meshes.iter_mut().enumerate() {
        let n = m.faces.len();
        let (with_normals, with_uvs) = with[k];
        if with_normals == n {
            m.normals = std::mem::take(&mut normals[k]);
        } else if with_normals > 0 {
            m.warnings.push(format!(
                "{with_normals} of its {n} faces have vertex normals, not all: it is shaded flat"
            ));
        }
        if with_uvs == n {
            m.uvs = std::mem::take(&mut uvs[k]);
        } else if with_uvs > 0 {
            m.warnings.push(format!(
                "{with_uvs} of its {n} faces have texture coordinates, not all: none are used"
            ));
        }
    }
    meshes.retain(|m| !m.faces.is_empty());
    let most = tessera_core::mesh::MAX_MESHES;
    if meshes.len() > most {
        return Err(format!(
            "{}: its triangles use {} materials: a scene has one mesh per material, and \
             tessera draws at most {most} meshes",
            crate::escape(obj),
            meshes.len()
        ));
    }
    Ok(meshes)
}

/// The smallest and largest coordinates of the vertices of `faces`.
fn bounds(faces: &[[[f64; 3]; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in faces.iter().flatten() {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// The camera of the file's camera `c`, and the render size its aspect ratio
/// sets; `(lo, hi)` bound the meshes (for an infinite far plane).
fn file_camera(
    c: &ImportedCamera,
    (lo, hi): ([f64; 3], [f64; 3]),
    shown: &str,
    warnings: &mut Vec<String>,
) -> (CameraDesc, Option<(u16, u16)>) {
    let name = crate::escape(&c.name);
    let far = c.zfar.unwrap_or_else(|| {
        let centre = mid(lo, hi);
        let far = 100.0 * length(sub(hi, lo)) + length(sub(c.position, centre));
        let far = far.max(2.0 * c.znear);
        warnings.push(format!(
            "{shown}: camera '{name}': its far plane is infinite: far = {} is used (100 \
             times the meshes' bounding box diagonal, plus the camera's distance to its \
             centre)",
            num(far)
        ));
        far
    });
    let size = c.aspect.map(|a| {
        let want = (f64::from(CAMERA_HEIGHT) * a).round();
        let width = want.clamp(1.0, f64::from(u16::MAX));
        if width != want {
            warnings.push(format!(
                "{shown}: camera '{name}': its aspect ratio {} would make the render {} \
                 pixels wide: {width} are used",
                num(a),
                num(want)
            ));
        }
        // Within [1, 65535]: exact.
        (width as u16, CAMERA_HEIGHT)
    });
    let camera = CameraDesc {
        position: c.position,
        forward: Some(c.forward),
        look_at: None,
        up: c.up,
        fovy: c.yfov_degrees,
        near: c.znear,
        far,
    };
    (camera, size)
}

/// A camera looking at the centre of the box `(lo, hi)` from the front (+Z),
/// up +Y, the box's bounding sphere filling its [`DEFAULT_FOVY`] field of view.
fn front_camera(lo: [f64; 3], hi: [f64; 3]) -> CameraDesc {
    let centre = mid(lo, hi);
    let r = length(sub(hi, lo)) / 2.0;
    let d = r / (DEFAULT_FOVY / 2.0).to_radians().sin();
    CameraDesc {
        position: [centre[0], centre[1], centre[2] + d],
        forward: Some([0.0, 0.0, -1.0]),
        look_at: None,
        up: [0.0, 1.0, 0.0],
        fovy: DEFAULT_FOVY,
        near: (d - r) / 2.0,
        far: 2.0 * (d + r),
    }
}

/// The direction of the sun over `camera`'s left shoulder: its rays travel
/// forward, down and a little to the right, `forward - up + right / 2` (the
/// camera's axes, made unit and perpendicular).
fn shoulder_sun(camera: &CameraDesc) -> [f64; 3] {
    let f = unit(camera.forward.unwrap_or([0.0, 0.0, -1.0]));
    let along = dot(camera.up, f);
    let u = unit(sub(camera.up, f.map(|x| x * along)));
    let r = cross(f, u);
    unit(std::array::from_fn(|k| f[k] - u[k] + 0.5 * r[k]))
}

/// `(a + b) / 2`.
fn mid(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| (a[k] + b[k]) / 2.0)
}

/// `a / |a|` (`a` itself when it has no length).
fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = length(a);
    if l > 0.0 && l.is_finite() {
        a.map(|x| x / l)
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    //! Against the sample models of tests/data/gltf (see its README) and
    //! hand-written files; expectations from the files' own JSON or by hand.

    use super::*;
    use crate::desc::{ChannelDesc, TextureDesc};
    use base64::Engine as _;
    use gltf::json::Value;
    use std::path::PathBuf;

    /// A sample model's path.
    fn data(rel: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/data/gltf")
            .join(rel)
    }

    /// A sample model's JSON, read with `serde_json` (not through the reader).
    fn json(rel: &str) -> Value {
        let text = std::fs::read(data(rel)).unwrap();
        gltf::json::deserialize::from_slice(&text).unwrap()
    }

    /// The placement of a `[[mesh]]` of these keys.
    fn placement(toml: &str) -> Placement {
        let mesh: MeshDesc =
            toml::from_str(&format!("obj = \"x\"\nmaterial = \"m\"\n{toml}")).unwrap();
        Placement::of(&mesh).unwrap()
    }

    /// Decodes the embedded images of `d`'s image textures as the scene loader
    /// does, so that `to_core` has their texels.
    fn decode_images(d: &mut SceneDesc) {
        crate::file::textures::read_images(d, Path::new("")).unwrap();
    }

    /// `a` and `b` within `eps`, component by component.
    fn near(a: &[f64], b: &[f64], eps: f64) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= eps)
    }

    /// Box.gltf: its 12 triangles, their normals, its one material "Red" of the
    /// file's base colour factor; placed by a scale 2 and a translation. By
    /// hand: the node's column-major matrix has columns (1,0,0), (0,0,-1),
    /// (0,1,0), so it takes (x, y, z) to (x, z, -y); the POSITION accessor's
    /// corner `min` (-0.5, -0.5, -0.5) becomes (-0.5, -0.5, 0.5), scaled (-1,
    /// -1, 1), moved by (1, 2, 3): (0, 1, 4). The placed box spans 2 (min.x,
    /// min.z, -max.y) + t to 2 (max.x, max.z, -min.y) + t.
    #[test]
    fn box_mesh_file_has_the_files_faces_normals_and_material_placed() {
        let j = json("Box/Box.gltf");
        let position = j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
            .as_u64()
            .unwrap() as usize;
        let acc = &j["accessors"][position];
        let v = |key: &str, k: usize| acc[key][k].as_f64().unwrap();
        let (min, max) = (
            [0, 1, 2].map(|k| v("min", k)),
            [0, 1, 2].map(|k| v("max", k)),
        );
        let t = [1.0, 2.0, 3.0];
        let place = placement("scale = 2\ntranslate = [1, 2, 3]");
        let m = mesh_file(&data("Box/Box.gltf"), "Box.gltf", &place, MAX_TRIANGLES).unwrap();

        assert_eq!(m.faces.len(), 12);
        assert_eq!(m.degenerate, 0);
        let corner = [
            2.0 * min[0] + t[0],
            2.0 * min[2] + t[1],
            -2.0 * min[1] + t[2],
        ];
        assert_eq!(corner, [0.0, 1.0, 4.0]);
        assert!(
            m.faces.iter().flatten().any(|p| *p == corner),
            "{:?}",
            m.faces
        );
        let (lo, hi) = bounds(&m.faces);
        assert_eq!(
            lo,
            [
                2.0 * min[0] + t[0],
                2.0 * min[2] + t[1],
                -2.0 * max[1] + t[2]
            ]
        );
        assert_eq!(
            hi,
            [
                2.0 * max[0] + t[0],
                2.0 * max[2] + t[1],
                -2.0 * min[1] + t[2]
            ]
        );

        // Every face has normals: the box's are flat, each the face's own unit
        // normal by its winding (counter-clockwise seen from the front).
        assert_eq!(m.normals.len(), 12);
        for (f, n) in m.faces.iter().zip(&m.normals) {
            let n = n.expect("a face without normals");
            let geometric = unit(cross(sub(f[1], f[0]), sub(f[2], f[0])));
            for corner in n {
                assert!(near(&corner, &geometric, 1e-6), "{corner:?} {geometric:?}");
            }
        }
        assert!(m.uvs.iter().all(Option::is_none));

        let factor = &j["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"];
        // glTF's factors are f32.
        let rgb = [0, 1, 2].map(|k| f64::from(factor[k].as_f64().unwrap() as f32));
        assert_eq!(m.materials.len(), 1);
        assert_eq!(m.materials[0].name, "Box.gltf/Red");
        assert_eq!(m.materials[0].color, rgb);
        // Metallic 0, roughness 1 (the default): matte, by the rule.
        assert_eq!(
            (m.materials[0].diffuse, m.materials[0].specular),
            (1.0, 0.0)
        );
        assert!(m.face_materials.iter().all(|k| *k == Some(0)));
        assert!(m.embedded.is_empty());
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    }

    /// BoxTextured: texture coordinates on every face, its one image embedded
    /// (the PNG, byte for byte the one kept beside it), and the material's
    /// texture naming it, with the file's sampler (magFilter 9729 LINEAR, wrap
    /// 10497 REPEAT).
    #[test]
    fn box_textured_embeds_its_png_and_the_texture_names_it() {
        let m = mesh_file(
            &data("BoxTextured/BoxTextured.gltf"),
            "models/BoxTextured.gltf",
            &placement(""),
            MAX_TRIANGLES,
        )
        .unwrap();
        assert_eq!(m.faces.len(), 12);
        assert!(m.uvs.iter().all(Option::is_some));
        let uv = m.uvs.iter().flatten().flatten().flatten();
        assert!(uv.clone().all(|x| x.is_finite()));
        assert_eq!(m.embedded.len(), 1);
        let (name, bytes) = &m.embedded[0];
        assert_eq!(name, "models/BoxTextured.gltf#image0");
        assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"));
        assert_eq!(
            bytes,
            &std::fs::read(data("BoxTextured/CesiumLogoFlat.png")).unwrap()
        );
        assert_eq!(m.materials.len(), 1);
        // The file's material has no name.
        assert_eq!(m.materials[0].name, "models/BoxTextured.gltf/material 0");
        let Some(TextureDesc::Image {
            file, filter, wrap, ..
        }) = &m.materials[0].texture
        else {
            panic!("{:?}", m.materials[0].texture)
        };
        assert_eq!(file, name);
        assert_eq!(
            (*filter, *wrap),
            (FilterDesc::Bilinear, [WrapDesc::Repeat; 2])
        );
    }

    /// Cameras.gltf's mesh has no material: glTF's default (white, metallic 1,
    /// roughness 1) by the rule: no diffuse term, no highlight, no mirror. Its
    /// one quad is two triangles without normals.
    #[test]
    fn a_primitive_without_material_takes_the_default_material() {
        let m = mesh_file(
            &data("Cameras/Cameras.gltf"),
            "Cameras.gltf",
            &placement(""),
            MAX_TRIANGLES,
        )
        .unwrap();
        assert_eq!(m.faces.len(), 2);
        assert!(m.normals.iter().all(Option::is_none));
        assert_eq!(m.materials.len(), 1);
        let d = &m.materials[0];
        assert_eq!(d.name, "Cameras.gltf/default material");
        assert_eq!(d.color, [1.0; 3]);
        // glTF's default (metallic 1, roughness 1): a rough metal, drawn diffuse.
        assert_eq!((d.diffuse, d.specular, d.reflectivity), (1.0, 0.0, 0.0));
        assert_eq!(m.face_materials, vec![Some(0); 2]);
        // The reader's warning about the orthographic camera names the file once.
        let ortho: Vec<&String> = m
            .warnings
            .iter()
            .filter(|w| w.contains("orthographic"))
            .collect();
        assert_eq!(ortho.len(), 1, "{:?}", m.warnings);
        assert!(ortho[0].starts_with("Cameras.gltf: "));
        assert_eq!(ortho[0].matches("Cameras.gltf").count(), 1, "{}", ortho[0]);
    }

    /// More faces than the room left is refused, in `read`'s words.
    #[test]
    fn more_faces_than_the_room_left_is_refused() {
        let e = mesh_file(&data("Box/Box.gltf"), "Box.gltf", &placement(""), 5).unwrap_err();
        let words = too_many(List::Triangles, MAX_TRIANGLES);
        assert!(e.starts_with(&words), "{e}");
        assert!(
            e.contains("the faces of Box.gltf come after 8187 triangles"),
            "{e}"
        );
    }

    /// Box.gltf has neither camera nor light: the camera made for it sees the
    /// whole box (each corner within its frustum, counted by hand from its
    /// numbers), a sun over its shoulder lights it, both with a warning; the
    /// core scene is built, and (with the renderer) its centre pixel is the
    /// lit red box, not the background.
    #[test]
    fn box_scene_has_a_camera_and_a_sun_made_for_it() {
        let d = scene(&data("Box/Box.gltf"), None).unwrap();
        assert_eq!(d.meshes.len(), 1);
        let mesh = &d.meshes[0];
        assert!(
            mesh.material.as_deref().unwrap().ends_with("Box.gltf/Red"),
            "{:?}",
            mesh.material
        );
        assert_eq!((mesh.faces.len(), mesh.normals.len()), (12, 12));
        assert!(mesh.uvs.is_empty());
        assert_eq!((mesh.scale, mesh.rotate, mesh.smooth), (1.0, None, None));
        assert_eq!(d.background, [0.05; 3]);

        let c = &d.camera;
        assert_eq!((c.forward, c.look_at), (Some([0.0, 0.0, -1.0]), None));
        let tan = (c.fovy.to_radians() / 2.0).tan();
        let aspect = f64::from(d.render.width) / f64::from(d.render.height);
        for corner in 0..8 {
            // The box spans [-0.5, 0.5] on every axis (see the mesh test).
            let p = [0, 1, 2].map(|k| if corner >> k & 1 == 1 { 0.5 } else { -0.5 });
            let depth = c.position[2] - p[2];
            assert!(depth > c.near && depth < c.far, "{p:?} {c:?}");
            assert!((p[1] - c.position[1]).abs() < depth * tan, "{p:?} {c:?}");
            assert!((p[0] - c.position[0]).abs() < depth * tan * aspect);
        }
        assert_eq!(d.lights.len(), 1);
        let sun = d.lights[0].direction.expect("a sun");
        assert!(
            sun[1] < 0.0 && sun[2] < 0.0,
            "{sun:?}: down, and away from the camera"
        );
        assert_eq!(d.ambient, [0.1; 3]);
        let all = d.warnings.join("\n");
        assert!(
            all.contains("Box.gltf: the file has no perspective camera"),
            "{all}"
        );
        assert!(all.contains("Box.gltf: the file has no light"), "{all}");

        let core = d.to_core().unwrap();
        #[cfg(feature = "cli")]
        {
            let vp = tessera_core::Viewport::new(64, 48);
            let img = core
                .with_view(|v| {
                    crate::render(v, core.camera(), vp, d.settings().unwrap(), d.render.tile)
                })
                .unwrap();
            // The background's linear 0.05, sRGB-encoded by hand.
            let bg = (255.0 * (1.055 * 0.05f64.powf(1.0 / 2.4) - 0.055)).round() as u8;
            assert_eq!(img.get_pixel(0, 0).0, [bg; 3]);
            let centre = img.get_pixel(32, 24).0;
            assert_ne!(centre, [bg; 3]);
            assert!(
                centre[0] > bg && centre[1] < centre[0] && centre[2] < centre[0],
                "{centre:?}"
            );
        }
        #[cfg(not(feature = "cli"))]
        let _ = core;
    }

    /// Cameras.gltf: its perspective camera (node translation (0.5, 0.5, 3), no
    /// rotation: looking down -Z; yfov 0.7 radians, aspect 1, znear 0.01, zfar
    /// 100), the render 240 x 240; by its name too. A name the file lacks is an
    /// error listing its cameras.
    #[test]
    fn cameras_scene_takes_the_files_camera() {
        let path = data("Cameras/Cameras.gltf");
        let j = json("Cameras/Cameras.gltf");
        let p = &j["cameras"][0]["perspective"];
        let f = |k: &str| f64::from(p[k].as_f64().unwrap() as f32);
        let d = scene(&path, None).unwrap();
        let c = &d.camera;
        assert!(near(&c.position, &[0.5, 0.5, 3.0], 1e-12), "{c:?}");
        assert!(near(&c.forward.unwrap(), &[0.0, 0.0, -1.0], 1e-12));
        assert!(near(&c.up, &[0.0, 1.0, 0.0], 1e-12));
        assert!((c.fovy - f("yfov").to_degrees()).abs() < 1e-9, "{}", c.fovy);
        assert_eq!((c.near, c.far), (f("znear"), f("zfar")));
        assert_eq!((d.render.width, d.render.height), (240, 240));
        let named = scene(&path, Some("camera 0")).unwrap();
        assert_eq!(named.camera, d.camera);
        let e = scene(&path, Some("nope")).unwrap_err();
        assert!(e.contains("'nope'") && e.contains("'camera 0'"), "{e}");
        d.to_core().unwrap();
    }

    /// BoxAnimated: its first animation (of the two its JSON has; the other
    /// named in a warning) turns node 2, the inner box: that box is an
    /// instance of a mesh of its own, its rotation keyframes those of the
    /// sampler's accessors (count, first and last time from the JSON); the
    /// outer box stays in world space. One mesh per material and node.
    #[test]
    fn box_animated_plays_its_first_animation() {
        let j = json("BoxAnimated/BoxAnimated.gltf");
        let n = j["animations"].as_array().unwrap().len();
        assert_eq!(n, 2);
        let d = scene(&data("BoxAnimated/BoxAnimated.gltf"), None).unwrap();
        let all = d.warnings.join("\n");
        assert!(
            all.contains(
                "BoxAnimated.gltf: only the first animation, animation 0, is read: animation 1 ignored"
            ),
            "{all}"
        );
        let names: Vec<Option<&str>> = d.meshes.iter().map(|m| m.name.as_deref()).collect();
        assert_eq!(names, [Some("outer_box"), Some("inner_box/inner")]);
        assert_eq!(d.instances.len(), 1);
        assert_eq!(d.instances[0].name.as_deref(), Some("inner_box"));
        assert_eq!(d.keyframes.len(), 1);
        let k = &d.keyframes[0];
        assert_eq!(
            (k.target.as_str(), k.channel),
            ("inner_box", ChannelDesc::Rotation)
        );
        let sampler = &j["animations"][0]["samplers"][0];
        let input = &j["accessors"][sampler["input"].as_u64().unwrap() as usize];
        let f = |v: &Value| f64::from(v.as_f64().unwrap() as f32);
        assert_eq!(k.times.len() as u64, input["count"].as_u64().unwrap());
        assert_eq!(k.times[0], f(&input["min"][0]));
        assert_eq!(*k.times.last().unwrap(), f(&input["max"][0]));
        assert_eq!(d.render.fps, 30.0);
        // Its keyframes run from 1.25 s to 2.5 s: frame 60 (2 s) is between.
        let mid = d.at_frame(60).unwrap();
        assert_ne!(mid.instances[0].quaternion, d.instances[0].quaternion);
        mid.to_core().unwrap();
    }

    /// Every sample model makes a scene the core builds, but the Draco one,
    /// which the reader refuses by name.
    #[test]
    fn every_sample_model_builds_a_core_scene() {
        let mut files = Vec::new();
        for dir in std::fs::read_dir(data("")).unwrap() {
            let dir = dir.unwrap().path();
            if !dir.is_dir() {
                continue;
            }
            for f in std::fs::read_dir(&dir).unwrap() {
                let f = f.unwrap().path();
                if f.extension().is_some_and(|e| e == "gltf" || e == "glb") {
                    files.push(f);
                }
            }
        }
        files.sort();
        assert!(files.len() >= 6, "{files:?}");
        for f in &files {
            let got = scene(f, None);
            if f.parent().unwrap().ends_with("Box-Draco") {
                let e = got.unwrap_err();
                assert!(e.contains("KHR_draco_mesh_compression"), "{e}");
                continue;
            }
            let mut d = got.unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            decode_images(&mut d);
            d.to_core()
                .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        }
    }

    /// A glTF file of one triangle drawn by `materials` primitives, each its own
    /// material, with `nodes` after the mesh's node 0 (all of them roots of the
    /// scene) and `extra` members of the root (lights); written in `dir`.
    fn triangles(dir: &Path, materials: usize, nodes: &[String], extra: &str) -> PathBuf {
        let bin: Vec<u8> = [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let uri = base64::engine::general_purpose::STANDARD.encode(&bin);
        let prims: Vec<String> = (0..materials)
            .map(|i| format!(r#"{{"attributes":{{"POSITION":0}},"material":{i}}}"#))
            .collect();
        let mats: Vec<String> = (0..materials)
            .map(|i| format!(r#"{{"name":"m{i}"}}"#))
            .collect();
        let text = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0{}]}}],
            "nodes":[{{"mesh":0}}{}],
            "meshes":[{{"primitives":[{}]}}],"materials":[{}],
            "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{uri}"}}],
            "bufferViews":[{{"buffer":0,"byteLength":36}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]
            {extra}}}"#,
            (1..=nodes.len())
                .map(|i| format!(",{i}"))
                .collect::<String>(),
            nodes.iter().map(|n| format!(",{n}")).collect::<String>(),
            prims.join(","),
            mats.join(",")
        );
        let path = dir.join(format!("t{materials}.gltf"));
        std::fs::write(&path, text).unwrap();
        path
    }

    /// A whole scene's meshes take their node's name: `NODE/MATERIAL` for a
    /// node in several meshes (one a material), none for a mesh of several
    /// nodes; a name a light has too is left to the light, with a warning.
    #[test]
    fn meshes_take_their_nodes_names() {
        let dir = tempfile::tempdir().unwrap();
        let one = scene(&triangles(dir.path(), 1, &[], ""), None).unwrap();
        assert_eq!(one.meshes[0].name.as_deref(), Some("node 0"));
        assert_eq!(one.find("node 0"), Some(crate::desc::Object::Mesh(0)));
        let two = scene(&triangles(dir.path(), 2, &[], ""), None).unwrap();
        let names: Vec<_> = two.meshes.iter().map(|m| m.name.as_deref()).collect();
        assert_eq!(names, [Some("node 0/m0"), Some("node 0/m1")]);
        two.to_core().unwrap();
        let lid = [r#"{"mesh":0,"name":"lid","translation":[0,0,1]}"#.to_string()];
        let shared = scene(&triangles(dir.path(), 1, &lid, ""), None).unwrap();
        assert_eq!(shared.meshes[0].name, None);
        // A light of the mesh's name keeps it.
        let light =
            [r#"{"name":"node 0","extensions":{"KHR_lights_punctual":{"light":0}}}"#.to_string()];
        let lights = r#","extensionsUsed":["KHR_lights_punctual"],
            "extensions":{"KHR_lights_punctual":{"lights":[{"type":"directional"}]}}"#;
        let clash = scene(&triangles(dir.path(), 1, &light, lights), None).unwrap();
        assert_eq!(clash.lights[0].name.as_deref(), Some("node 0"));
        assert_eq!(clash.meshes[0].name, None);
        assert!(
            clash
                .warnings
                .iter()
                .any(|w| w.contains("a mesh and a light would both be named 'node 0'")),
            "{:?}",
            clash.warnings
        );
        clash.to_core().unwrap();
    }

    /// One mesh per material: 16 are a scene, 17 are refused with the count.
    #[test]
    fn more_materials_than_meshes_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let d = scene(&triangles(dir.path(), 16, &[], ""), None).unwrap();
        assert_eq!(d.meshes.len(), 16);
        assert_eq!(d.meshes[15].material.as_deref(), Some("t16.gltf/m15"));
        d.to_core().unwrap();
        let e = scene(&triangles(dir.path(), 17, &[], ""), None).unwrap_err();
        assert!(
            e.contains("17 materials") && e.contains("at most 16 meshes"),
            "{e}"
        );
    }

    /// KHR_lights_punctual: a point light of 20 candela at (0, 2, 0) with a
    /// range (a warning naming it), and a sun of 3 lux whose node is turned
    /// -90 degrees about X, so that its -Z points down: (0, -1, 0). No default
    /// light, no ambient.
    #[test]
    fn punctual_lights_become_lights_in_the_files_units() {
        let dir = tempfile::tempdir().unwrap();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let nodes = [
            r#"{"translation":[0,2,0],"extensions":{"KHR_lights_punctual":{"light":0}}}"#
                .to_string(),
            format!(
                r#"{{"rotation":[{},0,0,{h}],"extensions":{{"KHR_lights_punctual":{{"light":1}}}}}}"#,
                -h
            ),
        ];
        let lights = r#","extensionsUsed":["KHR_lights_punctual"],
            "extensions":{"KHR_lights_punctual":{"lights":[
              {"type":"point","name":"lamp","color":[1,0.5,0.25],"intensity":20,"range":5},
              {"type":"directional","name":"day","intensity":3}]}}"#;
        let d = scene(&triangles(dir.path(), 1, &nodes, lights), None).unwrap();
        assert_eq!(d.lights.len(), 2);
        let lamp = &d.lights[0];
        assert_eq!(lamp.direction, None);
        assert!(near(&lamp.position, &[0.0, 2.0, 0.0], 1e-12));
        assert_eq!((lamp.color, lamp.intensity), ([1.0, 0.5, 0.25], 20.0));
        let day = &d.lights[1];
        assert!(
            near(&day.direction.unwrap(), &[0.0, -1.0, 0.0], 1e-6),
            "{day:?}"
        );
        assert_eq!((day.color, day.intensity), ([1.0; 3], 3.0));
        assert_eq!(d.ambient, [0.0; 3]);
        let all = d.warnings.join("\n");
        assert!(
            all.contains("light 'lamp': its range 5 is not modelled"),
            "{all}"
        );
        assert!(!all.contains("no light"), "{all}");
        // Each light keeps its name, for the scene's lookup and the baker.
        assert_eq!(d.find("lamp"), Some(crate::desc::Object::Light(0)));
        assert_eq!(d.find("day"), Some(crate::desc::Object::Light(1)));
        d.to_core().unwrap();

        // Two lights of one name: the second is left unnamed, with a warning.
        let same = lights.replace("\"day\"", "\"lamp\"");
        let d = scene(&triangles(dir.path(), 1, &nodes, &same), None).unwrap();
        assert_eq!(d.lights[0].name.as_deref(), Some("lamp"));
        assert_eq!(d.lights[1].name, None);
        let all = d.warnings.join("\n");
        assert!(
            all.contains("light 'lamp': an earlier light has its name: it is left unnamed"),
            "{all}"
        );
        d.to_core().unwrap();
    }
}
