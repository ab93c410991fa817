//! The node tree: the scene's nodes visited with their world matrices (in `f64`,
//! column-major), the animated nodes whose meshes are drawn in their own space
//! (the anchors of [`super::animation`]), and the cameras and lights they
//! carry.

use super::{Cx, ImportedCamera, ImportedLight, ImportedLightKind, named};
use crate::arr3::dot;
use gltf::json;
use json::validation::Checked;

/// A 4×4 matrix, column-major as glTF stores it: `m[column][row]`.
pub(super) type Mat4 = [[f64; 4]; 4];

/// The identity.
pub(super) const IDENTITY: Mat4 = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// A node of the scene, reached once, and where it is.
#[derive(Clone, Copy, Debug)]
pub(super) struct Placed {
    /// The node's index.
    pub node: usize,
    /// Its world matrix (its ancestors' matrices times its own).
    pub world: Mat4,
    /// The determinant of the world matrix's upper 3×3 (negative: a mirror;
    /// zero or not finite: singular, nothing on the node is drawn).
    pub det: f64,
    /// The animated node (an anchor, this node or an ancestor) whose own space
    /// its meshes are drawn in, or `None`: drawn in world space.
    pub anchor: Option<usize>,
    /// The matrix its meshes are drawn with: `world`, or for a node under an
    /// anchor its matrix relative to the anchor (the identity for the anchor).
    pub draw: Mat4,
    /// The determinant of `draw`'s upper 3×3.
    pub draw_det: f64,
}

impl Placed {
    /// Whether the world matrix can be inverted (a zero scale cannot): its
    /// camera and light are placed.
    pub fn regular(&self) -> bool {
        self.det != 0.0 && self.det.is_finite()
    }

    /// Whether the matrix its meshes are drawn with can be inverted: its
    /// mesh is drawn.
    pub fn drawn(&self) -> bool {
        self.draw_det != 0.0 && self.draw_det.is_finite()
    }
}

/// An animated node whose animation is read: its meshes and its descendants'
/// are drawn in its own space, placed by an instance.
#[derive(Clone, Copy, Debug)]
pub(super) struct Anchor {
    /// The node's index.
    pub node: usize,
    /// Its parent's world matrix, a similarity (identity for a root).
    pub parent: Mat4,
    /// Its world matrix at rest (the parent's times its own TRS).
    pub world: Mat4,
}

/// The nodes of the visit and the anchors among them.
pub(super) struct Visit {
    /// Every node of the scene, depth first.
    pub placed: Vec<Placed>,
    /// The animated nodes whose animation is read, in the order visited.
    pub anchors: Vec<Anchor>,
}

