//! The random scenes of the property tests: one generator for all of them. A
//! [`Recipe`] is a scene in plain numbers, drawn by [`recipe`] from the numbers of
//! a [`Values`] and built through the public API by [`Recipe::build`], which
//! leaves out whatever a constructor refuses. `finite` (no NaN or infinite
//! colour, the same bytes for every tile size) draws [`Values::Wild`] scenes;
//! `culling` (the same bytes culled or not, with or without a BVH) draws
//! [`Values::Tame`] ones.

use proptest::prelude::*;
use std::marker::PhantomData;
use tessera_core::Capacities;
use tessera_core::{
    Camera, Color, Encoding, RenderSettings, Sampler, Scene, Vec3, error::MAX_COLOR,
    error::MAX_EXTENT, error::MIN_LENGTH, geometry::Aabb, geometry::Cylinder, geometry::Disk,
    geometry::Plane, geometry::Sphere, geometry::Triangle, light::Light, material::Material,
    material::MaterialId, texture::Texture,
};

/// The numbers a recipe is drawn from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Values {
    /// From the whole `f32` range that matters: the exact ends of the accepted
    /// ranges, just beyond them, log-uniform magnitudes of either sign; colours up
    /// to `MAX_COLOR` and beyond, every weight of a material drawn (ends included),
    /// textures at extreme scales, lights of any colour and intensity, some on a
    /// sphere's surface or a plane's point. The camera is kept within the accepted
    /// ranges (a refused camera refuses the whole scene); most recipes hold a
    /// value some other constructor refuses. Depths 0 to 8; the samplers
    /// `Centre`, `Stratified(2)`, `Prefiltered`, `Adaptive` and `Sparse`.
    Wild,
    /// An ordinary scene: shapes within a few units of the origin, a camera up to
    /// 8 units away looking at a point near it (far plane at 100), colours and
    /// weights in `[0, 1]`, a fixed ambient light and background, textures at
    /// fixed scales, white lights of intensity 1 to 60. Depths 0 to 3; the
    /// samplers `Centre`, `Stratified(2)`, `Random(2)`, `Prefiltered`,
    /// `Adaptive` and `Sparse`.
    Tame,
}

/// A cylinder: the base and top centres, the radius, whether capped, material.
pub type CylinderRecipe = ([f32; 3], [f32; 3], f32, bool, usize);

/// A disk: the centre, the normal, the radius, the inner radius (as a share of
/// the radius), material.
pub type DiskRecipe = ([f32; 3], [f32; 3], f32, f32, usize);

/// A random scene's ingredients, in plain numbers, for a `Scene<C>`: fewer
/// primitives of each kind than `C`'s capacity of that kind, 1 to fewer
/// materials than its capacity and fewer lights than its capacity.
/// Each item names its material by an index (modulo the materials accepted).
#[derive(Clone, Debug)]
pub struct Recipe<C: Capacities> {
    /// The camera.
    pub camera: CameraRecipe,
    /// The scene's ambient light.
    pub ambient: [f32; 3],
    /// The background colour.
    pub background: [f32; 3],
    /// Centre, radius, material.
    pub spheres: Vec<([f32; 3], f32, usize)>,
    /// A point, the normal, material.
    pub planes: Vec<([f32; 3], [f32; 3], usize)>,
    /// The three vertices, material.
    pub triangles: Vec<([[f32; 3]; 3], usize)>,
    /// The minimum corner, the size (its absolute value is taken), material.
    pub boxes: Vec<([f32; 3], [f32; 3], usize)>,
    /// The cylinders.
    pub cylinders: Vec<CylinderRecipe>,
    /// The disks.
    pub disks: Vec<DiskRecipe>,
    /// The materials.
    pub materials: Vec<MaterialRecipe>,
    /// The lights.
    pub lights: Vec<LightRecipe>,
    /// How pixels are sampled.
    pub sampler: Sampler,
    /// The largest number of bounces.
    pub depth: u8,
    scene: PhantomData<fn() -> Scene<C>>,
}

/// The camera of a [`Recipe`]: position, forward direction, vertical field of
/// view (degrees), near and far.
pub type CameraRecipe = ([f32; 3], [f32; 3], f32, f32, f32);

/// A material of a [`Recipe`].
#[derive(Clone, Debug)]
pub struct MaterialRecipe {
    /// The base colour (and a texture's first colour).
    pub color: [f32; 3],
    /// Ambient, diffuse, specular, reflectivity, transparency (times 1 -
    /// reflectivity when `split`).
    pub weights: [f32; 5],
    /// Whether the transparency is scaled down to leave room for the
    /// reflectivity.
    pub split: bool,
    /// The Blinn-Phong exponent.
    pub shininess: f32,
    /// The index of refraction.
    pub ior: f32,
    /// 0 none, 1 a checker of `color` and `other` with `scale` squares a uv unit,
    /// 2 fringes of `color` with spacing `scale`.
    pub texture: u8,
    /// A checker's second colour.
    pub other: [f32; 3],
    /// A checker's scale or the fringes' spacing.
    pub scale: f32,
}

