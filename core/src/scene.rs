//! The scene: primitives (a geometry and a material reference), materials, lights,
//! the camera, an ambient light and a background colour.
//!
//! Fixed capacity, sized per scene: one `heapless` list per geometry kind, plus
//! materials and lights, each with its own `const` capacity. A scene of spheres
//! alone sets the other capacities to 0 and pays neither RAM nor a loop for them.
//! Adding past a capacity returns [`Error::CapacityExceeded`]; every value is
//! checked when it is added, so a scene that exists is a valid scene.

use crate::camera::Camera;
use crate::color::Color;
use crate::error::{Error, List};
use crate::geometry::{Aabb, Plane, Sphere, Triangle};
use crate::light::PointLight;
use crate::material::{Material, MaterialId};
use crate::vec::Vec3;
use heapless::Vec;

/// An object of the scene: a geometry and the material it is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primitive<G> {
    /// The shape.
    pub geometry: G,
    /// Its material, an index checked against the scene's materials when added.
    pub material: MaterialId,
}

/// A scene with capacities `S` spheres, `P` planes, `T` triangles, `B` boxes, `M`
/// materials and `L` lights.
///
/// ```
/// use tessera::{Camera, Color, Error, Material, Scene, Sphere, Vec3};
/// use tessera::List;
///
/// let cam = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.1, 100.0)?;
/// let mut scene: Scene<1, 0, 0, 0, 1, 0> = Scene::new(cam);
/// let blue = scene.add_material(Material::matte(Color::new(0.1, 0.2, 0.9)))?;
/// scene.add_sphere(Sphere::try_new(Vec3::ZERO, 1.0)?, blue)?;
/// let full = scene.add_sphere(Sphere::try_new(Vec3::ZERO, 2.0)?, blue);
/// assert_eq!(full, Err(Error::CapacityExceeded { list: List::Spheres, capacity: 1 }));
/// # Ok::<(), Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Scene<
    const S: usize,
    const P: usize,
    const T: usize,
    const B: usize,
    const M: usize,
    const L: usize,
> {
    camera: Camera,
    ambient: Color,
    background: Color,
    spheres: Vec<Primitive<Sphere>, S>,
    planes: Vec<Primitive<Plane>, P>,
    triangles: Vec<Primitive<Triangle>, T>,
    boxes: Vec<Primitive<Aabb>, B>,
    materials: Vec<Material, M>,
    lights: Vec<PointLight, L>,
    /// The bounds of the triangles, kept as they are added.
    triangle_bounds: (Vec3, Vec3),
}

/// Empty bounds: any point widens them.
const NO_BOUNDS: (Vec3, Vec3) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));

/// `b` widened to `[min, max]`.
fn widen(b: &mut (Vec3, Vec3), min: Vec3, max: Vec3) {
    *b = (b.0.min(min), b.1.max(max));
}

fn push<X, const N: usize>(list: &mut Vec<X, N>, x: X, which: List) -> Result<(), Error> {
    list.push(x).map_err(|_| Error::CapacityExceeded {
        list: which,
        capacity: N,
    })
}

