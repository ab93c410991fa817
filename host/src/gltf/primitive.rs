//! The meshes: the primitives to read, counted before anything is read; their
//! accessors checked, then read through `gltf`'s reader; their triangles put in
//! world space for every node that instances them.

use super::scene::{self, Placed};
use super::{Cx, ImportedMesh, named};
use gltf::accessor::{DataType, Dimensions};
use gltf::json;
use gltf::mesh::Mode;
use json::validation::Checked;
use std::borrow::Cow;
use std::collections::HashMap;

/// The resolved buffers, by the file's buffer index (`None`: not needed).
type Buffers<'b> = [Option<Cow<'b, [u8]>>];

/// What will be read: the distinct triangle primitives the scene instances, the
/// materials they use.
pub(super) struct Plan {
    /// (mesh, primitive) of each distinct primitive, in order of first use.
    prims: Vec<(usize, usize)>,
    /// Where each (mesh, primitive) is in `prims`.
    slot: HashMap<(usize, usize), usize>,
    /// The file's material indices the primitives use, in order of first use.
    pub materials: Vec<usize>,
    /// Where each material index is in `materials`.
    material_slot: HashMap<usize, usize>,
    /// The primitives read so far, by slot.
    read: Vec<Option<Local>>,
}

/// The triangles of `mesh`'s triangle primitives instanced by the visited
/// nodes, counted from the accessors' counts and bounded by the limit; points
/// and lines are warned about, and so are morph targets.
pub(super) fn plan(
    document: &gltf::Document,
    visit: &[Placed],
    cx: &mut Cx,
) -> Result<Plan, String> {
    let root = document.as_json();
    let mut plan = Plan {
        prims: Vec::new(),
        slot: HashMap::new(),
        materials: Vec::new(),
        material_slot: HashMap::new(),
        read: Vec::new(),
    };
    let mut total: usize = 0;
    for placed in visit.iter().filter(|p| p.drawn()) {
        let Some(m) = root.nodes[placed.node].mesh.map(|m| m.value()) else {
            continue;
        };
        let Some(mesh) = root.meshes.get(m) else {
            return Err(cx.err(format!("mesh {m} does not exist")));
        };
        let mesh_name = named("mesh", m, mesh.name.as_deref());
        let morphs = mesh.weights.is_some()
            || root.nodes[placed.node].weights.is_some()
            || mesh
                .primitives
                .iter()
                .any(|p| p.targets.as_ref().is_some_and(|t| !t.is_empty()));
        if morphs {
            cx.warn(format!(
                "{mesh_name}: morph targets ignored: the base shape is drawn"
            ));
        }
        for (j, prim) in mesh.primitives.iter().enumerate() {
            let at = format!("{mesh_name}, primitive {j}");
            let mode = match prim.mode {
                Checked::Valid(mode) => mode,
                Checked::Invalid => return Err(cx.err(format!("{at}: an unknown mode"))),
            };
            let n = prim
                .indices
                .or_else(|| position_of(prim))
                .and_then(|a| root.accessors.get(a.value()))
                .map_or(0, |a| a.count.0);
            let n = usize::try_from(n).unwrap_or(usize::MAX);
            let triangles = match mode {
                Mode::Triangles => Some(n / 3),
                Mode::TriangleStrip | Mode::TriangleFan => Some(n.saturating_sub(2)),
                _ => None,
            };
            // Each primitive instance counts at least 1, so that the work of a
            // file of many empty ones (or points, lines) is bounded too.
            total = total.saturating_add(triangles.unwrap_or(0).max(1));
            let limit = cx.limits.max_triangles;
            if total > limit {
                return Err(cx.err(format!(
                    "the scene's meshes have more than the limit of {limit} triangles (every instance of every primitive counted)"
                )));
            }
            if triangles.is_none() {
                cx.warn(format!(
                    "{at}: {} skipped: only triangles are drawn",
                    mode_name(mode)
                ));
                continue;
            }
            if !plan.slot.contains_key(&(m, j)) {
                plan.slot.insert((m, j), plan.prims.len());
                plan.prims.push((m, j));
                plan.read.push(None);
            }
            if let Some(mat) = prim.material.map(|i| i.value())
                && !plan.material_slot.contains_key(&mat)
            {
                plan.material_slot.insert(mat, plan.materials.len());
                plan.materials.push(mat);
            }
        }
    }
    Ok(plan)
}

