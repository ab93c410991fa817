//! The scene as the renderer sees it ([`SceneView`]): the lists as slices, no
//! capacities, so the renderer is compiled once whatever the scene's capacities;
//! and what a view may carry besides (hierarchies, meshes, the triangles' hull).

#[cfg(feature = "bvh")]
use crate::bvh::{BakedBvh, check_faces, list_bounds};
use crate::color::Color;
use crate::cull::LISTS;
use crate::error::Error;
#[cfg(feature = "bvh")]
use crate::error::List;
use crate::geometry::{Aabb, Plane, Sphere, Triangle};
use crate::kind::Primitives;
use crate::light::Light;
use crate::material::{Material, MaterialId};
#[cfg(feature = "bvh")]
use crate::mesh::{MAX_MESHES, Mesh};
use crate::primitive::Primitive;

/// A scene's lists, which a view borrows ([`Scene::view`], and a baked scene's
/// `view`).
pub(crate) struct Lists<'a> {
    pub(crate) primitives: Primitives<'a>,
    pub(crate) materials: &'a [Material],
    pub(crate) lights: &'a [Light],
}

impl<'a> Lists<'a> {
    /// The view of these lists searched flat (no hierarchy, no meshes), each
    /// tile's culling lists sized by the capacities `C`, the triangles within
    /// `triangle_hull`.
    pub(crate) fn view<C: crate::kind::Capacities>(
        self,
        ambient: Color,
        background: Color,
        triangle_hull: Option<crate::cull::Hull>,
    ) -> SceneView<'a> {
        SceneView {
            primitives: self.primitives,
            materials: self.materials,
            lights: self.lights,
            ambient,
            background,
            // Model only what the scene requires: without a mirror or a transparent
            // material no secondary ray can exist, so the tracer skips that work.
            secondary: self.materials.iter().any(Material::sends_rays),
            tile_storage: crate::cull::TileStorage::<C>::lend,
            culling: true,
            triangle_hull,
            #[cfg(feature = "bvh")]
            bvh: None,
            #[cfg(feature = "bvh")]
            sphere_bvh: None,
            #[cfg(feature = "bvh")]
            meshes: &[],
            #[cfg(feature = "instances")]
            instances: &[],
            #[cfg(feature = "instances")]
            instanced: 0,
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
/// the tile, listed before its pixels: 6 bytes for each primitive of capacity, and
/// their lengths, on the stack of
/// [`Renderer::render_tile`](crate::Renderer::render_tile)); [`crate::Scene::view`] gives the
/// view a small function of the scene's type that lends that room, so the
/// capacities never reach the renderer's code.
#[derive(Clone, Copy)]
pub struct SceneView<'a> {
    pub(crate) primitives: Primitives<'a>,
    pub(crate) materials: &'a [Material],
    pub(crate) lights: &'a [Light],
    pub(crate) ambient: Color,
    pub(crate) background: Color,
    pub(crate) secondary: bool,
    /// Lends a tile the storage of its candidate lists (the scene's capacities
    /// are known only there: see [`crate::cull::TileStorage::lend`]).
    pub(crate) tile_storage: crate::cull::Lender,
    /// Whether tiles build candidate lists (false only for the test hook
    /// `without_culling`).
    pub(crate) culling: bool,
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
    /// The meshes' instances ([`SceneView::with_instances`]), searched after
    /// the meshes drawn in place.
    #[cfg(feature = "instances")]
    pub(crate) instances: &'a [crate::instance::Placed<'a>],
    /// The meshes drawn only through instances, a bit each.
    #[cfg(feature = "instances")]
    pub(crate) instanced: u16,
}

