//! A whole scene as `static` data: camera, settings, materials, lights and
//! every primitive in tables that a firmware keeps in flash (`tessera bake`
//! writes them from a scene file). The renderer reads the tables where they
//! lie; a [`BakedScene`] takes no RAM of its own.
//!
//! The tables are made in a `const` context, where the checked constructors
//! cannot run: each item is made by its kind's `baked` constructor (its numbers
//! as the host computed them), and [`BakedScene::view`] checks every item once,
//! against what the checked constructor makes of the same numbers, before a
//! render can take it. A baked scene that gives a view is a valid scene, as a
//! [`crate::Scene`] is.

use crate::camera::{Camera, Viewport};
use crate::color::Color;
use crate::error::{Error, List};
use crate::geometry::Kinded;
use crate::kind::{Capacities, Geometry, Kind, LISTS, Primitives, each_kind};
use crate::light::Light;
use crate::material::Material;
use crate::tile::{RenderSettings, Renderer};
use crate::vec::Vec3;
use crate::view::{Lists, SceneView, check_material};
use core::marker::PhantomData;

/// A camera as a scene file gives it, before [`Camera::try_new`] checks and
/// normalises it: a baked scene keeps these numbers and makes its camera when
/// a frame is made ([`BakedScene::renderer`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakedCamera {
    /// Where the camera is.
    pub position: [f32; 3],
    /// Where it looks (any non-zero length).
    pub forward: [f32; 3],
    /// Its up direction (any non-zero length).
    pub up: [f32; 3],
    /// The vertical opening angle, in degrees.
    pub fovy_degrees: f32,
    /// The near distance.
    pub near: f32,
    /// The far distance.
    pub far: f32,
}

impl BakedCamera {
    /// The checked camera ([`Camera::try_new`]).
    ///
    /// # Errors
    /// As [`Camera::try_new`].
    pub fn camera(&self) -> Result<Camera, Error> {
        Camera::try_new(
            Vec3::from_array(self.position),
            Vec3::from_array(self.forward),
            Vec3::from_array(self.up),
            self.fovy_degrees,
            self.near,
            self.far,
        )
    }
}

/// A whole scene in `static` tables, with the settings and the size it is
/// meant to be rendered at: at most as many primitives of each kind as its
/// capacities `C` ([`capacities!`](crate::capacities); the tables' lengths,
/// which size a tile's candidate lists), and any number of materials and
/// lights.
///
/// Made in a `const` context (a `static` in flash) with [`BakedScene::new`],
/// its triangles' hierarchy and its meshes added with
/// `BakedScene::with_bvh` and `BakedScene::with_meshes` (feature `bvh`);
/// rendered through [`BakedScene::view`] and [`BakedScene::renderer`], which
/// check it first:
///
/// ```
/// use tessera_core::geometry::Sphere;
/// use tessera_core::light::Light;
/// use tessera_core::material::{Material, MaterialId};
/// use tessera_core::{
///     capacities, BakedCamera, BakedScene, Color, Encoding, Primitive, Primitives,
///     RenderSettings, Sampler, Tile, TileCoord, Viewport,
/// };
///
/// const RED: MaterialId = MaterialId(0);
/// static MATERIALS: [Material; 1] = [Material::matte(Color::new(0.9, 0.1, 0.1))];
/// static LIGHTS: [Light; 1] = [Light::baked_point([2.0, 4.0, 3.0], Color::WHITE, 1.0)];
/// static SPHERES: [Primitive<Sphere>; 1] =
///     [Primitive { geometry: Sphere::baked([0.0, 0.0, 0.0], 1.0), material: RED }];
/// static SCENE: BakedScene<'static, capacities!(spheres: 1)> = BakedScene::new(
///     BakedCamera {
///         position: [0.0, 0.0, 5.0],
///         forward: [0.0, 0.0, -1.0],
///         up: [0.0, 1.0, 0.0],
///         fovy_degrees: 60.0,
///         near: 0.1,
///         far: 100.0,
///     },
///     Viewport::new(32, 32),
///     RenderSettings { sampler: Sampler::Centre, max_depth: 0, seed: 0, encoding: Encoding::Srgb },
///     Color::BLACK,
///     Color::BLACK,
///     &MATERIALS,
///     &LIGHTS,
///     Primitives { spheres: &SPHERES, ..Primitives::NONE },
/// );
///
/// let view = SCENE.view()?;
/// let renderer = SCENE.renderer()?;
/// let mut tile = Tile::<16>::new();
/// renderer.render_tile(&view, TileCoord::new(0, 0), &mut tile, &mut ())?;
/// # Ok::<(), tessera_core::Error>(())
/// ```
pub struct BakedScene<'a, C: Capacities> {
    camera: BakedCamera,
    viewport: Viewport,
    settings: RenderSettings,
    ambient: Color,
    background: Color,
    materials: &'a [Material],
    lights: &'a [Light],
    primitives: Primitives<'a>,
    #[cfg(feature = "bvh")]
    bvh: Option<crate::bvh::BakedBvh<'a>>,
    #[cfg(feature = "bvh")]
    meshes: &'a [crate::mesh::Mesh<'a>],
    #[cfg(feature = "instances")]
    instances: &'a [crate::instance::Placed<'a>],
    capacities: PhantomData<fn() -> C>,
}

