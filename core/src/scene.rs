//! The scene: primitives (a geometry and a material reference), materials, lights,
//! the camera, an ambient light and a background colour.
//!
//! Fixed capacity, sized per scene: one `heapless` list per geometry kind, plus
//! materials and lights, each with its own `const` capacity. A scene of spheres
//! alone sets the other capacities to 0 and pays neither RAM nor a loop for them.
//! Adding past a capacity returns [`Error::CapacityExceeded`]; every value is
//! checked when it is added, so a scene that exists is a valid scene.

use crate::camera::Camera;
use crate::camera::Viewport;
use crate::color::Color;
use crate::error::{Error, List};
use crate::geometry::{Aabb, Plane, Sphere, Triangle};
use crate::kind::{Capacities, Capacity, Geometry, ListStore, Store, each_kind, empty};
use crate::light::Light;
use crate::material::{Material, MaterialId};
use crate::primitive::Primitive;
use crate::tile::{RenderSettings, Renderer};
use crate::vec::Vec3;
use crate::view::{Lists, SceneView, check_material};
use heapless::vec::VecView;

/// A scene with capacities `C`, by name ([`capacities!`](crate::capacities)):
/// `Scene<capacities!(spheres: 4, planes: 1, materials: 5, lights: 1)>`.
///
/// ```
/// use tessera_core::{capacities, Camera, Color, Error, material::Material, Scene, geometry::Sphere, Vec3};
/// use tessera_core::error::List;
///
/// let cam = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.1, 100.0)?;
/// let mut scene: Scene<capacities!(spheres: 1, materials: 1)> = Scene::new(cam);
/// let blue = scene.add_material(Material::matte(Color::new(0.1, 0.2, 0.9)))?;
/// scene.add_sphere(Sphere::try_new(Vec3::ZERO, 1.0)?, blue)?;
/// let full = scene.add_sphere(Sphere::try_new(Vec3::ZERO, 2.0)?, blue);
/// assert_eq!(full, Err(Error::CapacityExceeded { list: List::Spheres, capacity: 1 }));
/// # Ok::<(), Error>(())
/// ```
pub struct Scene<C: Capacities> {
    camera: Camera,
    ambient: Color,
    background: Color,
    primitives: Store<C>,
    materials: <C::Materials as Capacity>::List<Material>,
    lights: <C::Lights as Capacity>::List<Light>,
    /// The bounds of the triangles, kept as they are added.
    triangle_bounds: (Vec3, Vec3),
}

impl<C: Capacities> Clone for Scene<C> {
    fn clone(&self) -> Self {
        Self {
            primitives: self.primitives.clone(),
            materials: self.materials.clone_list(),
            lights: self.lights.clone_list(),
            ..*self
        }
    }
}

impl<C: Capacities> core::fmt::Debug for Scene<C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Scene")
            .field("camera", &self.camera)
            .field("ambient", &self.ambient)
            .field("background", &self.background)
            .field("primitives", &self.primitives.primitives())
            .field("materials", &&**self.materials.view())
            .field("lights", &&**self.lights.view())
            .finish()
    }
}

/// Empty bounds: any point widens them.
const NO_BOUNDS: (Vec3, Vec3) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));

/// `b` widened to `[min, max]`.
fn widen(b: &mut (Vec3, Vec3), min: Vec3, max: Vec3) {
    *b = (b.0.min(min), b.1.max(max));
}

fn push<X>(list: &mut VecView<X>, x: X, which: List) -> Result<(), Error> {
    let capacity = list.capacity();
    list.push(x).map_err(|_| Error::CapacityExceeded {
        list: which,
        capacity,
    })
}

impl<C: Capacities> Scene<C> {
    /// An empty scene seen by `camera`, with no ambient light and a black background.
    #[must_use]
    pub const fn new(camera: Camera) -> Self {
        Self {
            camera,
            ambient: Color::BLACK,
            background: Color::BLACK,
            primitives: Store::EMPTY,
            materials: empty::<C::Materials, Material>(),
            lights: empty::<C::Lights, Light>(),
            triangle_bounds: NO_BOUNDS,
        }
    }

    /// Sets the ambient light (each component in `[0, `[`crate::error::MAX_COLOR`]`]`).
    pub fn set_ambient(&mut self, ambient: Color) -> Result<(), Error> {
        self.ambient = crate::error::color(ambient, crate::error::Field::AmbientLight)?;
        Ok(())
    }