impl<const S: usize, const P: usize, const T: usize, const B: usize, const M: usize, const L: usize>
    Scene<S, P, T, B, M, L>
{
    /// An empty scene seen by `camera`, with no ambient light and a black background.
    #[must_use]
    pub const fn new(camera: Camera) -> Self {
        Self {
            camera,
            ambient: Color::BLACK,
            background: Color::BLACK,
            spheres: Vec::new(),
            planes: Vec::new(),
            triangles: Vec::new(),
            boxes: Vec::new(),
            materials: Vec::new(),
            lights: Vec::new(),
            triangle_bounds: NO_BOUNDS,
        }
    }

    /// Sets the ambient light (each component in `[0, `[`crate::MAX_COLOR`]`]`).
    pub fn set_ambient(&mut self, ambient: Color) -> Result<(), Error> {
        self.ambient = crate::error::color(ambient, crate::error::Field::AmbientLight)?;
        Ok(())
    }

    /// Sets the background colour seen by rays that hit nothing (each component in
    /// `[0, `[`crate::MAX_COLOR`]`]`).
    pub fn set_background(&mut self, background: Color) -> Result<(), Error> {
        self.background = crate::error::color(background, crate::error::Field::Background)?;
        Ok(())
    }

    /// Replaces the camera.
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = camera;
    }

    /// Adds a material (checked) and returns its reference.
    pub fn add_material(&mut self, material: Material) -> Result<MaterialId, Error> {
        let material = material.flushed();
        material.validate()?;
        let id = u16::try_from(self.materials.len()).map_err(|_| Error::CapacityExceeded {
            list: List::Materials,
            capacity: M,
        })?;
        push(&mut self.materials, material, List::Materials)?;
        Ok(MaterialId(id))
    }

    fn check_material(&self, id: MaterialId) -> Result<(), Error> {
        check_material(id, self.materials.len())
    }

    /// Adds a sphere made of `material`.
    pub fn add_sphere(&mut self, geometry: Sphere, material: MaterialId) -> Result<(), Error> {
        self.check_material(material)?;
        push(
            &mut self.spheres,
            Primitive { geometry, material },
            List::Spheres,
        )
    }

    /// Adds a plane made of `material`.
    pub fn add_plane(&mut self, geometry: Plane, material: MaterialId) -> Result<(), Error> {
        self.check_material(material)?;
        push(
            &mut self.planes,
            Primitive { geometry, material },
            List::Planes,
        )
    }

    /// Adds a triangle made of `material`.
    pub fn add_triangle(&mut self, geometry: Triangle, material: MaterialId) -> Result<(), Error> {
        self.check_material(material)?;
        push(
            &mut self.triangles,
            Primitive { geometry, material },
            List::Triangles,
        )?;
        for v in geometry.vertices() {
            widen(&mut self.triangle_bounds, v, v);
        }
        Ok(())
    }

    /// Adds an axis-aligned box made of `material`.
    pub fn add_box(&mut self, geometry: Aabb, material: MaterialId) -> Result<(), Error> {
        self.check_material(material)?;
        push(
            &mut self.boxes,
            Primitive { geometry, material },
            List::Boxes,
        )
    }

    /// Adds a point light.
    pub fn add_light(&mut self, light: PointLight) -> Result<(), Error> {
        push(&mut self.lights, light, List::Lights)
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The same scene with every length multiplied by `2^k` (positions, radii, the
    /// camera's near and far, plane textures' world-unit scales) and every light
    /// intensity by `4^k`, so that the image is unchanged in exact arithmetic. The
    /// products are exact while the values stay normal `f32`, and every value is
    /// checked again (a scale beyond the supported range is refused). Used to check
    /// scale invariance, on the host and on the chip.
    ///
    /// A textured material used both by a plane (whose uv are world units) and by
    /// another kind (whose uv are not) cannot be scaled consistently:
    /// [`Error::OutOfRange`] on the texture scale.
    #[cfg(feature = "testing")]
    pub fn scaled_pow2(&self, k: i32) -> Result<Self, Error> {
        use crate::error::Field;
        use crate::texture::Texture;
        let k = k.clamp(-200, 200);
        let f = libm::ldexpf(1.0, k);
        let c = &self.camera;
        let mut out = Self::new(Camera::try_new(
            c.position() * f,
            c.forward(),
            c.up(),
            c.fovy_degrees(),
            c.near() * f,
            c.far() * f,
        )?);
        out.set_ambient(self.ambient)?;
        out.set_background(self.background)?;
        let on_planes = |i: usize| self.planes.iter().any(|p| usize::from(p.material.0) == i);
        let elsewhere = |i: usize| {
            self.spheres.iter().any(|p| usize::from(p.material.0) == i)
                || self
                    .triangles
                    .iter()
                    .any(|p| usize::from(p.material.0) == i)
                || self.boxes.iter().any(|p| usize::from(p.material.0) == i)
        };
        for (i, m) in self.materials.iter().enumerate() {
            let t = *m.texture();
            let mut m = *m;
            if t.needs_uv() && on_planes(i) {
                if elsewhere(i) {
                    return Err(Error::OutOfRange {
                        field: Field::TextureScale,
                        range: "a texture used by planes only, to be scaled",
                    });
                }
                m = m.with_texture(match t {
                    Texture::Checker { a, b, scale } => Texture::Checker {
                        a,
                        b,
                        scale: scale / f,
                    },
                    Texture::Fringes { color, spacing } => Texture::Fringes {
                        color,
                        spacing: spacing * f,
                    },
                    solid => solid,
                })?;
            }
            out.add_material(m)?;
        }
        for l in &self.lights {
            out.add_light(PointLight::try_new(
                l.position() * f,
                l.color(),
                l.intensity() * f * f,
            )?)?;
        }
        for p in &self.spheres {
            let g = Sphere::try_new(p.geometry.center() * f, p.geometry.radius() * f)?;
            out.add_sphere(g, p.material)?;
        }
        for p in &self.planes {
            let g = Plane::try_new(p.geometry.point() * f, p.geometry.normal())?;
            out.add_plane(g, p.material)?;
        }
        for p in &self.triangles {
            let [a, b, c] = p.geometry.vertices();
            out.add_triangle(Triangle::try_new(a * f, b * f, c * f)?, p.material)?;
        }
        for p in &self.boxes {
            let g = Aabb::try_new(p.geometry.min() * f, p.geometry.max() * f)?;
            out.add_box(g, p.material)?;
        }
        Ok(out)
    }

    /// A borrowed, capacity-free view of the scene: what the renderer reads.
    #[must_use]
    pub fn view(&self) -> SceneView<'_> {
        Lists {
            spheres: &self.spheres,
            planes: &self.planes,
            triangles: &self.triangles,
            boxes: &self.boxes,
            materials: &self.materials,
            lights: &self.lights,
        }
        .view::<S, P, T, B>(
            self.ambient,
            self.background,
            crate::cull::Hull::new(self.triangle_bounds.0, self.triangle_bounds.1),
        )
    }
}