impl<C: Capacities> Clone for BakedScene<'_, C> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C: Capacities> Copy for BakedScene<'_, C> {}

impl<C: Capacities> core::fmt::Debug for BakedScene<'_, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("BakedScene")
            .field("capacities", &C::COUNTS)
            .field("camera", &self.camera)
            .field("viewport", &self.viewport)
            .field("settings", &self.settings)
            .field("ambient", &self.ambient)
            .field("background", &self.background)
            .field("materials", &self.materials)
            .field("lights", &self.lights)
            .field("primitives", &self.primitives)
            .finish_non_exhaustive()
    }
}

impl<'a, C: Capacities> BakedScene<'a, C> {
    /// A baked scene of these tables, not checked here ([`BakedScene::view`]
    /// and [`BakedScene::renderer`] check it, a table longer than its capacity
    /// among the rest). Primitives refer to materials by their index in
    /// `materials`.
    #[must_use]
    #[allow(clippy::too_many_arguments)]
    pub const fn new(
        camera: BakedCamera,
        viewport: Viewport,
        settings: RenderSettings,
        ambient: Color,
        background: Color,
        materials: &'a [Material],
        lights: &'a [Light],
        primitives: Primitives<'a>,
    ) -> Self {
        Self {
            camera,
            viewport,
            settings,
            ambient,
            background,
            materials,
            lights,
            primitives,
            #[cfg(feature = "bvh")]
            bvh: None,
            #[cfg(feature = "bvh")]
            meshes: &[],
            #[cfg(feature = "instances")]
            instances: &[],
            capacities: PhantomData,
        }
    }

    /// The same scene, its triangles searched through `bvh` (the hierarchy
    /// `tessera bake` builds over them).
    #[cfg(feature = "bvh")]
    #[must_use]
    pub const fn with_bvh(self, bvh: crate::bvh::BakedBvh<'a>) -> Self {
        Self {
            bvh: Some(bvh),
            ..self
        }
    }