/// The nodes of the scene (the default one, else scene 0, else the root
/// nodes), depth first, each with its world matrix. A node reached twice (a
/// cycle, a node with two parents) is an error; skins are warned about.
///
/// Each node of `animated` (a node the animation read moves, by index, with
/// the animation's name for messages) becomes an anchor, its meshes and its
/// descendants' drawn in its own space, unless (each with a warning naming the
/// node, and then drawn still, at its rest pose) it is given by a `matrix`, an
/// ancestor is an anchor already (the outermost animated node is kept), or its
/// parent's world matrix is not a similarity (a shear or an uneven scale,
/// which an instance's translation, rotation and per-axis scale cannot carry
/// once the node turns).
pub(super) fn visit(
    root: &json::Root,
    animated: &[usize],
    animation: &str,
    cx: &mut Cx,
) -> Result<Visit, String> {
    let roots: Vec<usize> = match root
        .scene
        .or_else(|| (!root.scenes.is_empty()).then(|| json::Index::new(0)))
    {
        Some(s) => {
            let Some(scene) = root.scenes.get(s.value()) else {
                return Err(cx.err(format!("scene {} does not exist", s.value())));
            };
            scene.nodes.iter().map(|n| n.value()).collect()
        }
        None => {
            let mut child = vec![false; root.nodes.len()];
            for node in &root.nodes {
                for c in node.children.iter().flatten() {
                    if let Some(flag) = child.get_mut(c.value()) {
                        *flag = true;
                    }
                }
            }
            (0..root.nodes.len()).filter(|&n| !child[n]).collect()
        }
    };
    let mut seen = vec![false; root.nodes.len()];
    let mut out = Vec::new();
    let mut anchors: Vec<Anchor> = Vec::new();
    // (node, parent's world matrix, the parent's anchor and its matrix
    // relative to it), the next one on top.
    type Entry = (usize, Mat4, Option<(usize, Mat4)>);
    let mut stack: Vec<Entry> = roots.iter().rev().map(|&n| (n, IDENTITY, None)).collect();
    while let Some((n, parent, within)) = stack.pop() {
        let Some(node) = root.nodes.get(n) else {
            return Err(cx.err(format!("node {n} does not exist")));
        };
        let at = named("node", n, node.name.as_deref());
        if std::mem::replace(&mut seen[n], true) {
            return Err(cx.err(format!(
                "{at}: reached twice by the scene's hierarchy (a cycle, or a node with two parents): glTF nodes form trees"
            )));
        }
        let own = local(node).map_err(|e| cx.err(format!("{at}: {e}")))?;
        let world = mul(&parent, &own);
        let det = det3(&world);
        if node.skin.is_some() {
            cx.warn(format!(
                "{at}: skin ignored: the mesh is drawn as stored (its bind pose), not deformed by its joints"
            ));
        }
        let mut within = within.map(|(a, m)| (a, mul(&m, &own)));
        if animated.contains(&n) {
            let refused = if node.matrix.is_some() {
                Some("it is given by a matrix, which glTF forbids on an animated node".to_string())
            } else if let Some((a, _)) = within {
                Some(format!(
                    "{} above it is animated too: only the outermost animated node's \
                     animation is read, this one stays at its rest pose within it",
                    named("node", a, root.nodes.get(a).and_then(|o| o.name.as_deref()))
                ))
            } else if super::animation::similarity(&parent).is_none() {
                Some(
                    "its parent's world matrix shears or scales unevenly, which an \
                     instance (translation, rotation, per-axis scale) cannot carry as \
                     it turns"
                        .to_string(),
                )
            } else {
                None
            };
            match refused {
                Some(why) => cx.warn(format!(
                    "{at}: its animation ({animation}) is not read: {why}; it is drawn still, at its rest pose"
                )),
                None => {
                    anchors.push(Anchor {
                        node: n,
                        parent,
                        world,
                    });
                    within = Some((n, IDENTITY));
                }
            }
        }
        let (anchor, draw) = match within {
            Some((a, m)) => (Some(a), m),
            None => (None, world),
        };
        let draw_det = det3(&draw);
        let singular = |d: f64| !(d != 0.0 && d.is_finite());
        let camera_or_light = node.camera.is_some() || light_of(node).is_some();
        if (node.mesh.is_some() && singular(draw_det)) || (camera_or_light && singular(det)) {
            cx.warn(format!(
                "{at}: its world matrix cannot be inverted (a zero scale, or one past the range of f64): its mesh, camera or light is skipped"
            ));
        }
        out.push(Placed {
            node: n,
            world,
            det,
            anchor,
            draw,
            draw_det,
        });
        for c in node.children.iter().flatten().rev() {
            stack.push((c.value(), world, within));
        }
    }
    Ok(Visit {
        placed: out,
        anchors,
    })
}

/// The node's own matrix: its `matrix`, else translation × rotation × scale.
fn local(node: &json::Node) -> Result<Mat4, String> {
    let m = if let Some(m) = node.matrix {
        let m = m.map(f64::from);
        let cols: Mat4 = std::array::from_fn(|c| std::array::from_fn(|r| m[4 * c + r]));
        if cols.iter().flatten().any(|x| !x.is_finite()) {
            return Err("its matrix has a value too large for f32 (infinite)".to_string());
        }
        if [cols[0][3], cols[1][3], cols[2][3], cols[3][3]] != [0.0, 0.0, 0.0, 1.0] {
            return Err(format!(
                "its matrix is not affine: its last row is [{}], glTF needs [0, 0, 0, 1]",
                [cols[0][3], cols[1][3], cols[2][3], cols[3][3]]
                    .map(crate::desc::num)
                    .join(", ")
            ));
        }
        cols
    } else {
        let t = node.translation.unwrap_or([0.0; 3]).map(f64::from);
        let s = node.scale.unwrap_or([1.0; 3]).map(f64::from);
        let q = node
            .rotation
            .map_or([0.0, 0.0, 0.0, 1.0], |q| q.0)
            .map(f64::from);
        if t.iter().chain(&s).chain(&q).any(|x| !x.is_finite()) {
            return Err(
                "its translation, rotation or scale has a value too large for f32 (infinite)"
                    .to_string(),
            );
        }
        let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        if len == 0.0 {
            return Err("its rotation is the zero quaternion".to_string());
        }
        // Rows of the rotation matrix (times the scale of each column below).
        let r = crate::mesh::quaternion_matrix(q.map(|v| v / len));
        let mut m = IDENTITY;
        for c in 0..3 {
            for row in 0..3 {
                m[c][row] = r[row][c] * s[c];
            }
        }
        m[3] = [t[0], t[1], t[2], 1.0];
        m
    };
    Ok(m)
}

