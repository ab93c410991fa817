//! The reference scene: the description's values in `f64`, in plain `Vec`s, with
//! its textures and the nearest-hit and shadow queries (a plain loop over every
//! primitive).

use super::geometry::{Hit, Ray, Shape};
use super::vec::V3;
use crate::desc::{DescError, SceneDesc, TextureDesc};
use crate::kinds::{HostKind, Listed, each_kind};
use std::f64::consts::PI;
use tessera_core::Geometry;
use tessera_core::kind::Kind;

/// A texture in `f64`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tex {
    /// One colour.
    Solid(V3),
    /// `a` where `floor(u s) + floor(v s)` is even, else `b`.
    Checker {
        /// Even squares.
        a: V3,
        /// Odd squares.
        b: V3,
        /// Squares per uv unit.
        scale: f64,
    },
    /// `color (0.5 + 0.5 cos(2 pi u / spacing))`.
    Fringes {
        /// Bright colour.
        color: V3,
        /// Fringe spacing, uv units.
        spacing: f64,
    },
    /// The core's texels, sampled in `f64` ([`super::image_texture`]).
    Image(tessera_core::image::Image),
}

impl Tex {
    /// For a checker, the parity of the cell at `uv` (0 = colour `a`); `None` for
    /// textures without edges.
    #[must_use]
    pub fn checker_parity(&self, [u, v]: [f64; 2]) -> Option<u64> {
        match *self {
            Self::Checker { scale, .. } => Some(cell_parity(u * scale) ^ cell_parity(v * scale)),
            _ => None,
        }
    }

    /// Which piece of a texture with edges the point at `uv` is on: a checker's
    /// cell parity, a nearest-filtered image's texel (its index); `None` for
    /// textures without edges. Neighbouring samples on different pieces meet a
    /// discontinuity, which rounding may put either side of.
    #[must_use]
    pub fn edge_piece(&self, uv: [f64; 2]) -> Option<u64> {
        match *self {
            Self::Image(ref image) => super::image_texture::nearest_texel(image, uv)
                .map(|(x, y)| (x as u64) << 16 | y as u64),
            _ => self.checker_parity(uv),
        }
    }

    /// The mean colour over the uv box `[lo, hi]`, in closed form: `cos^2` fringes
    /// integrate to a difference of sines; a checker's share of even squares comes
    /// from the share of even cells along each axis ([`even_share`]). A box thinner
    /// than 1e-9 of a period (on either axis) is the point value at its centre.
    #[must_use]
    pub fn eval_box(&self, lo: [f64; 2], hi: [f64; 2]) -> V3 {
        let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        match *self {
            Self::Solid(c) => c,
            Self::Checker { a, b, scale } => {
                match (
                    even_share(lo[0] * scale, hi[0] * scale),
                    even_share(lo[1] * scale, hi[1] * scale),
                ) {
                    // A point of the box is on an even square when its two cells
                    // are both even or both odd; over a box (a product of two
                    // intervals) the two axes are independent.
                    (Some(pu), Some(pv)) => {
                        let even = pu * pv + (1.0 - pu) * (1.0 - pv);
                        a * even + b * (1.0 - even)
                    }
                    _ => self.eval(mid),
                }
            }
            Self::Fringes { color, spacing } => {
                let (x0, x1) = (lo[0] / spacing, hi[0] / spacing);
                if x1 - x0 <= 1e-9 {
                    return self.eval(mid);
                }
                let s = |x: f64| (2.0 * PI * x).sin();
                color * (0.5 + 0.5 * (s(x1) - s(x0)) / (2.0 * PI * (x1 - x0)))
            }
            Self::Image(ref image) => V3::from_array(super::image_texture::average(image, lo, hi)),
        }
    }

    /// The colour at `uv`.
    #[must_use]
    pub fn eval(&self, [u, v]: [f64; 2]) -> V3 {
        match *self {
            Self::Solid(c) => c,
            Self::Checker { a, b, scale } => {
                if cell_parity(u * scale) ^ cell_parity(v * scale) == 0 {
                    a
                } else {
                    b
                }
            }
            Self::Fringes { color, spacing } => {
                color * (0.5 + 0.5 * (2.0 * PI * u / spacing).cos())
            }
            Self::Image(ref image) => V3::from_array(super::image_texture::sample(image, [u, v])),
        }
    }
}