/// A scene's lists, which a view borrows ([`Scene::view`], and a baked scene's
/// `view`).
pub(crate) struct Lists<'a> {
    pub(crate) spheres: &'a [Primitive<Sphere>],
    pub(crate) planes: &'a [Primitive<Plane>],
    pub(crate) triangles: &'a [Primitive<Triangle>],
    pub(crate) boxes: &'a [Primitive<Aabb>],
    pub(crate) materials: &'a [Material],
    pub(crate) lights: &'a [PointLight],
}

impl<'a> Lists<'a> {
    /// The view of these lists searched flat (no hierarchy, no meshes), each
    /// tile's culling lists sized by the capacities `S`, `P`, `T`, `B`, the
    /// triangles within `triangle_hull`.
    pub(crate) fn view<const S: usize, const P: usize, const T: usize, const B: usize>(
        self,
        ambient: Color,
        background: Color,
        triangle_hull: Option<crate::cull::Hull>,
    ) -> SceneView<'a> {
        SceneView {
            spheres: self.spheres,
            planes: self.planes,
            triangles: self.triangles,
            boxes: self.boxes,
            materials: self.materials,
            lights: self.lights,
            ambient,
            background,
            // Model only what the scene requires: without a mirror or a transparent
            // material no secondary ray can exist, so the tracer skips that work.
            secondary: self.materials.iter().any(Material::sends_rays),
            tile_lists: crate::cull::lend::<S, P, T, B>,
            triangle_hull,
            #[cfg(feature = "bvh")]
            bvh: None,
            #[cfg(feature = "bvh")]
            sphere_bvh: None,
            #[cfg(feature = "bvh")]
            meshes: &[],
            #[cfg(feature = "bvh")]
            through: false,
        }
    }
}

/// Checks a material reference against `count` materials.
pub(crate) fn check_material(id: MaterialId, count: usize) -> Result<(), Error> {
    if usize::from(id.0) < count {
        Ok(())
    } else {
        Err(Error::MaterialOutOfRange {
            id: id.0,
            count: u16::try_from(count).unwrap_or(u16::MAX),
        })
    }
}