/// The `POSITION` accessor of `prim`.
fn position_of(prim: &json::mesh::Primitive) -> Option<json::Index<json::Accessor>> {
    prim.attributes
        .get(&Checked::Valid(json::mesh::Semantic::Positions))
        .copied()
}

/// A mode as glTF names it.
fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "points (mode POINTS)",
        Mode::Lines => "lines (mode LINES)",
        Mode::LineLoop => "a line loop (mode LINE_LOOP)",
        Mode::LineStrip => "a line strip (mode LINE_STRIP)",
        Mode::Triangles => "triangles (mode TRIANGLES)",
        Mode::TriangleStrip => "a triangle strip (mode TRIANGLE_STRIP)",
        Mode::TriangleFan => "a triangle fan (mode TRIANGLE_FAN)",
    }
}

/// The buffers the planned primitives' accessors (`POSITION`, `NORMAL`,
/// `TEXCOORD_0`, indices, sparse parts included) and the images of `images`
/// (the file's image indices) use, ascending.
pub(super) fn needed_buffers(
    document: &gltf::Document,
    plan: &Plan,
    images: &[usize],
) -> Vec<usize> {
    let root = document.as_json();
    let view_buffer = |v: json::Index<json::buffer::View>| {
        root.buffer_views.get(v.value()).map(|v| v.buffer.value())
    };
    let mut out = Vec::new();
    for &(m, j) in &plan.prims {
        let Some(prim) = root.meshes.get(m).and_then(|m| m.primitives.get(j)) else {
            continue;
        };
        let read = [
            position_of(prim),
            attribute(prim, json::mesh::Semantic::Normals),
            attribute(prim, json::mesh::Semantic::TexCoords(0)),
            prim.indices,
        ];
        for a in read
            .into_iter()
            .flatten()
            .filter_map(|a| root.accessors.get(a.value()))
        {
            out.extend(a.buffer_view.and_then(view_buffer));
            if let Some(s) = &a.sparse {
                out.extend(view_buffer(s.indices.buffer_view));
                out.extend(view_buffer(s.values.buffer_view));
            }
        }
    }
    for &i in images {
        out.extend(
            root.images
                .get(i)
                .and_then(|im| im.buffer_view)
                .and_then(view_buffer),
        );
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// The accessor of `prim`'s attribute `semantic`.
fn attribute(
    prim: &json::mesh::Primitive,
    semantic: json::mesh::Semantic,
) -> Option<json::Index<json::Accessor>> {
    prim.attributes.get(&Checked::Valid(semantic)).copied()
}

/// A primitive read, in its mesh's space, compacted to the vertices its
/// triangles use.
#[derive(Clone)]
struct Local {
    positions: Vec<[f64; 3]>,
    normals: Option<Vec<[f64; 3]>>,
    uvs: Option<Vec<[f64; 2]>>,
    triangles: Vec<[u32; 3]>,
    material: Option<usize>,
}

/// The meshes of the scene: each planned primitive read once (checked), then
/// put in world space for each visited node that instances it.
pub(super) fn meshes(
    document: &gltf::Document,
    visit: &[Placed],
    plan: &mut Plan,
    buffers: &Buffers,
    cx: &mut Cx,
) -> Result<Vec<ImportedMesh>, String> {
    let root = document.as_json();
    let mut out = Vec::new();
    for placed in visit.iter().filter(|p| p.drawn()) {
        let node = &root.nodes[placed.node];
        let Some(m) = node.mesh.map(|m| m.value()) else {
            continue;
        };
        let Some(mesh) = document.meshes().nth(m) else {
            continue;
        };
        for prim in mesh.primitives() {
            let j = prim.index();
            let Some(&slot) = plan.slot.get(&(m, j)) else {
                continue;
            };
            if plan.read[slot].is_none() {
                let at = format!("{}, primitive {j}", named("mesh", m, mesh.name()));
                let mut local =
                    read(&prim, buffers, &at, cx).map_err(|e| cx.err(format!("{at}: {e}")))?;
                local.material = prim
                    .material()
                    .index()
                    .and_then(|i| plan.material_slot.get(&i).copied());
                plan.read[slot] = Some(local);
            }
            let Some(local) = &plan.read[slot] else {
                continue;
            };
            if local.triangles.is_empty() {
                continue;
            }
            let name = node
                .name
                .clone()
                .or_else(|| mesh.name().map(str::to_string))
                .unwrap_or_else(|| format!("node {}", placed.node));
            let placed_mesh = place(local, placed, name, m, j);
            if !placed_mesh
                .positions
                .iter()
                .flatten()
                .all(|x| x.is_finite())
            {
                return Err(cx.err(format!(
                    "{}: its world matrix moves {} past the range of f64",
                    named("node", placed.node, node.name.as_deref()),
                    named("mesh", m, mesh.name())
                )));
            }
            out.push(placed_mesh);
        }
    }
    Ok(out)
}

/// `local` in world space as `placed` puts it (or in its anchor's space, for a
/// node under an animated one): positions by the matrix,
/// normals by its inverse transpose (unit length), the winding reversed under
/// a mirror.
fn place(
    local: &Local,
    placed: &Placed,
    name: String,
    mesh: usize,
    primitive: usize,
) -> ImportedMesh {
    let w = &placed.draw;
    let positions = local
        .positions
        .iter()
        .map(|&p| scene::point(w, p))
        .collect();
    let n = scene::normal_matrix(w, placed.draw_det);
    let normals = local.normals.as_ref().map(|normals| {
        normals
            .iter()
            .map(|v| {
                let turned =
                    std::array::from_fn(|r| n[r][0] * v[0] + n[r][1] * v[1] + n[r][2] * v[2]);
                // A regular matrix keeps a non-zero normal non-zero.
                scene::unit(turned).unwrap_or(*v)
            })
            .collect()
    });
    let triangles = if placed.draw_det < 0.0 {
        local.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
    } else {
        local.triangles.clone()
    };
    ImportedMesh {
        name,
        node: placed.node,
        anchor: placed.anchor,
        mesh,
        primitive,
        positions,
        normals,
        uvs: local.uvs.clone(),
        triangles,
        material: local.material,
    }
}

/// What an accessor is read as.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Use {
    Position,
    Normal,
    TexCoord,
    Indices,
    /// An animation sampler's input: keyframe times.
    Times,
    /// An animation sampler's output for a translation or a scale.
    Vectors,
    /// An animation sampler's output for a rotation.
    Rotations,
}

impl Use {
    /// How glTF names it.
    fn name(self) -> &'static str {
        match self {
            Use::Position => "POSITION",
            Use::Normal => "NORMAL",
            Use::TexCoord => "TEXCOORD_0",
            Use::Indices => "indices",
            Use::Times => "input",
            Use::Vectors | Use::Rotations => "output",
        }
    }

    /// Whether glTF allows `data` × `dims` (normalized or not) for this use.
    fn allows(self, data: DataType, dims: Dimensions, normalized: bool) -> bool {
        match self {
            Use::Position | Use::Normal => {
                data == DataType::F32 && dims == Dimensions::Vec3 && !normalized
            }
            Use::TexCoord => {
                dims == Dimensions::Vec2
                    && match data {
                        DataType::F32 => !normalized,
                        DataType::U8 | DataType::U16 => normalized,
                        _ => false,
                    }
            }
            Use::Indices => {
                dims == Dimensions::Scalar
                    && matches!(data, DataType::U8 | DataType::U16 | DataType::U32)
            }
            Use::Times => data == DataType::F32 && dims == Dimensions::Scalar && !normalized,
            Use::Vectors => data == DataType::F32 && dims == Dimensions::Vec3 && !normalized,
            Use::Rotations => {
                dims == Dimensions::Vec4
                    && match data {
                        DataType::F32 => !normalized,
                        DataType::I8 | DataType::U8 | DataType::I16 | DataType::U16 => normalized,
                        DataType::U32 => false,
                    }
            }
        }
    }

    /// What glTF allows, for a message.
    fn allowed(self) -> &'static str {
        match self {
            Use::Position | Use::Normal => "VEC3 of FLOAT",
            Use::TexCoord => "VEC2 of FLOAT, or of normalized UNSIGNED_BYTE or UNSIGNED_SHORT",
            Use::Indices => "SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT",
            Use::Times => "SCALAR of FLOAT (keyframe times)",
            Use::Vectors => "VEC3 of FLOAT (a translation or scale)",
            Use::Rotations => {
                "VEC4 of FLOAT, or of normalized BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT (a rotation)"
            }
        }
    }
}

