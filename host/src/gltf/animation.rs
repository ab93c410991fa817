//! Animations: the channels of the file's first animation that move a node's
//! translation, rotation or scale, read as keyframe tracks of the animated
//! nodes (the anchors of [`super::scene::visit`]) in world space: each
//! keyframe composed with the node's parent's world matrix, a similarity.

use super::primitive::{self, Use};
use super::scene::{self, Mat4, Visit};
use super::{AnimatedNode, Cx, ImportedAnimation, ImportedMesh, ImportedTrack, named};
use crate::mesh::{quaternion_product, unit_quaternion};
use gltf::json;
use json::validation::Checked;
use std::borrow::Cow;
use tessera_core::animation::{Channel, Interpolation};

/// The resolved buffers, by the file's buffer index (`None`: not needed).
type Buffers<'b> = [Option<Cow<'b, [u8]>>];

/// How far a parent's matrix may be from a similarity: the columns'
/// products against their mean squared length, relatively.
const SIMILARITY_TOLERANCE: f64 = 1e-6;

/// The TRS channels of the animation read, by the node they move.
pub(super) struct Targets {
    /// The animation read (its index), or `None`.
    pub index: Option<usize>,
    /// Its name for messages: `animation 'Walk'`, `animation 0`.
    pub name: String,
    /// Each node a TRS channel moves, with those channels (index in the
    /// animation, what it moves), in the order of their first channel.
    pub nodes: Vec<(usize, Vec<(usize, Channel)>)>,
}

impl Targets {
    /// The nodes moved.
    pub fn animated(&self) -> Vec<usize> {
        self.nodes.iter().map(|(n, _)| *n).collect()
    }
}

/// The channels of the file's first animation that move a node's
/// translation, rotation or scale, when `read` (a whole scene); without
/// `read` (a mesh file's triangles), every animation is left out with a
/// warning. The other animations are named in a warning; `weights` channels
/// (morph targets) are warned about. A channel naming a sampler or a node
/// the file lacks, and two channels moving the same property of a node, are
/// errors naming the animation and the channel.
pub(super) fn targets(root: &json::Root, read: bool, cx: &mut Cx) -> Result<Targets, String> {
    let mut out = Targets {
        index: None,
        name: String::new(),
        nodes: Vec::new(),
    };
    let all = &root.animations;
    let Some(first) = all.first() else {
        return Ok(out);
    };
    let name_of = |i: usize, a: &json::Animation| named("animation", i, a.name.as_deref());
    if !read {
        cx.warn(format!(
            "animations are not read for a [[mesh]] file: {} animation{} ignored, the \
             triangles are as the file poses them (`tessera render` of the glTF file \
             itself plays its first animation)",
            all.len(),
            if all.len() == 1 { "" } else { "s" }
        ));
        return Ok(out);
    }
    let anim = name_of(0, first);
    if all.len() > 1 {
        let others: Vec<String> = all
            .iter()
            .enumerate()
            .skip(1)
            .map(|(i, a)| name_of(i, a))
            .collect();
        cx.warn(format!(
            "only the first animation, {anim}, is read: {} ignored",
            others.join(", ")
        ));
    }
    for (c, channel) in first.channels.iter().enumerate() {
        let at = format!("{anim}, channel {c}");
        let s = channel.sampler.value();
        if s >= first.samplers.len() {
            return Err(cx.err(format!(
                "{at}: sampler {s} does not exist (the animation has {})",
                first.samplers.len()
            )));
        }
        let n = channel.target.node.value();
        let Some(node) = root.nodes.get(n) else {
            return Err(cx.err(format!("{at}: node {n} does not exist")));
        };
        let node_name = named("node", n, node.name.as_deref());
        let path = match channel.target.path {
            Checked::Valid(json::animation::Property::Translation) => Channel::Translation,
            Checked::Valid(json::animation::Property::Rotation) => Channel::Rotation,
            Checked::Valid(json::animation::Property::Scale) => Channel::Scale,
            Checked::Valid(json::animation::Property::MorphTargetWeights) => {
                cx.warn(format!(
                    "{at}: the morph target weights of {node_name} are not animated (morph \
                     targets are not read): its base shape stays still"
                ));
                continue;
            }
            Checked::Invalid => {
                return Err(cx.err(format!("{at}: a target path glTF does not define")));
            }
        };
        let slot = match out.nodes.iter().position(|(m, _)| *m == n) {
            Some(k) => k,
            None => {
                out.nodes.push((n, Vec::new()));
                out.nodes.len() - 1
            }
        };
        let list = &mut out.nodes[slot].1;
        if let Some((other, _)) = list.iter().find(|(_, p)| *p == path) {
            return Err(cx.err(format!(
                "{at}: channel {other} moves the {} of {node_name} already (glTF allows one \
                 channel a target)",
                path_name(path)
            )));
        }
        list.push((c, path));
    }
    out.index = Some(0);
    out.name = anim;
    Ok(out)
}