impl core::fmt::Debug for SceneView<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SceneView")
            .field("primitives", &self.primitives)
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
    #[cfg(any(feature = "testing", all(test, feature = "instances")))]
    #[must_use]
    pub(crate) fn without_culling_hook(&self) -> Self {
        Self {
            culling: false,
            triangle_hull: None,
            #[cfg(feature = "bvh")]
            bvh: None,
            #[cfg(feature = "bvh")]
            sphere_bvh: None,
            #[cfg(feature = "bvh")]
            meshes: self.meshes,
            ..*self
        }
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
        bvh: &'a crate::bvh::Bvh<N, T>,
    ) -> Result<Self, Error> {
        if bvh.triangle_count() != self.primitives.triangles.len()
            || bvh.key() != crate::bvh::key(self.primitives.triangles)
        {
            return Err(Error::BvhMismatch);
        }
        let pays = self.primitives.triangles.len() >= crate::bvh::CROSSOVER;
        Ok(Self {
            bvh: pays.then(|| bvh.view()),
            ..*self
        })
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
    pub(crate) fn with_bvh_always_hook<const N: usize, const T: usize>(
        &self,
        bvh: &'a crate::bvh::Bvh<N, T>,
    ) -> Result<Self, Error> {
        let v = self.with_bvh(bvh)?;
        Ok(Self {
            bvh: Some(bvh.view()),
            ..v
        })
    }

    /// The same view without its BVH: the flat lists (a test hook, with the feature
    /// `testing`).
    #[cfg(feature = "bvh")]
    #[cfg(feature = "testing")]
    #[must_use]
    pub(crate) fn without_bvh_hook(&self) -> Self {
        Self {
            bvh: None,
            sphere_bvh: None,
            ..*self
        }
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
        bvh: &'a crate::bvh::Bvh<N, T>,
    ) -> Result<Self, Error> {
        if bvh.triangle_count() != self.primitives.spheres.len()
            || bvh.key() != crate::bvh::key(self.primitives.spheres)
        {
            return Err(Error::BvhMismatch);
        }
        let pays = self.primitives.spheres.len() >= crate::bvh::SPHERE_CROSSOVER;
        Ok(Self {
            sphere_bvh: pays.then(|| bvh.view()),
            ..*self
        })
    }

    /// [`SceneView::with_sphere_bvh`] whatever the number of spheres (a test hook,
    /// with the feature `testing`).
    ///
    /// # Errors
    /// As [`SceneView::with_sphere_bvh`].
    #[cfg(feature = "bvh")]
    #[cfg(feature = "testing")]
    pub(crate) fn with_sphere_bvh_always_hook<const N: usize, const T: usize>(
        &self,
        bvh: &'a crate::bvh::Bvh<N, T>,
    ) -> Result<Self, Error> {
        let v = self.with_sphere_bvh(bvh)?;
        Ok(Self {
            sphere_bvh: Some(bvh.view()),
            ..v
        })
    }

    /// The meshes drawn only through instances (a bit each) and the number of
    /// instances: none of either without the feature `instances`.
    #[cfg(feature = "bvh")]
    #[inline(always)]
    pub(crate) fn instancing(&self) -> (u16, usize) {
        #[cfg(feature = "instances")]
        let instancing = (self.instanced, self.instances.len());
        #[cfg(not(feature = "instances"))]
        let instancing = (0, 0);
        instancing
    }

    /// True when a list is searched through a hierarchy (triangles, spheres):
    /// the searches go through it and the tiles build no lists. (The meshes'
    /// hierarchies are searched from a tile's list of meshes and instances.)
    #[inline(always)]
    pub(crate) fn through(&self) -> bool {
        #[cfg(feature = "bvh")]
        let through = self.bvh.is_some() || self.sphere_bvh.is_some();
        #[cfg(not(feature = "bvh"))]
        let through = false;
        through
    }

    /// The hull the view keeps of list `kind`'s primitives (the triangles'
    /// only), if any.
    #[inline(always)]
    pub(crate) fn hull(&self, kind: crate::kind::Kind) -> Option<crate::cull::Hull> {
        match kind {
            crate::kind::Kind::Triangle => self.triangle_hull,
            _ => None,
        }
    }

    /// The lengths of the lists a tile culls (spheres, planes, triangles, boxes,
    /// then the meshes drawn where they lie and the instances: see
    /// [`crate::cull::LISTS`]), or `None` when its tiles build no lists: a list
    /// is searched through a hierarchy, or culling is off.
    #[inline(always)]
    pub(crate) fn culled_lists(&self) -> Option<[usize; LISTS]> {
        let kinds = self.primitives.lens();
        #[cfg(feature = "bvh")]
        let tops = self.meshes.len() + self.instancing().1;
        #[cfg(not(feature = "bvh"))]
        let tops = 0;
        let lens = core::array::from_fn(|k| kinds.get(k).copied().unwrap_or(tops));
        (self.culling && !self.through()).then_some(lens)
    }

    /// The depth that rays reach in this scene when `max_depth` is asked for: at
    /// most [`crate::error::MAX_DEPTH`], and 0 without a mirror or a transparent material.
    pub(crate) fn depth(&self, max_depth: u8) -> u8 {
        if self.secondary {
            max_depth.min(crate::error::MAX_DEPTH)
        } else {
            0
        }
    }

    /// The same view with `list` in place of its primitives of kind `G`: a
    /// frame's changes to a scene that lies in flash. Copy the kind's table
    /// into RAM (a baked scene's `SPHERES`, say: the only bytes of the scene in
    /// RAM), change what moves, and render the frame through the view this
    /// returns; every other list, the lights, the materials, the meshes and
    /// their hierarchies stay the view's, read where they lie, so no part of the
    /// scene can be left out. Checked here in time linear in `list` alone (each
    /// item as its checked constructor makes it, each material reference in
    /// range): a frame's set-up costs what changed, not the scene.
    ///
    /// `list` holds at most as many items as the view's list of that kind (the
    /// room its tiles' culling lists have; fewer hides the rest). Per-tile and
    /// shadow culling follow the new list. A hierarchy built over the old list
    /// (a baked scene's triangle BVH, a sphere BVH) is left out: the new list
    /// is searched flat, to the same pixels.
    ///
    /// ```
    /// use tessera_core::{builtin::Builtin, geometry::Sphere, Primitive, Tile, TileCoord, Vec3};
    ///
    /// Builtin::Showcase.with_baked_scene(|view, camera| -> Result<(), tessera_core::Error> {
    ///     // The spheres in RAM; the rest of the scene stays where it lies.
    ///     let mut spheres = [view.spheres()[0]; 8];
    ///     let spheres = &mut spheres[..view.spheres().len()];
    ///     spheres.copy_from_slice(view.spheres());
    ///     let renderer = tessera_core::Renderer::try_new(
    ///         camera,
    ///         tessera_core::Viewport::new(32, 32),
    ///         tessera_core::RenderSettings::default(),
    ///     )?;
    ///     let mut tile = Tile::<16>::new();
    ///     for frame in 0..3 {
    ///         let s = spheres[0].geometry;
    ///         let lifted = s.center() + Vec3::new(0.0, 0.1 * frame as f32, 0.0);
    ///         spheres[0].geometry = Sphere::try_new(lifted, s.radius())?; // checked here
    ///         let moved = view.with_list(&*spheres)?;
    ///         renderer.render_tile(&moved, TileCoord::new(0, 0), &mut tile, &mut ())?;
    ///     }
    ///     Ok(())
    /// })??;
    /// # Ok::<(), tessera_core::Error>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] for a list longer than the view's;
    /// [`Error::MaterialOutOfRange`]; the kind's own error for numbers its
    /// constructor refuses, and [`Error::BadBaked`] for an item that is not
    /// what its constructor makes of its numbers (written by hand).
    pub fn with_list<G: crate::kind::Geometry>(
        &self,
        list: &'a [Primitive<G>],
    ) -> Result<Self, Error> {
        let room = G::of(&self.primitives).len();
        if list.len() > room {
            return Err(Error::CapacityExceeded {
                list: G::KIND.list(),
                capacity: room,
            });
        }
        let count = self.materials.len();
        let mut lo = crate::Vec3::splat(f32::INFINITY);
        let mut hi = crate::Vec3::splat(f32::NEG_INFINITY);
        for (i, p) in list.iter().enumerate() {
            check_material(p.material, count)?;
            if !p.geometry.is_as_made()? {
                return Err(Error::BadBaked {
                    list: G::KIND.list(),
                    index: u16::try_from(i).unwrap_or(u16::MAX),
                });
            }
            if let Some(points) = p.geometry.hull_points() {
                for v in points {
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
        }
        let mut primitives = self.primitives;
        G::set(&mut primitives, list);
        let mut view = Self {
            primitives,
            ..*self
        };
        match G::KIND {
            crate::kind::Kind::Triangle => {
                view.triangle_hull = crate::cull::Hull::new(lo, hi);
                #[cfg(feature = "bvh")]
                {
                    view.bvh = None;
                }
            }
            #[cfg(feature = "bvh")]
            crate::kind::Kind::Sphere => view.sphere_bvh = None,
            _ => {}
        }
        Ok(view)
    }

    /// The same view with `lights` in place of its lights (a frame's moved or
    /// recoloured lights, copied into RAM and changed), checked here in time
    /// linear in them; the rest of the scene stays the view's, as
    /// [`SceneView::with_list`] keeps it.
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] for more lights than the view has; the
    /// light's own error for numbers [`Light`]'s constructors refuse;
    /// [`Error::BadBaked`] for a light that is not what they make of its
    /// numbers.
    pub fn with_lights(&self, lights: &'a [Light]) -> Result<Self, Error> {
        if lights.len() > self.lights.len() {
            return Err(Error::CapacityExceeded {
                list: crate::error::List::Lights,
                capacity: self.lights.len(),
            });
        }
        for (i, l) in lights.iter().enumerate() {
            if l.checked()? != *l {
                return Err(Error::BadBaked {
                    list: crate::error::List::Lights,
                    index: u16::try_from(i).unwrap_or(u16::MAX),
                });
            }
        }
        Ok(Self { lights, ..*self })
    }

    /// The same view with `materials` in place of its materials (a frame's
    /// changed colours, copied into RAM and changed), checked here in time
    /// linear in them; the primitives keep referring to them by index. A
    /// mirror or glass added or taken away turns secondary rays on or off.
    ///
    /// # Errors
    /// [`Error::MaterialOutOfRange`] for fewer materials than the view has
    /// (the primitives refer to them all as far as this knows: the first
    /// missing one is named); the material's own error
    /// ([`Material::validate`]); [`Error::BadBaked`] for a material with a
    /// subnormal number (one its constructors read as zero).
    pub fn with_materials(&self, materials: &'a [Material]) -> Result<Self, Error> {
        if materials.len() < self.materials.len() {
            return Err(Error::MaterialOutOfRange {
                id: u16::try_from(materials.len()).unwrap_or(u16::MAX),
                count: u16::try_from(materials.len()).unwrap_or(u16::MAX),
            });
        }
        if materials.len() > usize::from(u16::MAX) {
            return Err(Error::CapacityExceeded {
                list: crate::error::List::Materials,
                capacity: usize::from(u16::MAX),
            });
        }
        for (i, m) in materials.iter().enumerate() {
            m.validate()?;
            if m.flushed() != *m {
                return Err(Error::BadBaked {
                    list: crate::error::List::Materials,
                    index: u16::try_from(i).unwrap_or(u16::MAX),
                });
            }
        }
        Ok(Self {
            materials,
            secondary: materials.iter().any(Material::sends_rays),
            ..*self
        })
    }

    /// The primitives of one kind: `view.list::<Sphere>()`.
    #[must_use]
    pub fn list<G: crate::kind::Geometry>(&self) -> &'a [Primitive<G>] {
        G::of(&self.primitives)
    }

    /// The spheres.
    #[must_use]
    pub fn spheres(&self) -> &'a [Primitive<Sphere>] {
        self.primitives.spheres
    }
    /// The planes.
    #[must_use]
    pub fn planes(&self) -> &'a [Primitive<Plane>] {
        self.primitives.planes
    }
    /// The triangles.
    #[must_use]
    pub fn triangles(&self) -> &'a [Primitive<Triangle>] {
        self.primitives.triangles
    }
    /// The boxes.
    #[must_use]
    pub fn boxes(&self) -> &'a [Primitive<Aabb>] {
        self.primitives.boxes
    }
    /// The indexed meshes ([`SceneView::with_meshes`]).
    #[cfg(feature = "bvh")]
    #[must_use]
    pub fn meshes(&self) -> &'a [crate::mesh::Mesh<'a>] {
        self.meshes
    }
    /// The materials.
    #[must_use]
    pub fn materials(&self) -> &'a [Material] {
        self.materials
    }
    /// The lights.
    #[must_use]
    pub fn lights(&self) -> &'a [Light] {
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