/// The parity (0 even, 1 odd) of the checker cell `floor(x) as i64` (which
/// saturates, NaN giving 0), as the core defines it; a cell of the plane is even
/// when the parities of its two indices agree. An exclusive or of parities, not the
/// parity of a sum: nothing can overflow (the sum of two saturated indices did).
#[must_use]
pub fn cell_parity(x: f64) -> u64 {
    (x.floor() as i64 & 1) as u64
}

/// The share of `[x0, x1]` (in cells) that lies on even cells `[2k, 2k + 1)`;
/// `None` for an interval thinner than 1e-9 of a cell (or not a number).
///
/// The square wave that is +1 on even cells and -1 on odd ones has the
/// antiderivative `E(x)` (its integral from 0 to `x`) = the distance from `x` to
/// the nearest even integer: it rises by 1 across an even cell and falls back by 1
/// across the odd cell after it, and it is even and of period 2, so it holds for
/// negative `x` too. The wave's mean over the interval is `(E(x1) - E(x0)) /
/// width`, and the share of even cells is `(1 + mean) / 2`. `E` is exact in `f64`
/// (`x` and its nearest even integer are within a factor of 2 of each other, or
/// that integer is 0), so only the subtraction of the two and the division round.
///
/// This is the mean of the periodic checker. From `2^63` on, where the point
/// value's saturated cell index is odd ([`cell_parity`]) and `f64` has no fraction
/// of a cell left, `E` stays 0 (every such `x` is an even integer): an interval
/// reaching across `2^63` gets the periodic mean, not that of one odd cell index
/// repeated.
#[must_use]
pub fn even_share(x0: f64, x1: f64) -> Option<f64> {
    let width = x1 - x0;
    if width.is_nan() || width <= 1e-9 {
        return None;
    }
    let e = |x: f64| (x - 2.0 * (0.5 * x).round()).abs();
    Some(0.5 + 0.5 * (e(x1) - e(x0)) / width)
}

/// A material in `f64`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mat {
    /// Base colour.
    pub texture: Tex,
    /// Ambient weight `ka`.
    pub ka: f64,
    /// Diffuse weight `kd`.
    pub kd: f64,
    /// Specular weight `ks`.
    pub ks: f64,
    /// Blinn-Phong exponent.
    pub shininess: f64,
    /// Mirror weight `kr`.
    pub kr: f64,
    /// Transparency `kt`.
    pub kt: f64,
    /// Index of refraction.
    pub ior: f64,
}

/// A light: a point light, or a directional light (a sun).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// A point light's position, or a sun's unit direction towards it.
    pub position: V3,
    /// Colour times intensity.
    pub power: V3,
    /// A sun: `position` is the unit direction towards it, and the irradiance
    /// does not fall off.
    pub directional: bool,
}

impl Light {
    /// The unit direction from `p` to the light, the distance a shadow ray
    /// searches, and the irradiance of a surface facing it; `None` at the light
    /// itself.
    #[must_use]
    pub fn toward(&self, p: V3) -> Option<(V3, f64, V3)> {
        if self.directional {
            return Some((self.position, f64::INFINITY, self.power));
        }
        let to_light = self.position - p;
        let dist = to_light.length();
        if dist.is_nan() || dist <= 0.0 {
            return None;
        }
        let e = self.power * (1.0 / (dist * dist));
        Some((to_light * (1.0 / dist), dist, e))
    }
}

/// The [`Object::kind`] of a mesh's face.
pub const MESH_FACE: u64 = Kind::Mesh.index() as u64;