/// glTF's name of a channel's path.
fn path_name(path: Channel) -> &'static str {
    match path {
        Channel::Translation => "translation",
        Channel::Rotation => "rotation",
        Channel::Scale => "scale",
    }
}

/// The buffers the channels of the anchors read (their samplers' input and
/// output accessors, sparse parts included).
pub(super) fn needed_buffers(root: &json::Root, targets: &Targets, visit: &Visit) -> Vec<usize> {
    let mut out = Vec::new();
    let Some(anim) = targets.index.and_then(|i| root.animations.get(i)) else {
        return out;
    };
    let view_buffer = |v: json::Index<json::buffer::View>| {
        root.buffer_views.get(v.value()).map(|v| v.buffer.value())
    };
    for anchor in &visit.anchors {
        let Some((_, channels)) = targets.nodes.iter().find(|(n, _)| *n == anchor.node) else {
            continue;
        };
        for &(c, _) in channels {
            let Some(sampler) = anim
                .channels
                .get(c)
                .and_then(|ch| anim.samplers.get(ch.sampler.value()))
            else {
                continue;
            };
            for a in [sampler.input, sampler.output]
                .into_iter()
                .filter_map(|a| root.accessors.get(a.value()))
            {
                out.extend(a.buffer_view.and_then(view_buffer));
                if let Some(s) = &a.sparse {
                    out.extend(view_buffer(s.indices.buffer_view));
                    out.extend(view_buffer(s.values.buffer_view));
                }
            }
        }
    }
    out
}

/// The similarity `m`'s upper 3×3 is, as its scale (negative for a mirror:
/// a point reflection times a rotation) and its rotation (a unit quaternion
/// `x, y, z, w`), or `None` when it shears, scales unevenly, is singular or
/// not finite (checked in `f64`, within [`SIMILARITY_TOLERANCE`]).
pub(super) fn similarity(m: &Mat4) -> Option<(f64, [f64; 4])> {
    let col = |c: usize| [m[c][0], m[c][1], m[c][2]];
    let cols = [col(0), col(1), col(2)];
    if cols.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let s2 = cols.iter().map(|&c| dot(c, c)).sum::<f64>() / 3.0;
    if !(s2 > 0.0 && s2.is_finite()) {
        return None;
    }
    for i in 0..3 {
        for j in 0..3 {
            let want = if i == j { s2 } else { 0.0 };
            if (dot(cols[i], cols[j]) - want).abs() > SIMILARITY_TOLERANCE * s2 {
                return None;
            }
        }
    }
    let det = dot(cols[0], crate::arr3::cross(cols[1], cols[2]));
    let s = s2.sqrt() * det.signum();
    // The rotation's rows: r[row][col].
    let r: [[f64; 3]; 3] = std::array::from_fn(|row| std::array::from_fn(|c| cols[c][row] / s));
    Some((s, quaternion_of(&r)))
}

/// The unit quaternion `x, y, z, w` of the rotation matrix `r` (rows).
fn quaternion_of(r: &[[f64; 3]; 3]) -> [f64; 4] {
    let trace = r[0][0] + r[1][1] + r[2][2];
    let q = if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        [
            (r[2][1] - r[1][2]) / s,
            (r[0][2] - r[2][0]) / s,
            (r[1][0] - r[0][1]) / s,
            s / 4.0,
        ]
    } else if r[0][0] > r[1][1] && r[0][0] > r[2][2] {
        let s = (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt() * 2.0;
        [
            s / 4.0,
            (r[0][1] + r[1][0]) / s,
            (r[0][2] + r[2][0]) / s,
            (r[2][1] - r[1][2]) / s,
        ]
    } else if r[1][1] > r[2][2] {
        let s = (1.0 + r[1][1] - r[0][0] - r[2][2]).sqrt() * 2.0;
        [
            (r[0][1] + r[1][0]) / s,
            s / 4.0,
            (r[1][2] + r[2][1]) / s,
            (r[0][2] - r[2][0]) / s,
        ]
    } else {
        let s = (1.0 + r[2][2] - r[0][0] - r[1][1]).sqrt() * 2.0;
        [
            (r[0][2] + r[2][0]) / s,
            (r[1][2] + r[2][1]) / s,
            s / 4.0,
            (r[1][0] - r[0][1]) / s,
        ]
    };
    unit_quaternion(q).unwrap_or([0.0, 0.0, 0.0, 1.0])
}