#[cfg(feature = "bvh")]
impl<'a> SceneView<'a> {
    /// The same view with baked triangles and their hierarchy, kept where they lie
    /// (in flash: `static` data written by `tessera bake`), searched through the
    /// hierarchy. The view's own scene must have no triangles; the baked ones
    /// follow its other primitives and use its materials by index.
    ///
    /// Checked once here (time linear in the triangles; no memory beyond a
    /// small bitmap): each triangle as [`Triangle::try_new`] makes it, each
    /// material in range, and the hierarchy's structure and bounds (every leaf's
    /// triangles within it, every node within its parent, each triangle in
    /// exactly one leaf), so that every search finds what the flat list would.
    ///
    /// # Errors
    /// [`Error::BvhMismatch`] when the scene has triangles of its own or the
    /// hierarchy does not fit the triangles; [`Error::MaterialOutOfRange`];
    /// the triangle's own error for a vertex [`Triangle::try_new`] refuses.
    pub fn with_baked(
        &self,
        triangles: &'a [Primitive<Triangle>],
        bvh: &BakedBvh<'a>,
    ) -> Result<Self, Error> {
        if !self.primitives.triangles.is_empty() {
            return Err(Error::BvhMismatch);
        }
        let face = |i: usize| triangles.get(i).copied().ok_or(Error::BvhMismatch);
        check_faces(triangles.len(), face, self.materials.len(), bvh)?;
        let all = list_bounds(triangles);
        Ok(Self {
            primitives: Primitives {
                triangles,
                ..self.primitives
            },
            triangle_hull: crate::cull::Hull::new(all.0, all.1),
            bvh: (!triangles.is_empty()).then_some(bvh.view()),
            ..*self
        })
    }