/// A primitive: shape, kind (the core's numbering, [`Kind::index`]: a
/// sphere's, a plane's, a triangle's, a box's, [`MESH_FACE`]), index in its kind's list (a mesh's faces: the mesh's, and
/// the face's in the mesh), material index, and a smooth mesh's vertex normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Object {
    /// The shape.
    pub shape: Shape,
    /// Kind, for the signature.
    pub kind: u64,
    /// Index in the description's list of that kind.
    pub index: u64,
    /// A mesh's face: its index in the mesh (0 for the other kinds).
    pub face: u64,
    /// Index in [`RefScene::materials`].
    pub material: usize,
    /// A face of a smooth mesh: its vertices' unit normals.
    pub normals: Option<[V3; 3]>,
    /// A face of a mesh with texture coordinates: its vertices' uvs.
    pub uvs: Option<[[f64; 2]; 3]>,
}

impl Object {
    /// The texture coordinate at a hit of the shape: a mesh face's vertex uvs
    /// weighted by the hit's barycentrics, or the shape's own uv.
    #[must_use]
    pub fn uv(&self, p: V3, n: V3, hit: &Hit) -> [f64; 2] {
        match self.uvs {
            Some([a, b, c]) => {
                let b0 = 1.0 - hit.b1 - hit.b2;
                [0, 1].map(|d| a[d] * b0 + b[d] * hit.b1 + c[d] * hit.b2)
            }
            None => self.shape.uv(p, n, hit),
        }
    }

    /// Where a smooth mesh's shadow rays leave, as a move from the hit `p`: the
    /// point lifted above each vertex's tangent plane, weighted by the
    /// barycentrics (Hanika, "Hacking the shadow terminator", Ray Tracing Gems II
    /// ch. 4); `side` -1 when the ray sees the face from behind its normals.
    /// Zero otherwise.
    #[must_use]
    pub fn lift(&self, p: V3, hit: &Hit, side: f64) -> V3 {
        let (Some(normals), Shape::Triangle { p: vertices }) = (self.normals, self.shape) else {
            return V3::new(0.0, 0.0, 0.0);
        };
        let w = [1.0 - hit.b1 - hit.b2, hit.b1, hit.b2];
        // Each vertex normal on the side of the face's own normal.
        let g = (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]);
        let mut lift = V3::new(0.0, 0.0, 0.0);
        for i in 0..3 {
            let n = if normals[i].dot(g) < 0.0 {
                -normals[i]
            } else {
                normals[i]
            } * side;
            let below = (p - vertices[i]).dot(n).min(0.0);
            lift = lift - n * (below * w[i]);
        }
        lift
    }

    /// The normal the light is weighed with, given `n`, the surface normal turned
    /// to the ray: a smooth mesh's vertex normals interpolated at the hit's
    /// barycentrics, turned to `n`'s side; `n` itself otherwise.
    #[must_use]
    pub fn shading(&self, n: V3, hit: &Hit) -> V3 {
        let Some([a, b, c]) = self.normals else {
            return n;
        };
        let s = (a * (1.0 - hit.b1 - hit.b2) + b * hit.b1 + c * hit.b2).normalize();
        if !s.is_finite() {
            n
        } else if s.dot(n) < 0.0 {
            -s
        } else {
            s
        }
    }
}

/// The index of a mesh's instance `k` as a hit names it (`16 + k`: the core
/// names the meshes drawn in place below).
const MESH_INDEXES: usize = 16;

/// Where an instance puts its mesh, in `f64`, derived here on its own:
/// `world = R (s * p) + t`, the rotation from the quaternion by Rodrigues'
/// formula (its axis and angle), or from `rotate`'s degrees as the product of
/// the turns about the fixed X, then Y, then Z axes; normals carried by the
/// inverse transpose (the cofactors), normalised.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Placing {
    m: [[f64; 3]; 3],
    cof: [[f64; 3]; 3],
    t: V3,
}

impl Placing {
    const IDENTITY: Self = Self {
        m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        cof: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        t: V3::new(0.0, 0.0, 0.0),
    };

