//! Triangle meshes from files (`[[mesh]]` in a scene file): Wavefront OBJ read
//! with `tobj` (glTF through [`crate::gltf`]), every face a triangle (polygons
//! split into fans), scaled, turned and moved ([`Placement`]).
//!
//! Positions, faces, vertex normals (`vn`, turned with the mesh) and texture
//! coordinates (`vt`, `v` turned to run down from the image's top) are read;
//! normals or uvs for some corners only are not used, with a warning. The MTL
//! file (`mtllib`) is read when the mesh names no material of the scene: its
//! materials are mapped by [`crate::material_rule`] and the mesh split by them
//! ([`by_material`]). Groups are not read. Faces whose vertices are collinear
//! once in `f32` are left out and counted (no ray can hit a triangle of zero
//! area, and the core refuses one); every other face is kept, so that a vertex
//! out of range is refused with the face it belongs to. A face's texture
//! coordinate and normal indices are checked as its vertex indices are: one out
//! of range is a broken file. A UTF-8 byte-order mark at the start of the file
//! is skipped; one further on is refused (outside comments).

use crate::arr3::{cross, sub};
use crate::desc::{Face, MAX_TRIANGLES, MeshDesc, core_triangle_of, num, too_many};
use std::io::{BufRead, Read};
use std::path::{Path, PathBuf};
use tessera_core::error::List;

/// The most OBJ text a scene reads, in bytes, all its meshes together: 16 MiB.
/// The host's 8,192 triangles take about 1 MiB of OBJ text (with normals and
/// texture coordinates, 3); the bound keeps a wrong path (a disk image) or a
/// file naming one large OBJ many times from being read at length. With the
/// faces bounded too ([`MAX_FACE_VERTICES`], [`MAX_OBJ_TRIANGLES`]) the
/// command's peak memory reading a 16 MiB OBJ file is at most 69 MiB: the text
/// is held once (tobj reads it in place), and 16 MiB of `v 0 0 0` lines (2.1
/// million vertices) peak at 69,948 KiB, of `vn 0 0 1` lines (1.86 million
/// normals) at 64,388 KiB, of `vt 0 0` lines at 58,228 KiB, one face line of
/// 8.4 million vertices (refused) at 20,688 KiB (`/usr/bin/time -v tessera
/// render SCENE --size 16x16`, release build, SCENE a `[[mesh]]` of such a file).
pub const MAX_OBJ_BYTES: usize = 16 << 20;

/// The `obj` of a mesh that is tessera's own teapot ([`crate::teapot`], at its
/// default tessellation) rather than a file: no file is needed.
pub const BUILTIN_TEAPOT: &str = "builtin:teapot";

/// The OBJ file of `mesh`, relative to `base` (the scene file's folder), or
/// `None` for the built-in teapot, which is no file.
#[must_use]
pub fn obj_file(mesh: &MeshDesc, base: &Path) -> Option<PathBuf> {
    (mesh.obj != BUILTIN_TEAPOT).then(|| base.join(&mesh.obj))
}