    /// The same view with `meshes` (at most [`MAX_MESHES`]) among its primitives,
    /// after every list: at equal times a mesh's face is found only where no
    /// other primitive is, and among faces the mesh listed first, then the face
    /// listed first, is. Each mesh is checked once here ([`Mesh::new`] says what),
    /// in time linear in its faces.
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] for [`List::Meshes`] beyond [`MAX_MESHES`];
    /// [`Error::BadMesh`] when a mesh's faces, normals or hierarchy do not fit, or
    /// the view has meshes already;
    /// [`Error::MaterialOutOfRange`]; a face's own error ([`Triangle::try_new`]).
    pub fn with_meshes(&self, meshes: &'a [Mesh<'a>]) -> Result<Self, Error> {
        if !self.meshes.is_empty() {
            return Err(Error::BadMesh);
        }
        if meshes.len() > MAX_MESHES {
            return Err(Error::CapacityExceeded {
                list: List::Meshes,
                capacity: MAX_MESHES,
            });
        }
        for m in meshes {
            m.check(self.materials.len())?;
        }
        Ok(Self { meshes, ..*self })
    }

    /// The same view with the meshes drawn where `instances` place them: a
    /// mesh that an instance names is drawn at each of its instances and no
    /// longer where it lies; the others stay. Checked when each instance was
    /// placed ([`crate::instance::Instances::set`]); here only that they are of
    /// this view's meshes, in time linear in their count.
    ///
    /// # Errors
    /// [`Error::BadMesh`] for instances of another view's meshes.
    #[cfg(feature = "instances")]
    pub fn with_instances<const N: usize>(
        &self,
        instances: &'a crate::instance::Instances<'a, N>,
    ) -> Result<Self, Error> {
        let theirs = instances.meshes();
        if theirs.len() != self.meshes.len() || !core::ptr::eq(theirs, self.meshes) {
            return Err(Error::BadMesh);
        }
        let placed = instances.placed();
        Ok(Self {
            instances: placed,
            instanced: crate::instance::instanced(placed),
            ..*self
        })
    }

    /// The same view with baked `instances` (checked).
    #[cfg(feature = "instances")]
    pub(crate) fn with_placed(
        &self,
        instances: &'a [crate::instance::Placed<'a>],
    ) -> Result<Self, Error> {
        crate::instance::check_baked(self.meshes, instances)?;
        Ok(Self {
            instances,
            instanced: crate::instance::instanced(instances),
            ..*self
        })
    }

    /// How many instances of the meshes the view draws
    /// ([`SceneView::with_instances`]).
    #[cfg(feature = "instances")]
    #[must_use]
    pub fn instance_count(&self) -> usize {
        self.instances.len()
    }
}