/// `accessor`, read as `usage`, checked: its type, its count (at least 1, at
/// most `max_bytes` of elements), and that every element it reads (sparse
/// parts too) lies within its buffer view, within its buffer. `gltf`'s reader
/// indexes no further than this.
pub(super) fn check(
    accessor: &gltf::Accessor,
    usage: Use,
    buffers: &Buffers,
    max_bytes: usize,
) -> Result<(), String> {
    let (data, dims) = (accessor.data_type(), accessor.dimensions());
    if !usage.allows(data, dims, accessor.normalized()) {
        return Err(format!(
            "{dims:?} of {data:?}{}, glTF allows {}",
            if accessor.normalized() {
                " (normalized)"
            } else {
                ""
            },
            usage.allowed()
        ));
    }
    let count = accessor.count();
    if count == 0 {
        return Err("a count of 0 (glTF needs at least 1)".to_string());
    }
    let elem = data.size() * dims.multiplicity();
    if count.checked_mul(elem).is_none_or(|n| n > max_bytes) {
        return Err(format!(
            "{count} elements of {elem} bytes, more than the limit of {max_bytes} buffer bytes"
        ));
    }
    if let Some(view) = accessor.view() {
        within(&view, accessor.offset(), count, elem, buffers)?;
    }
    if let Some(sparse) = accessor.sparse() {
        let n = sparse.count();
        if n == 0 || n > count {
            return Err(format!(
                "sparse: a count of {n}, glTF needs 1 to the accessor's {count}"
            ));
        }
        let indices = sparse.indices();
        within(
            &indices.view(),
            indices.offset(),
            n,
            indices.index_type().size(),
            buffers,
        )
        .map_err(|e| format!("sparse indices: {e}"))?;
        let values = sparse.values();
        within(&values.view(), values.offset(), n, elem, buffers)
            .map_err(|e| format!("sparse values: {e}"))?;
    }
    Ok(())
}