/// The faces of `mesh`'s OBJ file (its path relative to `base`), scaled and
/// moved, and how many degenerate faces were left out. At most `*budget` bytes of
/// OBJ text are read, and the file's size is taken from it; more than `room` faces
/// (the room left in the host's triangle list) is an error as soon as the face
/// past it is made. The error names the file, and
/// the line where the OBJ text is wrong.
pub fn read(
    mesh: &MeshDesc,
    base: &Path,
    budget: &mut usize,
    room: usize,
) -> Result<MeshFile, String> {
    let place = Placement::of(mesh)?;
    let (shown, text) = if let Some(path) = obj_file(mesh, base) {
        let shown = path.display().to_string();
        // Said only of a file above the limit (not of one that cannot be read).
        let left = if *budget < MAX_OBJ_BYTES {
            format!(
                ": what is left of the {} MiB that the OBJ files of a scene may take together",
                MAX_OBJ_BYTES >> 20
            )
        } else {
            String::new()
        };
        let text = crate::file::read_limited(&path, *budget, "OBJ file", &left)
            .map_err(|e| format!("{shown}: {e}"))?;
        (shown, text)
    } else {
        let obj = crate::teapot::teapot(crate::teapot::SEGMENTS).to_obj();
        (BUILTIN_TEAPOT.to_string(), obj)
    };
    *budget = budget.saturating_sub(text.len());
    // A UTF-8 byte-order mark (Windows tools write one) is no part of the text:
    // read as a word it would hide the first line's statement.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let corners = check_lines(text).map_err(|(line, why)| format!("{shown}:{line}: {why}"))?;
    let mut reader = Consumed {
        text,
        at: 0,
        line_start: true,
    };
    let options = tobj::LoadOptions {
        triangulate: true,
        ..Default::default()
    };
    // The file's materials (`mtllib`), read when the mesh names none of the
    // scene's; an MTL file that cannot be read is an error then, named.
    let folder = Path::new(&mesh.obj)
        .parent()
        .map(|p| p.to_string_lossy().into_owned())
        .unwrap_or_default();
    let own = mesh.material.is_none();
    let mtl_error: std::cell::RefCell<Option<String>> = Default::default();
    let mtl_files: std::cell::RefCell<Vec<String>> = Default::default();
    let loaded = tobj::load_obj_buf(&mut reader, &options, |mtl| {
        mtl_files.borrow_mut().push(mtl.display().to_string());
        if !own {
            return Err(tobj::LoadError::OpenFileFailed);
        }
        let path = base.join(&folder).join(mtl);
        match crate::file::read_limited(&path, MAX_MTL_BYTES, "MTL file", "") {
            Ok(text) => tobj::load_mtl_buf(&mut text.as_bytes()).map_err(|e| {
                *mtl_error.borrow_mut() =
                    Some(format!("{}: not a valid MTL file: {e}", path.display()));
                tobj::LoadError::MaterialParseError
            }),
            Err(e) => {
                *mtl_error.borrow_mut() = Some(format!("{}: {e}", path.display()));
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    });
    if let Some(e) = mtl_error.into_inner() {
        return Err(e);
    }
    let mtl_files = mtl_files.into_inner();
    let (models, materials) = loaded.map_err(|e| {
        // The line being parsed when tobj stopped, the last one consumed. (Face
        // indices, which tobj checks only when an object ends, are checked line by
        // line before: see `check_lines`.)
        let mut done = &text.as_bytes()[..reader.at];
        while let [rest @ .., b'\n' | b'\r'] = done {
            done = rest;
        }
        let line = done.iter().filter(|&&b| b == b'\n').count() + 1;
        format!("{shown}:{line}: not a valid OBJ file: {e}")
    })?;
    let mut out = MeshFile::default();
    if own {
        for m in materials.unwrap_or_default() {
            let (d, notes) =
                crate::material_rule::from_mtl(&format!("{}/{}", mesh.obj, m.name), &m, &folder);
            out.materials.push(d);
            out.warnings.extend(notes);
        }
    } else if !mtl_files.is_empty() {
        out.warnings.push(format!(
            "{shown}: its materials ({}) are not used: the mesh is of the scene's material \
             {:?} (leave `material` out to use the file's)",
            mtl_files.join(", "),
            mesh.material.as_deref().unwrap_or_default()
        ));
    }
    // Normals or uvs for some corners only: none is used (tobj makes up the
    // missing ones from their neighbours'; a face without would be shaded or
    // textured unlike the others), and the warning says so.
    let mut usable = [true; 2];
    for (k, (what, [without, with])) in [
        ("vertex normals", corners.normals),
        ("texture coordinates", corners.uvs),
    ]
    .into_iter()
    .enumerate()
    {
        if with > 0 && without > 0 {
            usable[k] = false;
            out.warnings.push(format!(
                "{shown}: {with} of its {} face corners have {what}, not all: none are used",
                with + without
            ));
        }
    }
    for model in &models {
        let m = &model.mesh;
        let material = m.material_id.filter(|&k| k < out.materials.len());
        let vertex = |i: u32| -> Option<[f64; 3]> {
            let i = usize::try_from(i).ok()?.checked_mul(3)?;
            let p = m.positions.get(i..i + 3)?;
            Some(place.point([p[0], p[1], p[2]]))
        };
        // The file's normals and texture coordinates, when every corner of the
        // file has one (tobj leaves an object's index list empty when none has).
        let has = |idx: &[u32], data: &[f64]| !data.is_empty() && idx.len() == m.indices.len();
        let (with_normals, with_uvs) = (
            usable[0] && has(&m.normal_indices, &m.normals),
            usable[1] && has(&m.texcoord_indices, &m.texcoords),
        );
        let normal = |i: u32| -> Option<[f64; 3]> {
            let i = usize::try_from(i).ok()?.checked_mul(3)?;
            let n = m.normals.get(i..i + 3)?;
            Some(place.normal([n[0], n[1], n[2]]))
        };
        // OBJ's `v` runs up from the image's bottom; tessera's (glTF's) down
        // from its top.
        let uv = |i: u32| -> Option<[f64; 2]> {
            let i = usize::try_from(i).ok()?.checked_mul(2)?;
            let t = m.texcoords.get(i..i + 2)?;
            Some([t[0], 1.0 - t[1]])
        };
        for (j, f) in m.indices.chunks(3).enumerate() {
            let face = match f {
                [a, b, c] => [vertex(*a), vertex(*b), vertex(*c)],
                _ => [None; 3],
            };
            let [Some(a), Some(b), Some(c)] = face else {
                return Err(format!(
                    "{shown}: object {:?}, triangle {}: a vertex index beyond the object's \
                     {} vertices",
                    model.name,
                    j + 1,
                    m.positions.len() / 3
                ));
            };
            let corners = |idx: &[u32]| -> Option<[u32; 3]> {
                let c = idx.get(3 * j..3 * j + 3)?;
                Some([c[0], c[1], c[2]])
            };
            let normals = if with_normals {
                let [na, nb, nc] = corners(&m.normal_indices).map_or([None; 3], |c| c.map(normal));
                let (Some(na), Some(nb), Some(nc)) = (na, nb, nc) else {
                    return Err(format!(
                        "{shown}: object {:?}, triangle {}: a normal index beyond the \
                         object's {} normals",
                        model.name,
                        j + 1,
                        m.normals.len() / 3
                    ));
                };
                Some([na, nb, nc])
            } else {
                None
            };
            let uvs = if with_uvs {
                let [ta, tb, tc] = corners(&m.texcoord_indices).map_or([None; 3], |c| c.map(uv));
                let (Some(ta), Some(tb), Some(tc)) = (ta, tb, tc) else {
                    return Err(format!(
                        "{shown}: object {:?}, triangle {}: a texture coordinate index \
                         beyond the object's {} texture coordinates",
                        model.name,
                        j + 1,
                        m.texcoords.len() / 2
                    ));
                };
                Some([ta, tb, tc])
            } else {
                None
            };
            let face = [a, b, c];
            if core_triangle_of(&face) == Err(tessera_core::Error::DegenerateTriangle) {
                out.degenerate += 1;
            } else if out.faces.len() == room {
                return Err(format!(
                    "{}: the faces of {} come after {} triangles",
                    too_many(List::Triangles, MAX_TRIANGLES),
                    mesh.obj,
                    MAX_TRIANGLES.saturating_sub(room)
                ));
            } else {
                out.faces.push(face);
                out.normals.push(normals);
                out.uvs.push(uvs);
                out.face_materials.push(material);
            }
        }
    }
    if out.faces.is_empty() {
        return Err(format!(
            "{shown}: no face to render ({} degenerate faces left out)",
            out.degenerate
        ));
    }
    Ok(out)
}

/// What [`read`] makes of a mesh's OBJ file: its faces (scaled, turned and
/// moved), the normal and texture coordinate at each corner when the file gives
/// them, the faces left out and what was dropped, by name.
#[derive(Debug, Default)]
pub struct MeshFile {
    /// The faces.
    pub faces: Vec<Face>,
    /// Each face's corner normals, when its object gives them.
    pub normals: Vec<Option<[[f64; 3]; 3]>>,
    /// Each face's corner texture coordinates (`v` down from the image's top),
    /// when its object gives them.
    pub uvs: Vec<Option<[[f64; 2]; 3]>>,
    /// Faces left out because their vertices are collinear once in `f32`.
    pub degenerate: usize,
    /// What the file has that is not used, each a sentence naming it.
    pub warnings: Vec<String>,
    /// Each face's material in the file: an index into `materials`, or `None`
    /// (the mesh's `material` then, which must be given).
    pub face_materials: Vec<Option<usize>>,
    /// The file's materials, mapped onto tessera's by the rule of
    /// [`crate::material_rule`], named `FILE/NAME` (the mesh's file as the scene
    /// names it, the material's name in the file).
    pub materials: Vec<crate::desc::MaterialDesc>,
    /// Encoded images the file carries inside it, by the name its materials'
    /// image textures give them (see [`crate::desc::SceneDesc::embedded`]).
    pub embedded: Vec<(String, Vec<u8>)>,
}

impl MeshFile {
    /// The corner normals of every face, or none when some face has none.
    #[must_use]
    pub fn all_normals(&self) -> Vec<[[f64; 3]; 3]> {
        self.normals
            .iter()
            .copied()
            .collect::<Option<Vec<_>>>()
            .unwrap_or_default()
    }

    /// The corner texture coordinates of every face, or none when some face has
    /// none.
    #[must_use]
    pub fn all_uvs(&self) -> Vec<[[f64; 2]; 3]> {
        self.uvs
            .iter()
            .copied()
            .collect::<Option<Vec<_>>>()
            .unwrap_or_default()
    }
}

/// Where a `[[mesh]]` puts its file's vertices: scaled by `scale` about the
/// origin, turned by `rotate` or `quaternion`, moved by `translate`.
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    scale: f64,
    turn: Rotation,
    translate: [f64; 3],
}

impl Placement {
    /// The placement of `mesh`, its numbers checked (finite; a scale `> 0`; a
    /// rotation by one of `rotate` and `quaternion`).
    ///
    /// # Errors
    /// The message naming the key.
    pub fn of(mesh: &MeshDesc) -> Result<Self, String> {
        if !(mesh.scale.is_finite() && mesh.scale > 0.0) {
            return Err(format!(
                "mesh scale must be finite and > 0, got {}",
                num(mesh.scale)
            ));
        }
        if !mesh.translate.iter().all(|x| x.is_finite()) {
            return Err(format!(
                "mesh translate must be finite, got [{}]",
                mesh.translate.map(num).join(", ")
            ));
        }
        Ok(Self {
            scale: mesh.scale,
            turn: rotation(mesh)?,
            translate: mesh.translate,
        })
    }

    /// A vertex of the file, placed.
    #[must_use]
    pub fn point(&self, p: [f64; 3]) -> [f64; 3] {
        let turned = apply(&self.turn, p.map(|x| x * self.scale));
        [0, 1, 2].map(|k| turned[k] + self.translate[k])
    }

    /// A normal of the file, turned (a uniform scale keeps directions).
    #[must_use]
    pub fn normal(&self, n: [f64; 3]) -> [f64; 3] {
        apply(&self.turn, n)
    }
}

/// `r p`.
fn apply(r: &Rotation, p: [f64; 3]) -> [f64; 3] {
    r.map(|row| row[0] * p[0] + row[1] * p[1] + row[2] * p[2])
}

/// The faces of `mesh`'s file, by its kind: a glTF file (`.gltf`, `.glb`) or
/// an OBJ file (any other name; see [`read`]).
///
/// # Errors
/// The file's, naming it.
pub fn read_file(
    mesh: &MeshDesc,
    base: &Path,
    budget: &mut usize,
    room: usize,
) -> Result<MeshFile, String> {
    let lower = mesh.obj.to_ascii_lowercase();
    if lower.ends_with(".gltf") || lower.ends_with(".glb") {
        let place = Placement::of(mesh)?;
        crate::gltf::desc::mesh_file(&base.join(&mesh.obj), &mesh.obj, &place, room)
    } else {
        read(mesh, base, budget, room)
    }
}

/// `mesh` (whose `material` is left out) split into one mesh a material of its
/// file (`read`), those materials added to `materials` (a name already there is
/// that material: the same file named twice), the file's images to
/// `embedded`. Faces of no material take a matte grey one, `FILE/(none)`, with
/// a warning.
///
/// # Errors
/// A file without materials, naming it.
pub fn by_material(
    mesh: MeshDesc,
    mut read: MeshFile,
    materials: &mut Vec<crate::desc::MaterialDesc>,
    embedded: &mut Vec<(String, Vec<u8>)>,
) -> Result<Vec<MeshDesc>, String> {
    if read.materials.is_empty() {
        return Err(format!(
            "{}: the file has no materials and the mesh names none of the scene's: give \
             it `material = \"...\"`",
            mesh.obj
        ));
    }
    if read.face_materials.iter().any(Option::is_none) {
        let none = read.face_materials.iter().filter(|m| m.is_none()).count();
        read.warnings.push(format!(
            "{}: {none} faces have no material in the file: a matte grey one is used",
            mesh.obj
        ));
        let k = read.materials.len();
        read.materials.push(crate::desc::MaterialDesc::matte(
            format!("{}/(none)", mesh.obj),
            [0.8; 3],
        ));
        for m in &mut read.face_materials {
            m.get_or_insert(k);
        }
    }
    embedded.extend(std::mem::take(&mut read.embedded));
    let mut parts = Vec::new();
    for (k, material) in read.materials.iter().enumerate() {
        let faces: Vec<usize> = (0..read.faces.len())
            .filter(|&j| read.face_materials.get(j).copied().flatten() == Some(k))
            .collect();
        if faces.is_empty() {
            continue;
        }
        if !materials.iter().any(|m| m.name == material.name) {
            materials.push(material.clone());
        }
        let normals: Option<Vec<_>> = faces.iter().map(|&j| read.normals[j]).collect();
        let uvs: Option<Vec<_>> = faces.iter().map(|&j| read.uvs[j]).collect();
        parts.push(MeshDesc {
            material: Some(material.name.clone()),
            name: mesh.name.clone(),
            faces: faces.iter().map(|&j| read.faces[j]).collect(),
            normals: normals.unwrap_or_default(),
            uvs: uvs.unwrap_or_default(),
            degenerate: if parts.is_empty() { read.degenerate } else { 0 },
            warnings: if parts.is_empty() {
                std::mem::take(&mut read.warnings)
            } else {
                Vec::new()
            },
            ..mesh.clone()
        });
    }
    // A named mesh split in parts: each part is named by its material.
    if parts.len() > 1 {
        for p in &mut parts {
            if let (Some(name), Some(material)) = (&mut p.name, &p.material) {
                *name = format!("{name}/{material}");
            }
        }
    }
    Ok(parts)
}

/// A turned `[[box]]` (`rotate` or `quaternion`) as the mesh of its 12
/// triangles, turned about the box's centre, each face's corners with the uv a
/// box gives its faces (0 to 1 along the face's first other axis, x on the y
/// and z faces and y on the x faces, then along its second), flat; `None` for
/// a box that is not turned. `index` is the box's (from 0), for the mesh's name.
///
/// # Errors
/// The rotation's message (both keys, a zero quaternion, a number not finite).
pub fn turned_box(b: &crate::kinds::BoxDesc, index: usize) -> Result<Option<MeshDesc>, String> {
    if b.rotate.is_none() && b.quaternion.is_none() {
        return Ok(None);
    }
    let mut m = MeshDesc {
        rotate: b.rotate,
        quaternion: b.quaternion,
        smooth: Some(false),
        name: b.name.clone(),
        ..MeshDesc::unplaced(
            format!("(box {}, turned)", index + 1),
            Some(b.material.clone()),
        )
    };
    let turn = rotation(&m).map_err(|e| e.replace("mesh ", "box "))?;
    m.rotate = None;
    m.quaternion = None;
    let centre: [f64; 3] = std::array::from_fn(|k| 0.5 * (b.min[k] + b.max[k]));
    let at = |p: [f64; 3]| {
        let t = apply(&turn, std::array::from_fn(|k| p[k] - centre[k]));
        std::array::from_fn(|k| t[k] + centre[k])
    };
    // Per face: the axis it is across, then the axes of its u and v.
    for (axis, u, v) in [(0, 1, 2), (1, 0, 2), (2, 0, 1)] {
        for side in [b.min[axis], b.max[axis]] {
            let corner = |cu: usize, cv: usize| {
                let mut p = [0.0; 3];
                p[axis] = side;
                p[u] = if cu == 0 { b.min[u] } else { b.max[u] };
                p[v] = if cv == 0 { b.min[v] } else { b.max[v] };
                (p, [cu as f64, cv as f64])
            };
            let quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            // Wound so that the face's normal points out of the box.
            let (a, bb, c) = (quad[0].0, quad[1].0, quad[2].0);
            let normal_axis = cross(sub(bb, a), sub(c, a))[axis];
            let outward = if side == b.max[axis] { 1.0 } else { -1.0 };
            let order: [[usize; 3]; 2] = if normal_axis * outward > 0.0 {
                [[0, 1, 2], [0, 2, 3]]
            } else {
                [[0, 2, 1], [0, 3, 2]]
            };
            for tri in order {
                m.faces.push(tri.map(|k| at(quad[k].0)));
                m.uvs.push(tri.map(|k| quad[k].1));
            }
        }
    }
    Ok(Some(m))
}

/// A 3x3 rotation matrix, rows first.
pub type Rotation = [[f64; 3]; 3];

/// The rotation of `mesh` (identity without `rotate` or `quaternion`): `rotate`
/// is degrees about the fixed X axis, then Y, then Z, so the matrix is
/// `Rz Ry Rx`; `quaternion` is `[x, y, z, w]`, normalised. Both at once, a
/// number that is not finite, or a quaternion of length 0 is an error.
pub fn rotation(mesh: &MeshDesc) -> Result<Rotation, String> {
    match (mesh.rotate, mesh.quaternion) {
        (Some(_), Some(_)) => {
            Err("a mesh is rotated by `rotate` (degrees) or `quaternion`, not both".into())
        }
        (Some(r), None) => {
            if !r.iter().all(|x| x.is_finite()) {
                return Err(format!(
                    "mesh rotate must be finite, got [{}]",
                    r.map(num).join(", ")
                ));
            }
            Ok(euler_xyz(r))
        }
        (None, Some(q)) => {
            let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !len.is_finite() || !q.iter().all(|x| x.is_finite()) {
                return Err(format!(
                    "mesh quaternion must be finite, got [{}]",
                    q.map(num).join(", ")
                ));
            }
            if len == 0.0 {
                return Err("mesh quaternion has zero length, got [0, 0, 0, 0]".into());
            }
            Ok(quaternion_matrix(q.map(|x| x / len)))
        }
        (None, None) => Ok([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
    }
}

/// `Rz(z) Ry(y) Rx(x)` for degrees `[x, y, z]`: about X first, then Y, then Z
/// (the fixed axes). Quarter turns are exact (`sin` and `cos` of multiples of
/// 90 degrees are taken as 0 and +-1), so `[0, 90, 0]` moves no vertex off its
/// grid.
#[must_use]
pub fn euler_xyz(degrees: [f64; 3]) -> Rotation {
    let sc = |d: f64| {
        let q = d / 90.0;
        if q == q.round() && q.abs() < 1e15 {
            let k = (q.round() as i64).rem_euclid(4);
            [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0)][k as usize]
        } else {
            d.to_radians().sin_cos()
        }
    };
    let [(sx, cx), (sy, cy), (sz, cz)] = degrees.map(sc);
    let rx = [[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]];
    let ry = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
    let rz = [[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]];
    mul(rz, mul(ry, rx))
}

/// `q` normalised in f64, scaled by its largest component first so that no
/// square overflows or underflows: any finite length but 0. `None` for a
/// component that is not finite, or all zero.
#[must_use]
pub fn unit_quaternion(q: [f64; 4]) -> Option<[f64; 4]> {
    let big = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if !q.iter().all(|x| x.is_finite()) || big == 0.0 {
        return None;
    }
    let q = q.map(|x| x / big);
    let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    Some(q.map(|x| x / len))
}

/// The unit quaternion `[x, y, z, w]` of [`euler_xyz`]'s rotation: `qz qy qx`
/// of the half angles (quarter turns as exact as `f64` gives `sqrt(1/2)`).
#[must_use]
pub fn euler_quaternion(degrees: [f64; 3]) -> [f64; 4] {
    let half = |d: f64| {
        let q = d / 90.0;
        if q == q.round() && q.abs() < 1e15 {
            // Multiples of 45 degrees for the half angle.
            let k = (q.round() as i64).rem_euclid(8);
            let h = std::f64::consts::FRAC_1_SQRT_2;
            [
                (0.0, 1.0),
                (h, h),
                (1.0, 0.0),
                (h, -h),
                (0.0, -1.0),
                (-h, -h),
                (-1.0, 0.0),
                (-h, h),
            ][k as usize]
        } else {
            (d / 2.0).to_radians().sin_cos()
        }
    };
    let [(sx, cx), (sy, cy), (sz, cz)] = degrees.map(half);
    // qy qx, then qz (qy qx).
    let qx = [sx, 0.0, 0.0, cx];
    let qy = [0.0, sy, 0.0, cy];
    let qz = [0.0, 0.0, sz, cz];
    quaternion_product(qz, quaternion_product(qy, qx))
}

/// The product `a b` of quaternions `[x, y, z, w]`: `b`'s turn, then `a`'s.
#[must_use]
pub fn quaternion_product(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

/// The rotation of the unit quaternion `[x, y, z, w]`.
#[must_use]
pub fn quaternion_matrix([x, y, z, w]: [f64; 4]) -> Rotation {
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

fn mul(a: Rotation, b: Rotation) -> Rotation {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

/// The most bytes an OBJ file's MTL file may have: 1 MiB (Blender writes about
/// 250 bytes a material).
pub const MAX_MTL_BYTES: usize = 1 << 20;

/// The most vertices of an OBJ face: its fan of `MAX_TRIANGLES` triangles fills
/// the scene's triangle list.
pub const MAX_FACE_VERTICES: usize = MAX_TRIANGLES + 2;

/// The most triangles the faces of an OBJ file may make (polygons counted as
/// fans), degenerate faces (left out) included: twice what the scene holds.
/// Bounding them before tobj reads the file bounds tobj's lists, which grow
/// with the faces (a file of 2 million faces takes 275 MB there, one face line of
/// 2.8 million vertices 340 MB).
pub const MAX_OBJ_TRIANGLES: usize = 2 * MAX_TRIANGLES;

/// Checks the lines of OBJ `text` as tobj will read them, before it does
/// (without allocating): else the 1-based line at fault and why.
///
/// - A face (a line whose first word is `f`) has at most [`MAX_FACE_VERTICES`]
///   vertices, and the faces make at most [`MAX_OBJ_TRIANGLES`] triangles in all.
/// - Every index of a face, to a vertex (`v`), a texture coordinate (`vt`) or a
///   normal (`vn`), names one defined before its line: OBJ indices count from 1,
///   or back from the last one when negative. tessera reads neither texture
///   coordinates nor normals, but a file that names ones it lacks is broken
///   (tobj lets some of them by: an index 0, or one counting back one past the
///   first, reads as none at all, and an index to a kind the file has none of is
///   not looked at). An index that is not an integer is left to tobj, which
///   refuses it on its line.
/// - A byte-order mark (U+FEFF) past the start of the text (two files joined) is
///   refused, but in a comment or on a line of nothing else: read as a word, it
///   would hide the statement of its line.
fn check_lines(text: &str) -> Result<Corners, (usize, String)> {
    let mut corners = Corners::default();
    let mut triangles = 0;
    // The vertices, texture coordinates and normals so far.
    let mut defined = [0i64; 3];
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let first = words.next().unwrap_or("");
        // A comment, or no word but marks: nothing hidden.
        let bare = first.trim_start_matches('\u{feff}');
        if bare.is_empty() || bare.starts_with('#') {
            continue;
        }
        if line.contains('\u{feff}') {
            return Err((
                n + 1,
                "a byte-order mark (U+FEFF) past the start of the file, where it hides \
                 the line's words (two files joined?)"
                    .to_string(),
            ));
        }
        match first {
            "v" => defined[0] += 1,
            "vt" => defined[1] += 1,
            "vn" => defined[2] += 1,
            "f" => {
                let vertices = words.clone().take(MAX_FACE_VERTICES + 1).count();
                if vertices > MAX_FACE_VERTICES {
                    return Err((
                        n + 1,
                        format!(
                            "a face of {} vertices, more than the {MAX_FACE_VERTICES} whose \
                             fan fills the scene's {MAX_TRIANGLES} triangles",
                            words.count()
                        ),
                    ));
                }
                triangles += vertices.saturating_sub(2);
                if triangles > MAX_OBJ_TRIANGLES {
                    return Err((
                        n + 1,
                        format!(
                            "the faces up to this line make more than {MAX_OBJ_TRIANGLES} \
                             triangles (twice the {MAX_TRIANGLES} the scene holds, degenerate \
                             faces included)"
                        ),
                    ));
                }
                for (corner, word) in words.enumerate() {
                    let mut parts = word.split('/');
                    let _ = parts.next();
                    let vt = parts.next().is_some_and(|p| !p.is_empty());
                    let vn = parts.next().is_some_and(|p| !p.is_empty());
                    corners.uvs[usize::from(vt)] += 1;
                    corners.normals[usize::from(vn)] += 1;
                    bad_corner(word, defined).map_err(|why| {
                        (
                            n + 1,
                            format!(
                                "not a valid OBJ file: corner {} of the face: {why}",
                                corner + 1
                            ),
                        )
                    })?;
                }
            }
            _ => {}
        }
    }
    Ok(corners)
}

/// How many face corners of an OBJ file lack (`[0]`) or have (`[1]`) a texture
/// coordinate index, and a normal index.
#[derive(Debug, Default)]
struct Corners {
    uvs: [usize; 2],
    normals: [usize; 2],
}

/// Checks one corner of a face (`v`, `v/vt`, `v//vn` or `v/vt/vn`) against the
/// vertices, texture coordinates and normals `defined` before it; else why not.
/// Parts that are not integers (or more than three) are left to tobj.
fn bad_corner(word: &str, defined: [i64; 3]) -> Result<(), String> {
    const KINDS: [(&str, &str, &str); 3] = [
        ("vertex", "vertex (v)", "vertices (v)"),
        (
            "texture coordinate",
            "texture coordinate (vt)",
            "texture coordinates (vt)",
        ),
        ("normal", "normal (vn)", "normals (vn)"),
    ];
    for ((part, count), (kind, one, many)) in word.split('/').zip(defined).zip(KINDS) {
        let defined = || {
            let what = if count == 1 { one } else { many };
            format!("the {count} {what} before this line")
        };
        if part.is_empty() {
            if kind == "vertex" {
                return Err("no vertex index".to_string());
            }
            continue;
        }
        let Ok(i) = part.parse::<i64>() else {
            continue;
        };
        if i == 0 {
            return Err(format!(
                "{kind} index 0: OBJ indices count from 1 (back from the last when negative)"
            ));
        }
        if i > count {
            return Err(format!("{kind} index {i} is beyond {}", defined()));
        }
        if i < -count {
            return Err(format!(
                "{kind} index {i} counts back past the first of {}",
                defined()
            ));
        }
    }
    Ok(())
}

/// The OBJ text as tobj reads it, a line at a time, remembering how far it got.
/// Lines (`l`) and points (`p`) are no faces, but tobj reads them as faces: it is
/// given only their line breaks (so that line numbers stay right), without a
/// copy of the text.
struct Consumed<'t> {
    text: &'t str,
    /// Bytes consumed (or passed over) so far.
    at: usize,
    /// `at` is at the start of a line.
    line_start: bool,
}

impl Read for Consumed<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let rest = self.fill_buf()?;
        let n = rest.len().min(buf.len());
        buf[..n].copy_from_slice(&rest[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl BufRead for Consumed<'_> {
    /// The rest of the current line, its line break included.
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        let line = |at: usize| {
            let rest = self.text.as_bytes().get(at..).unwrap_or_default();
            &rest[..rest
                .iter()
                .position(|&b| b == b'\n')
                .map_or(rest.len(), |i| i + 1)]
        };
        if self.line_start {
            self.line_start = false;
            // A whole line: UTF-8, as the text is.
            let text = std::str::from_utf8(line(self.at)).unwrap_or_default();
            let word = text.split_whitespace().next().unwrap_or_default();
            if word == "l" || word == "p" {
                self.at += text.trim_end_matches(['\n', '\r']).len();
            }
        }
        Ok(line(self.at))
    }

    fn consume(&mut self, n: usize) {
        self.at = (self.at + n).min(self.text.len());
        self.line_start = self.text.as_bytes()[..self.at].ends_with(b"\n");
    }
}

#[cfg(test)]
mod tests {
    use super::{Rotation, euler_xyz, quaternion_matrix};
    use crate::arr3::{cross, sub};
    use crate::file::{self, FileError};
    use std::path::Path;

    /// A scene with one material and `items` after it.
    fn scene(items: &str) -> String {
        format!(
            "[camera]\nposition = [0, 0, 6]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\n\
             [[material]]\nname = \"m\"\n\n[[light]]\nposition = [3, 4, 5]\nintensity = 30\n\n{items}"
        )
    }

    /// Loads `toml` written as `scene.toml` next to OBJ files `objs` (name, text).
    fn load(toml: &str, objs: &[(&str, &str)]) -> Result<crate::desc::SceneDesc, FileError> {
        let dir = tempfile::tempdir().unwrap();
        for (name, text) in objs {
            std::fs::write(dir.path().join(name), text).unwrap();
        }
        let path = dir.path().join("scene.toml");
        std::fs::write(&path, toml).unwrap();
        file::load(&path)
    }

    /// A unit cube as 3D tools write it: quads, one `vn` per face (hard edges),
    /// `vt` per corner (each face the whole texture).
    const CUBE: &str = "o Cube\n\
        v 1 1 -1\nv 1 -1 -1\nv 1 1 1\nv 1 -1 1\nv -1 1 -1\nv -1 -1 -1\nv -1 1 1\nv -1 -1 1\n\
        vn 0 1 0\nvn 0 0 1\nvn -1 0 0\nvn 0 -1 0\nvn 1 0 0\nvn 0 0 -1\n\
        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
        s 0\n\
        f 1/1/1 5/2/1 7/3/1 3/4/1\nf 4/1/2 3/2/2 7/3/2 8/4/2\nf 8/1/3 7/2/3 5/3/3 6/4/3\n\
        f 6/1/4 2/2/4 4/3/4 8/4/4\nf 2/1/5 1/2/5 3/3/5 4/4/5\nf 6/1/6 5/2/6 1/3/6 2/4/6\n";

    /// The file's normals are used as given: a cube's hard edges stay hard (24
    /// vertices, 4 a face, each with its face's normal), and its `vt`s give
    /// each face's corners their uvs (`v` flipped: OBJ's runs up, tessera's
    /// down), so a quad's two triangles share one mapping. Turned with the mesh.
    #[test]
    fn a_tools_cube_keeps_its_normals_and_uvs() {
        let mesh = "[[mesh]]\nobj = \"cube.obj\"\nmaterial = \"m\"\nrotate = [0, 90, 0]\n";
        let d = load(&scene(mesh), &[("cube.obj", CUBE)]).unwrap();
        let m = &d.meshes[0];
        assert_eq!((m.faces.len(), m.normals.len(), m.uvs.len()), (12, 12, 12));
        let w = m.welded();
        assert_eq!(
            (w.positions.len(), w.normals.len(), w.uvs.len()),
            (24, 24, 24)
        );
        // Each vertex's normal is its face's: the face's own normal, turned.
        for f in &w.faces {
            let [a, b, c] = f.map(|i| w.positions[i]);
            let g = cross(sub(b, a), sub(c, a));
            let len = g.iter().map(|x| x * x).sum::<f64>().sqrt();
            for &i in f {
                let n = w.normals[i];
                let cos = (0..3).map(|k| n[k] * g[k] / len).sum::<f64>();
                assert!((cos - 1.0).abs() < 1e-12, "{n:?} against {g:?}");
            }
        }
        // The first quad (the top, +y: the rotation leaves it the top) has its
        // corners' uvs, flipped: (0, 1), (1, 1), (1, 0), (0, 0).
        assert_eq!(m.uvs[0], [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]);
        assert_eq!(m.uvs[1], [[0.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
        // `smooth = false`: flat, whatever the file says; the uvs stay.
        let flat = "[[mesh]]\nobj = \"cube.obj\"\nmaterial = \"m\"\nsmooth = false\n";
        let d = load(&scene(flat), &[("cube.obj", CUBE)]).unwrap();
        let w = d.meshes[0].welded();
        // Corners welded where position and uv agree.
        assert_eq!((w.normals.len(), w.uvs.len()), (0, w.positions.len()));
        assert!(
            w.positions.len() > 8 && w.positions.len() < 24,
            "{}",
            w.positions.len()
        );
        // A file without normals: flat unless `smooth = true` averages them (8
        // vertices then, as uvs are none either).
        let bare: String = CUBE
            .lines()
            .filter(|l| !l.starts_with("vn") && !l.starts_with("vt"))
            .map(|l| {
                let l = if l.starts_with("f ") {
                    l.split(' ')
                        .map(|w| w.split('/').next().unwrap())
                        .collect::<Vec<_>>()
                        .join(" ")
                } else {
                    l.to_string()
                };
                l + "\n"
            })
            .collect();
        let smooth = "[[mesh]]\nobj = \"cube.obj\"\nmaterial = \"m\"\nsmooth = true\n";
        let d = load(&scene(smooth), &[("cube.obj", &bare)]).unwrap();
        let w = d.meshes[0].welded();
        assert_eq!((w.positions.len(), w.normals.len(), w.uvs.len()), (8, 8, 0));
    }

    /// Blender's files with their MTL materials (`material` left out): the
    /// three boxes become three meshes of `box_stack.obj/mat_bot` ... with the
    /// MTL's terms by the rule (Kd 0.64, Ks 0.5, Ns 96.078431, Ni 1, d 1,
    /// illum 2); the cube's map_Kd becomes an image texture tinted by its Kd of
    /// 0.8, read in the scene's format; the face counts add up to the files'.
    #[test]
    fn mtl_materials_split_the_mesh_by_the_rule() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/blender/mtl.toml");
        let d = file::load(&path).unwrap();
        let names: Vec<&str> = d
            .meshes
            .iter()
            .map(|m| m.material.as_deref().unwrap())
            .collect();
        assert_eq!(
            names,
            [
                "happy-cube.obj/Material",
                "box_stack.obj/mat_bot",
                "box_stack.obj/mat_mid",
                "box_stack.obj/mat_top"
            ]
        );
        // 26 faces (18 quads, 8 triangles) and 18 quads, as triangles.
        assert_eq!(d.meshes[0].faces.len(), 18 * 2 + 8);
        assert_eq!(
            d.meshes[1..].iter().map(|m| m.faces.len()).sum::<usize>(),
            36
        );
        let m = |name: &str| d.materials.iter().find(|m| m.name == name).unwrap();
        let top = m("box_stack.obj/mat_top");
        assert_eq!(
            (
                top.color,
                top.specular,
                top.shininess,
                top.reflectivity,
                top.transparency,
                top.ior
            ),
            ([0.64; 3], 0.5, 96.078431, 0.0, 0.0, 1.0)
        );
        let cube = m("happy-cube.obj/Material");
        let Some(crate::desc::TextureDesc::Image {
            file,
            tint,
            image: Some(img),
            ..
        }) = &cube.texture
        else {
            panic!("{:?}", cube.texture)
        };
        assert_eq!((file.as_str(), *tint), ("happy-tree.png", [0.8; 3]));
        assert_eq!(img.format(), tessera_core::image::TexelFormat::Rgb565);
        assert!(img.bytes() <= 16384, "{}", img.bytes());
        // The scene renders, with the file's materials.
        d.to_core().unwrap();
    }

    /// A file without materials and no `material`: refused, naming the fix.
    #[test]
    fn a_mesh_needs_a_material_from_somewhere() {
        let mesh = "[[mesh]]\nobj = \"t.obj\"\n";
        let e = load(
            &scene(mesh),
            &[("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")],
        )
        .unwrap_err();
        assert!(e.to_string().contains("the file has no materials"), "{e}");
        // A missing MTL file is an error naming it.
        let obj = "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
        let e = load(&scene(mesh), &[("t.obj", obj)]).unwrap_err();
        assert!(e.to_string().contains("gone.mtl"), "{e}");
        // With the scene's material, the MTL file is not read, and a warning says so.
        let named = "[[mesh]]\nobj = \"t.obj\"\nmaterial = \"m\"\n";
        let d = load(&scene(named), &[("t.obj", obj)]).unwrap();
        let shown = crate::file::warnings(&d).join("\n");
        assert!(
            shown.contains("its materials (gone.mtl) are not used"),
            "{shown}"
        );
    }

    /// A turned box is the mesh of its 12 triangles, turned about its centre:
    /// the cube `[-1, 1]^3` turned 45 degrees about y has its corner `(1, 1, 1)`
    /// at `(sqrt 2, 1, 0)`; each face keeps the box's uv (corners at 0 and 1);
    /// an unturned box stays a box.
    #[test]
    fn a_turned_box_is_a_mesh_of_its_faces() {
        let boxes = "[[box]]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\nmaterial = \"m\"\nrotate = [0, 45, 0]\n\n\
                     [[box]]\nmin = [2, 0, 0]\nmax = [3, 1, 1]\nmaterial = \"m\"\n";
        let d = load(&scene(boxes), &[]).unwrap();
        assert_eq!((d.boxes.len(), d.meshes.len()), (1, 1));
        let m = &d.meshes[0];
        assert_eq!((m.faces.len(), m.uvs.len()), (12, 12));
        let corners: Vec<[f64; 3]> = m.faces.iter().flatten().copied().collect();
        let want = [2f64.sqrt(), 1.0, 0.0];
        assert!(
            corners
                .iter()
                .any(|p| (0..3).all(|k| (p[k] - want[k]).abs() < 1e-12)),
            "{corners:?}"
        );
        assert!(
            m.uvs
                .iter()
                .flatten()
                .flatten()
                .all(|&x| x == 0.0 || x == 1.0)
        );
        // Every face's normal points away from the centre.
        for f in &m.faces {
            let n = cross(sub(f[1], f[0]), sub(f[2], f[0]));
            let c: Vec<f64> = (0..3)
                .map(|k| (f[0][k] + f[1][k] + f[2][k]) / 3.0)
                .collect();
            assert!((0..3).map(|k| n[k] * c[k]).sum::<f64>() > 0.0, "{f:?}");
        }
        let e = load(&scene("[[box]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nmaterial = \"m\"\nquaternion = [0, 0, 0, 0]\n"), &[]).unwrap_err();
        assert!(
            e.to_string().contains("box 1") && e.to_string().contains("quaternion has zero length"),
            "{e}"
        );
        // A turned box is checked as a box first: min above max is refused.
        let inverted =
            "[[box]]\nmin = [1, 0, 0]\nmax = [0, 1, 1]\nmaterial = \"m\"\nrotate = [0, 10, 0]\n";
        let e = load(&scene(inverted), &[]).unwrap_err().to_string();
        assert!(
            e.contains("box 1") && e.contains("box min corner must be <= max corner"),
            "{e}"
        );
    }

    /// Normals for some faces only are not used, and the warning says so.
    #[test]
    fn normals_for_some_faces_only_are_warned_about() {
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n";
        let mesh = "[[mesh]]\nobj = \"p.obj\"\nmaterial = \"m\"\n";
        let d = load(&scene(mesh), &[("p.obj", obj)]).unwrap();
        let m = &d.meshes[0];
        assert!(m.normals.is_empty());
        let shown = crate::file::warnings(&d).join("\n");
        assert!(shown.contains("normals"), "{shown}");
    }

    /// `rotate` turns about the fixed X, then Y, then Z axes: a vertex on +X
    /// turned `[0, 90, 0]` goes to -Z; `[90, 0, 90]` takes +Y first to +Z (about
    /// X), which Z leaves; +X goes to +Y. The quaternion of a half turn about
    /// the diagonal `(1, 1, 0) / sqrt 2` swaps X and Y and flips Z. Each on the
    /// vertices a scene file reads: scale, then rotation, then translation.
    #[test]
    fn rotations_turn_as_written() {
        let apply =
            |r: Rotation, p: [f64; 3]| r.map(|row| row[0] * p[0] + row[1] * p[1] + row[2] * p[2]);
        assert_eq!(
            apply(euler_xyz([0.0, 90.0, 0.0]), [1.0, 0.0, 0.0]),
            [0.0, 0.0, -1.0]
        );
        let r = euler_xyz([90.0, 0.0, 90.0]);
        assert_eq!(apply(r, [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(apply(r, [1.0, 0.0, 0.0]), [0.0, 1.0, 0.0]);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let q = quaternion_matrix([h, h, 0.0, 0.0]);
        let p = apply(q, [1.0, 2.0, 3.0]);
        for (a, b) in p.iter().zip([2.0, 1.0, -3.0]) {
            assert!((a - b).abs() < 4.0 * f64::EPSILON * 3.0, "{p:?}");
        }
        // 30 degrees about Z by hand: (cos 30, sin 30, 0).
        let p = apply(euler_xyz([0.0, 0.0, 30.0]), [1.0, 0.0, 0.0]);
        assert!((p[0] - 0.75f64.sqrt()).abs() < 1e-15 && (p[1] - 0.5).abs() < 1e-15);
        // In a scene file, on a triangle: scale 2, turn +X to -Z, move up 1.
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let mesh = "[[mesh]]\nobj = \"t.obj\"\nmaterial = \"m\"\nscale = 2\nrotate = [0, 90, 0]\ntranslate = [0, 1, 0]\n";
        let d = load(&scene(mesh), &[("t.obj", obj)]).unwrap();
        assert_eq!(
            d.meshes[0].faces,
            [[[0.0, 1.0, 0.0], [0.0, 1.0, -2.0], [0.0, 3.0, 0.0]]]
        );
        let mesh = "[[mesh]]\nobj = \"t.obj\"\nmaterial = \"m\"\nquaternion = [0, 0.7071067811865476, 0, 0.7071067811865476]\n";
        let d = load(&scene(mesh), &[("t.obj", obj)]).unwrap();
        let [_, b, _] = d.meshes[0].faces[0];
        assert!((b[2] + 1.0).abs() < 1e-15 && b[0].abs() < 1e-15, "{b:?}");
    }

    /// A mesh of `obj` as the file gives it: material `m`, no scale, no move.
    fn unplaced(obj: &str) -> crate::desc::MeshDesc {
        crate::desc::MeshDesc::unplaced(obj, Some("m".into()))
    }

    #[cfg(feature = "cli")]
    fn icosahedron() -> String {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/examples/icosahedron.obj");
        std::fs::read_to_string(path).unwrap()
    }

    /// A mesh is its faces written as `[[triangle]]`s: the same core triangles in
    /// the same order, hence the same pixels; scale then translate.
    #[test]
    #[cfg(feature = "cli")] // renders
    fn a_mesh_is_the_triangles_of_its_faces() {
        let obj = icosahedron();
        let mesh = "[[mesh]]\nobj = \"ico.obj\"\nmaterial = \"m\"\nscale = 0.5\ntranslate = [1, -2, 0.25]\n";
        let d = load(&scene(mesh), &[("ico.obj", &obj)]).unwrap();
        assert_eq!(d.meshes[0].faces.len(), 20);
        assert_eq!(d.meshes[0].degenerate, 0);
        // The faces from the OBJ text by hand: `v` lines, then `f` lines.
        let vs: Vec<[f64; 3]> = obj
            .lines()
            .filter_map(|l| l.strip_prefix("v "))
            .map(|l| {
                let x: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
                [x[0] * 0.5 + 1.0, x[1] * 0.5 - 2.0, x[2] * 0.5 + 0.25]
            })
            .collect();
        let mut triangles = String::new();
        for f in obj.lines().filter_map(|l| l.strip_prefix("f ")) {
            let p: Vec<String> = f
                .split_whitespace()
                .map(|i| {
                    let v = vs[i.parse::<usize>().unwrap() - 1];
                    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
                })
                .collect();
            triangles += &format!(
                "[[triangle]]\nvertices = [{}]\nmaterial = \"m\"\n",
                p.join(", ")
            );
        }
        let written = file::parse(&scene(&triangles), "t.toml").unwrap();
        let (a, b) = (d.to_core().unwrap(), written.to_core().unwrap());
        let (mesh, list) = (a.mesh_parts().next().unwrap(), b.lists().view());
        assert_eq!(mesh.faces.len(), 20);
        let faces: Vec<tessera_core::geometry::Triangle> = mesh
            .faces
            .iter()
            .map(|f| {
                let [p, q, r] = f.map(|i| {
                    let [x, y, z] = mesh.vertices[usize::from(i)];
                    tessera_core::Vec3::new(x, y, z)
                });
                tessera_core::geometry::Triangle::try_new(p, q, r).unwrap()
            })
            .collect();
        let listed: Vec<tessera_core::geometry::Triangle> =
            list.triangles().iter().map(|t| t.geometry).collect();
        assert_eq!(faces, listed);
        let vp = tessera_core::Viewport::new(32, 24);
        let render = |s: &crate::desc::HostScene| {
            s.with_view(|v| crate::render(v, s.camera(), vp, d.settings().unwrap(), 16))
                .unwrap()
        };
        assert_eq!(render(&a), render(&b));
    }

    /// Polygons are split into fans; faces of zero area are left out, counted and
    /// warned about.
    #[test]
    fn polygons_are_fans_and_flat_faces_are_left_out() {
        let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 0\nf 1 2 3 4\nf 1 3 5\n";
        let mesh = "[[mesh]]\nobj = \"q.obj\"\nmaterial = \"m\"\n";
        let d = load(&scene(mesh), &[("q.obj", obj)]).unwrap();
        assert_eq!(d.meshes[0].faces.len(), 2);
        assert_eq!(d.meshes[0].degenerate, 1);
        let w = file::warnings(&d);
        assert!(
            w.iter()
                .any(|w| w.contains("mesh 1 (\"q.obj\"): 1 of its faces left out")),
            "{w:?}"
        );
    }

    /// Every problem names the scene file's line of the mesh, the OBJ file and,
    /// for bad OBJ text, its line.
    #[test]
    fn bad_meshes_are_clear_errors() {
        let mesh = |extra: &str| {
            scene(&format!(
                "# a comment\n[[mesh]]\nobj = \"x.obj\"\nmaterial = \"m\"\n{extra}"
            ))
        };
        let line = mesh("").lines().position(|l| l == "[[mesh]]").unwrap() + 1;
        type Case<'a> = (String, &'a [(&'a str, &'a str)], &'a str);
        let cases: [Case; 10] = [
            (mesh(""), &[], "x.obj: cannot read the OBJ file"),
            (
                mesh(""),
                &[("x.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n")],
                "x.obj:4: not a valid OBJ file",
            ),
            (
                mesh(""),
                &[("x.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n")],
                "x.obj:3: not a valid OBJ file: corner 3 of the face: vertex index 3 is beyond \
                 the 2 vertices (v) before this line",
            ),
            (
                mesh(""),
                &[("x.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")],
                "no face to render (1 degenerate faces left out)",
            ),
            (
                mesh("scale = 0\n"),
                &[("x.obj", "v 0 0 0\n")],
                "mesh scale must be finite and > 0, got 0",
            ),
            (
                mesh("translate = [0, nan, 0]\n"),
                &[("x.obj", "v 0 0 0\n")],
                "mesh translate must be finite, got [0, NaN, 0]",
            ),
            (
                mesh("rotate = [0, 90, 0]\nquaternion = [0, 0, 0, 1]\n"),
                &[("x.obj", "v 0 0 0\n")],
                "a mesh is rotated by `rotate` (degrees) or `quaternion`, not both",
            ),
            (
                mesh("quaternion = [0, 0, 0, 0]\n"),
                &[("x.obj", "v 0 0 0\n")],
                "mesh quaternion has zero length",
            ),
            (
                mesh("rotate = [0, inf, 0]\n"),
                &[("x.obj", "v 0 0 0\n")],
                "mesh rotate must be finite, got [0, inf, 0]",
            ),
            (
                mesh("scale = 1e39\n"),
                &[("x.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")],
                "face 1",
            ),
        ];
        for (toml, objs, want) in cases {
            let e = load(&toml, objs).unwrap_err();
            let shown = e.to_string();
            assert!(shown.contains(want), "{shown:?} lacks {want:?}");
            assert!(shown.contains("mesh 1"), "{shown}");
            assert_eq!(e.line, Some(line), "{shown}");
        }
    }

    /// An unknown material and a mesh that overflows the triangle list are named.
    #[test]
    fn meshes_count_against_the_triangle_list() {
        let unknown = "[[mesh]]\nobj = \"t.obj\"\nmaterial = \"nope\"\n";
        let tri = ("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let e = load(&scene(unknown), &[tri]).unwrap_err().to_string();
        assert!(
            e.contains("mesh 1 (\"t.obj\"): unknown material \"nope\""),
            "{e}"
        );
        // 8,192 triangles fill the list; a mesh of 2 after 8,191 overflows it.
        let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
        obj += &"f 1 2 3\n".repeat(2);
        let mesh = "[[mesh]]\nobj = \"big.obj\"\nmaterial = \"m\"\n";
        let own = "[[triangle]]\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nmaterial = \"m\"\n"
            .repeat(crate::desc::MAX_TRIANGLES - 1);
        let e = load(&scene(&format!("{own}{mesh}")), &[("big.obj", &obj)])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(
                "mesh 1: too many triangles: the scene holds at most 8192: the faces \
                 of big.obj come after 8191 triangles"
            ),
            "{e}"
        );
        // One triangle fewer of its own: exactly full.
        let own = &own[own.find("\n[[triangle]]").unwrap() + 1..];
        let fits = load(&scene(&format!("{own}{mesh}")), &[("big.obj", &obj)]);
        assert!(fits.is_ok(), "{:?}", fits.err());
    }

    /// The OBJ text a scene reads is bounded, all meshes together; the budget
    /// shrinks by each file read.
    #[test]
    fn obj_text_is_read_within_a_budget() {
        let dir = tempfile::tempdir().unwrap();
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        std::fs::write(dir.path().join("t.obj"), text).unwrap();
        let mesh = unplaced("t.obj");
        let mut budget = 100;
        assert!(super::read(&mesh, dir.path(), &mut budget, 10).is_ok());
        assert_eq!(budget, 100 - text.len());
        let mut budget = 10;
        let e = super::read(&mesh, dir.path(), &mut budget, 10).unwrap_err();
        assert!(
            e.contains("more than the limit of 10 bytes")
                && e.contains("what is left of the 16 MiB that the OBJ files of a scene may take"),
            "{e}"
        );
    }

    /// OBJ lines (`l`) and points (`p`) are no faces (tobj would read them as
    /// faces); the faces stop at the room left, at once.
    #[test]
    fn lines_and_points_are_not_faces_and_faces_stop_at_the_room_left() {
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nl 1 2 3\np 1 2 3\nf 1 2 3\nl 2 3 4\n";
        let mesh = "[[mesh]]\nobj = \"l.obj\"\nmaterial = \"m\"\n";
        let d = load(&scene(mesh), &[("l.obj", obj)]).unwrap();
        assert_eq!(d.meshes[0].faces.len(), 1);
        assert_eq!(d.meshes[0].degenerate, 0);
        // Line numbers count the lines and points passed over.
        let e = faces_of("v 0 0 0\r\nl 1 1\r\n  p 1\r\nv 1 0 x\r\nf 1 1 1\r\n").unwrap_err();
        assert!(
            e.ends_with("x.obj:4: not a valid OBJ file: position parse error"),
            "{e}"
        );
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("two.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n",
        )
        .unwrap();
        let two = unplaced("two.obj");
        let mut budget = super::MAX_OBJ_BYTES;
        assert_eq!(
            super::read(&two, dir.path(), &mut budget, 2).map(|f| f.faces.len()),
            Ok(2)
        );
        assert_eq!(
            super::read(&two, dir.path(), &mut budget, 1)
                .err()
                .as_deref(),
            Some(
                "too many triangles: the scene holds at most 8192: the faces of two.obj \
                 come after 8191 triangles"
            )
        );
    }

    /// A face index out of range is reported at the face's line, though tobj finds
    /// it only when the object ends; a hostile index does not panic.
    #[test]
    fn index_errors_name_the_face_line() {
        let mesh = "[[mesh]]\nobj = \"x.obj\"\nmaterial = \"m\"\n";
        for (obj, line) in [
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\ng a\nf 1 2 3\n", 4),
            ("v 0 0 0\nv 1 0 0\nf 1 2 9\nv 0 1 0\nv 1 1 0\n# end\n", 3),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-9223372036854775807 2 3\n",
                5,
            ),
        ] {
            let e = load(&scene(mesh), &[("x.obj", obj)])
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(&format!("x.obj:{line}: not a valid OBJ file")),
                "{obj:?}: {e}"
            );
        }
    }

    /// `parse` reads OBJ paths from the current folder, `load` from the scene
    /// file's: the same scene text finds its mesh only next to its file.
    #[test]
    fn obj_paths_are_relative_to_the_scene_file() {
        let text = scene("[[mesh]]\nobj = \"only-here-4f2a.obj\"\nmaterial = \"m\"\n");
        let tri = ("only-here-4f2a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert!(load(&text, &[tri]).is_ok());
        let e = file::parse(&text, "t.toml").unwrap_err().to_string();
        assert!(
            e.contains("only-here-4f2a.obj: cannot read the OBJ file"),
            "{e}"
        );
    }

    /// The faces `super::read` makes of OBJ `text` (written as `x.obj`), or its
    /// error.
    fn faces_of(text: &str) -> Result<(Vec<crate::desc::Face>, usize), String> {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("x.obj"), text).unwrap();
        let mut budget = super::MAX_OBJ_BYTES;
        super::read(&unplaced("x.obj"), dir.path(), &mut budget, 100)
            .map(|m| (m.faces, m.degenerate))
    }

    /// The fixture `name` of `host/tests/fixtures`.
    fn fixture(name: &str) -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures")
            .join(name)
    }

    /// An OBJ file that starts with a UTF-8 byte-order mark reads as the same file
    /// without it: its first vertex counts, so every face has the vertices its
    /// indices name (also when a face names the last vertex).
    #[test]
    fn a_byte_order_mark_at_the_start_is_not_read() {
        for obj in [
            // No face names the last vertex: read wrong, the mesh would be shifted.
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n",
            // The last face names the last vertex.
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n",
            // Relative indices count back from the last vertex.
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -3 -1\n",
        ] {
            let plain = faces_of(obj).unwrap();
            assert_eq!(
                faces_of(&format!("\u{feff}{obj}")),
                Ok(plain.clone()),
                "{obj:?}"
            );
            // The faces by hand: the file's `v` lines, then each face's indices.
            let vs: Vec<[f64; 3]> = obj
                .lines()
                .filter_map(|l| l.strip_prefix("v "))
                .map(|l| {
                    let x: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
                    [x[0], x[1], x[2]]
                })
                .collect();
            let want: Vec<crate::desc::Face> = obj
                .lines()
                .filter_map(|l| l.strip_prefix("f "))
                .map(|f| {
                    let v: Vec<[f64; 3]> = f
                        .split_whitespace()
                        .map(|w| {
                            let i: i64 = w.parse().unwrap();
                            let n = i64::try_from(vs.len()).unwrap();
                            vs[usize::try_from(if i < 0 { n + i } else { i - 1 }).unwrap()]
                        })
                        .collect();
                    [v[0], v[1], v[2]]
                })
                .collect();
            assert_eq!(plain, (want, 0), "{obj:?}");
        }
        // A file as a Windows tool writes it: the mark, CRLF line ends, texture
        // coordinates and normals; its faces by hand, polygons as fans.
        let bytes = std::fs::read(fixture("bom-crlf.obj")).unwrap();
        assert!(bytes.starts_with("\u{feff}v ".as_bytes()) && bytes.ends_with(b"\r\n"));
        let text = String::from_utf8(bytes).unwrap();
        let vs: Vec<[f64; 3]> = text
            .lines()
            .filter_map(|l| l.trim_start_matches('\u{feff}').strip_prefix("v "))
            .map(|l| {
                let x: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
                [x[0], x[1], x[2]]
            })
            .collect();
        assert_eq!(vs.len(), 5);
        let mut want = Vec::new();
        for f in text.lines().filter_map(|l| l.strip_prefix("f ")) {
            let v: Vec<[f64; 3]> = f
                .split_whitespace()
                .map(|w| vs[w.split('/').next().unwrap().parse::<usize>().unwrap() - 1])
                .collect();
            for k in 2..v.len() {
                want.push([v[0], v[k - 1], v[k]]);
            }
        }
        assert_eq!(want.len(), 4);
        let dir = tempfile::tempdir().unwrap();
        std::fs::copy(fixture("bom-crlf.obj"), dir.path().join("x.obj")).unwrap();
        let mut budget = super::MAX_OBJ_BYTES;
        let read = super::read(&unplaced("x.obj"), dir.path(), &mut budget, 100)
            .map(|m| (m.faces, m.degenerate));
        assert_eq!(read, Ok((want, 0)));
        // The mark is OBJ text read: it counts against the budget.
        assert_eq!(budget, super::MAX_OBJ_BYTES - text.len());
    }

    /// The line checks before tobj read the first line of a file with a
    /// byte-order mark as its words: a face there is bounded and its indices
    /// checked.
    #[test]
    fn the_line_checks_read_past_a_byte_order_mark() {
        let vertices = super::MAX_FACE_VERTICES + 1;
        let indices: Vec<String> = (1..=vertices).map(|i| i.to_string()).collect();
        let big = format!("\u{feff}f {}\nv 0 0 0\n", indices.join(" "));
        let e = faces_of(&big).unwrap_err();
        assert!(
            e.contains(&format!("x.obj:1: a face of {vertices} vertices")),
            "{e}"
        );
        let e = faces_of("\u{feff}f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap_err();
        assert!(
            e.contains("x.obj:1: not a valid OBJ file: corner 1 of the face: vertex index 1 is beyond the 0 vertices (v) before this line"),
            "{e}"
        );
    }

    /// A byte-order mark past the file's start (two files joined) is refused on
    /// its line, unless the line is a comment: read as a word it would hide the
    /// line's statement.
    #[test]
    fn a_byte_order_mark_past_the_start_is_refused() {
        for (obj, line) in [
            ("v 0 0 0\n\u{feff}v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n", 2),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\n\u{feff}f 1 2 3\n", 4),
            ("\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 \u{feff}\n", 4),
        ] {
            let e = faces_of(obj).unwrap_err();
            assert!(
                e.contains(&format!(
                    "x.obj:{line}: a byte-order mark (U+FEFF) past the start of the file"
                )),
                "{obj:?}: {e}"
            );
        }
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let commented = format!("# \u{feff}joined\n{obj}\u{feff}# end\n\u{feff}\n");
        assert_eq!(faces_of(&commented), faces_of(obj));
        assert!(faces_of(obj).is_ok());
    }

    /// A scene file that starts with a byte-order mark reads as the same file
    /// without it (the TOML parser skips it; the line checks before it too), also
    /// when its first line is a table; its mesh's OBJ file may have one too.
    #[test]
    fn a_scene_file_may_start_with_a_byte_order_mark() {
        let text = scene("[[mesh]]\nobj = \"t.obj\"\nmaterial = \"m\"\n");
        assert!(text.starts_with("[camera]"));
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let plain = load(&text, &[("t.obj", tri)]).unwrap();
        let marked = load(&format!("\u{feff}{text}"), &[("t.obj", tri)]);
        assert_eq!(marked, Ok(plain.clone()));
        let marked = load(
            &format!("\u{feff}{text}"),
            &[("t.obj", &format!("\u{feff}{tri}"))],
        );
        assert_eq!(marked, Ok(plain));
        // The fixture: the mark and CRLF line ends in the scene file and its OBJ.
        let d = file::load(&fixture("bom-crlf.toml")).unwrap();
        let bytes = std::fs::read(fixture("bom-crlf.toml")).unwrap();
        assert!(bytes.starts_with("\u{feff}#".as_bytes()) && bytes.ends_with(b"\r\n"));
        let plain = String::from_utf8(bytes)
            .unwrap()
            .replace(['\u{feff}', '\r'], "");
        let obj = std::fs::read_to_string(fixture("bom-crlf.obj")).unwrap();
        let obj = obj.replace(['\u{feff}', '\r'], "");
        let want = load(&plain, &[("bom-crlf.obj", &obj)]).unwrap();
        assert_eq!(d, want);
        assert_eq!(d.meshes[0].faces.len(), 4);
    }

    /// A face's texture coordinate and normal indices are checked as its vertex
    /// indices are (tessera reads neither): one out of range, 0, or counting back
    /// past the first is refused at the face's line, naming the index.
    #[test]
    fn texture_and_normal_indices_are_checked_like_vertex_indices() {
        let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvn 0 0 1\n";
        for (face, why) in [
            (
                "f 1/1 2/2 3/3",
                "corner 3 of the face: texture coordinate index 3 is beyond the 2 texture coordinates (vt) before this line",
            ),
            (
                "f 1//1 2//1 3//2",
                "corner 3 of the face: normal index 2 is beyond the 1 normal (vn) before this line",
            ),
            (
                "f 1/1/1 2/2/1 3/2/9",
                "corner 3 of the face: normal index 9 is beyond the 1 normal (vn) before this line",
            ),
            (
                "f 1 2 4",
                "corner 3 of the face: vertex index 4 is beyond the 3 vertices (v) before this line",
            ),
            (
                "f 1/0 2/1 3/1",
                "corner 1 of the face: texture coordinate index 0: OBJ indices count from 1 (back from the last when negative)",
            ),
            (
                "f 1//1 2//0 3//1",
                "corner 2 of the face: normal index 0: OBJ indices count from 1 (back from the last when negative)",
            ),
            (
                "f 0 2 3",
                "corner 1 of the face: vertex index 0: OBJ indices count from 1 (back from the last when negative)",
            ),
            (
                "f 1/-3 2/-1 3/-2",
                "corner 1 of the face: texture coordinate index -3 counts back past the first of the 2 texture coordinates (vt) before this line",
            ),
            (
                "f 1//-1 2//-2 3//-1",
                "corner 2 of the face: normal index -2 counts back past the first of the 1 normal (vn) before this line",
            ),
            (
                "f -1 -2 -4",
                "corner 3 of the face: vertex index -4 counts back past the first of the 3 vertices (v) before this line",
            ),
            ("f 1 /1 3", "corner 2 of the face: no vertex index"),
        ] {
            let e = faces_of(&format!("{head}{face}\n")).unwrap_err();
            let want = format!("/x.obj:7: not a valid OBJ file: {why}");
            assert!(e.ends_with(&want), "{face}: {e:?} is not {want:?}");
        }
        // No texture coordinate or normal at all: an index to one is out of range.
        let e = faces_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n").unwrap_err();
        assert!(
            e.contains("x.obj:4: not a valid OBJ file: corner 1 of the face: texture coordinate index 1 is beyond the 0 texture coordinates (vt) before this line"),
            "{e}"
        );
        let e = faces_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\nvn 0 0 1\n").unwrap_err();
        assert!(e.contains("x.obj:4: not a valid OBJ file: corner 1 of the face: normal index 1 is beyond the 0 normals (vn) before this line"), "{e}");
        // Valid references, absolute and relative, in every form: the faces of
        // the same file without them.
        let plain =
            faces_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
                .unwrap();
        let referenced = faces_of(&format!(
            "{head}v 0 0 1\nvn 1 1 1\nf 1/1 2/2 3/1\nf 1//1 2//2 4//1\nf 1/1/2 3/2/1 4/-1/-2\nf -3/-2/-1 -2/-1/-1 -1/1/2\n"
        ))
        .unwrap();
        assert_eq!(referenced, plain);
        assert_eq!(plain.0.len(), 4);
    }
}