/// `a × b`.
pub(super) fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    std::array::from_fn(|c| std::array::from_fn(|r| (0..4).map(|k| a[k][r] * b[c][k]).sum()))
}

/// The determinant of `m`'s upper 3×3.
fn det3(m: &Mat4) -> f64 {
    let a = |r: usize, c: usize| m[c][r];
    a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1))
        - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0))
        + a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0))
}

/// The point `p` moved by `m`.
pub(super) fn point(m: &Mat4, p: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r])
}

/// The direction `v` turned by `m` (no translation).
pub(super) fn direction(m: &Mat4, v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[0][r] * v[0] + m[1][r] * v[1] + m[2][r] * v[2])
}

/// The matrix that carries normals: the inverse transpose of `m`'s upper 3×3
/// (its cofactor matrix, divided by the determinant `det`), row-major.
pub(super) fn normal_matrix(m: &Mat4, det: f64) -> [[f64; 3]; 3] {
    let a = |r: usize, c: usize| m[c % 3][r % 3];
    // The cofactor of (r, c) (cyclic indices give the signs).
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            (a(r + 1, c + 1) * a(r + 2, c + 2) - a(r + 1, c + 2) * a(r + 2, c + 1)) / det
        })
    })
}

/// `v / |v|`, or `None` for a zero or non-finite vector.
pub(super) fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let len = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    (len > 0.0 && len.is_finite()).then(|| v.map(|x| x / len))
}

/// The light a node carries (`KHR_lights_punctual`), by index.
fn light_of(node: &json::Node) -> Option<usize> {
    let ext = node.extensions.as_ref()?.khr_lights_punctual.as_ref()?;
    Some(ext.light.value())
}

/// The perspective cameras of the visited nodes, in world space; orthographic
/// ones are skipped with a warning.
pub(super) fn cameras(
    root: &json::Root,
    visit: &[Placed],
    cx: &mut Cx,
) -> Result<Vec<ImportedCamera>, String> {
    let mut out = Vec::new();
    for placed in visit.iter().filter(|p| p.regular()) {
        let node = &root.nodes[placed.node];
        let Some(c) = node.camera.map(|c| c.value()) else {
            continue;
        };
        let Some(camera) = root.cameras.get(c) else {
            return Err(cx.err(format!("camera {c} does not exist")));
        };
        let at = named("camera", c, camera.name.as_deref());
        let perspective = match camera.type_ {
            Checked::Valid(json::camera::Type::Perspective) => camera.perspective.as_ref(),
            _ => {
                cx.warn(format!(
                    "{at} (on {}): orthographic, skipped: only perspective cameras are read",
                    named("node", placed.node, node.name.as_deref())
                ));
                continue;
            }
        };
        let Some(p) = perspective else {
            return Err(cx.err(format!(
                "{at}: of type perspective, but has no perspective object"
            )));
        };
        let (yfov, znear) = (f64::from(p.yfov), f64::from(p.znear));
        let (aspect, zfar) = (p.aspect_ratio.map(f64::from), p.zfar.map(f64::from));
        let bad = if !(yfov > 0.0 && yfov < std::f64::consts::PI) {
            Some(format!(
                "yfov must be in (0, π) radians, got {}",
                crate::desc::num(yfov)
            ))
        } else if !(znear > 0.0 && znear.is_finite()) {
            Some(format!(
                "znear must be finite and > 0, got {}",
                crate::desc::num(znear)
            ))
        } else if let Some(f) = zfar.filter(|&f| !(f > znear && f.is_finite())) {
            Some(format!(
                "zfar must be finite and > znear, got {}",
                crate::desc::num(f)
            ))
        } else {
            aspect.filter(|&a| !(a > 0.0 && a.is_finite())).map(|a| {
                format!(
                    "aspectRatio must be finite and > 0, got {}",
                    crate::desc::num(a)
                )
            })
        };
        if let Some(why) = bad {
            return Err(cx.err(format!("{at}: {why}")));
        }
        let w = &placed.world;
        let (Some(forward), Some(up)) = (
            unit(direction(w, [0.0, 0.0, -1.0])),
            unit(direction(w, [0.0, 1.0, 0.0])),
        ) else {
            continue;
        };
        let along = dot(up, forward);
        let Some(up) = unit(std::array::from_fn(|i| up[i] - along * forward[i])) else {
            return Err(cx.err(format!(
                "{at}: its node's matrix turns +Y onto -Z: no up direction"
            )));
        };
        let name = camera
            .name
            .clone()
            .or_else(|| node.name.clone())
            .unwrap_or_else(|| format!("camera {c}"));
        let position = point(w, [0.0; 3]);
        if !position.iter().all(|x| x.is_finite()) {
            return Err(cx.err(format!(
                "{at}: its node's matrix moves it past the range of f64"
            )));
        }
        out.push(ImportedCamera {
            name,
            node: placed.node,
            position,
            forward,
            up,
            yfov_degrees: yfov.to_degrees(),
            aspect,
            znear,
            zfar,
        });
    }
    Ok(out)
}

