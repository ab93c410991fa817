//! Rigid mesh instances (feature `instances`): a mesh of the view (its faces and
//! BVH where they lie, in flash on a chip, in the mesh's own space) drawn any
//! number of times, each [`Instance`] with its own rotation, scale (uniform or
//! per axis, a mirror allowed) and translation, which may change every frame.
//!
//! The two levels of the search: the top level is [`Instances`], in RAM, each
//! instance with its transforms both ways and its box in the world (the mesh's
//! root box carried through its transform), rebuilt for an instance only when
//! it moves ([`Instances::set`]); a ray tests an instance's box, then is
//! carried into its space (`origin' = M^-1 (origin - t)`, `dir' = M^-1 dir`,
//! not normalised, so that a time along it is the time along the world ray)
//! and searches the mesh's BVH there, as every production ray tracer does. The
//! nearest face is then located in the mesh's space and carried into the
//! world, its normals by the inverse transpose.
//!
//! **Error bounds.** The hit is located in the mesh's space, with the ray
//! the search used there (the world ray's barycentrics would not add up with
//! them: a point far from the origin would move by their difference times its
//! coordinates), then carried into the world. Its bound is the face's own in
//! the mesh's space carried (`|M| e`), plus what carrying the point rounds
//! (`gamma(3) (|M| |p| + |t|)`, pbrt 3rd ed. 3.9.4), plus twice what
//! carrying a leaving ray's origin back into the mesh's space rounds, seen in
//! the world (`|M| gamma(3) (|M^-1| |p_w| + |M^-1 t|)`): a shadow or bounced
//! ray moved off the surface by the sum starts, in the mesh's space too, on
//! its side of every face.
//!
//! The top level is a list, not a tree: an instance's box test is one slab
//! test, and a scene holds few instances (a tree pays from some tens of boxes;
//! `MAX_INSTANCES` bounds what the hit's index holds). A tile's culling lists
//! the instances and meshes its rays may reach (module `cull`), by the same
//! boxes: its camera and shadow rays test only those.

use crate::cull::Hull;
use crate::error::{Error, Field, List, MAX_EXTENT, flush};
use crate::geometry::Triangle;
use crate::mesh::{MAX_MESHES, Mesh};
use crate::ray::Ray;
use crate::vec::Vec3;

/// The most instances a view takes: a hit names an instance and its face in one
/// index (`(MAX_MESHES + instance) << 16 | face`, under `2^29`).
pub const MAX_INSTANCES: usize = 4096;

/// The smallest and largest magnitude of an instance's scale on an axis: `2^-20`
/// and `2^20`. Beyond, the mesh's faces (whose own numbers the view checked)
/// could collapse below the rounding of their vertices or grow past the scene's
/// extent within one instance.
pub const MIN_SCALE: f32 = 1.0 / (1u32 << 20) as f32;
/// See [`MIN_SCALE`].
pub const MAX_SCALE: f32 = (1u32 << 20) as f32;

/// Where an instance lies: `world = translation + R(rotation) (scale * p)` for a
/// point `p` of its mesh (glTF's TRS order). Written as numbers (a `const`
/// table for a baked scene); checked by [`Instances::push`] and
/// [`Instances::set`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The rotation, a quaternion `[x, y, z, w]` (normalised when checked; of
    /// length 0 refused).
    pub rotation: [f32; 4],
    /// The scale on each axis of the mesh (a negative one mirrors).
    pub scale: [f32; 3],
    /// The translation.
    pub translation: [f32; 3],
}

impl Placement {
    /// The mesh where it lies.
    pub const IDENTITY: Self = Self {
        rotation: [0.0, 0.0, 0.0, 1.0],
        scale: [1.0; 3],
        translation: [0.0; 3],
    };

    /// A placement of these numbers (checked when an instance takes it).
    #[must_use]
    pub const fn new(rotation: [f32; 4], scale: [f32; 3], translation: [f32; 3]) -> Self {
        Self {
            rotation,
            scale,
            translation,
        }
    }

    /// The transform it stands for, checked: each number finite, the
    /// quaternion of non-zero length (normalised), each scale's magnitude in
    /// `[MIN_SCALE, MAX_SCALE]`, the translation within the scene's extent
    /// (subnormal numbers read as zeros, the scene's rule).
    fn transform(&self) -> Result<Affine, Error> {
        let q = self.rotation.map(flush);
        if q.iter().any(|x| !x.is_finite()) {
            return Err(Error::NotFinite(Field::InstanceRotation));
        }
        let [x, y, z, w] = q;
        let len2 = x * x + y * y + z * z + w * w;
        // Below 2^-60 the squares underflow towards subnormals: no direction.
        let tiny = 1.0 / (1u64 << 60) as f32;
        if len2.is_nan() || len2 < tiny || !len2.is_finite() {
            return Err(Error::ZeroLength(Field::InstanceRotation));
        }
        let inv = 1.0 / crate::math::sqrt(len2);
        let [x, y, z, w] = [x * inv, y * inv, z * inv, w * inv];
        let s = self.scale.map(flush);
        if s.iter().any(|x| !x.is_finite()) {
            return Err(Error::NotFinite(Field::InstanceScale));
        }
        if s.iter()
            .any(|v| !(v.abs() >= MIN_SCALE && v.abs() <= MAX_SCALE))
        {
            return Err(Error::OutOfRange {
                field: Field::InstanceScale,
                range: "[2^-20, 2^20] in magnitude on each axis (not 0)",
            });
        }
        let t = Vec3::new(
            self.translation[0],
            self.translation[1],
            self.translation[2],
        );
        let t = crate::error::position(crate::error::flush3(t), Field::InstanceTranslation)?;
        // The rotation's matrix (unit quaternion), rows.
        let r = [
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
        ];
        let r = r.map(|row| row.map(flush));
        // M = R diag(s): column j scaled by s_j. M^-1 = diag(1/s) R^T.
        let [sx, sy, sz] = s;
        let m = r.map(|[a, b, c]| Vec3::new(a * sx, b * sy, c * sz));
        let [[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]] = r;
        let (kx, ky, kz) = (1.0 / sx, 1.0 / sy, 1.0 / sz);
        let inv = [
            Vec3::new(r00 * kx, r10 * kx, r20 * kx),
            Vec3::new(r01 * ky, r11 * ky, r21 * ky),
            Vec3::new(r02 * kz, r12 * kz, r22 * kz),
        ];
        let to_object = Linear(inv);
        let back = to_object.apply(t);
        Ok(Affine {
            to_world: Linear(m),
            t,
            to_object,
            back: -back,
        })
    }
}

/// A 3x3 matrix by its rows.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Linear([Vec3; 3]);