/// How a parent's similarity moves an anchor's channels into world space.
#[derive(Clone, Copy)]
struct Compose {
    parent: Mat4,
    scale: f64,
    rotation: [f64; 4],
}

impl Compose {
    /// A value of channel `path` (the node's own) in world space.
    fn apply(&self, path: Channel, v: [f64; 4]) -> [f64; 4] {
        match path {
            Channel::Translation => {
                let [x, y, z] = scene::point(&self.parent, [v[0], v[1], v[2]]);
                [x, y, z, 0.0]
            }
            Channel::Rotation => quaternion_product(self.rotation, v),
            Channel::Scale => [v[0] * self.scale, v[1] * self.scale, v[2] * self.scale, 0.0],
        }
    }
}

/// The animation read: for each anchor that draws a mesh (itself or a node
/// below it, `meshes`), its rest placement and the tracks of its channels,
/// in world space. An anchor that draws nothing is warned about (left
/// still). Every accessor is checked before it is read; bad keyframes are
/// errors naming the animation, the channel and the sampler.
pub(super) fn read(
    document: &gltf::Document,
    targets: &Targets,
    visit: &Visit,
    meshes: &[ImportedMesh],
    buffers: &Buffers,
    cx: &mut Cx,
) -> Result<Option<ImportedAnimation>, String> {
    let root = document.as_json();
    let Some(index) = targets.index else {
        return Ok(None);
    };
    let Some(anim) = root.animations.get(index) else {
        return Ok(None);
    };
    let mut nodes = Vec::new();
    let mut keyframes: usize = 0;
    // Nodes moved but not anchors were warned about by the visit; those
    // not in the scene are said here.
    for &(n, _) in &targets.nodes {
        if !visit.placed.iter().any(|p| p.node == n) {
            let name = named("node", n, root.nodes.get(n).and_then(|o| o.name.as_deref()));
            cx.warn(format!(
                "{}: moves {name}, which is not in the scene: ignored",
                targets.name
            ));
        }
    }
    for anchor in &visit.anchors {
        let node = &root.nodes[anchor.node];
        let node_name = named("node", anchor.node, node.name.as_deref());
        let draws = meshes
            .iter()
            .any(|m| m.anchor == Some(anchor.node) && !m.triangles.is_empty());
        if !draws {
            cx.warn(format!(
                "{}: moves {node_name}, which draws no mesh (itself or below it: a camera, a \
                 light, a joint or an empty node): it is left still",
                targets.name
            ));
            continue;
        }
        let Some(channels) = targets
            .nodes
            .iter()
            .find(|(n, _)| *n == anchor.node)
            .map(|(_, c)| c)
        else {
            continue;
        };
        let Some((scale, rotation)) = similarity(&anchor.parent) else {
            // The visit made it an anchor only for a similarity.
            continue;
        };
        let compose = Compose {
            parent: anchor.parent,
            scale,
            rotation,
        };
        let mut tracks = Vec::new();
        for &(c, path) in channels {
            let track = channel(document, anim, targets, c, path, buffers, cx)?;
            keyframes = keyframes.saturating_add(track.times.len());
            let limit = cx.limits.max_keyframes;
            if keyframes > limit {
                return Err(cx.err(format!(
                    "{}: more than the limit of {limit} keyframes (every channel read counted)",
                    targets.name
                )));
            }
            let values = track
                .values
                .iter()
                .enumerate()
                .map(|(k, &v)| {
                    let w = compose.apply(path, v);
                    if w.iter().all(|x| x.is_finite()) {
                        Ok(w)
                    } else {
                        Err(cx.err(format!(
                            "{}, channel {c}: keyframe {k} moved by the parent of {node_name} \
                             lies past the range of f64",
                            targets.name
                        )))
                    }
                })
                .collect::<Result<Vec<_>, String>>()?;
            tracks.push(ImportedTrack { values, ..track });
        }
        let (translation, rotation, scale) = rest(node, &compose);
        // As a still node's meshes are named: its name, else its mesh's.
        let name = node
            .name
            .clone()
            .or_else(|| {
                let m = node.mesh.map(|m| m.value())?;
                root.meshes.get(m)?.name.clone()
            })
            .unwrap_or_else(|| format!("node {}", anchor.node));
        nodes.push(AnimatedNode {
            node: anchor.node,
            name,
            translation,
            rotation,
            scale,
            world: anchor.world,
            tracks,
        });
    }
    if nodes.is_empty() {
        return Ok(None);
    }
    Ok(Some(ImportedAnimation {
        name: anim.name.clone().unwrap_or_default(),
        index,
        nodes,
    }))
}