#[cfg(feature = "instances")]
impl<'a, const N: usize> crate::instance::Instances<'a, N> {
    /// No instance yet, of the meshes of `view`.
    #[must_use]
    pub fn new(view: &SceneView<'a>) -> Self {
        Self::empty(view.meshes)
    }

    /// The instances `view` draws (a baked scene's, say), copied into RAM to
    /// be moved ([`crate::instance::Instances::set`]), then given back to the
    /// view ([`SceneView::with_instances`]).
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] when the view has more than `N`.
    pub fn of(view: &SceneView<'a>) -> Result<Self, Error> {
        Self::over(view.meshes, view.instances)
    }
}

impl crate::cull::Source for SceneView<'_> {
    #[inline(always)]
    fn primitives(&self) -> Primitives<'_> {
        self.primitives
    }
    #[inline(always)]
    fn lights(&self) -> &[Light] {
        self.lights
    }

    /// The meshes drawn where they lie, each in its root box (its faces' exact
    /// bounds); then the instances, each in its hull's grown box, its lift
    /// scaled by its largest scale (the rotation keeps lengths).
    #[cfg(feature = "bvh")]
    fn each_top(&self, mut f: impl FnMut(usize, Option<crate::cull::TopBox>)) {
        let (instanced, _) = self.instancing();
        for (m, mesh) in self.meshes.iter().enumerate() {
            if instanced >> m & 1 != 0 {
                continue;
            }
            if let Some(root) = mesh.bvh().nodes.first() {
                let (min, max, lift) = (root.min, root.max, mesh.lift_bound());
                f(m, Some(crate::cull::TopBox { min, max, lift }));
            }
        }
        #[cfg(feature = "instances")]
        for (i, p) in self.instances.iter().enumerate() {
            if p.mesh.bvh().nodes.is_empty() {
                continue;
            }
            let lift = p.mesh.lift_bound() * p.largest_scale();
            let b = p.hull.map(|h| {
                let (min, max) = h.corners();
                crate::cull::TopBox { min, max, lift }
            });
            f(MAX_MESHES + i, b);
        }
    }
}