/// A light of a [`Recipe`].
#[derive(Clone, Debug)]
pub struct LightRecipe {
    /// Where it is (unless `on_surface` puts it elsewhere).
    pub position: [f32; 3],
    /// Its colour.
    pub color: [f32; 3],
    /// Its intensity.
    pub intensity: f32,
    /// `Some(i)`: on the `i`-th surface point of the scene instead (the points
    /// on the accepted spheres' surfaces, then the accepted planes' points), when
    /// there is one.
    pub on_surface: Option<usize>,
    /// A directional light (a sun) whose rays travel along `position` instead
    /// (`on_surface` unused).
    pub directional: bool,
}

/// A number from the whole `f32` range that matters here: exact ends of the
/// accepted ranges, just beyond them, and log-uniform magnitudes of either sign.
fn wild() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        2 => Just(0.0f32),
        1 => Just(1.0f32),
        1 => Just(MAX_COLOR),
        1 => Just(MAX_EXTENT),
        1 => Just(MIN_LENGTH),
        1 => Just(f32::MIN_POSITIVE),
        1 => Just(3.4e38f32),
        6 => (-60i32..60, 1.0f32..2.0, any::<bool>())
            .prop_map(|(e, m, neg)| if neg { -m * 2f32.powi(e) } else { m * 2f32.powi(e) }),
        4 => -4.0f32..4.0,
    ]
}

/// A non-negative number: colours, weights, intensities, scales.
fn amount() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        2 => Just(0.0f32),
        2 => 0.0f32..1.0,
        1 => Just(MAX_COLOR),
        1 => Just(3e38f32),
        3 => (-60i32..60, 1.0f32..2.0).prop_map(|(e, m)| m * 2f32.powi(e)),
    ]
}

/// A weight in `[0, 1]`, its ends included, sometimes tiny.
fn unit() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        2 => Just(0.0f32),
        2 => Just(1.0f32),
        1 => Just(f32::MIN_POSITIVE),
        5 => 0.0f32..=1.0,
    ]
}

/// A weight in `[0, 1)`, often exactly 0 (no specular, mirror, glass).
fn often_zero() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![Just(0.0f32), 0.0f32..1.0]
}

fn three<S: Strategy + Clone>(s: S) -> [S; 3] {
    [s.clone(), s.clone(), s]
}

impl Values {
    /// A point: [`wild`] coordinates, or each within `extent` of 0.
    fn point(self, extent: f32) -> BoxedStrategy<[f32; 3]> {
        match self {
            Self::Wild => three(wild()).boxed(),
            Self::Tame => three(-extent..extent).boxed(),
        }
    }

    /// A length (radius, a box's side): an [`amount`], or in `[lo, hi)`.
    fn length(self, lo: f32, hi: f32) -> BoxedStrategy<f32> {
        match self {
            Self::Wild => amount().boxed(),
            Self::Tame => (lo..hi).boxed(),
        }
    }

    /// A colour: [`amount`]s, or in `[0, 1)`.
    fn color(self) -> BoxedStrategy<[f32; 3]> {
        match self {
            Self::Wild => three(amount()).boxed(),
            Self::Tame => three(0.0f32..1.0).boxed(),
        }
    }

    /// A camera (see [`Recipe::camera`]).
    fn camera(self) -> BoxedStrategy<CameraRecipe> {
        match self {
            // Within the accepted ranges (the other items go beyond them).
            Self::Wild => (
                three(wild()),
                three(wild()),
                1.0f32..179.0,
                amount(),
                amount(),
            )
                .prop_map(|(pos, fwd, fovy, near, far)| {
                    let pos = pos.map(|x| x.clamp(-MAX_EXTENT / 4.0, MAX_EXTENT / 4.0));
                    let fwd = if fwd.iter().all(|&x| x == 0.0) {
                        [0.0, 0.0, -1.0]
                    } else {
                        fwd
                    };
                    let near = near.clamp(1e-6, 1e3);
                    (pos, fwd, fovy, near, near * (2.0 + far.min(1e6)))
                })
                .boxed(),
            // From up to 8 away towards a point within 2 of the origin.
            Self::Tame => (
                self.point(8.0),
                self.point(2.0),
                20.0f32..110.0,
                0.01f32..0.5,
            )
                .prop_map(|(pos, target, fovy, near)| {
                    let fwd = [0, 1, 2].map(|i| target[i] - pos[i]);
                    (pos, fwd, fovy, near, 100.0)
                })
                .boxed(),
        }
    }