impl Linear {
    /// `M v`.
    #[inline(always)]
    fn apply(&self, v: Vec3) -> Vec3 {
        let [a, b, c] = &self.0;
        Vec3::new(a.dot(v), b.dot(v), c.dot(v))
    }

    /// `M^T v`.
    #[inline(always)]
    fn apply_transposed(&self, v: Vec3) -> Vec3 {
        let [a, b, c] = self.0;
        a * v.x + b * v.y + c * v.z
    }

    /// `|M| v` for `v >= 0` (each entry's magnitude).
    #[inline(always)]
    fn abs_apply(&self, v: Vec3) -> Vec3 {
        let [a, b, c] = &self.0;
        Vec3::new(a.abs().dot(v), b.abs().dot(v), c.abs().dot(v))
    }
}

/// An instance's transforms: `world = M p + t`, `p = M^-1 world + back`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Affine {
    to_world: Linear,
    t: Vec3,
    to_object: Linear,
    back: Vec3,
}

/// A mesh of the view and where it lies: what [`Instances`] takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// The mesh, by its index in the view's meshes.
    pub mesh: u16,
    /// Where it lies.
    pub placement: Placement,
}

impl Instance {
    /// Mesh `mesh` placed by `placement` (checked when [`Instances`] takes it).
    #[must_use]
    pub const fn new(mesh: u16, placement: Placement) -> Self {
        Self { mesh, placement }
    }
}

/// An instance as the search takes it: its mesh, its transforms and its box in
/// the world. Made by [`Instances`] (in RAM), or baked (`tessera bake` writes
/// a scene's instances as a `static` table of them, which
/// [`crate::BakedScene::view`] checks against what [`Instances`] makes of
/// the same placements).
#[derive(Clone, Copy, Debug)]
pub struct Placed<'a> {
    pub(crate) mesh: &'a Mesh<'a>,
    index: u16,
    placement: Placement,
    affine: Affine,
    /// The box of its faces in the world, grown as the culling's hulls are.
    pub(crate) hull: Option<Hull>,
}

/// The numbers of a [`Placed`] beyond its placement: its transforms (`M`,
/// `t`, `M^-1`, `M^-1 t` negated, rows) and its hull (grown box and reach;
/// NaN for none).
#[doc(hidden)]
pub type PlacedNumbers = ([f32; 24], [f32; 7]);

impl<'a> Placed<'a> {
    /// Baked data (what [`Placed::numbers`] gave on the host), not checked
    /// here: [`crate::BakedScene::view`] checks it.
    #[doc(hidden)]
    #[must_use]
    pub const fn baked(
        mesh: &'a Mesh<'a>,
        index: u16,
        placement: Placement,
        numbers: PlacedNumbers,
    ) -> Self {
        let (a, h) = numbers;
        let [
            m0,
            m1,
            m2,
            m3,
            m4,
            m5,
            m6,
            m7,
            m8,
            t0,
            t1,
            t2,
            i0,
            i1,
            i2,
            i3,
            i4,
            i5,
            i6,
            i7,
            i8,
            b0,
            b1,
            b2,
        ] = a;
        Self {
            mesh,
            index,
            placement,
            affine: Affine {
                to_world: Linear([
                    Vec3::new(m0, m1, m2),
                    Vec3::new(m3, m4, m5),
                    Vec3::new(m6, m7, m8),
                ]),
                t: Vec3::new(t0, t1, t2),
                to_object: Linear([
                    Vec3::new(i0, i1, i2),
                    Vec3::new(i3, i4, i5),
                    Vec3::new(i6, i7, i8),
                ]),
                back: Vec3::new(b0, b1, b2),
            },
            hull: if h[6].is_nan() {
                None
            } else {
                Some(Hull::from_parts(h))
            },
        }
    }

    /// The numbers [`Placed::baked`] takes back.
    #[doc(hidden)]
    #[must_use]
    pub fn numbers(&self) -> PlacedNumbers {
        let a = &self.affine;
        let mut out = [0.0; 24];
        let parts = [
            a.to_world.0[0],
            a.to_world.0[1],
            a.to_world.0[2],
            a.t,
            a.to_object.0[0],
            a.to_object.0[1],
            a.to_object.0[2],
            a.back,
        ];
        for (o, v) in out.chunks_exact_mut(3).zip(parts) {
            o.copy_from_slice(&[v.x, v.y, v.z]);
        }
        let h = self.hull.map_or([f32::NAN; 7], |h| h.parts());
        (out, h)
    }

    /// Which mesh and where.
    #[must_use]
    pub fn instance(&self) -> Instance {
        Instance::new(self.index, self.placement)
    }

    /// True when `other` is the same instance to the bit (NaN a hull's
    /// absence on both).
    pub(crate) fn same(&self, other: &Self) -> bool {
        let bits = |p: &Self| {
            let (a, h) = p.numbers();
            let mut out = [0u32; 31];
            for (o, x) in out.iter_mut().zip(a.iter().chain(h.iter())) {
                *o = x.to_bits();
            }
            out
        };
        core::ptr::eq(self.mesh, other.mesh)
            && self.index == other.index
            && self.placement == other.placement
            && bits(self) == bits(other)
    }
}