    fn of(d: &crate::desc::InstanceDesc) -> Self {
        let r = match (d.rotate, d.quaternion) {
            (Some(deg), _) => {
                let turn = |axis: usize, a: f64| {
                    let (s, c) = a.to_radians().sin_cos();
                    let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
                    let mut m = [[0.0; 3]; 3];
                    m[axis][axis] = 1.0;
                    m[i][i] = c;
                    m[j][j] = c;
                    m[i][j] = -s;
                    m[j][i] = s;
                    m
                };
                mul(turn(2, deg[2]), mul(turn(1, deg[1]), turn(0, deg[0])))
            }
            (None, Some(q)) => {
                let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
                let q = q.map(|x| x / len);
                let s = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
                let angle = 2.0 * s.atan2(q[3]);
                let k = if s > 0.0 {
                    [q[0] / s, q[1] / s, q[2] / s]
                } else {
                    [1.0, 0.0, 0.0]
                };
                let (sn, cs) = angle.sin_cos();
                let kx = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]];
                let mut r = [[0.0; 3]; 3];
                for (i, row) in r.iter_mut().enumerate() {
                    for (j, x) in row.iter_mut().enumerate() {
                        let delta = if i == j { 1.0 } else { 0.0 };
                        *x = cs * delta + sn * kx[i][j] + (1.0 - cs) * k[i] * k[j];
                    }
                }
                r
            }
            (None, None) => Self::IDENTITY.m,
        };
        let s = d.scale.axes();
        let m = r.map(|row| [row[0] * s[0], row[1] * s[1], row[2] * s[2]]);
        let c = |i: usize, j: usize| {
            let (a, b) = ((i + 1) % 3, (i + 2) % 3);
            let (x, y) = ((j + 1) % 3, (j + 2) % 3);
            m[a][x] * m[b][y] - m[a][y] * m[b][x]
        };
        let cof = [0, 1, 2].map(|i| [0, 1, 2].map(|j| c(i, j)));
        Self {
            m,
            cof,
            t: V3::from_array(d.translate),
        }
    }

    fn apply(m: &[[f64; 3]; 3], p: V3) -> V3 {
        let r = m.map(|row| row[0] * p.x + row[1] * p.y + row[2] * p.z);
        V3::from_array(r)
    }

    fn point(&self, p: V3) -> V3 {
        Self::apply(&self.m, p) + self.t
    }

    /// A unit normal carried (the cofactor matrix is `det M` times the
    /// inverse transpose: a mirror's negative determinant turns it back).
    fn normal(&self, n: V3) -> V3 {
        let c = Self::apply(&self.cof, n);
        let det = self.m[0][0] * self.cof[0][0]
            + self.m[0][1] * self.cof[0][1]
            + self.m[0][2] * self.cof[0][2];
        (c * det.signum()).normalize()
    }
}

fn mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// The scene in `f64`: every primitive in one list, spheres, planes, triangles,
/// boxes in that order (ties in `t` go to the earlier one, as in the core).
#[derive(Clone, Debug, PartialEq)]
pub struct RefScene {
    /// Ambient light.
    pub ambient: V3,
    /// Colour of a miss.
    pub background: V3,
    /// Materials.
    pub materials: Vec<Mat>,
    /// Lights.
    pub lights: Vec<Light>,
    /// Primitives.
    pub objects: Vec<Object>,
}