/// A scene as the renderer sees it: slices, no capacities, so the renderer is
/// compiled once whatever the scene's capacities. The one thing that depends on the
/// capacities is the room for a tile's culling lists (the primitives that may reach
/// the tile, listed before its pixels: `6 (S + P + T + B)` bytes and their lengths
/// on the stack of [`Frame::render_tile`](crate::Frame::render_tile), for `S`
/// spheres, `P` planes, `T` triangles and `B` boxes); [`Scene::view`] gives the
/// view a small function of the scene's type that lends that room, so the
/// capacities never reach the renderer's code.
#[derive(Clone, Copy)]
pub struct SceneView<'a> {
    pub(crate) spheres: &'a [Primitive<Sphere>],
    pub(crate) planes: &'a [Primitive<Plane>],
    pub(crate) triangles: &'a [Primitive<Triangle>],
    pub(crate) boxes: &'a [Primitive<Aabb>],
    pub(crate) materials: &'a [Material],
    pub(crate) lights: &'a [PointLight],
    pub(crate) ambient: Color,
    pub(crate) background: Color,
    pub(crate) secondary: bool,
    /// Lends a tile's candidate lists, sized by the scene's capacities.
    pub(crate) tile_lists: crate::cull::Lender,
    /// The hull of the triangles (`None` for an empty list).
    pub(crate) triangle_hull: Option<crate::cull::Hull>,
    /// The triangles' hierarchy, when it pays ([`SceneView::with_bvh`]).
    #[cfg(feature = "bvh")]
    pub(crate) bvh: Option<crate::bvh::BvhView<'a>>,
    /// The spheres' hierarchy, when it pays ([`SceneView::with_sphere_bvh`]).
    #[cfg(feature = "bvh")]
    pub(crate) sphere_bvh: Option<crate::bvh::BvhView<'a>>,
    /// The indexed meshes ([`SceneView::with_meshes`]), searched after every list.
    #[cfg(feature = "bvh")]
    pub(crate) meshes: &'a [crate::mesh::Mesh<'a>],
    /// Something is searched through a hierarchy: [`SceneView::through`], one
    /// flag for the searches' dispatch ([`SceneView::settled`] keeps it right).
    #[cfg(feature = "bvh")]
    pub(crate) through: bool,
}

impl core::fmt::Debug for SceneView<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SceneView")
            .field("spheres", &self.spheres)
            .field("planes", &self.planes)
            .field("triangles", &self.triangles)
            .field("boxes", &self.boxes)
            .field("materials", &self.materials)
            .field("lights", &self.lights)
            .field("ambient", &self.ambient)
            .field("background", &self.background)
            .finish_non_exhaustive()
    }
}

impl<'a> SceneView<'a> {
    /// The same view with every culling bound off: no tile lists, no list hull.
    /// Renders to the same bytes (the point of the culling's conservative bounds,
    /// which the tests check this way); slower. A test hook, with the feature
    /// `testing`.
    #[cfg(feature = "testing")]
    #[must_use]
    pub fn without_culling(&self) -> Self {
        Self {
            tile_lists: crate::cull::lend_none,
            triangle_hull: None,
            #[cfg(feature = "bvh")]
            bvh: None,
            #[cfg(feature = "bvh")]
            sphere_bvh: None,
            #[cfg(feature = "bvh")]
            meshes: self.meshes,
            ..*self
        }
        .settled()
    }

    /// The same view, its triangles found through `bvh` when there are at least
    /// [`crate::bvh::CROSSOVER`] of them (below, the flat list costs less and the
    /// view is returned as it is). The image is the same bytes either way.
    ///
    /// # Errors
    /// [`Error::BvhMismatch`] when `bvh` was not built from these triangles.
    #[cfg(feature = "bvh")]
    pub fn with_bvh<const N: usize, const T: usize>(
        &self,
        bvh: &'a crate::Bvh<N, T>,
    ) -> Result<Self, Error> {
        if bvh.triangle_count() != self.triangles.len()
            || bvh.key() != crate::bvh::key(self.triangles)
        {
            return Err(Error::BvhMismatch);
        }
        let pays = self.triangles.len() >= crate::bvh::CROSSOVER;
        Ok(Self {
            bvh: pays.then(|| bvh.view()),
            ..*self
        }
        .settled())
    }

    /// True when the triangles are found through a BVH ([`SceneView::with_bvh`]).
    #[cfg(feature = "bvh")]
    #[must_use]
    pub fn uses_bvh(&self) -> bool {
        self.bvh.is_some()
    }

    /// True when the spheres are found through a BVH
    /// ([`SceneView::with_sphere_bvh`]).
    #[cfg(feature = "bvh")]
    #[must_use]
    pub fn uses_sphere_bvh(&self) -> bool {
        self.sphere_bvh.is_some()
    }