impl Placed<'_> {
    /// The ray in the mesh's space (times along it are the world ray's).
    #[inline(always)]
    pub(crate) fn ray(&self, ray: &Ray) -> Ray {
        let a = &self.affine;
        Ray {
            origin: a.to_object.apply(ray.origin) + a.back,
            dir: a.to_object.apply(ray.dir),
        }
    }

    /// A point of the mesh in the world.
    #[inline(always)]
    fn point(&self, p: Vec3) -> Vec3 {
        self.affine.to_world.apply(p) + self.affine.t
    }

    /// The largest magnitude of its scale: no length grows more when carried
    /// into the world (the rotation keeps lengths).
    pub(crate) fn largest_scale(&self) -> f32 {
        let [x, y, z] = self.placement.scale.map(crate::math::abs);
        crate::math::max(x, crate::math::max(y, z))
    }

    /// Face `f` in the world: its vertices carried there.
    #[inline(always)]
    pub(crate) fn triangle(&self, f: usize) -> Option<Triangle> {
        let [a, b, c] = self.mesh.triangle(f)?.vertices();
        let v = |p: Vec3| {
            let q = self.point(p);
            [q.x, q.y, q.z]
        };
        Some(Triangle::baked(v(a), v(b), v(c)))
    }

    /// A normal of the mesh in the world (the inverse transpose; not
    /// normalised).
    #[inline(always)]
    fn normal(&self, n: Vec3) -> Vec3 {
        self.affine.to_object.apply_transposed(n)
    }

    /// The hit `hit` of `ray` on face `f` located in the mesh's space, where
    /// the search found it (the point from the same ray's barycentrics, which
    /// the world ray's would not match to the rounding of carrying it): the
    /// point there, the face's normal there and the `aux` of
    /// [`crate::geometry::Locate`].
    #[inline(always)]
    pub(crate) fn locate(
        &self,
        f: usize,
        ray: &Ray,
        hit: &crate::geometry::Candidate,
    ) -> Option<(Triangle, Ray, Vec3, Vec3, Vec3)> {
        use crate::geometry::Locate;
        let tri = self.mesh.triangle(f)?;
        let local = self.ray(ray);
        let (p, n, aux) = tri.locate(&local, hit);
        Some((tri, local, p, n, aux))
    }

    /// The point `p` and unit normal `n` of the mesh's space in the world.
    #[inline(always)]
    pub(crate) fn carry(&self, p: Vec3, n: Vec3) -> (Vec3, Vec3) {
        (self.point(p), self.normal(n).normalize_or(n))
    }

    /// The error bound in the world of the point of `hit` on face `f` (see
    /// the module doc): the face's own bound in the mesh's space carried
    /// there, what carrying the point rounds, and what carrying a leaving
    /// ray's origin back rounds.
    pub(crate) fn error(&self, f: usize, ray: &Ray, hit: &crate::geometry::Candidate) -> Vec3 {
        use crate::geometry::Locate;
        let Some((tri, local, p, _, aux)) = self.locate(f, ray, hit) else {
            return Vec3::ZERO;
        };
        let a = &self.affine;
        let g = crate::math::gamma(3);
        let own = a.to_world.abs_apply(tri.error(&local, hit, p, aux));
        let carried = (a.to_world.abs_apply(p.abs()) + a.t.abs()) * g;
        let w = self.point(p);
        let back = a.to_object.abs_apply(w.abs()) + a.back.abs();
        // The sum's own rounding is far inside the factor 2 on the last term.
        own + carried + a.to_world.abs_apply(back) * (2.0 * g)
    }

    /// [`Mesh::shading_normal`] in the world: the vertex normals carried by
    /// the inverse transpose and normalised (the normals of the mesh carried
    /// into the world), interpolated, turned to the side of `n`.
    pub(crate) fn shading_normal(&self, f: usize, b: [f32; 3], n: Vec3) -> Vec3 {
        self.mesh
            .shading_normal_with(f, b, n, |m| self.normal(m).normalize_or(m))
    }

    /// [`Mesh::lift`] in the world, as for the mesh carried there (its unit
    /// normals carried, its tangent planes the carried ones), from the point
    /// where `ray` hit face `f` in the mesh's space: the differences of
    /// points carried as vectors, so that a far translation cancels in none.
    pub(crate) fn lift(
        &self,
        f: usize,
        b: [f32; 3],
        ray: &Ray,
        hit: &crate::geometry::Candidate,
        out: f32,
    ) -> Vec3 {
        let Some((_, _, p, _, _)) = self.locate(f, ray, hit) else {
            return Vec3::ZERO;
        };
        let [x, y, z] = self.placement.scale;
        let winding = if x * y * z < 0.0 { -1.0 } else { 1.0 };
        self.mesh.lift_with(
            f,
            b,
            p,
            out,
            |v| self.affine.to_world.apply(v),
            |m| self.normal(m).normalize_or(m),
            winding,
        )
    }
}

/// The top level of a view's instances, in RAM: at most `N` (and
/// [`MAX_INSTANCES`]) instances of the meshes of one view, each checked and
/// carried into the world when it is placed, so that a frame whose instances
/// move pays for those alone ([`Instances::set`]), then
/// `SceneView::with_instances` for the frame's view.
///
/// ```
/// use tessera_core::instance::{Instance, Instances, Placement};
///
/// # #[cfg(feature = "teapot")]
/// # fn main() -> Result<(), tessera_core::Error> {
/// # use tessera_core::{Camera, Scene, Vec3};
/// # let cam = Camera::look_at(Vec3::new(0.0, 2.0, 9.0), Vec3::ZERO, Vec3::Y, 0.1, 100.0)?;
/// # let mut scene: Scene<tessera_core::capacities!(materials: 2)> = Scene::new(cam);
/// # for _ in 0..2 {
/// #     scene.add_material(tessera_core::material::Material::matte(tessera_core::Color::WHITE))?;
/// # }
/// let view = scene.view().with_meshes(tessera_core::builtin::TEAPOT_MESHES)?;
/// let mut teapots: Instances<'_, 4> = Instances::new(&view);
/// for x in [-3.0, 3.0] {
///     teapots.push(Instance::new(0, Placement::new([0.0, 0.0, 0.0, 1.0], [0.5; 3], [x, 0.0, 0.0])))?;
/// }
/// // A frame: the second teapot turns a quarter about y.
/// let s = core::f32::consts::FRAC_1_SQRT_2;
/// teapots.set(1, Placement::new([0.0, s, 0.0, s], [0.5; 3], [3.0, 0.0, 0.0]))?;
/// let frame = view.with_instances(&teapots)?;
/// assert_eq!(frame.instance_count(), 2);
/// # Ok(())
/// # }
/// # #[cfg(not(feature = "teapot"))]
/// # fn main() {}
/// ```
#[derive(Clone, Debug)]
pub struct Instances<'a, const N: usize> {
    meshes: &'a [Mesh<'a>],
    placed: heapless::Vec<Placed<'a>, N>,
}