/// The `KHR_lights_punctual` lights of the visited nodes, in world space; spot
/// lights become point lights, with a warning.
pub(super) fn lights(
    root: &json::Root,
    visit: &[Placed],
    cx: &mut Cx,
) -> Result<Vec<ImportedLight>, String> {
    use json::extensions::scene::khr_lights_punctual::Type;
    let mut out = Vec::new();
    let all = root
        .extensions
        .as_ref()
        .and_then(|e| e.khr_lights_punctual.as_ref())
        .map_or(&[][..], |l| &l.lights[..]);
    for placed in visit.iter().filter(|p| p.regular()) {
        let node = &root.nodes[placed.node];
        let Some(l) = light_of(node) else {
            continue;
        };
        let Some(light) = all.get(l) else {
            return Err(cx.err(format!(
                "{}: light {l} does not exist (the file has {})",
                named("node", placed.node, node.name.as_deref()),
                all.len()
            )));
        };
        let at = named("light", l, light.name.as_deref());
        let color = light.color.map(f64::from);
        let intensity = f64::from(light.intensity);
        let range = light.range.map(f64::from);
        if !color.iter().all(|c| *c >= 0.0 && c.is_finite()) {
            return Err(cx.err(format!("{at}: color must be finite and >= 0")));
        }
        if !(intensity >= 0.0 && intensity.is_finite()) {
            return Err(cx.err(format!(
                "{at}: intensity must be finite and >= 0, got {}",
                crate::desc::num(intensity)
            )));
        }
        if let Some(r) = range.filter(|&r| !(r > 0.0 && r.is_finite())) {
            return Err(cx.err(format!(
                "{at}: range must be finite and > 0, got {}",
                crate::desc::num(r)
            )));
        }
        let w = &placed.world;
        let kind = match light.type_ {
            Checked::Valid(Type::Directional) => {
                let Some(direction) = unit(direction(w, [0.0, 0.0, -1.0])) else {
                    continue;
                };
                ImportedLightKind::Directional { direction }
            }
            Checked::Valid(Type::Spot) => {
                cx.warn(format!(
                    "{at}: a spot light, read as a point light: its cone is ignored"
                ));
                ImportedLightKind::Point {
                    position: point(w, [0.0; 3]),
                    range,
                }
            }
            Checked::Valid(Type::Point) => ImportedLightKind::Point {
                position: point(w, [0.0; 3]),
                range,
            },
            Checked::Invalid => return Err(cx.err(format!("{at}: a light of unknown type"))),
        };
        if let ImportedLightKind::Point { position, .. } = kind
            && !position.iter().all(|x| x.is_finite())
        {
            return Err(cx.err(format!(
                "{at}: its node's matrix moves it past the range of f64"
            )));
        }
        let name = light
            .name
            .clone()
            .or_else(|| node.name.clone())
            .unwrap_or_else(|| format!("light {l}"));
        out.push(ImportedLight {
            name,
            kind,
            color,
            intensity,
        });
    }
    Ok(out)
}