    /// [`SceneView::with_bvh`] whatever the number of triangles (a test hook, with
    /// the feature `testing`: the tests compare every scene with and without one).
    ///
    /// # Errors
    /// As [`SceneView::with_bvh`].
    #[cfg(feature = "bvh")]
    #[cfg(feature = "testing")]
    pub fn with_bvh_always<const N: usize, const T: usize>(
        &self,
        bvh: &'a crate::Bvh<N, T>,
    ) -> Result<Self, Error> {
        let v = self.with_bvh(bvh)?;
        Ok(Self {
            bvh: Some(bvh.view()),
            ..v
        }
        .settled())
    }

    /// The same view without its BVH: the flat lists (a test hook, with the feature
    /// `testing`).
    #[cfg(feature = "bvh")]
    #[cfg(feature = "testing")]
    #[must_use]
    pub fn without_bvh(&self) -> Self {
        Self {
            bvh: None,
            sphere_bvh: None,
            ..*self
        }
        .settled()
    }

    /// The same view, its spheres found through `bvh` when there are at least
    /// [`crate::bvh::SPHERE_CROSSOVER`] of them (below, the view is returned as
    /// it is). The image is the same bytes either way.
    ///
    /// # Errors
    /// [`Error::BvhMismatch`] when `bvh` was not built from these spheres.
    #[cfg(feature = "bvh")]
    pub fn with_sphere_bvh<const N: usize, const T: usize>(
        &self,
        bvh: &'a crate::Bvh<N, T>,
    ) -> Result<Self, Error> {
        if bvh.triangle_count() != self.spheres.len() || bvh.key() != crate::bvh::key(self.spheres)
        {
            return Err(Error::BvhMismatch);
        }
        let pays = self.spheres.len() >= crate::bvh::SPHERE_CROSSOVER;
        Ok(Self {
            sphere_bvh: pays.then(|| bvh.view()),
            ..*self
        }
        .settled())
    }

    /// [`SceneView::with_sphere_bvh`] whatever the number of spheres (a test hook,
    /// with the feature `testing`).
    ///
    /// # Errors
    /// As [`SceneView::with_sphere_bvh`].
    #[cfg(feature = "bvh")]
    #[cfg(feature = "testing")]
    pub fn with_sphere_bvh_always<const N: usize, const T: usize>(
        &self,
        bvh: &'a crate::Bvh<N, T>,
    ) -> Result<Self, Error> {
        let v = self.with_sphere_bvh(bvh)?;
        Ok(Self {
            sphere_bvh: Some(bvh.view()),
            ..v
        }
        .settled())
    }

    /// True when something is searched through a hierarchy (triangles, spheres,
    /// meshes): the searches take [`SceneView::nearest_through`]'s way and the
    /// tiles build no lists.
    #[cfg(feature = "bvh")]
    #[inline(always)]
    pub(crate) fn through(&self) -> bool {
        self.through
    }

    /// The view with its `through` flag set from what it holds (feature `bvh`;
    /// the view itself without).
    #[cfg(any(feature = "bvh", feature = "testing"))]
    pub(crate) fn settled(self) -> Self {
        #[cfg(feature = "bvh")]
        let settled = Self {
            through: self.bvh.is_some() || self.sphere_bvh.is_some() || !self.meshes.is_empty(),
            ..self
        };
        #[cfg(not(feature = "bvh"))]
        let settled = self;
        settled
    }