impl RefScene {
    /// The scene of a description (assumed validated by `to_core`).
    pub fn from_desc(desc: &SceneDesc) -> Result<Self, DescError> {
        let v = V3::from_array;
        let materials = desc
            .materials
            .iter()
            .map(|m| -> Result<Mat, DescError> {
                Ok(Mat {
                    texture: match &m.texture {
                        None => Tex::Solid(v(m.color)),
                        Some(TextureDesc::Checker { a, b, scale }) => Tex::Checker {
                            a: v(*a),
                            b: v(*b),
                            scale: *scale,
                        },
                        Some(TextureDesc::Young {
                            color,
                            d,
                            wavelength,
                            distance,
                        }) => Tex::Fringes {
                            color: v(*color),
                            spacing: wavelength * distance / d,
                        },
                        Some(TextureDesc::Fringes { color, spacing }) => Tex::Fringes {
                            color: v(*color),
                            spacing: *spacing,
                        },
                        Some(TextureDesc::Image { image, file, .. }) => {
                            Tex::Image(image.ok_or_else(|| DescError {
                                item: format!("material {:?}", m.name),
                                message: format!("texture image {file:?} was not read"),
                            })?)
                        }
                    },
                    ka: m.ambient,
                    kd: m.diffuse,
                    ks: m.specular,
                    shininess: m.shininess,
                    kr: m.reflectivity,
                    kt: m.transparency,
                    ior: m.ior,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let lights = desc
            .lights
            .iter()
            .map(|l| match l.direction {
                // Towards the sun: against the way its rays travel.
                Some(d) => Light {
                    position: -v(d).normalize(),
                    power: v(l.color) * l.intensity,
                    directional: true,
                },
                None => Light {
                    position: v(l.position),
                    power: v(l.color) * l.intensity,
                    directional: false,
                },
            })
            .collect();
        let mut objects = Vec::new();
        let mut add = |kind: u64, index: usize, shape: Shape, name: &str| {
            let material = desc.material_index(name).ok_or_else(|| DescError {
                item: format!("primitive {kind}:{index}"),
                message: format!("unknown material {name:?}"),
            })?;
            objects.push(Object {
                shape,
                kind,
                index: index as u64,
                face: 0,
                material,
                normals: None,
                uvs: None,
            });
            Ok::<(), DescError>(())
        };
        each_kind!(|G| {
            for (i, d) in G::descs(desc).iter().enumerate() {
                add(G::KIND.index() as u64, i, G::reference(d), G::material(d))?;
            }
        });
        // The meshes, after every list (as the core searches them), a face at a
        // time; a smooth one's normals welded as the host welds them. A mesh
        // that an instance names is drawn where its instances are, after the
        // meshes in place: its faces carried there in f64 (`Placing`).
        let instanced: Vec<(usize, Placing)> = desc
            .instances
            .iter()
            .flat_map(|d| {
                let placing = Placing::of(d);
                desc.instance_parts(&d.mesh)
                    .into_iter()
                    .map(move |part| (part, placing))
            })
            .collect();
        let drawn = (0..desc.meshes.len())
            .filter(|i| !instanced.iter().any(|(part, _)| part == i))
            .map(|i| (i, i, Placing::IDENTITY))
            .chain(
                instanced
                    .iter()
                    .enumerate()
                    .map(|(k, &(part, placing))| (part, MESH_INDEXES + k, placing)),
            );
        for (i, index, placing) in drawn {
            let m = &desc.meshes[i];
            let w = m.welded();
            let name = m.material.as_deref().unwrap_or_default();
            let material = desc.material_index(name).ok_or_else(|| DescError {
                item: format!("mesh {}", i + 1),
                message: format!("unknown material {name:?}"),
            })?;
            for (face, f) in w.faces.iter().enumerate() {
                objects.push(Object {
                    shape: Shape::Triangle {
                        p: f.map(|k| placing.point(v(w.positions[k]))),
                    },
                    kind: MESH_FACE,
                    index: index as u64,
                    face: face as u64,
                    material,
                    normals: (!w.normals.is_empty())
                        .then(|| f.map(|k| placing.normal(v(w.normals[k])))),
                    uvs: (!w.uvs.is_empty()).then(|| f.map(|k| w.uvs[k])),
                });
            }
        }
        Ok(Self {
            ambient: v(desc.ambient),
            background: v(desc.background),
            materials,
            lights,
            objects,
        })
    }

    /// The nearest primitive hit with `0 < t < t_max`.
    #[must_use]
    pub fn nearest(&self, ray: &Ray, t_max: f64) -> Option<(&Object, Hit)> {
        let mut best: Option<(&Object, Hit)> = None;
        let mut limit = t_max;
        for o in &self.objects {
            if let Some(h) = o.shape.intersect(ray, limit) {
                limit = h.t;
                best = Some((o, h));
            }
        }
        best
    }

    /// True when a primitive is hit with `0 < t < t_max`.
    #[must_use]
    pub fn blocked(&self, ray: &Ray, t_max: f64) -> bool {
        self.objects
            .iter()
            .any(|o| o.shape.intersect(ray, t_max).is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The checker's cell parity where the cell indices saturate (their sum would
    /// overflow an `i64`): the reference and the core pick the same colour, computed
    /// the same way (an exclusive or of the two parities).
    #[test]
    fn checker_parity_agrees_with_the_core_where_indices_saturate() {
        let (a, b) = (V3::new(1.0, 1.0, 1.0), V3::ZERO);
        for scale in [1e20f32, 3.4e38] {
            let core = tessera_core::texture::Texture::Checker {
                a: tessera_core::Color::WHITE,
                b: tessera_core::Color::BLACK,
                scale,
            };
            let reference = Tex::Checker {
                a,
                b,
                scale: f64::from(scale),
            };
            for uv in [
                [3e38f32, 3e38],
                [-3e38, 3e38],
                [-3e38, -3e38],
                [1e30, 0.25],
                [-1e30, 0.25],
            ] {
                let want_a = core.eval(uv) == tessera_core::Color::WHITE;
                let got = reference.eval(uv.map(f64::from));
                assert_eq!(got == a, want_a, "scale {scale} uv {uv:?}");
                let parity = reference.checker_parity(uv.map(f64::from));
                assert_eq!(parity, Some(u64::from(!want_a)), "scale {scale} uv {uv:?}");
            }
        }
        assert_eq!(cell_parity(f64::MAX), 1);
        assert_eq!(cell_parity(f64::NEG_INFINITY), 0);
        assert_eq!(cell_parity(f64::NAN), 0);
        assert_eq!(cell_parity(-3.5), 0);
        assert_eq!(cell_parity(-2.5), 1);
    }

    #[test]
    fn textures() {
        let (a, b) = (V3::new(1.0, 1.0, 1.0), V3::ZERO);
        let t = Tex::Checker { a, b, scale: 2.0 };
        assert_eq!(t.eval([0.1, 0.1]), a);
        assert_eq!(t.eval([0.6, 0.1]), b);
        assert_eq!(t.eval([0.6, 0.6]), a);
        assert_eq!(t.eval([-0.1, 0.1]), b);
        let f = Tex::Fringes {
            color: a,
            spacing: 0.75e-3,
        };
        assert!((f.eval([0.0, 0.0]).x - 1.0).abs() < 1e-15);
        assert!(f.eval([0.375e-3, 0.0]).x.abs() < 1e-15);
        assert!((f.eval([0.1875e-3, 0.0]).x - 0.5).abs() < 1e-15);
    }

    /// A checker with even squares `X` and odd ones `Y`: a mean's `x` is the share
    /// of the box on even squares.
    fn unit_checker(scale: f64) -> Tex {
        Tex::Checker {
            a: V3::X,
            b: V3::Y,
            scale,
        }
    }

    /// The share of the uv box `[lo, hi]` on the even squares of a checker of
    /// `scale`, summed piece by piece: each axis cut at the cell edges it crosses,
    /// and each pair of pieces weighed by its area and coloured by the checker's
    /// point value (`Tex::eval`) at its centre. No formula for the mean: what the
    /// closed form must agree with.
    fn even_share_by_cells(scale: f64, lo: [f64; 2], hi: [f64; 2]) -> f64 {
        // The pieces of [x0, x1] (uv) in each cell: (centre in uv, length in cells).
        let pieces = |x0: f64, x1: f64| {
            let (c0, c1) = (x0 * scale, x1 * scale);
            let mut out = Vec::new();
            let mut edge = c0.floor();
            while edge < c1 {
                let (from, to) = (c0.max(edge), c1.min(edge + 1.0));
                out.push((0.5 * (from + to) / scale, to - from));
                edge += 1.0;
            }
            out
        };
        let checker = unit_checker(scale);
        let (mut even, mut area) = (0.0, 0.0);
        for &(u, du) in &pieces(lo[0], hi[0]) {
            for &(v, dv) in &pieces(lo[1], hi[1]) {
                even += du * dv * checker.eval([u, v]).x;
                area += du * dv;
            }
        }
        even / area
    }

    /// The boxes the checker's mean is tried on, `(scale, lo, hi)` with `lo` and
    /// `hi` in uv: inside one cell, across cell edges (one axis, both, around the
    /// origin), over many cells, thin (just above the point-value threshold), far
    /// from the origin, at negative coordinates; then 3,000 seeded random boxes
    /// (up to 2^30 cells from the origin, 2^-16 to 32 cells wide on each axis).
    fn boxes() -> Vec<(f64, [f64; 2], [f64; 2])> {
        let big = 2f64.powi(40);
        let mut boxes = vec![
            // Inside one cell: even, odd, even again at negative coordinates.
            (1.0, [0.1, 0.3], [0.2, 0.9]),
            (2.0, [0.55, 0.05], [0.95, 0.45]),
            (1.0, [-0.9, -3.7], [-0.2, -3.1]),
            // Across one edge, two edges, the origin on both axes.
            (1.0, [0.9, 0.5], [1.1, 0.6]),
            (1.0, [1.7, 2.9], [2.3, 3.2]),
            (1.0, [-0.25, -0.25], [0.25, 0.25]),
            (1.0, [-0.6, 0.2], [0.3, 0.4]),
            (3.0, [-0.1, -0.45], [0.4, -0.2]),
            // Over many cells.
            (1.0, [-7.3, -3.1], [12.9, 40.45]),
            (0.37, [-100.0, 3.0], [250.0, 90.0]),
            (1000.0, [0.01234, 0.5], [0.05, 0.5137]),
            // Thin: 2e-9 of a cell across an edge, by a wide one.
            (1.0, [0.999_999_999, 0.3], [1.000_000_001, 2.6]),
            (1.0, [-1.7, -2.000_000_001], [0.6, -1.999_999_999]),
            // Far from the origin, and far at negative coordinates.
            (1.0, [1e6 + 0.3, -1e6 - 2.2], [1e6 + 2.8, -1e6 + 0.4]),
            (1.0, [big + 0.25, -big - 0.5], [big + 1.75, -big + 3.5]),
            (
                1e4,
                [123_456.789_01, -98_765.432_1],
                [123_456.790_43, -98_765.430_11],
            ),
            (0.001, [-3.3e9, 7.7e9], [-3.2995e9, 7.7006e9]),
        ];
        // SplitMix64.
        let mut state = 0x7e55_e7a0_u64;
        let mut unit = move || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..3000 {
            let scale = 2f64.powf(8.0 * unit() - 4.0);
            let mut lo = [0.0; 2];
            let mut hi = [0.0; 2];
            for axis in 0..2 {
                let centre = (2.0 * unit() - 1.0) * 2f64.powf(30.0 * unit());
                let width = 2f64.powf(21.0 * unit() - 16.0);
                lo[axis] = (centre - width * unit()) / scale;
                hi[axis] = lo[axis] + width / scale;
            }
            boxes.push((scale, lo, hi));
        }
        boxes
    }

    /// A way to the share of the box `[lo, hi]` on the even squares of a checker
    /// of `scale`: `(scale, lo, hi) -> share`.
    type Mean = dyn Fn(f64, [f64; 2], [f64; 2]) -> f64;

    /// The largest difference between `mean` and the sum over the box's cells,
    /// over [`boxes`], and where.
    fn worst_gap(mean: &Mean) -> (f64, String) {
        let mut worst = (0.0, String::new());
        for (scale, lo, hi) in boxes() {
            let (got, want) = (mean(scale, lo, hi), even_share_by_cells(scale, lo, hi));
            let gap = (got - want).abs();
            // NaN is the worst.
            if gap.is_nan() || gap > worst.0 {
                worst = (
                    gap,
                    format!("scale {scale}, {lo:?} to {hi:?}: {got}, not {want}"),
                );
            }
        }
        worst
    }

    /// The closed form of the checker's box mean is the mean of the checker over
    /// the box: within 1e-9 of the sum over its cells on every box of [`boxes`],
    /// and the odd squares take the rest.
    #[test]
    fn checker_box_mean_is_the_sum_over_its_cells() {
        let (gap, at) = worst_gap(&|scale, lo, hi| unit_checker(scale).eval_box(lo, hi).x);
        assert!(gap <= 1e-9, "{gap:e} at {at}");
        for (scale, lo, hi) in boxes() {
            let mean = unit_checker(scale).eval_box(lo, hi);
            assert!(
                (mean.x + mean.y - 1.0).abs() <= 1e-12 && mean.z == 0.0,
                "{mean:?}"
            );
        }
    }

    /// The check above catches a wrong mean: each of these plausible mistakes is
    /// off by more than 0.05 somewhere among the boxes (the mistakes each need a
    /// kind of box: negative coordinates, edges on both axes, many cells).
    #[test]
    fn a_wrong_checker_mean_is_caught_by_the_sum_over_cells() {
        // The share of even cells on each axis from an antiderivative `e` of the
        // square wave (as `even_share`), and the two shares combined by `combine`.
        fn by_axes(
            e: fn(f64) -> f64,
            combine: fn(f64, f64) -> f64,
        ) -> impl Fn(f64, [f64; 2], [f64; 2]) -> f64 {
            move |scale, lo, hi| {
                let share = |x0: f64, x1: f64| {
                    let (x0, x1) = (x0 * scale, x1 * scale);
                    0.5 + 0.5 * (e(x1) - e(x0)) / (x1 - x0)
                };
                combine(share(lo[0], hi[0]), share(lo[1], hi[1]))
            }
        }
        fn right_e(x: f64) -> f64 {
            (x - 2.0 * (0.5 * x).round()).abs()
        }
        fn right_combine(pu: f64, pv: f64) -> f64 {
            pu * pv + (1.0 - pu) * (1.0 - pv)
        }
        let wrong: [(&str, Box<Mean>); 7] = [
            (
                "distance to the nearest integer (period 1)",
                Box::new(by_axes(|x| (x - x.round()).abs(), right_combine)),
            ),
            (
                "sawtooth: the length since the last even integer",
                Box::new(by_axes(|x| x.rem_euclid(2.0), right_combine)),
            ),
            (
                "cells from truncation toward 0, not floor",
                Box::new(by_axes(
                    |x| {
                        let n = x.trunc();
                        if n.rem_euclid(2.0) == 0.0 {
                            x - n
                        } else {
                            1.0 - (x - n)
                        }
                    },
                    right_combine,
                )),
            ),
            (
                "both axes even, forgetting both odd",
                Box::new(by_axes(right_e, |pu, pv| pu * pv)),
            ),
            (
                "the mean of the two axes' shares",
                Box::new(by_axes(right_e, |pu, pv| 0.5 * (pu + pv))),
            ),
            (
                "the odd squares' share",
                Box::new(by_axes(right_e, |pu, pv| 1.0 - right_combine(pu, pv))),
            ),
            (
                "the point value at the centre",
                Box::new(|scale, lo: [f64; 2], hi: [f64; 2]| {
                    unit_checker(scale)
                        .eval([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])])
                        .x
                }),
            ),
        ];
        for (what, mean) in &wrong {
            let (gap, at) = worst_gap(mean.as_ref());
            assert!(gap > 0.05, "{what}: not caught (worst {gap} at {at})");
        }
        // The right one, assembled the same way, passes.
        let (gap, at) = worst_gap(&by_axes(right_e, right_combine));
        assert!(gap <= 1e-9, "{gap:e} at {at}");
    }

    /// A box of no width on an axis (or thinner than 1e-9 of a cell) has no mean:
    /// it is the point value at its centre, as in the core (whose threshold, in
    /// `f32`, is 1e-4).
    #[test]
    fn a_degenerate_box_is_the_point_value_at_its_centre() {
        let t = unit_checker(1.0);
        for (lo, hi) in [
            ([0.3, 0.1], [0.3, 2.7]),
            ([-2.5, 0.7], [3.5, 0.7]),
            ([-0.7, -0.7], [-0.7, -0.7]),
            ([0.999_999_999_8, -4.0], [1.000_000_000_2, 4.0]),
            ([1e6 + 0.5, -3.0], [1e6 + 0.5, 9.0]),
        ] {
            let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
            assert_eq!(t.eval_box(lo, hi), t.eval(centre), "{lo:?} to {hi:?}");
        }
        // Just above the threshold: a box 1e-8 of a cell wide across the edge at
        // u = 1 is averaged.
        let (lo, hi) = ([0.999_999_995, 0.25], [1.000_000_005, 0.75]);
        assert!((t.eval_box(lo, hi).x - 0.5).abs() < 1e-6);
    }
}