/// The node's rest translation, rotation and scale (its own, glTF's
/// defaults where it gives none) composed with its parent.
fn rest(node: &json::Node, compose: &Compose) -> ([f64; 3], [f64; 4], [f64; 3]) {
    let t = node.translation.unwrap_or([0.0; 3]).map(f64::from);
    let q = node
        .rotation
        .map_or([0.0, 0.0, 0.0, 1.0], |q| q.0)
        .map(f64::from);
    let q = unit_quaternion(q).unwrap_or([0.0, 0.0, 0.0, 1.0]);
    let s = node.scale.unwrap_or([1.0; 3]).map(f64::from);
    let [tx, ty, tz, _] = compose.apply(Channel::Translation, [t[0], t[1], t[2], 0.0]);
    let r = compose.apply(Channel::Rotation, q);
    let [sx, sy, sz, _] = compose.apply(Channel::Scale, [s[0], s[1], s[2], 0.0]);
    ([tx, ty, tz], r, [sx, sy, sz])
}

/// Channel `c` of `anim` (moving `path`), its sampler's accessors checked
/// and read: times in seconds, values as the node's own (a rotation made
/// unit length). CUBICSPLINE is read as linear through the keyframes' values,
/// with a warning.
fn channel(
    document: &gltf::Document,
    anim: &json::Animation,
    targets: &Targets,
    c: usize,
    path: Channel,
    buffers: &Buffers,
    cx: &mut Cx,
) -> Result<ImportedTrack, String> {
    let max_bytes = cx.limits.max_buffer_bytes;
    let Some(ch) = anim.channels.get(c) else {
        return Err(cx.err(format!("{}: channel {c} does not exist", targets.name)));
    };
    let s = ch.sampler.value();
    let at = format!(
        "{}, channel {c} ({}), sampler {s}",
        targets.name,
        path_name(path)
    );
    let Some(sampler) = anim.samplers.get(s) else {
        return Err(cx.err(format!("{at}: the sampler does not exist")));
    };
    let (interpolation, cubic) = match sampler.interpolation {
        Checked::Valid(json::animation::Interpolation::Linear) => (Interpolation::Linear, false),
        Checked::Valid(json::animation::Interpolation::Step) => (Interpolation::Step, false),
        Checked::Valid(json::animation::Interpolation::CubicSpline) => {
            cx.warn(format!(
                "{}, channel {c} ({}): CUBICSPLINE interpolation is read as LINEAR through \
                 the keyframes' values (their tangents dropped)",
                targets.name,
                path_name(path)
            ));
            (Interpolation::Linear, true)
        }
        Checked::Invalid => {
            return Err(cx.err(format!("{at}: an interpolation glTF does not define")));
        }
    };
    let accessor = |i: usize, what: &str| {
        document
            .accessors()
            .nth(i)
            .ok_or_else(|| cx.err(format!("{at}: {what}: accessor {i} does not exist")))
    };
    let input = accessor(sampler.input.value(), "input")?;
    let output = accessor(sampler.output.value(), "output")?;
    let usage = match path {
        Channel::Rotation => Use::Rotations,
        _ => Use::Vectors,
    };
    for (a, u) in [(&input, Use::Times), (&output, usage)] {
        primitive::check(a, u, buffers, max_bytes).map_err(|e| {
            cx.err(format!(
                "{at}: {}: accessor {}: {e}",
                if u == Use::Times { "input" } else { "output" },
                a.index()
            ))
        })?;
    }
    let n = input.count();
    let per = if cubic { 3 } else { 1 };
    if n.checked_mul(per) != Some(output.count()) {
        return Err(cx.err(format!(
            "{at}: {n} times (input accessor {}) and {} values (output accessor {}): {} \
             needs {}",
            input.index(),
            output.count(),
            output.index(),
            if cubic {
                "CUBICSPLINE (an in-tangent, a value and an out-tangent a time)"
            } else {
                "one value a time"
            },
            n.saturating_mul(per)
        )));
    }
    let limit = cx.limits.max_keyframes;
    if n > limit {
        return Err(cx.err(format!(
            "{at}: {n} keyframes, more than the limit of {limit}"
        )));
    }
    let data = |b: gltf::Buffer<'_>| buffers.get(b.index()).and_then(|d| d.as_deref());
    let unreadable = |what: &str| cx.err(format!("{at}: {what}: its data could not be read"));
    let times: Vec<f64> = gltf::accessor::Iter::<f32>::new(input.clone(), data)
        .ok_or_else(|| unreadable("input"))?
        .map(f64::from)
        .collect();
    let mut last = f64::NEG_INFINITY;
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            return Err(cx.err(format!("{at}: input: time {k} is not finite")));
        }
        if t < 0.0 {
            return Err(cx.err(format!(
                "{at}: input: time {k} is {}: tessera's animations start at 0 s",
                crate::desc::num(t)
            )));
        }
        if t <= last {
            return Err(cx.err(format!(
                "{at}: input: the times are not strictly increasing: time {k} is {} after {}",
                crate::desc::num(t),
                crate::desc::num(last)
            )));
        }
        last = t;
    }
    if times.len() != n {
        return Err(unreadable("input"));
    }
    let all: Vec<[f64; 4]> = match path {
        Channel::Rotation => rotations(&output, data).ok_or_else(|| unreadable("output"))?,
        _ => gltf::accessor::Iter::<[f32; 3]>::new(output.clone(), data)
            .ok_or_else(|| unreadable("output"))?
            .map(|[x, y, z]| [f64::from(x), f64::from(y), f64::from(z), 0.0])
            .collect(),
    };
    if all.len() != n * per {
        return Err(unreadable("output"));
    }
    let mut values = Vec::with_capacity(n);
    for (k, v) in all.into_iter().skip(per / 2).step_by(per).enumerate() {
        if !v.iter().all(|x| x.is_finite()) {
            return Err(cx.err(format!("{at}: output: value {k} is not finite")));
        }
        let v = match path {
            Channel::Rotation => unit_quaternion(v).ok_or_else(|| {
                cx.err(format!(
                    "{at}: output: value {k} is a quaternion of length 0 (no rotation)"
                ))
            })?,
            _ => v,
        };
        values.push(v);
    }
    Ok(ImportedTrack {
        channel: c,
        path,
        interpolation,
        times,
        values,
    })
}