impl<'a, const N: usize> Instances<'a, N> {
    /// No instance of `meshes` (a view's: `Instances::new`, in module `view`).
    pub(crate) fn empty(meshes: &'a [Mesh<'a>]) -> Self {
        Self {
            meshes,
            placed: heapless::Vec::new(),
        }
    }

    /// The instances `placed` of `meshes` (a view's: `Instances::new` and
    /// `Instances::of`, in module `view`, which this layer does not import).
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] for more than `N`.
    pub(crate) fn over(meshes: &'a [Mesh<'a>], placed: &[Placed<'a>]) -> Result<Self, Error> {
        let mut out = heapless::Vec::new();
        for &p in placed {
            out.push(p).map_err(|_| Error::CapacityExceeded {
                list: List::Instances,
                capacity: N,
            })?;
        }
        Ok(Self {
            meshes,
            placed: out,
        })
    }

    /// Adds `instance`; returns its index.
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] beyond `N` (or [`MAX_INSTANCES`]) instances;
    /// [`Error::MeshOutOfRange`] for a mesh the view does not have; the
    /// placement's errors ([`Instances::set`]).
    pub fn push(&mut self, instance: Instance) -> Result<usize, Error> {
        let room = N.min(MAX_INSTANCES);
        if self.placed.len() >= room {
            return Err(Error::CapacityExceeded {
                list: List::Instances,
                capacity: room,
            });
        }
        let placed = self.place(instance)?;
        let i = self.placed.len();
        self.placed
            .push(placed)
            .map_err(|_| Error::CapacityExceeded {
                list: List::Instances,
                capacity: room,
            })?;
        Ok(i)
    }

    /// Replaces the instances with `list` (all checked before any is kept).
    ///
    /// # Errors
    /// As [`Instances::push`], for the first instance refused; the instances are
    /// then left as they were.
    pub fn place_all(&mut self, list: &[Instance]) -> Result<(), Error> {
        let mut placed = heapless::Vec::new();
        let room = N.min(MAX_INSTANCES);
        for &i in list {
            let p = self.place(i)?;
            if placed.len() >= room || placed.push(p).is_err() {
                return Err(Error::CapacityExceeded {
                    list: List::Instances,
                    capacity: room,
                });
            }
        }
        self.placed = placed;
        Ok(())
    }

    /// Moves instance `index` to `placement`: its transforms and box alone are
    /// computed again (the frame's cost of a moving instance).
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] for an index beyond the instances;
    /// [`Error::NotFinite`], [`Error::ZeroLength`] (a quaternion of length 0)
    /// or [`Error::OutOfRange`] (a scale of 0 or beyond [`MAX_SCALE`], a
    /// translation or a placed mesh beyond the scene's extent) naming the
    /// instance's rotation, scale or translation. The instance is then left
    /// where it was.
    pub fn set(&mut self, index: usize, placement: Placement) -> Result<(), Error> {
        let len = self.placed.len();
        let Some(old) = self.placed.get(index) else {
            return Err(Error::CapacityExceeded {
                list: List::Instances,
                capacity: len,
            });
        };
        let placed = self.place(Instance::new(old.index, placement))?;
        if let Some(slot) = self.placed.get_mut(index) {
            *slot = placed;
        }
        Ok(())
    }

    /// How many instances.
    #[must_use]
    pub fn len(&self) -> usize {
        self.placed.len()
    }

    /// True when there is none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.placed.is_empty()
    }

    /// Instance `index` as it was placed.
    #[must_use]
    pub fn get(&self, index: usize) -> Option<Instance> {
        self.placed
            .get(index)
            .map(|p| Instance::new(p.index, p.placement))
    }

    /// The numbers of instance `index` as a baked table writes them
    /// ([`Placed::baked`]).
    #[doc(hidden)]
    #[must_use]
    pub fn numbers(&self, index: usize) -> Option<PlacedNumbers> {
        self.placed.get(index).map(Placed::numbers)
    }

    /// The instances as the view takes them.
    pub(crate) fn placed(&self) -> &[Placed<'a>] {
        &self.placed
    }

    /// The meshes they are of.
    pub(crate) fn meshes(&self) -> &'a [Mesh<'a>] {
        self.meshes
    }

    /// `instance` checked and carried into the world.
    fn place(&self, instance: Instance) -> Result<Placed<'a>, Error> {
        let count = self.meshes.len();
        let Some(mesh) = self.meshes.get(usize::from(instance.mesh)) else {
            return Err(Error::MeshOutOfRange {
                id: instance.mesh,
                count: u16::try_from(count).unwrap_or(u16::MAX),
            });
        };
        let affine = instance.placement.transform()?;
        let mut placed = Placed {
            mesh,
            index: instance.mesh,
            placement: instance.placement,
            affine,
            hull: None,
        };
        // The mesh's root box, its eight corners carried into the world.
        if let Some(root) = mesh.bvh().nodes.first() {
            let (lo, hi) = (root.min, root.max);
            let mut min = Vec3::splat(f32::INFINITY);
            let mut max = Vec3::splat(f32::NEG_INFINITY);
            for k in 0..8 {
                let c = Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                let w = placed.point(c);
                min = min.min(w);
                max = max.max(w);
            }
            let m = min.abs().max(max.abs()).max_element();
            if m.is_nan() || m > MAX_EXTENT {
                return Err(Error::OutOfRange {
                    field: Field::InstanceTranslation,
                    range: "the scene's extent for every point of the placed mesh (2^60)",
                });
            }
            // A point of the mesh far from the mesh's origin may cancel the
            // translation: the carried point's rounding then scales with both.
            let far = placed.affine.t.abs().max_element();
            placed.hull = Hull::reaching(min, max, far);
        }
        Ok(placed)
    }
}

/// Checks baked instances `placed` of `meshes`: each of one of them (by
/// index and place), at most [`MAX_INSTANCES`], and to the bit what
/// [`Instances`] makes of its placement.
pub(crate) fn check_baked(meshes: &[Mesh<'_>], placed: &[Placed<'_>]) -> Result<(), Error> {
    if placed.len() > MAX_INSTANCES {
        return Err(Error::CapacityExceeded {
            list: List::Instances,
            capacity: MAX_INSTANCES,
        });
    }
    let made: Instances<'_, 1> = Instances {
        meshes,
        placed: heapless::Vec::new(),
    };
    for (i, p) in placed.iter().enumerate() {
        let again = made.place(p.instance())?;
        if !again.same(p) {
            return Err(Error::BadBaked {
                list: List::Instances,
                index: u16::try_from(i).unwrap_or(u16::MAX),
            });
        }
    }
    Ok(())
}