/// Checks that `count` elements of `elem` bytes from `offset` in `view` (at
/// its stride) lie within the view, and the view within its buffer's declared
/// length and data.
fn within(
    view: &gltf::buffer::View,
    offset: usize,
    count: usize,
    elem: usize,
    buffers: &Buffers,
) -> Result<(), String> {
    let v = view.index();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "buffer view {v}: a byteStride of {stride}, less than the element's {elem} bytes"
        ));
    }
    let end = stride
        .checked_mul(count - 1)
        .and_then(|n| n.checked_add(elem))
        .and_then(|n| n.checked_add(offset));
    if end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{count} elements of {elem} bytes every {stride} from byte {offset} lie past the end of buffer view {v} ({} bytes)",
            view.length()
        ));
    }
    let buffer = view.buffer();
    let b = buffer.index();
    let data = buffers
        .get(b)
        .and_then(|d| d.as_deref())
        .ok_or_else(|| format!("buffer view {v}: buffer {b} was not read"))?;
    let size = buffer.length().min(data.len());
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > size) {
        return Err(format!(
            "buffer view {v} (bytes {} + {}) lies past the end of buffer {b} ({size} bytes)",
            view.offset(),
            view.length()
        ));
    }
    Ok(())
}

/// `prim` read and checked (in its mesh's space), compacted to the vertices its
/// triangles use. `at` names it in warnings.
fn read(prim: &gltf::Primitive, buffers: &Buffers, at: &str, cx: &mut Cx) -> Result<Local, String> {
    let max_bytes = cx.limits.max_buffer_bytes;
    let accessor_of = |semantic: &gltf::Semantic| prim.get(semantic);
    let position = accessor_of(&gltf::Semantic::Positions).ok_or("no POSITION")?;
    let normal = accessor_of(&gltf::Semantic::Normals);
    let uv = accessor_of(&gltf::Semantic::TexCoords(0));
    let indices = prim.indices();
    let n = position.count();
    let parts = [
        (Some(&position), Use::Position),
        (normal.as_ref(), Use::Normal),
        (uv.as_ref(), Use::TexCoord),
        (indices.as_ref(), Use::Indices),
    ];
    for (accessor, usage) in parts {
        let Some(a) = accessor else { continue };
        let named = |e: String| format!("{}: accessor {}: {e}", usage.name(), a.index());
        check(a, usage, buffers, max_bytes).map_err(named)?;
        if usage != Use::Indices && a.count() != n {
            return Err(named(format!("{} elements, POSITION has {n}", a.count())));
        }
    }
    for (semantic, _) in prim.attributes() {
        if let gltf::Semantic::Colors(set) = semantic {
            cx.warn(format!("{at}: COLOR_{set} vertex colours ignored"));
        }
    }
    let reader = prim.reader(|b| buffers.get(b.index()).and_then(|d| d.as_deref()));
    let missing = |usage: Use| format!("{}: its data could not be read", usage.name());
    let positions = finite(
        reader
            .read_positions()
            .ok_or_else(|| missing(Use::Position))?,
        n,
        Use::Position,
    )?;
    let mut normals = match normal {
        Some(_) => Some(finite(
            reader.read_normals().ok_or_else(|| missing(Use::Normal))?,
            n,
            Use::Normal,
        )?),
        None => None,
    };
    let uvs = match uv {
        Some(_) => {
            let read = reader
                .read_tex_coords(0)
                .ok_or_else(|| missing(Use::TexCoord))?;
            Some(finite(read.into_f32(), n, Use::TexCoord)?)
        }
        None => None,
    };
    if let Some(k) = normals
        .as_ref()
        .and_then(|v| v.iter().position(|x| scene::unit(*x).is_none()))
    {
        cx.warn(format!(
            "{at}: NORMAL: vertex {k} has a zero normal: the primitive's normals are dropped"
        ));
        normals = None;
    }
    let order: Vec<u32> = match &indices {
        Some(_) => {
            let read = reader.read_indices().ok_or_else(|| missing(Use::Indices))?;
            let mut list = Vec::with_capacity(indices.as_ref().map_or(0, |a| a.count()));
            for (k, i) in read.into_u32().enumerate() {
                if i as usize >= n {
                    return Err(format!(
                        "indices: index {i} (at {k}) is past the {n} vertices"
                    ));
                }
                list.push(i);
            }
            list
        }
        None => {
            let n =
                u32::try_from(n).map_err(|_| format!("{n} vertices without indices: too many"))?;
            (0..n).collect()
        }
    };
    let triangles = triangulate(&order, prim.mode(), at, cx);
    Ok(compact(positions, normals, uvs, &triangles))
}