    /// Sets the background colour seen by rays that hit nothing (each component in
    /// `[0, `[`crate::error::MAX_COLOR`]`]`).
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
        let id =
            u16::try_from(self.materials.view().len()).map_err(|_| Error::CapacityExceeded {
                list: List::Materials,
                capacity: C::COUNTS.materials,
            })?;
        push(self.materials.view_mut(), material, List::Materials)?;
        Ok(MaterialId(id))
    }

    fn check_material(&self, id: MaterialId) -> Result<(), Error> {
        check_material(id, self.materials.view().len())
    }

    /// Adds a primitive of any kind (a [`Sphere`], a [`Plane`], ...) made of
    /// `material`.
    ///
    /// # Errors
    /// [`Error::MaterialOutOfRange`] for a material the scene does not hold,
    /// [`Error::CapacityExceeded`] when the kind's list is full.
    pub fn add<G: Geometry>(&mut self, geometry: G, material: MaterialId) -> Result<(), Error> {
        self.check_material(material)?;
        push(
            G::list_mut(&mut self.primitives),
            Primitive { geometry, material },
            G::KIND.list(),
        )?;
        if let Some(points) = geometry.hull_points() {
            for v in points {
                widen(&mut self.triangle_bounds, v, v);
            }
        }
        Ok(())
    }

    /// Adds a sphere made of `material` ([`Scene::add`]).
    pub fn add_sphere(&mut self, geometry: Sphere, material: MaterialId) -> Result<(), Error> {
        self.add(geometry, material)
    }

    /// Adds a plane made of `material` ([`Scene::add`]).
    pub fn add_plane(&mut self, geometry: Plane, material: MaterialId) -> Result<(), Error> {
        self.add(geometry, material)
    }

    /// Adds a triangle made of `material` ([`Scene::add`]).
    pub fn add_triangle(&mut self, geometry: Triangle, material: MaterialId) -> Result<(), Error> {
        self.add(geometry, material)
    }

    /// Adds an axis-aligned box made of `material` ([`Scene::add`]).
    pub fn add_box(&mut self, geometry: Aabb, material: MaterialId) -> Result<(), Error> {
        self.add(geometry, material)
    }

    /// Adds a point light.
    pub fn add_light(&mut self, light: Light) -> Result<(), Error> {
        push(self.lights.view_mut(), light, List::Lights)
    }

    /// A scene in RAM holding a copy of `view`'s lists (materials, lights,
    /// primitives; its ambient light and background), seen by `camera`: a baked
    /// scene copied to be changed, for instance. A view's meshes and hierarchies
    /// are not lists of the scene and are not copied (give them to the copy's
    /// view again). Each item is added as [`Scene::add_material`] and the other
    /// `add_` methods add it, checked.
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] naming the first list longer than its
    /// capacity here.
    pub fn from_view(camera: Camera, view: &SceneView<'_>) -> Result<Self, Error> {
        let mut s = Self::new(camera);
        s.set_ambient(view.ambient())?;
        s.set_background(view.background())?;
        for &m in view.materials() {
            s.add_material(m)?;
        }
        for &l in view.lights() {
            s.add_light(l)?;
        }
        each_kind!(|G| {
            for p in view.list::<G>() {
                s.add(p.geometry, p.material)?;
            }
        });
        Ok(s)
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
    pub(crate) fn scaled_pow2_hook(&self, k: i32) -> Result<Self, Error> {
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
        let lists = self.primitives.primitives();
        let on_planes = |i: usize| lists.planes.iter().any(|p| usize::from(p.material.0) == i);
        let elsewhere = |i: usize| {
            let mut used = false;
            each_kind!(|G| {
                if G::KIND != crate::kind::Kind::Plane {
                    used |= G::of(&lists).iter().any(|p| usize::from(p.material.0) == i);
                }
            });
            used
        };
        for (i, m) in self.materials.view().iter().enumerate() {
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
        for l in self.lights.view().iter() {
            // A sun's light does not fall off: its direction and intensity stay.
            out.add_light(match l.kind() {
                crate::light::LightKind::Point(p) => {
                    Light::point(p * f, l.color(), l.intensity() * f * f)?
                }
                #[cfg(feature = "sun")]
                crate::light::LightKind::Directional(_) => *l,
            })?;
        }
        each_kind!(|G| {
            for p in G::of(&lists) {
                out.add(p.geometry.scaled(f)?, p.material)?;
            }
        });
        Ok(out)
    }

    /// The frame of this scene's camera for `viewport` and `settings` (all checked):
    /// [`Renderer::try_new`] with [`Scene::camera`].
    pub fn renderer(
        &self,
        viewport: Viewport,
        settings: RenderSettings,
    ) -> Result<Renderer, Error> {
        Renderer::try_new(self.camera(), viewport, settings)
    }

    /// A borrowed, capacity-free view of the scene: what the renderer reads.
    #[must_use]
    pub fn view(&self) -> SceneView<'_> {
        Lists {
            primitives: self.primitives.primitives(),
            materials: self.materials.view(),
            lights: self.lights.view(),
        }
        .view::<C>(
            self.ambient,
            self.background,
            crate::cull::Hull::new(self.triangle_bounds.0, self.triangle_bounds.1),
        )
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
        let mut s: Scene<
            crate::capacities!(spheres: 1, planes: 1, triangles: 1, boxes: 1, materials: 1, lights: 1),
        > = Scene::new(cam());
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
        let li = Light::point(Vec3::Y, Color::WHITE, 1.0).unwrap();
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
        let mut only: Scene<crate::capacities!(spheres: 2, materials: 1)> = Scene::new(cam());
        let m = only.add_material(Material::matte(Color::WHITE)).unwrap();
        assert_eq!(
            only.add_plane(pl, m),
            Err(Error::CapacityExceeded {
                list: List::Planes,
                capacity: 0
            })
        );
    }

    /// A copy of a view holds the same lists, bit for bit, and its own view
    /// renders the same bytes; a capacity too small is named.
    #[test]
    fn from_view_copies_every_list_and_names_one_too_small() {
        let mut s: Scene<
            crate::capacities!(spheres: 1, planes: 1, triangles: 1, boxes: 1, materials: 2, lights: 1),
        > = Scene::new(cam());
        s.set_ambient(Color::splat(0.2)).unwrap();
        s.set_background(Color::new(0.1, 0.2, 0.3)).unwrap();
        s.add_material(Material::matte(Color::WHITE)).unwrap();
        let m = s
            .add_material(
                Material::matte(Color::new(0.9, 0.2, 0.1))
                    .with_reflectivity(0.5)
                    .unwrap(),
            )
            .unwrap();
        s.add_sphere(Sphere::try_new(Vec3::ZERO, 1.0).unwrap(), m)
            .unwrap();
        s.add_plane(
            Plane::try_new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y).unwrap(),
            MaterialId(0),
        )
        .unwrap();
        s.add_triangle(
            Triangle::try_new(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::Y).unwrap(),
            m,
        )
        .unwrap();
        s.add_box(
            Aabb::try_new(Vec3::splat(-2.0), Vec3::splat(-1.5)).unwrap(),
            m,
        )
        .unwrap();
        s.add_light(Light::point(Vec3::new(0.0, 4.0, 2.0), Color::WHITE, 20.0).unwrap())
            .unwrap();
        let copy: Scene<
            crate::capacities!(spheres: 2, planes: 1, triangles: 1, boxes: 1, materials: 2, lights: 1),
        > = Scene::from_view(*s.camera(), &s.view()).unwrap();
        let (a, b) = (s.view(), copy.view());
        assert_eq!(a.spheres(), b.spheres());
        assert_eq!(a.planes(), b.planes());
        assert_eq!(a.triangles(), b.triangles());
        assert_eq!(a.boxes(), b.boxes());
        assert_eq!(a.materials(), b.materials());
        assert_eq!(a.lights(), b.lights());
        assert_eq!((a.ambient(), a.background()), (b.ambient(), b.background()));
        let settings = RenderSettings {
            max_depth: 2,
            ..RenderSettings::default()
        };
        let renderer = s.renderer(Viewport::new(16, 16), settings).unwrap();
        let (mut ta, mut tb) = (crate::Tile::<16>::new(), crate::Tile::<16>::new());
        let origin = crate::TileCoord::new(0, 0);
        renderer.render_tile(&a, origin, &mut ta, &mut ()).unwrap();
        renderer.render_tile(&b, origin, &mut tb, &mut ()).unwrap();
        assert!(ta.rows().eq(tb.rows()));
        assert!(ta.rows().flatten().any(|p| p.r > 0));
        let small: Result<
            Scene<crate::capacities!(spheres: 1, planes: 1, boxes: 1, materials: 2, lights: 1)>,
            Error,
        > = Scene::from_view(*s.camera(), &a);
        assert_eq!(
            small.err(),
            Some(Error::CapacityExceeded {
                list: List::Triangles,
                capacity: 0
            })
        );
    }

    #[test]
    fn material_references_are_checked() {
        let mut s: Scene<crate::capacities!(spheres: 2, materials: 2)> = Scene::new(cam());
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
        let mut s: Scene<crate::capacities!()> = Scene::new(cam());
        assert!(s.set_ambient(Color::new(0.0, f32::NAN, 0.0)).is_err());
        assert!(s.set_background(Color::new(-1.0, 0.0, 0.0)).is_err());
        assert!(s.set_ambient(Color::splat(0.1)).is_ok());
    }

    #[test]
    fn unused_kinds_cost_no_memory() {
        use core::mem::size_of;
        let spheres_only =
            size_of::<Scene<crate::capacities!(spheres: 4, materials: 2, lights: 1)>>();
        let with_triangles = size_of::<
            Scene<crate::capacities!(spheres: 4, triangles: 16, materials: 2, lights: 1)>,
        >();
        assert!(with_triangles >= spheres_only + 16 * size_of::<Primitive<Triangle>>());
    }
}