/// The meshes that `instances` draw (a bit per mesh of the view): these are
/// drawn only where their instances lie.
pub(crate) fn instanced(instances: &[Placed<'_>]) -> u16 {
    instances.iter().fold(0, |m, p| {
        m | 1u16.checked_shl(u32::from(p.index)).unwrap_or(0)
    })
}

const _: () = assert!(MAX_MESHES <= 16 && ((MAX_MESHES + MAX_INSTANCES) << 16) < (1 << 29) - 1);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{BakedBvh, Bvh, BvhNode};
    use crate::material::{Material, MaterialId};
    use crate::primitive::Primitive;
    use crate::{
        Camera, Color, RenderSettings, Renderer, Scene, SceneView, Tile, TileCoord, Viewport,
    };
    use crate::{light::Light, search::first_hit};

    extern crate std;
    use std::vec::Vec as StdVec;

    /// A mesh's parts: vertices, faces, normals and its BVH.
    struct Parts {
        v: StdVec<[f32; 3]>,
        f: StdVec<[u16; 3]>,
        n: StdVec<[f32; 3]>,
        nodes: StdVec<BvhNode>,
        order: StdVec<u16>,
        reach: f32,
    }

    impl Parts {
        fn new(v: StdVec<[f32; 3]>, f: StdVec<[u16; 3]>, n: StdVec<[f32; 3]>) -> Self {
            let tris: StdVec<Primitive<Triangle>> = f
                .iter()
                .map(|&[a, b, c]| Primitive {
                    geometry: Triangle::baked(
                        v[usize::from(a)],
                        v[usize::from(b)],
                        v[usize::from(c)],
                    ),
                    material: MaterialId(0),
                })
                .collect();
            let mut bvh: std::boxed::Box<Bvh<4096, 2048>> = std::boxed::Box::default();
            bvh.build(&tris).unwrap();
            let (nodes, order, reach) = (bvh.nodes().to_vec(), bvh.order().to_vec(), bvh.reach());
            Self {
                v,
                f,
                n,
                nodes,
                order,
                reach,
            }
        }

        fn mesh(&self) -> Mesh<'_> {
            Mesh::new(
                &self.v,
                &self.f,
                &self.n,
                MaterialId(0),
                BakedBvh::new(&self.nodes, &self.order, self.reach),
            )
        }

        /// The same mesh carried by `to` in f64 (vertices, and normals by the
        /// inverse transpose): the world-space mesh an instance stands for.
        fn carried(&self, p: &Placement) -> Self {
            let m = matrix(p);
            let inv_t = inverse_transpose(&m);
            let t = p.translation.map(f64::from);
            let apply = |m: &[[f64; 3]; 3], x: [f32; 3]| {
                let x = x.map(f64::from);
                [0, 1, 2].map(|i| m[i][0] * x[0] + m[i][1] * x[1] + m[i][2] * x[2])
            };
            let v = self
                .v
                .iter()
                .map(|&x| {
                    let w = apply(&m, x);
                    [0, 1, 2].map(|i| (w[i] + t[i]) as f32)
                })
                .collect();
            let n = self
                .n
                .iter()
                .map(|&x| {
                    let w = apply(&inv_t, x);
                    let l = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                    // Subnormal components read as zeros (the scene's rule).
                    w.map(|c| crate::error::flush((c / l) as f32))
                })
                .collect();
            Self::new(v, self.f.clone(), n)
        }
    }

    /// `R diag(s)` in f64, from the placement's numbers (its own derivation:
    /// the rotation as Rodrigues' formula of the quaternion's axis and angle).
    fn matrix(p: &Placement) -> [[f64; 3]; 3] {
        let q = p.rotation.map(f64::from);
        let len = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
        let q = q.map(|c| c / len);
        let s = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
        let angle = 2.0 * s.atan2(q[3]);
        let k = if s > 0.0 {
            [q[0] / s, q[1] / s, q[2] / s]
        } else {
            [1.0, 0.0, 0.0]
        };
        let (sn, cs) = angle.sin_cos();
        let mut r = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let delta = if i == j { 1.0 } else { 0.0 };
                let kx = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]];
                r[i][j] = cs * delta + sn * kx[i][j] + (1.0 - cs) * k[i] * k[j];
            }
        }
        let sc = p.scale.map(f64::from);
        r.map(|row| [row[0] * sc[0], row[1] * sc[1], row[2] * sc[2]])
    }

    fn inverse_transpose(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        // The cofactor matrix is det * M^-T: its scale goes when normalised.
        let c = |i: usize, j: usize| {
            let (a, b) = ((i + 1) % 3, (i + 2) % 3);
            let (x, y) = ((j + 1) % 3, (j + 2) % 3);
            m[a][x] * m[b][y] - m[a][y] * m[b][x]
        };
        let det = m[0][0] * c(0, 0) + m[0][1] * c(0, 1) + m[0][2] * c(0, 2);
        [0, 1, 2].map(|i| [0, 1, 2].map(|j| c(i, j) / det))
    }

    /// A UV sphere of radius 1 at the origin, smooth (exact unit normals).
    fn sphere(rings: u16, sectors: u16) -> Parts {
        let mut v = StdVec::new();
        for i in 0..=rings {
            let th = core::f64::consts::PI * f64::from(i) / f64::from(rings);
            for j in 0..sectors {
                let ph = 2.0 * core::f64::consts::PI * f64::from(j) / f64::from(sectors);
                v.push([
                    (th.sin() * ph.cos()) as f32,
                    th.cos() as f32,
                    (th.sin() * ph.sin()) as f32,
                ]);
            }
        }
        let at = |i: u16, j: u16| i * sectors + j % sectors;
        let mut f = StdVec::new();
        for i in 0..rings {
            for j in 0..sectors {
                let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
                if i > 0 {
                    f.push([a, b, c]);
                }
                if i + 1 < rings {
                    f.push([a, c, d]);
                }
            }
        }
        let n = v
            .iter()
            .map(|p| {
                let q = Vec3::new(p[0], p[1], p[2]).normalize_or(Vec3::Y);
                [q.x, q.y, q.z]
            })
            .collect();
        Parts::new(v, f, n)
    }

    /// Where the scenes below lie: scaled by `k` about the origin, then moved
    /// by `o` (1 and 0 for the plain scene).
    #[derive(Clone, Copy)]
    struct Frame {
        k: f32,
        o: Vec3,
    }

    const PLAIN: Frame = Frame {
        k: 1.0,
        o: Vec3::ZERO,
    };

    impl Frame {
        fn at(self, p: Vec3) -> Vec3 {
            p * self.k + self.o
        }
    }

    fn camera_in(f: Frame) -> Camera {
        Camera::look_at(
            f.at(Vec3::new(0.3, 1.5, 4.0)),
            f.at(Vec3::ZERO),
            Vec3::Y,
            0.1 * f.k,
            100.0 * f.k,
        )
        .unwrap()
    }

    type Caps = crate::capacities!(planes: 1, materials: 2, lights: 2);

    /// A floor, a shiny red material for the meshes, two lights.
    fn scene() -> Scene<Caps> {
        scene_in(PLAIN)
    }

    fn scene_in(f: Frame) -> Scene<Caps> {
        let mut s = Scene::new(camera_in(f));
        s.set_ambient(Color::splat(0.05)).unwrap();
        let red = Material::matte(Color::new(0.9, 0.3, 0.2))
            .with_specular(0.4, 30.0)
            .unwrap();
        s.add_material(red).unwrap();
        let grey = s.add_material(Material::matte(Color::splat(0.7))).unwrap();
        s.add_plane(
            crate::geometry::Plane::try_new(f.at(Vec3::new(0.0, -1.2, 0.0)), Vec3::Y).unwrap(),
            grey,
        )
        .unwrap();
        let k2 = f.k * f.k;
        s.add_light(
            Light::point(f.at(Vec3::new(-2.0, 3.0, 4.0)), Color::WHITE, 30.0 * k2).unwrap(),
        )
        .unwrap();
        s.add_light(
            Light::point(
                f.at(Vec3::new(3.0, 2.0, -1.0)),
                Color::splat(0.5),
                20.0 * k2,
            )
            .unwrap(),
        )
        .unwrap();
        s
    }

    const W: u16 = 64;
    const H: u16 = 48;

    fn render(v: &SceneView<'_>) -> StdVec<[u8; 3]> {
        render_in(v, PLAIN)
    }

    fn render_in(v: &SceneView<'_>, f: Frame) -> StdVec<[u8; 3]> {
        let vp = Viewport::new(W, H);
        let renderer = Renderer::try_new(&camera_in(f), vp, RenderSettings::default()).unwrap();
        let (across, down) = renderer.tile_grid(8);
        let (w, h) = (usize::from(W), usize::from(H));
        let mut px = std::vec![[0u8; 3]; w * h];
        for ty in 0..down {
            for tx in 0..across {
                let mut tile = Tile::<8>::new();
                renderer
                    .render_tile(v, TileCoord::new(tx, ty), &mut tile, &mut ())
                    .unwrap();
                for (k, p) in tile.pixels().enumerate() {
                    let (x, y) = (usize::from(tx) * 8 + k % 8, usize::from(ty) * 8 + k / 8);
                    if x < w && y < h {
                        px[y * w + x] = [p.r, p.g, p.b];
                    }
                }
            }
        }
        px
    }

    /// Pixels off by more than `levels` in some channel.
    fn off(a: &[[u8; 3]], b: &[[u8; 3]], levels: u8) -> usize {
        a.iter()
            .zip(b)
            .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > levels))
            .count()
    }

    /// A quarter turn about `axis` (0 x, 1 y, 2 z) as a quaternion.
    fn quarter(axis: usize) -> [f32; 4] {
        let s = core::f32::consts::FRAC_1_SQRT_2;
        let mut q = [0.0, 0.0, 0.0, s];
        q[axis] = s;
        q
    }

    /// A tile lists the instances it may see and no more: of two instances
    /// far left and far right, the tiles of the left half list the left one
    /// only, those of the right half the right one only, the sky's none; a
    /// floor tile may list a shadow's caster without seeing it. Culled or not,
    /// the same bytes.
    #[test]
    fn tiles_list_the_instances_they_may_see() {
        use crate::cull::{LISTS, PLANE_RECEIVERS, TileStorage};
        use crate::kind::KINDS;
        let parts = sphere(8, 12);
        let meshes = [parts.mesh()];
        let s = scene();
        let view = s.view().with_meshes(&meshes).unwrap();
        let mut inst: Instances<'_, 2> = Instances::new(&view);
        for x in [-1.6, 1.6] {
            let at = Placement::new([0.0, 0.0, 0.0, 1.0], [0.5; 3], [x, 0.0, 0.0]);
            inst.push(Instance::new(0, at)).unwrap();
        }
        let placed = view.with_instances(&inst).unwrap();
        let held = placed.culled_lists().unwrap();
        assert_eq!(held[KINDS], 3); // the mesh (drawn only by its instances) and two
        let renderer = Renderer::try_new(
            &camera_in(PLAIN),
            Viewport::new(W, H),
            RenderSettings::default(),
        )
        .unwrap();
        let (left, right) = (MAX_MESHES as u16, MAX_MESHES as u16 + 1);
        // Per tile of 8, row by row: its camera list of tops, and the tops
        // that may shadow the floor it sees from the first light.
        let mut tiles = StdVec::new();
        for ty in 0..H / 8 {
            for tx in 0..W / 8 {
                let (x0, y0) = (f32::from(tx) * 8.0, f32::from(ty) * 8.0);
                TileStorage::<Caps>::lend(Some(held), &mut |lists| {
                    let picks = lists.unwrap().build(
                        renderer.basis(),
                        &placed,
                        (x0, y0, x0 + 8.0, y0 + 8.0),
                    );
                    let camera: [&[u16]; LISTS] = picks.camera.or(picks.with_tops).unwrap();
                    let floor = picks.shadow.map_or_else(StdVec::new, |sh| {
                        sh.lists[KINDS]
                            .iter()
                            .filter(|&&e| e & 1 << PLANE_RECEIVERS != 0)
                            .map(|&e| (e & 0xffff) as u16)
                            .collect()
                    });
                    tiles.push((tx, camera[KINDS].to_vec(), floor));
                });
            }
        }
        let half = W / 16;
        for (tx, camera, _) in &tiles {
            assert!(!camera.contains(&0), "{tiles:?}"); // drawn by its instances only
            let wrong = if *tx < half { right } else { left };
            assert!(!camera.contains(&wrong), "{tiles:?}");
        }
        let sees = |top: u16| tiles.iter().any(|(_, c, _)| c.contains(&top));
        assert!(sees(left) && sees(right), "{tiles:?}");
        assert!(tiles.iter().any(|(_, c, _)| c.is_empty()), "{tiles:?}");
        // A shadow list culls too: some tile's floor lists a caster it does not
        // see, and some lists neither.
        assert!(
            tiles
                .iter()
                .any(|(_, c, f)| f.iter().any(|t| !c.contains(t))),
            "{tiles:?}"
        );
        assert!(
            tiles.iter().any(|(_, c, f)| !c.is_empty() && f.len() < 2),
            "{tiles:?}"
        );
        assert_eq!(render(&placed), render(&placed.without_culling_hook()));
    }

    /// An instance placed where the mesh lies draws what the mesh draws there.
    #[test]
    fn an_instance_at_the_identity_draws_the_mesh() {
        let parts = sphere(12, 24);
        let meshes = [parts.mesh()];
        let s = scene();
        let view = s.view().with_meshes(&meshes).unwrap();
        let mut inst: Instances<'_, 2> = Instances::new(&view);
        inst.push(Instance::new(0, Placement::IDENTITY)).unwrap();
        let placed = view.with_instances(&inst).unwrap();
        let (a, b) = (render(&view), render(&placed));
        // The same rays and faces; only the leaving rays' offsets (the
        // transform's terms in the bound) differ.
        assert_eq!(off(&a, &b, 1), 0);
        assert!(off(&a, &b, 0) <= a.len() / 200, "{}", off(&a, &b, 0));
    }

    /// A turned, scaled (per axis, one a mirror) and moved instance draws the
    /// mesh carried there in f64 (normals by the inverse transpose), as a mesh
    /// in place: the same picture but for the carried vertices' rounding.
    #[test]
    fn a_placed_instance_draws_its_mesh_carried_into_the_world() {
        let parts = sphere(10, 20);
        let placements = [
            Placement::new(quarter(1), [0.6; 3], [0.5, -0.2, -0.3]),
            Placement::new([0.2, 0.7, -0.1, 0.6], [0.8, 0.4, 0.6], [-0.4, 0.1, 0.2]),
            Placement::new([0.0, 0.0, 0.3, 1.0], [-0.5, 0.5, 0.5], [0.2, 0.3, 0.8]),
        ];
        let s = scene();
        for p in placements {
            let carried = parts.carried(&p);
            let world = [carried.mesh()];
            let expected = render(&s.view().with_meshes(&world).unwrap());
            let meshes = [parts.mesh()];
            let view = s.view().with_meshes(&meshes).unwrap();
            let mut inst: Instances<'_, 1> = Instances::new(&view);
            inst.push(Instance::new(0, p)).unwrap();
            let got = render(&view.with_instances(&inst).unwrap());
            assert_eq!(off(&expected, &got, 2), 0, "{p:?}");
            assert!(off(&expected, &got, 0) <= got.len() / 50, "{p:?}");
            // And it is not the mesh where it lies.
            assert!(off(&render(&view), &got, 8) > got.len() / 20, "{p:?}");
        }
    }

    /// At the extremes of scale and distance the instance's error bounds
    /// still move its leaving rays off its faces: the scene scaled by 2^-12
    /// and 2^12 and moved far from the origin draws, placed, what the mesh
    /// carried there draws (no self-shadowed speck where the carried mesh
    /// has none).
    #[test]
    fn placed_instances_hold_at_the_extremes_of_scale_and_distance() {
        let parts = sphere(10, 20);
        let frames = [
            Frame {
                k: 1.0 / 4096.0,
                o: Vec3::new(0.01, -0.02, 0.005),
            },
            Frame {
                k: 4096.0,
                o: Vec3::new(3.0e6, -1.0e6, 2.0e6),
            },
            Frame {
                k: 1.0,
                o: Vec3::new(-2.0e4, 5.0e3, 1.0e4),
            },
        ];
        for f in frames {
            let p = Placement::new([0.2, 0.7, -0.1, 0.6], [0.8 * f.k, 0.4 * f.k, 0.6 * f.k], {
                let t = f.at(Vec3::new(-0.4, 0.1, 0.2));
                [t.x, t.y, t.z]
            });
            let s = scene_in(f);
            let carried = parts.carried(&p);
            let world = [carried.mesh()];
            let expected = render_in(&s.view().with_meshes(&world).unwrap(), f);
            let meshes = [parts.mesh()];
            let view = s.view().with_meshes(&meshes).unwrap();
            let mut inst: Instances<'_, 1> = Instances::new(&view);
            inst.push(Instance::new(0, p)).unwrap();
            let got = render_in(&view.with_instances(&inst).unwrap(), f);
            // Both round the carried vertices to f32, differently (the f64
            // product rounded once, the f32 one in the core), 2 x 10^4 times
            // the sphere's size from the origin in the last frame: a few
            // levels apart on a few pixels; a speck of self-shadow would be
            // some 100 darker.
            assert_eq!(off(&expected, &got, 8), 0, "k {} o {:?}", f.k, f.o);
            assert!(off(&expected, &got, 2) <= got.len() / 100, "k {}", f.k);
            // The sphere is in the picture.
            assert!(
                off(&render_in(&view, f), &got, 8) > got.len() / 20,
                "k {}",
                f.k
            );
        }
    }

    /// The time of a hit on a placed face is the analytic one: a square of
    /// side 2 in the plane z = 0, turned a quarter about x (into y = 0),
    /// scaled by 3 and moved down by 1, hit from above.
    #[test]
    fn a_ray_meets_a_placed_face_at_its_analytic_time() {
        let v = std::vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0]
        ];
        let parts = Parts::new(v, std::vec![[0, 1, 2], [0, 2, 3]], StdVec::new());
        let meshes = [parts.mesh()];
        let s = scene();
        let view = s.view().with_meshes(&meshes).unwrap();
        let mut inst: Instances<'_, 1> = Instances::new(&view);
        inst.push(Instance::new(
            0,
            Placement::new(quarter(0), [3.0; 3], [10.0, -1.0, 0.0]),
        ))
        .unwrap();
        let placed = view.with_instances(&inst).unwrap();
        let ray = |o: Vec3| crate::ray::Ray::new(o, -Vec3::Y).unwrap();
        // Over the square (x in [7, 13], z in [-3, 3]): the floor is further.
        let t = first_hit(&placed, &ray(Vec3::new(12.0, 4.0, 2.5)), 100.0).unwrap();
        assert!((t - 5.0).abs() <= 4.0 * f32::EPSILON * 5.0, "{t}");
        // Beside it: the floor at y = -1.2.
        let t = first_hit(&placed, &ray(Vec3::new(13.5, 4.0, 0.0)), 100.0).unwrap();
        assert!((t - 5.2).abs() <= 1e-5, "{t}");
        // The mesh no longer lies where it was (the square at z = 0 around 0).
        let side = crate::ray::Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z).unwrap();
        assert_eq!(first_hit(&placed, &side, 100.0), None);
        assert!(first_hit(&view, &side, 100.0).is_some());
    }

    /// A frame moves one instance: the others stay, the moved one is
    /// found where it now lies; a refused move leaves it where it was.
    #[test]
    fn set_moves_one_instance_and_a_refused_move_keeps_it() {
        let v = std::vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0]
        ];
        let parts = Parts::new(v, std::vec![[0, 1, 2], [0, 2, 3]], StdVec::new());
        let meshes = [parts.mesh()];
        let s = scene();
        let view = s.view().with_meshes(&meshes).unwrap();
        let mut inst: Instances<'_, 3> = Instances::new(&view);
        for x in [-5.0, 0.0, 5.0] {
            inst.push(Instance::new(
                0,
                Placement::new(quarter(3 % 3), [1.0; 3], [x, 0.0, 0.0]),
            ))
            .unwrap();
        }
        let down = |x: f32| crate::ray::Ray::new(Vec3::new(x, 3.0, 0.5), -Vec3::Y).unwrap();
        let hits = |inst: &Instances<'_, 3>| {
            let v = view.with_instances(inst).unwrap();
            [-5.0, 0.0, 5.0, 20.0].map(|x| first_hit(&v, &down(x), 100.0))
        };
        let before = hits(&inst);
        assert!(
            before[..3]
                .iter()
                .all(|t| t.is_some_and(|t| (t - 3.0).abs() < 1e-5))
        );
        inst.set(1, Placement::new(quarter(0), [1.0; 3], [20.0, 1.0, 0.0]))
            .unwrap();
        let after = hits(&inst);
        assert_eq!(after[0], before[0]);
        assert_eq!(after[2], before[2]);
        assert!(after[1].is_none_or(|t| (t - 4.2).abs() < 1e-5), "{after:?}"); // the floor
        assert!(
            after[3].is_some_and(|t| (t - 2.0).abs() < 1e-5),
            "{after:?}"
        );
        let refused = inst.set(1, Placement::new([0.0; 4], [1.0; 3], [0.0; 3]));
        assert_eq!(refused, Err(Error::ZeroLength(Field::InstanceRotation)));
        assert_eq!(hits(&inst), after);
    }

    /// Baked instances (their numbers written out and read back, as `tessera
    /// bake` does) are taken when they are what the placement makes, and
    /// refused by index when a bit differs; a copy of them in RAM moves.
    #[test]
    fn baked_instances_are_checked_to_the_bit() {
        let parts = sphere(6, 12);
        let meshes = [parts.mesh()];
        let s = scene();
        let view = s.view().with_meshes(&meshes).unwrap();
        let mut inst: Instances<'_, 2> = Instances::new(&view);
        inst.push(Instance::new(
            0,
            Placement::new(quarter(1), [0.5; 3], [1.0, 0.0, 0.0]),
        ))
        .unwrap();
        inst.push(Instance::new(0, Placement::IDENTITY)).unwrap();
        let baked: StdVec<Placed<'_>> = inst
            .placed()
            .iter()
            .map(|p| Placed::baked(&meshes[0], 0, p.placement, p.numbers()))
            .collect();
        let from_baked = view.with_placed(&baked).unwrap();
        assert_eq!(
            render(&from_baked),
            render(&view.with_instances(&inst).unwrap())
        );
        // One bit of one number off.
        let mut numbers = baked[1].numbers();
        numbers.0[10] = f32::from_bits(numbers.0[10].to_bits() ^ 1);
        let bad = [
            baked[0],
            Placed::baked(&meshes[0], 0, baked[1].placement, numbers),
        ];
        assert_eq!(
            view.with_placed(&bad).err(),
            Some(Error::BadBaked {
                list: List::Instances,
                index: 1
            })
        );
        // Of another mesh than the one it names.
        let other = parts.mesh();
        let stray = [Placed::baked(
            &other,
            0,
            baked[0].placement,
            baked[0].numbers(),
        )];
        assert!(view.with_placed(&stray).is_err());
        // Copied into RAM and moved.
        let mut moved: Instances<'_, 2> = Instances::of(&from_baked).unwrap();
        assert_eq!(moved.get(0), inst.get(0));
        moved
            .set(1, Placement::new(quarter(0), [0.5; 3], [-1.0, 0.0, 0.0]))
            .unwrap();
        let frame = from_baked.with_instances(&moved).unwrap();
        assert_ne!(render(&frame), render(&from_baked));
        let small: Result<Instances<'_, 1>, _> = Instances::of(&from_baked);
        assert!(small.is_err());
    }

    /// Bad placements and instances are refused, naming what is wrong.
    #[test]
    fn bad_placements_are_refused_by_name() {
        let v = std::vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0]];
        let parts = Parts::new(v, std::vec![[0, 1, 2]], StdVec::new());
        let meshes = [parts.mesh()];
        let s = scene();
        let view = s.view().with_meshes(&meshes).unwrap();
        let mut inst: Instances<'_, 1> = Instances::new(&view);
        let id = Placement::IDENTITY;
        let cases = [
            (
                Placement {
                    rotation: [0.0, f32::NAN, 0.0, 1.0],
                    ..id
                },
                Error::NotFinite(Field::InstanceRotation),
            ),
            (
                Placement {
                    rotation: [0.0; 4],
                    ..id
                },
                Error::ZeroLength(Field::InstanceRotation),
            ),
            (
                Placement {
                    rotation: [1e-30, 0.0, 0.0, 0.0],
                    ..id
                },
                Error::ZeroLength(Field::InstanceRotation),
            ),
            (
                Placement {
                    scale: [1.0, 0.0, 1.0],
                    ..id
                },
                Error::OutOfRange {
                    field: Field::InstanceScale,
                    range: "[2^-20, 2^20] in magnitude on each axis (not 0)",
                },
            ),
            (
                Placement {
                    scale: [1.0, 1.0, f32::INFINITY],
                    ..id
                },
                Error::NotFinite(Field::InstanceScale),
            ),
            (
                Placement {
                    translation: [0.0, f32::NAN, 0.0],
                    ..id
                },
                Error::NotFinite(Field::InstanceTranslation),
            ),
            (
                Placement {
                    translation: [2e18, 0.0, 0.0],
                    ..id
                },
                Error::OutOfRange {
                    field: Field::InstanceTranslation,
                    range: "[-2^60, 2^60] (about 1.15e18) per component",
                },
            ),
        ];
        for (p, e) in cases {
            assert_eq!(inst.push(Instance::new(0, p)), Err(e), "{p:?}");
            assert!(inst.is_empty());
        }
        // A mesh placed beyond the extent by its scale.
        let v = std::vec![[-1e15, -1e15, 0.0], [1e15, -1e15, 0.0], [1e15, 1e15, 0.0]];
        let big = Parts::new(v, std::vec![[0, 1, 2]], StdVec::new());
        let big = [big.mesh()];
        let big_view = s.view().with_meshes(&big).unwrap();
        let mut far: Instances<'_, 1> = Instances::new(&big_view);
        far.push(Instance::new(
            0,
            Placement::new([0.0, 0.0, 0.0, 1.0], [1e3; 3], [0.0; 3]),
        ))
        .unwrap();
        assert_eq!(
            far.set(0, Placement::new([0.0, 0.0, 0.0, 1.0], [1e4; 3], [0.0; 3])),
            Err(Error::OutOfRange {
                field: Field::InstanceTranslation,
                range: "the scene's extent for every point of the placed mesh (2^60)",
            })
        );
        assert_eq!(
            inst.push(Instance::new(1, id)),
            Err(Error::MeshOutOfRange { id: 1, count: 1 })
        );
        inst.push(Instance::new(0, id)).unwrap();
        assert_eq!(
            inst.push(Instance::new(0, id)),
            Err(Error::CapacityExceeded {
                list: List::Instances,
                capacity: 1
            })
        );
        // Instances of another view's meshes.
        let other = [parts.mesh()];
        let view2 = s.view().with_meshes(&other).unwrap();
        assert_eq!(view2.with_instances(&inst).err(), Some(Error::BadMesh));
        // Subnormal numbers read as zeros, as everywhere in a scene.
        let mut ok: Instances<'_, 1> = Instances::new(&view);
        ok.push(Instance::new(
            0,
            Placement::new([1e-40, 0.0, 0.0, 1.0], [1.0; 3], [1e-40, 0.0, 0.0]),
        ))
        .unwrap();
    }
}