    /// The spheres.
    #[must_use]
    pub fn spheres(&self) -> &'a [Primitive<Sphere>] {
        self.spheres
    }
    /// The planes.
    #[must_use]
    pub fn planes(&self) -> &'a [Primitive<Plane>] {
        self.planes
    }
    /// The triangles.
    #[must_use]
    pub fn triangles(&self) -> &'a [Primitive<Triangle>] {
        self.triangles
    }
    /// The boxes.
    #[must_use]
    pub fn boxes(&self) -> &'a [Primitive<Aabb>] {
        self.boxes
    }
    /// The indexed meshes ([`SceneView::with_meshes`]).
    #[cfg(feature = "bvh")]
    #[must_use]
    pub fn meshes(&self) -> &'a [crate::Mesh<'a>] {
        self.meshes
    }
    /// The materials.
    #[must_use]
    pub fn materials(&self) -> &'a [Material] {
        self.materials
    }
    /// The lights.
    #[must_use]
    pub fn lights(&self) -> &'a [PointLight] {
        self.lights
    }
    /// The ambient light.
    #[must_use]
    pub fn ambient(&self) -> Color {
        self.ambient
    }
    /// The background colour.
    #[must_use]
    pub fn background(&self) -> Color {
        self.background
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    fn cam() -> Camera {
        Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.1, 100.0).unwrap()
    }

    #[test]
    fn capacities_are_enforced_per_list() {
        let mut s: Scene<1, 1, 1, 1, 1, 1> = Scene::new(cam());
        let m = s.add_material(Material::matte(Color::WHITE)).unwrap();
        assert_eq!(
            s.add_material(Material::matte(Color::WHITE)),
            Err(Error::CapacityExceeded {
                list: List::Materials,
                capacity: 1
            })
        );
        let sph = Sphere::try_new(Vec3::ZERO, 1.0).unwrap();
        let pl = Plane::try_new(Vec3::ZERO, Vec3::Y).unwrap();
        let tri = Triangle::try_new(Vec3::ZERO, Vec3::X, Vec3::Y).unwrap();
        let bx = Aabb::try_new(Vec3::ZERO, Vec3::splat(1.0)).unwrap();
        let li = PointLight::try_new(Vec3::Y, Color::WHITE, 1.0).unwrap();
        s.add_sphere(sph, m).unwrap();
        s.add_plane(pl, m).unwrap();
        s.add_triangle(tri, m).unwrap();
        s.add_box(bx, m).unwrap();
        s.add_light(li).unwrap();
        let full = |list| Err(Error::CapacityExceeded { list, capacity: 1 });
        assert_eq!(s.add_sphere(sph, m), full(List::Spheres));
        assert_eq!(s.add_plane(pl, m), full(List::Planes));
        assert_eq!(s.add_triangle(tri, m), full(List::Triangles));
        assert_eq!(s.add_box(bx, m), full(List::Boxes));
        assert_eq!(s.add_light(li), full(List::Lights));
        // Zero capacity: a spheres-only scene refuses other kinds.
        let mut only: Scene<2, 0, 0, 0, 1, 0> = Scene::new(cam());
        let m = only.add_material(Material::matte(Color::WHITE)).unwrap();
        assert_eq!(
            only.add_plane(pl, m),
            Err(Error::CapacityExceeded {
                list: List::Planes,
                capacity: 0
            })
        );
    }

    #[test]
    fn material_references_are_checked() {
        let mut s: Scene<2, 0, 0, 0, 2, 0> = Scene::new(cam());
        let sph = Sphere::try_new(Vec3::ZERO, 1.0).unwrap();
        assert_eq!(
            s.add_sphere(sph, MaterialId(0)),
            Err(Error::MaterialOutOfRange { id: 0, count: 0 })
        );
        s.add_material(Material::matte(Color::WHITE)).unwrap();
        assert_eq!(
            s.add_sphere(sph, MaterialId(3)),
            Err(Error::MaterialOutOfRange { id: 3, count: 1 })
        );
        assert!(s.add_sphere(sph, MaterialId(0)).is_ok());
        let bad = Material::matte(Color::new(f32::NAN, 0.0, 0.0));
        assert!(s.add_material(bad).is_err());
    }

    #[test]
    fn ambient_and_background_are_checked() {
        let mut s: Scene<0, 0, 0, 0, 0, 0> = Scene::new(cam());
        assert!(s.set_ambient(Color::new(0.0, f32::NAN, 0.0)).is_err());
        assert!(s.set_background(Color::new(-1.0, 0.0, 0.0)).is_err());
        assert!(s.set_ambient(Color::splat(0.1)).is_ok());
    }

    #[test]
    fn unused_kinds_cost_no_memory() {
        use core::mem::size_of;
        let spheres_only = size_of::<Scene<4, 0, 0, 0, 2, 1>>();
        let with_triangles = size_of::<Scene<4, 0, 16, 0, 2, 1>>();
        assert!(with_triangles >= spheres_only + 16 * size_of::<Primitive<Triangle>>());
    }
}