/// The rotations of `output` as `f32` quaternions (normalized integers
/// turned into `[-1, 1]` as glTF says), in `f64`.
fn rotations<'s>(
    output: &gltf::Accessor<'_>,
    data: impl Clone + Fn(gltf::Buffer<'_>) -> Option<&'s [u8]>,
) -> Option<Vec<[f64; 4]>> {
    use gltf::accessor::{DataType, Iter};
    Some(match output.data_type() {
        DataType::F32 => Iter::<[f32; 4]>::new(output.clone(), data)?
            .map(|q| q.map(f64::from))
            .collect(),
        DataType::I8 => Iter::<[i8; 4]>::new(output.clone(), data)?
            .map(|q| q.map(|c| (f64::from(c) / 127.0).max(-1.0)))
            .collect(),
        DataType::U8 => Iter::<[u8; 4]>::new(output.clone(), data)?
            .map(|q| q.map(|c| f64::from(c) / 255.0))
            .collect(),
        DataType::I16 => Iter::<[i16; 4]>::new(output.clone(), data)?
            .map(|q| q.map(|c| (f64::from(c) / 32767.0).max(-1.0)))
            .collect(),
        DataType::U16 => Iter::<[u16; 4]>::new(output.clone(), data)?
            .map(|q| q.map(|c| f64::from(c) / 65535.0))
            .collect(),
        DataType::U32 => return None,
    })
}