/// The `expect`ed `n` values of `values`, each checked finite, in `f64`.
fn finite<const N: usize>(
    values: impl Iterator<Item = [f32; N]>,
    n: usize,
    usage: Use,
) -> Result<Vec<[f64; N]>, String> {
    let mut out = Vec::with_capacity(n);
    for (k, v) in values.enumerate() {
        if !v.iter().all(|x| x.is_finite()) {
            return Err(format!(
                "{}: vertex {k} is not finite ([{}])",
                usage.name(),
                v.map(|x| crate::desc::num(f64::from(x))).join(", ")
            ));
        }
        out.push(v.map(f64::from));
    }
    if out.len() != n {
        return Err(format!(
            "{}: {} values read, {n} expected",
            usage.name(),
            out.len()
        ));
    }
    Ok(out)
}

/// The triangles `order` (vertex indices) makes in `mode`, those with a
/// repeated vertex left out (a strip's restarts).
fn triangulate(order: &[u32], mode: Mode, at: &str, cx: &mut Cx) -> Vec<[u32; 3]> {
    let v = order;
    let all: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => (0..v.len().saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [v[i], v[i + 1], v[i + 2]]
                } else {
                    [v[i], v[i + 2], v[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan => (0..v.len().saturating_sub(2))
            .map(|i| [v[i + 1], v[i + 2], v[0]])
            .collect(),
        _ => {
            let rest = v.len() % 3;
            if rest != 0 {
                cx.warn(format!(
                    "{at}: {} vertices for triangles, not a multiple of 3: the last {rest} are ignored",
                    v.len()
                ));
            }
            v.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
    };
    all.into_iter()
        .filter(|&[a, b, c]| a != b && b != c && a != c)
        .collect()
}

/// The vertices `triangles` use, in order of first use, and the triangles
/// renumbered to them.
fn compact(
    positions: Vec<[f64; 3]>,
    normals: Option<Vec<[f64; 3]>>,
    uvs: Option<Vec<[f64; 2]>>,
    triangles: &[[u32; 3]],
) -> Local {
    let mut new = vec![u32::MAX; positions.len()];
    let mut used: Vec<usize> = Vec::new();
    let triangles = triangles
        .iter()
        .map(|t| {
            t.map(|i| {
                let i = i as usize;
                if new[i] == u32::MAX {
                    // At most positions.len() <= u32::MAX + 1 distinct vertices.
                    new[i] = used.len() as u32;
                    used.push(i);
                }
                new[i]
            })
        })
        .collect();
    let pick3 = |v: &Vec<[f64; 3]>| used.iter().map(|&i| v[i]).collect::<Vec<_>>();
    Local {
        positions: pick3(&positions),
        normals: normals.as_ref().map(pick3),
        uvs: uvs.map(|v| used.iter().map(|&i| v[i]).collect()),
        triangles,
        material: None,
    }
}