    /// The ambient light and the background.
    fn lighting(self) -> BoxedStrategy<([f32; 3], [f32; 3])> {
        match self {
            Self::Wild => (self.color(), self.color()).boxed(),
            Self::Tame => Just(([0.1; 3], [0.2, 0.3, 0.4])).boxed(),
        }
    }

    /// A material.
    fn material(self) -> BoxedStrategy<MaterialRecipe> {
        let (weights, shininess, ior, texture) = match self {
            Self::Wild => (
                (three(unit()), unit(), unit(), any::<bool>())
                    .prop_map(|([a, d, s], r, t, split)| ([a, d, s, r, t], split))
                    .boxed(),
                prop_oneof![Just(1.0f32), Just(10_000.0), 1.0f32..10_000.0].boxed(),
                (1.0f32..=4.0).boxed(),
                (0u8..3, self.color(), amount()).boxed(),
            ),
            // The ambient weight of `Material::matte`; textures at fixed scales.
            Self::Tame => (
                (0.0f32..1.0, often_zero(), often_zero(), often_zero())
                    .prop_map(|(d, s, r, t)| ([1.0, d, s, r, t], false))
                    .boxed(),
                prop_oneof![Just(8.0f32), Just(48.0), 1.0f32..300.0].boxed(),
                (1.0f32..2.5).boxed(),
                (0u8..3)
                    .prop_map(|t| (t, [0.2; 3], if t == 2 { 0.3 } else { 2.0 }))
                    .boxed(),
            ),
        };
        (self.color(), weights, shininess, ior, texture)
            .prop_map(
                |(color, (weights, split), shininess, ior, (texture, other, scale))| {
                    MaterialRecipe {
                        color,
                        weights,
                        split,
                        shininess,
                        ior,
                        texture,
                        other,
                        scale,
                    }
                },
            )
            .boxed()
    }

    /// A light.
    fn light(self) -> BoxedStrategy<LightRecipe> {
        let (color, intensity, on_surface) = match self {
            Self::Wild => (
                self.color(),
                amount().boxed(),
                (0usize..4).prop_map(|i| (i < 2).then_some(i)).boxed(),
            ),
            Self::Tame => (
                Just([1.0; 3]).boxed(),
                (1.0f32..60.0).boxed(),
                Just(None).boxed(),
            ),
        };
        // One light in four is a sun.
        let directional = (0u8..4).prop_map(|k| k == 0);
        (self.point(8.0), color, intensity, on_surface, directional)
            .prop_map(
                |(position, color, intensity, on_surface, directional)| LightRecipe {
                    position,
                    color,
                    intensity,
                    on_surface,
                    directional,
                },
            )
            .boxed()
    }

    /// The sampler and the depth.
    fn settings(self) -> BoxedStrategy<(Sampler, u8)> {
        let adaptive = Sampler::Adaptive { k: 2, threshold: 0 };
        match self {
            Self::Wild => (
                prop::sample::select(vec![
                    Sampler::Centre,
                    Sampler::Stratified(2),
                    Sampler::Prefiltered,
                    adaptive,
                    Sampler::sparse(),
                ]),
                0u8..=8,
            )
                .boxed(),
            Self::Tame => (
                prop::sample::select(vec![
                    Sampler::Centre,
                    Sampler::Stratified(2),
                    Sampler::Random(2),
                    Sampler::Prefiltered,
                    adaptive,
                    Sampler::sparse(),
                ]),
                0u8..4,
            )
                .boxed(),
        }
    }
}

/// Random recipes of `values` for a `Scene<C>` (see [`Recipe`]).
pub fn recipe<C: Capacities>(values: Values) -> impl Strategy<Value = Recipe<C>> {
    let tessera_core::kind::Counts {
        spheres: s,
        planes: p,
        triangles: t,
        boxes: b,
        cylinders: cy,
        disks: di,
        materials: m,
        lights: l,
        ..
    } = C::COUNTS;
    let index = 0..m;
    let size = match values {
        Values::Wild => three(wild()).boxed(),
        Values::Tame => three(0.05f32..2.0).boxed(),
    };
    (
        (values.camera(), values.lighting()),
        prop::collection::vec(
            (values.point(4.0), values.length(0.05, 2.0), index.clone()),
            0..s,
        ),
        prop::collection::vec((values.point(3.0), values.point(1.0), index.clone()), 0..p),
        prop::collection::vec((three(values.point(3.0)), index.clone()), 0..t),
        prop::collection::vec((values.point(3.0), size, index.clone()), 0..b),
        prop::collection::vec(
            (
                values.point(3.0),
                values.point(3.0),
                values.length(0.05, 2.0),
                any::<bool>(),
                index.clone(),
            ),
            0..cy,
        ),
        prop::collection::vec(
            (
                values.point(3.0),
                values.point(1.0),
                values.length(0.05, 2.0),
                0.0f32..1.0,
                index,
            ),
            0..di,
        ),
        prop::collection::vec(values.material(), 1..m),
        prop::collection::vec(values.light(), 0..l),
        values.settings(),
    )
        .prop_map(
            |(
                (camera, (ambient, background)),
                spheres,
                planes,
                triangles,
                boxes,
                cylinders,
                disks,
                materials,
                lights,
                (sampler, depth),
            )| Recipe {
                camera,
                ambient,
                background,
                spheres,
                planes,
                triangles,
                boxes,
                cylinders,
                disks,
                materials,
                lights,
                sampler,
                depth,
                scene: PhantomData,
            },
        )
}