    /// The same scene with `meshes`, after every other primitive (as
    /// [`SceneView::with_meshes`]).
    #[cfg(feature = "bvh")]
    #[must_use]
    pub const fn with_meshes(self, meshes: &'a [crate::mesh::Mesh<'a>]) -> Self {
        Self { meshes, ..self }
    }

    /// The same scene with its meshes drawn where `instances` place them
    /// (as [`SceneView::with_instances`]; the table `tessera bake` writes,
    /// checked by [`BakedScene::view`]).
    #[cfg(feature = "instances")]
    #[must_use]
    pub const fn with_instances(self, instances: &'a [crate::instance::Placed<'a>]) -> Self {
        Self { instances, ..self }
    }

    /// The same scene without its meshes: its lists alone, for a copy of them
    /// ([`crate::Scene::from_view`]) that does not check meshes it leaves out.
    #[must_use]
    pub(crate) const fn lists_only(self) -> Self {
        Self {
            #[cfg(feature = "bvh")]
            meshes: &[],
            #[cfg(feature = "instances")]
            instances: &[],
            ..self
        }
    }

    /// The camera as baked.
    #[must_use]
    pub const fn camera(&self) -> &BakedCamera {
        &self.camera
    }

    /// The size the scene is meant to be rendered at.
    #[must_use]
    pub const fn viewport(&self) -> Viewport {
        self.viewport
    }

    /// The settings the scene is meant to be rendered with.
    #[must_use]
    pub const fn settings(&self) -> RenderSettings {
        self.settings
    }

    /// The frame of the scene's camera at its own size and settings.
    ///
    /// # Errors
    /// As [`Renderer::try_new`] (the camera, the viewport and the settings
    /// checked).
    pub fn renderer(&self) -> Result<Renderer, Error> {
        self.renderer_at(self.viewport, self.settings)
    }

    /// The frame of the scene's camera over `viewport` with `settings`.
    ///
    /// # Errors
    /// As [`Renderer::try_new`].
    pub fn renderer_at(
        &self,
        viewport: Viewport,
        settings: RenderSettings,
    ) -> Result<Renderer, Error> {
        Renderer::try_new(&self.camera.camera()?, viewport, settings)
    }

    /// The view the renderer reads, borrowing the tables where they lie (no
    /// copy). Checked here, in time linear in the scene: the ambient light and
    /// the background, each material and light, each primitive against what
    /// its checked constructor makes of the same numbers, every material
    /// reference, the triangles' hierarchy and the meshes (as
    /// `SceneView::with_baked` and `SceneView::with_meshes` check them, feature
    /// `bvh`).
    ///
    /// # Errors
    /// The checked constructor's own error for a value it refuses;
    /// [`Error::BadBaked`] for an item that is not what it makes of its
    /// numbers; [`Error::MaterialOutOfRange`]; the hierarchy's and the
    /// meshes' errors.
    pub fn view(&self) -> Result<SceneView<'a>, Error> {
        // Read by the rule for subnormal numbers, as a scene's setters do.
        let ambient = crate::error::color(self.ambient, crate::error::Field::AmbientLight)?;
        let background = crate::error::color(self.background, crate::error::Field::Background)?;
        let caps = C::COUNTS.kinds();
        for ((&held, capacity), list) in self.primitives.lens().iter().zip(caps).zip(LISTS) {
            if held > capacity {
                return Err(Error::CapacityExceeded { list, capacity });
            }
        }
        let count = self.materials.len();
        if count > usize::from(u16::MAX) {
            return Err(Error::CapacityExceeded {
                list: List::Materials,
                capacity: usize::from(u16::MAX),
            });
        }
        for (i, m) in self.materials.iter().enumerate() {
            m.validate()?;
            if m.flushed() != *m {
                return Err(bad(List::Materials, i));
            }
        }
        for (i, l) in self.lights.iter().enumerate() {
            same(l.checked()?, *l, List::Lights, i)?;
        }
        let prims = &self.primitives;
        each_kind!(|G| {
            // The triangles are checked with their hierarchy or their hull
            // (`flat_triangles`).
            if G::KIND != Kind::Triangle {
                for (i, p) in G::of(prims).iter().enumerate() {
                    check_material(p.material, count)?;
                    if !p.geometry.check_baked()? {
                        return Err(bad(G::KIND.list(), i));
                    }
                }
            }
        });
        let view = Lists {
            primitives: Primitives {
                triangles: &[],
                ..*prims
            },
            materials: self.materials,
            lights: self.lights,
        }
        .view::<C>(ambient, background, None);
        #[cfg(feature = "bvh")]
        let view = match &self.bvh {
            Some(bvh) => view.with_baked(self.primitives.triangles, bvh)?,
            None => self.flat_triangles(view)?,
        };
        #[cfg(not(feature = "bvh"))]
        let view = self.flat_triangles(view)?;
        #[cfg(feature = "bvh")]
        let view = if self.meshes.is_empty() {
            view
        } else {
            view.with_meshes(self.meshes)?
        };
        #[cfg(feature = "instances")]
        let view = if self.instances.is_empty() {
            view
        } else {
            view.with_placed(self.instances)?
        };
        Ok(view)
    }

    /// `view` with the triangles as a flat list (culled per tile), each checked.
    fn flat_triangles(&self, view: SceneView<'a>) -> Result<SceneView<'a>, Error> {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for (i, p) in self.primitives.triangles.iter().enumerate() {
            check_material(p.material, self.materials.len())?;
            if !Kinded::check_baked(&p.geometry)? {
                return Err(bad(List::Triangles, i));
            }
            for v in p.geometry.vertices() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        Ok(SceneView {
            primitives: Primitives {
                triangles: self.primitives.triangles,
                ..view.primitives
            },
            triangle_hull: crate::cull::Hull::new(lo, hi),
            ..view
        })
    }
}

/// [`Error::BadBaked`] for item `i` of `list`.
fn bad(list: List, i: usize) -> Error {
    Error::BadBaked {
        list,
        index: u16::try_from(i).unwrap_or(u16::MAX),
    }
}

/// `Ok` when the checked constructor made the baked item again (equal numbers).
fn same<X: PartialEq>(made: X, baked: X, list: List, i: usize) -> Result<(), Error> {
    if made == baked {
        Ok(())
    } else {
        Err(bad(list, i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Sphere};
    use crate::material::MaterialId;
    use crate::primitive::Primitive;
    use crate::sample::Sampler;
    use crate::texture::Texture;

    const CAM: BakedCamera = BakedCamera {
        position: [0.0, 1.0, 5.0],
        forward: [0.0, 0.0, -1.0],
        up: [0.0, 1.0, 0.0],
        fovy_degrees: 60.0,
        near: 0.1,
        far: 100.0,
    };
    const SETTINGS: RenderSettings = RenderSettings {
        sampler: Sampler::Centre,
        max_depth: 2,
        seed: 0,
        encoding: crate::Encoding::Srgb,
    };
    const MATTE: Material = Material::matte(Color::new(0.5, 0.5, 0.5));
    static MATERIALS: [Material; 1] = [MATTE];
    static LIGHTS: [Light; 1] = [Light::baked_point([0.0, 5.0, 0.0], Color::WHITE, 1.0)];

    fn sphere(center: [f32; 3], radius: f32, m: u16) -> [Primitive<Sphere>; 1] {
        [Primitive {
            geometry: Sphere::baked(center, radius),
            material: MaterialId(m),
        }]
    }

    /// A scene of one sphere (and `materials`, `planes`).
    fn scene<'a>(
        materials: &'a [Material],
        spheres: &'a [Primitive<Sphere>; 1],
        planes: &'a [Primitive<Plane>; 1],
    ) -> BakedScene<'a, crate::capacities!(spheres: 1, planes: 1)> {
        BakedScene::new(
            CAM,
            Viewport::new(8, 8),
            SETTINGS,
            Color::BLACK,
            Color::BLACK,
            materials,
            &LIGHTS,
            Primitives {
                spheres,
                planes,
                ..Primitives::NONE
            },
        )
    }

    fn floor(normal: [f32; 3], offset: f32) -> [Primitive<Plane>; 1] {
        let made = Plane::try_new(Vec3::ZERO, Vec3::Y).unwrap();
        let (point, _, _, tangents) = made.parts();
        [Primitive {
            geometry: Plane::baked(point, normal, offset, tangents),
            material: MaterialId(0),
        }]
    }

    #[test]
    fn a_baked_scene_equal_to_the_checked_one_gives_a_view() {
        let s = sphere([0.0, 0.0, 0.0], 1.0, 0);
        let p = floor([0.0, 1.0, 0.0], 0.0);
        let view = scene(&MATERIALS, &s, &p).view().unwrap();
        assert_eq!(view.spheres().len(), 1);
        assert!(scene(&MATERIALS, &s, &p).renderer().is_ok());
    }

    /// A table longer than its capacity is refused, naming its list: the
    /// capacities size a tile's candidate lists, which must hold every item.
    #[test]
    fn a_table_longer_than_its_capacity_is_refused() {
        let two = [
            sphere([0.0, 0.0, 0.0], 1.0, 0)[0],
            sphere([2.0, 0.0, 0.0], 1.0, 0)[0],
        ];
        let p = floor([0.0, 1.0, 0.0], 0.0);
        let primitives = Primitives {
            spheres: &two,
            planes: &p,
            ..Primitives::NONE
        };
        let baked = |p| -> BakedScene<'_, crate::capacities!(spheres: 1, planes: 1)> {
            BakedScene::new(
                CAM,
                Viewport::new(8, 8),
                SETTINGS,
                Color::BLACK,
                Color::BLACK,
                &MATERIALS,
                &LIGHTS,
                p,
            )
        };
        assert_eq!(
            baked(primitives).view().err(),
            Some(Error::CapacityExceeded {
                list: List::Spheres,
                capacity: 1
            })
        );
        let one = Primitives {
            spheres: &two[..1],
            ..primitives
        };
        assert_eq!(baked(one).view().map(|v| v.spheres().len()), Ok(1));
    }

    #[test]
    fn every_altered_item_is_refused() {
        let ok_s = sphere([0.0, 0.0, 0.0], 1.0, 0);
        let ok_p = floor([0.0, 1.0, 0.0], 0.0);
        let bad_radius = sphere([0.0, 0.0, 0.0], -1.0, 0);
        assert_eq!(
            scene(&MATERIALS, &bad_radius, &ok_p).view().err(),
            Some(Error::NotPositive(crate::error::Field::SphereRadius))
        );
        // A subnormal centre: try_new reads it as 0, so the item is not what it
        // makes of its numbers.
        let subnormal = sphere([1e-42, 0.0, 0.0], 1.0, 0);
        assert_eq!(
            scene(&MATERIALS, &subnormal, &ok_p).view().err(),
            Some(Error::BadBaked {
                list: List::Spheres,
                index: 0
            })
        );
        let no_material = sphere([0.0, 0.0, 0.0], 1.0, 1);
        assert_eq!(
            scene(&MATERIALS, &no_material, &ok_p).view().err(),
            Some(Error::MaterialOutOfRange { id: 1, count: 1 })
        );
        for plane in [
            floor([0.0, 2.0, 0.0], 0.0),
            floor([0.0, 1.0, 0.0], 0.5),
            floor([0.0, 1.0, 0.0], f32::NAN),
        ] {
            assert_eq!(
                scene(&MATERIALS, &ok_s, &plane).view().err(),
                Some(Error::BadBaked {
                    list: List::Planes,
                    index: 0
                })
            );
        }
        let glow = [Material::baked(
            Texture::Solid(Color::WHITE),
            2.0,
            1.0,
            0.0,
            1.0,
            0.0,
            0.0,
            1.0,
        )];
        assert!(scene(&glow, &ok_s, &ok_p).view().is_err());
        let tiny = [Material::baked(
            Texture::Solid(Color::WHITE),
            1e-40,
            1.0,
            0.0,
            1.0,
            0.0,
            0.0,
            1.0,
        )];
        assert_eq!(
            scene(&tiny, &ok_s, &ok_p).view().err(),
            Some(Error::BadBaked {
                list: List::Materials,
                index: 0
            })
        );
        let mut camera = scene(&MATERIALS, &ok_s, &ok_p);
        camera.camera.near = 200.0;
        assert_eq!(camera.renderer().err(), Some(Error::NearNotBeforeFar));
    }

    /// The baked table of the plane `try_new(point, normal)` with `change`
    /// applied to its numbers.
    fn tampered(
        point: Vec3,
        normal: Vec3,
        change: impl Fn(&mut [f32; 3], &mut f32),
    ) -> [Primitive<Plane>; 1] {
        let (mut p, n, mut offset, tangents) = Plane::try_new(point, normal).unwrap().parts();
        change(&mut p, &mut offset);
        [Primitive {
            geometry: Plane::baked(p, n, offset, tangents),
            material: MaterialId(0),
        }]
    }

    const BAD_PLANE: Option<Error> = Some(Error::BadBaked {
        list: List::Planes,
        index: 0,
    });

    /// A subnormal in a baked plane's point is refused as in a sphere's centre:
    /// `Plane::try_new` reads it as zero, so the table is not what it makes.
    #[test]
    fn a_baked_plane_with_a_subnormal_point_is_refused() {
        let s = sphere([0.0, 0.0, 0.0], 1.0, 0);
        let ok = tampered(Vec3::new(0.0, -1.0, 0.0), Vec3::Y, |_, _| ());
        assert!(scene(&MATERIALS, &s, &ok).view().is_ok());
        for (axis, tiny) in [(0, 1e-42), (1, -1e-40), (2, 1.1e-38)] {
            let p = tampered(Vec3::new(0.0, -1.0, 0.0), Vec3::Y, |p, _| p[axis] = tiny);
            assert_eq!(
                scene(&MATERIALS, &s, &p).view().err(),
                BAD_PLANE,
                "{axis} {tiny}"
            );
        }
        let p = tampered(Vec3::ZERO, Vec3::Y, |p, _| p[1] = 1e-42);
        assert_eq!(scene(&MATERIALS, &s, &p).view().err(), BAD_PLANE);
    }

    /// A baked plane's offset is what `Plane::try_new` computes: one through
    /// `(1e6, 0, 0)` with the normal `y` has the offset 0, and 0.95 (within 8
    /// ulps of `|point|`) is refused; so is an oblique plane's offset moved by
    /// much less than that, and the untampered planes are taken.
    #[test]
    fn a_baked_plane_offset_not_the_constructors_is_refused() {
        let s = sphere([0.0, 0.0, 0.0], 1.0, 0);
        let far = Vec3::new(1e6, 0.0, 0.0);
        assert!(
            scene(&MATERIALS, &s, &tampered(far, Vec3::Y, |_, _| ()))
                .view()
                .is_ok()
        );
        for offset in [0.95, 1e-3, 1e-30, -1e-20] {
            let p = tampered(far, Vec3::Y, |_, o| *o = offset);
            assert_eq!(
                scene(&MATERIALS, &s, &p).view().err(),
                BAD_PLANE,
                "{offset}"
            );
        }
        let (point, normal) = (Vec3::new(1e6, 2e5, -3e5), Vec3::new(0.3, 0.9, -0.2));
        let made = Plane::try_new(point, normal).unwrap().parts().2;
        assert!(
            scene(&MATERIALS, &s, &tampered(point, normal, |_, _| ()))
                .view()
                .is_ok()
        );
        for delta in [0.5, -0.5, 0.25] {
            let p = tampered(point, normal, |_, o| *o = made + delta);
            assert_eq!(scene(&MATERIALS, &s, &p).view().err(), BAD_PLANE, "{delta}");
        }
    }

    #[test]
    fn a_baked_material_is_the_one_its_builders_make() {
        let built = Material::matte(Color::WHITE)
            .with_specular(0.4, 48.0)
            .and_then(|m| m.with_reflectivity(0.3))
            .unwrap();
        let baked = Material::baked(
            Texture::Solid(Color::WHITE),
            1.0,
            1.0,
            0.4,
            48.0,
            0.3,
            0.0,
            1.0,
        );
        assert_eq!(baked, built);
        let odd = Material::matte(Color::WHITE)
            .with_specular(0.4, 2.5)
            .unwrap();
        let baked = Material::baked(
            Texture::Solid(Color::WHITE),
            1.0,
            1.0,
            0.4,
            2.5,
            0.0,
            0.0,
            1.0,
        );
        assert_eq!(baked, odd);
    }
}
