//! The reference scene: the description's values in `f64`, in plain `Vec`s, with
//! its textures and the nearest-hit and shadow queries (a plain loop over every
//! primitive).

use super::geometry::{Hit, Ray, Shape};
use super::vec::V3;
use crate::desc::{DescError, SceneDesc, TextureDesc};
use std::f64::consts::PI;

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

    /// The mean colour over the uv box `[lo, hi]`, in closed form: `cos^2` fringes
    /// integrate to a difference of sines; a checker is the product of two square
    /// waves, whose means are differences of triangle waves. A box thinner than
    /// 1e-9 of a period is the point value at its centre.
    #[must_use]
    pub fn eval_box(&self, lo: [f64; 2], hi: [f64; 2]) -> V3 {
        let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        match *self {
            Self::Solid(c) => c,
            Self::Checker { a, b, scale } => {
                let square_mean = |x0: f64, x1: f64| {
                    let tri = |x: f64| {
                        let n = x.floor();
                        if cell_parity(n) == 0 {
                            x - n
                        } else {
                            1.0 - (x - n)
                        }
                    };
                    (x1 - x0 > 1e-9).then(|| (tri(x1) - tri(x0)) / (x1 - x0))
                };
                match (
                    square_mean(lo[0] * scale, hi[0] * scale),
                    square_mean(lo[1] * scale, hi[1] * scale),
                ) {
                    (Some(su), Some(sv)) => {
                        let even = 0.5 * (1.0 + su * sv);
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

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Position.
    pub position: V3,
    /// Colour times intensity.
    pub power: V3,
}

/// A primitive: shape, kind (0 sphere, 1 plane, 2 triangle, 3 box, 4 a mesh's
/// face), index in its kind's list (a mesh's faces: the mesh's), material index,
/// and a smooth mesh's vertex normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Object {
    /// The shape.
    pub shape: Shape,
    /// Kind, for the signature.
    pub kind: u64,
    /// Index in the description's list of that kind.
    pub index: u64,
    /// Index in [`RefScene::materials`].
    pub material: usize,
    /// A face of a smooth mesh: its vertices' unit normals.
    pub normals: Option<[V3; 3]>,
}

impl Object {
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
            .map(|m| Mat {
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
                },
                ka: m.ambient,
                kd: m.diffuse,
                ks: m.specular,
                shininess: m.shininess,
                kr: m.reflectivity,
                kt: m.transparency,
                ior: m.ior,
            })
            .collect();
        let lights = desc
            .lights
            .iter()
            .map(|l| Light {
                position: v(l.position),
                power: v(l.color) * l.intensity,
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
                material,
                normals: None,
            });
            Ok::<(), DescError>(())
        };
        for (i, s) in desc.spheres.iter().enumerate() {
            let shape = Shape::Sphere {
                center: v(s.center),
                radius: s.radius,
            };
            add(0, i, shape, &s.material)?;
        }
        for (i, p) in desc.planes.iter().enumerate() {
            let shape = Shape::plane(v(p.point), v(p.normal));
            add(1, i, shape, &p.material)?;
        }
        for (i, t) in desc.triangles.iter().enumerate() {
            let shape = Shape::Triangle {
                p: t.vertices.map(v),
            };
            add(2, i, shape, &t.material)?;
        }
        for (i, b) in desc.boxes.iter().enumerate() {
            let shape = Shape::Box {
                min: v(b.min),
                max: v(b.max),
            };
            add(3, i, shape, &b.material)?;
        }
        // The meshes, after every list (as the core searches them), a face at a
        // time; a smooth one's normals welded as the host welds them.
        for (i, m) in desc.meshes.iter().enumerate() {
            let w = m.welded();
            let material = desc.material_index(&m.material).ok_or_else(|| DescError {
                item: format!("mesh {}", i + 1),
                message: format!("unknown material {:?}", m.material),
            })?;
            for f in &w.faces {
                objects.push(Object {
                    shape: Shape::Triangle {
                        p: f.map(|k| v(w.positions[k])),
                    },
                    kind: 4,
                    index: i as u64,
                    material,
                    normals: (!w.normals.is_empty()).then(|| f.map(|k| v(w.normals[k]))),
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

    /// The checker's cell parity where the cell indices saturate (issue 10: the
    /// core's `i64` sum overflowed): the reference and the core pick the same
    /// colour, computed the same way (an exclusive or of the two parities).
    #[test]
    fn checker_parity_agrees_with_the_core_where_indices_saturate() {
        let (a, b) = (V3::new(1.0, 1.0, 1.0), V3::ZERO);
        for scale in [1e20f32, 3.4e38] {
            let core = tessera::Texture::Checker {
                a: tessera::Color::WHITE,
                b: tessera::Color::BLACK,
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
                let want_a = core.eval(uv) == tessera::Color::WHITE;
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
}