fn v(a: [f32; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

fn c(a: [f32; 3]) -> Color {
    Color::new(a[0], a[1], a[2])
}

impl MaterialRecipe {
    /// The material, or `None` where a value is refused.
    #[must_use]
    pub fn build(&self) -> Option<Material> {
        let [ambient, diffuse, specular, reflectivity, transparency] = self.weights;
        let transparency = if self.split {
            transparency * (1.0 - reflectivity)
        } else {
            transparency
        };
        let mat = Material::matte(c(self.color))
            .with_ambient(ambient)
            .ok()?
            .with_diffuse(diffuse)
            .ok()?
            .with_specular(specular, self.shininess)
            .ok()?
            .with_reflectivity(reflectivity)
            .ok()?
            .with_transparency(transparency, self.ior)
            .ok()?;
        let texture = match self.texture {
            1 => Texture::Checker {
                a: c(self.color),
                b: c(self.other),
                scale: self.scale,
            },
            2 => Texture::Fringes {
                color: c(self.color),
                spacing: self.scale,
            },
            _ => return Some(mat),
        };
        mat.with_texture(texture).ok()
    }
}

impl<C: Capacities> Recipe<C> {
    /// The scene of the recipe: each item (material, shape, light, the ambient
    /// light, the background) that its constructor refuses is left out; `None`
    /// when the camera or every material is refused.
    #[must_use]
    pub fn build(&self) -> Option<Scene<C>> {
        let (pos, fwd, fovy, near, far) = self.camera;
        let cam = Camera::try_new(v(pos), v(fwd), Vec3::Y, fovy, near, far).ok()?;
        let mut s = Scene::new(cam);
        let _ = s.set_ambient(c(self.ambient));
        let _ = s.set_background(c(self.background));
        for m in &self.materials {
            if let Some(mat) = m.build() {
                s.add_material(mat).ok()?;
            }
        }
        let count = s.view().materials().len();
        if count == 0 {
            return None;
        }
        let id = |i: usize| MaterialId((i % count) as u16);
        let mut surface_points = Vec::new();
        for &(centre, radius, m) in &self.spheres {
            if let Ok(g) = Sphere::try_new(v(centre), radius) {
                s.add_sphere(g, id(m)).ok()?;
                surface_points.push(v(centre) + Vec3::new(radius, 0.0, 0.0));
            }
        }
        for &(p, n, m) in &self.planes {
            if let Ok(g) = Plane::try_new(v(p), v(n)) {
                s.add_plane(g, id(m)).ok()?;
                surface_points.push(v(p));
            }
        }
        for &([a, b, c], m) in &self.triangles {
            if let Ok(g) = Triangle::try_new(v(a), v(b), v(c)) {
                s.add_triangle(g, id(m)).ok()?;
            }
        }
        for &(min, size, m) in &self.boxes {
            if let Ok(g) = Aabb::try_new(v(min), v(min) + v(size).abs()) {
                s.add_box(g, id(m)).ok()?;
            }
        }
        for &(base, top, radius, capped, m) in &self.cylinders {
            if let Ok(g) = Cylinder::try_new(v(base), v(top), radius, capped) {
                s.add(g, id(m)).ok()?;
            }
        }
        for &(centre, normal, radius, inner, m) in &self.disks {
            if let Ok(g) = Disk::try_new(v(centre), v(normal), radius, radius * inner) {
                s.add(g, id(m)).ok()?;
                surface_points.push(v(centre));
            }
        }
        for l in &self.lights {
            let p = match l.on_surface.and_then(|i| surface_points.get(i)) {
                Some(&q) => q,
                None => v(l.position),
            };
            let light = if l.directional {
                Light::directional(v(l.position), c(l.color), l.intensity)
            } else {
                Light::point(p, c(l.color), l.intensity)
            };
            if let Ok(light) = light {
                s.add_light(light).ok()?;
            }
        }
        Some(s)
    }

    /// The render settings: the recipe's sampler and depth, `seed`, linear
    /// output.
    #[must_use]
    pub fn settings(&self, seed: u32) -> RenderSettings {
        RenderSettings {
            sampler: self.sampler,
            max_depth: self.depth,
            seed,
            encoding: Encoding::Linear,
        }
    }
}
