//! Built-in scenes, usable by firmware with no files: the chapter's two pictures, the
//! interference screen, and a showcase of every geometry and material kind.
//!
//! Each scene type has exactly the capacities it uses.

use crate::camera::Camera;
use crate::color::Color;
use crate::error::Error;
use crate::geometry::{Aabb, Plane, Sphere, Triangle};
use crate::light::PointLight;
use crate::material::Material;
use crate::sample::Sampler;
use crate::scene::Scene;
use crate::texture::Texture;
use crate::tile::RenderSettings;
use crate::vec::Vec3;
use crate::view::SceneView;

/// The chapter's pictures: four spheres on a floor, one light.
pub type ChapterScene = Scene<4, 1, 0, 0, 5, 1>;
/// The interference screen: one plane, one material, no light.
pub type InterferenceScene = Scene<0, 1, 0, 0, 1, 0>;
/// The showcase: every geometry and material kind.
pub type ShowcaseScene = Scene<3, 2, 4, 2, 8, 2>;
/// The teapot's scene in RAM: the floor, two materials and two lights; its mesh
/// and the mesh's BVH are baked data in flash ([`teapot`]).
#[cfg(feature = "teapot")]
pub type TeapotScene = Scene<0, 1, 0, 0, 2, 2>;

/// The built-in scenes as `static` data (flash on a chip), baked by the host
/// from their scene files (`scenes/<name>.toml`; a test of the host checks
/// that each file here is what it bakes today): each module's `SCENE` is a
/// [`crate::BakedScene`] at the scene's own size and settings, with a constant
/// per material and the tile loops it needs (`SceneLoops`).
/// [`Builtin::baked`] gives any of them, checked.
pub mod baked {
    /// `scenes/chapter-direct.toml`.
    #[rustfmt::skip]
    pub mod chapter_direct; /// `scenes/chapter-reflect.toml`.
    #[rustfmt::skip]
    pub mod chapter_reflect; /// `scenes/interference.toml`.
    #[rustfmt::skip]
    pub mod interference; /// `scenes/showcase.toml`.
    #[rustfmt::skip]
    pub mod showcase; /// `scenes/teapot.toml` (feature `teapot`).
    #[cfg(feature = "teapot")]
    #[rustfmt::skip]
    pub mod teapot;
}

/// The teapot's mesh (baked `static` data: flash on a chip), to give to a view of
/// [`teapot`] with [`SceneView::with_meshes`]:
///
/// ```
/// # fn main() -> Result<(), tessera::Error> {
/// let scene = tessera::builtin::teapot()?;
/// let view = scene.view().with_meshes(&tessera::builtin::TEAPOT_MESHES)?;
/// assert_eq!(view.meshes()[0].faces().len(), 1088);
/// # Ok(())
/// # }
/// ```
#[cfg(feature = "teapot")]
pub static TEAPOT_MESHES: &[crate::mesh::Mesh<'static>] = &baked::teapot::MESHES;

/// The built-in scenes, by name. Non-exhaustive: the feature `teapot` adds one,
/// so that code written without it still compiles with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Builtin {
    /// The chapter's first picture: direct light only.
    ChapterDirect,
    /// The chapter's second picture: one level of mirror reflection (the default).
    ChapterReflect,
    /// Young's interference fringes on a screen.
    Interference,
    /// Every geometry and material kind.
    Showcase,
    /// A smooth teapot of 1,088 faces on a checkered floor, two lights: its
    /// mesh and BVH are baked `static` data (flash on a chip); feature `teapot`.
    #[cfg(feature = "teapot")]
    Teapot,
}

impl Builtin {
    /// Every built-in scene (a slice: its length depends on the features).
    pub const ALL: &'static [Self] = &[
        Self::ChapterDirect,
        Self::ChapterReflect,
        Self::Interference,
        Self::Showcase,
        #[cfg(feature = "teapot")]
        Self::Teapot,
    ];

    /// The default scene (the chapter's second picture).
    pub const DEFAULT: Self = Self::ChapterReflect;

    /// The scene's name (`chapter-direct`, `chapter-reflect`, `interference`,
    /// `showcase`, `teapot`).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::ChapterDirect => "chapter-direct",
            Self::ChapterReflect => "chapter-reflect",
            Self::Interference => "interference",
            Self::Showcase => "showcase",
            #[cfg(feature = "teapot")]
            Self::Teapot => "teapot",
        }
    }

    /// The scene called `name`, if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|b| b.name() == name)
    }

    /// The settings the scene is meant to be rendered with.
    #[must_use]
    pub fn settings(self) -> RenderSettings {
        let (sampler, max_depth) = match self {
            Self::ChapterDirect => (Sampler::Centre, 0),
            Self::ChapterReflect => (Sampler::Centre, 1),
            Self::Interference => (Sampler::Centre, 0),
            Self::Showcase => (Sampler::Centre, 5),
            #[cfg(feature = "teapot")]
            Self::Teapot => (Sampler::Centre, 0),
        };
        RenderSettings {
            sampler,
            max_depth,
            seed: 0,
            encoding: crate::Encoding::Srgb,
        }
    }

    /// The scene's `static` data ([`baked`]), checked: its view (which reads
    /// the tables where they lie, in flash on a chip) and its frame at the
    /// scene's own size and [settings](Builtin::settings). The same pixels as
    /// [`Builtin::with_scene`], with no scene in RAM.
    ///
    /// ```
    /// use tessera::{builtin::Builtin, Tile, TileCoord};
    /// let (view, renderer) = Builtin::Showcase.baked()?;
    /// let mut tile = Tile::<16>::new();
    /// renderer.render_tile(&view, TileCoord::new(0, 0), &mut tile, &mut ())?;
    /// # Ok::<(), tessera::Error>(())
    /// ```
    ///
    /// # Errors
    /// As [`crate::BakedScene::view`] and [`crate::BakedScene::renderer`] (none
    /// for data the host baked).
    pub fn baked(self) -> Result<(SceneView<'static>, crate::Renderer), Error> {
        self.with_baked_scene(|view, camera| {
            let renderer = crate::Renderer::try_new(camera, baked_viewport(self), self.settings())?;
            Ok((*view, renderer))
        })?
    }

    /// [`Builtin::with_scene`] from the scene's `static` data ([`baked`]): its
    /// checked view, which reads the tables where they lie, and its camera.
    ///
    /// # Errors
    /// As [`crate::BakedScene::view`] and its camera's check (none for data the
    /// host baked).
    pub fn with_baked_scene<R>(
        self,
        f: impl FnOnce(&SceneView<'static>, &Camera) -> R,
    ) -> Result<R, Error> {
        fn hand<const S: usize, const P: usize, const T: usize, const B: usize, R>(
            s: &'static crate::BakedScene<'static, S, P, T, B>,
            f: impl FnOnce(&SceneView<'static>, &Camera) -> R,
        ) -> Result<R, Error> {
            Ok(f(&s.view()?, &s.camera().camera()?))
        }
        match self {
            Self::ChapterDirect => hand(&baked::chapter_direct::SCENE, f),
            Self::ChapterReflect => hand(&baked::chapter_reflect::SCENE, f),
            Self::Interference => hand(&baked::interference::SCENE, f),
            Self::Showcase => hand(&baked::showcase::SCENE, f),
            #[cfg(feature = "teapot")]
            Self::Teapot => hand(&baked::teapot::SCENE, f),
        }
    }

    /// The text of the scene file the built-in scene is baked from
    /// (`scenes/<name>.toml` of the repository, which `tessera bake` turns into
    /// the scene's `static` tables, this text among them): not linked unless
    /// called.
    #[must_use]
    pub fn source(self) -> &'static str {
        match self {
            Self::ChapterDirect => baked::chapter_direct::SOURCE,
            Self::ChapterReflect => baked::chapter_reflect::SOURCE,
            Self::Interference => baked::interference::SOURCE,
            Self::Showcase => baked::showcase::SOURCE,
            #[cfg(feature = "teapot")]
            Self::Teapot => baked::teapot::SOURCE,
        }
    }

    /// Builds the scene (on the stack) and hands its view and camera to `f`.
    pub fn with_scene<R>(self, f: impl FnOnce(&SceneView<'_>, &Camera) -> R) -> Result<R, Error> {
        self.build(0, f)
    }

    /// [`Builtin::with_scene`] with the scene scaled by `2^k` (see
    /// [`Scene::scaled_pow2`]): a test hook, with the feature `testing`.
    #[cfg(feature = "testing")]
    pub(crate) fn with_scaled_scene_hook<R>(
        self,
        k: i32,
        f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
    ) -> Result<R, Error> {
        self.build(k, f)
    }

    /// Builds the scene, scaled by `2^k` unless `k` is 0, and hands it to `f`.
    fn build<R>(self, k: i32, f: impl FnOnce(&SceneView<'_>, &Camera) -> R) -> Result<R, Error> {
        match self {
            Self::ChapterDirect => hand(chapter_direct()?, k, f),
            Self::ChapterReflect => hand(chapter_reflect()?, k, f),
            Self::Interference => hand(interference()?, k, f),
            Self::Showcase => hand(showcase()?, k, f),
            #[cfg(feature = "teapot")]
            Self::Teapot => hand_teapot(k, f),
        }
    }
}

/// The size a built-in scene's file gives (each is 320x240).
fn baked_viewport(b: Builtin) -> crate::Viewport {
    match b {
        Builtin::ChapterDirect => baked::chapter_direct::SCENE.viewport(),
        Builtin::ChapterReflect => baked::chapter_reflect::SCENE.viewport(),
        Builtin::Interference => baked::interference::SCENE.viewport(),
        Builtin::Showcase => baked::showcase::SCENE.viewport(),
        #[cfg(feature = "teapot")]
        Builtin::Teapot => baked::teapot::SCENE.viewport(),
    }
}

/// `f` of the scene's view and camera, the scene scaled by `2^k` first unless `k`
/// is 0 (scaling is a test hook: without the feature `testing`, `k` is always 0).
fn hand<
    const S: usize,
    const P: usize,
    const T: usize,
    const B: usize,
    const M: usize,
    const L: usize,
    R,
>(
    scene: Scene<S, P, T, B, M, L>,
    k: i32,
    f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
) -> Result<R, Error> {
    #[cfg(feature = "testing")]
    let scene = if k == 0 {
        scene
    } else {
        scene.scaled_pow2_hook(k)?
    };
    #[cfg(not(feature = "testing"))]
    let _ = k;
    Ok(f(&scene.view(), scene.camera()))
}

/// `f` of the teapot scene's view (its baked mesh in flash, see
/// [`SceneView::with_meshes`]) and camera; scaled by `2^k` (a test hook), the
/// mesh's vertices are copied into RAM, scaled, and given a BVH built there.
#[cfg(feature = "teapot")]
fn hand_teapot<R>(k: i32, f: impl FnOnce(&SceneView<'_>, &Camera) -> R) -> Result<R, Error> {
    let scene = teapot()?;
    if k == 0 {
        let view = scene.view().with_meshes(TEAPOT_MESHES)?;
        return Ok(f(&view, scene.camera()));
    }
    #[cfg(feature = "testing")]
    {
        let [mesh] = &baked::teapot::MESHES;
        scaled_teapot(&scene, k, &baked::teapot::MESH0_VERTICES, mesh, f)
    }
    #[cfg(not(feature = "testing"))]
    Err(Error::BvhMismatch)
}

/// The teapot scaled by `2^k`, in RAM (a test hook: its triangles and their BVH on
/// the stack, in its own frame: never inlined, so that the unscaled scenes do not
/// reserve it).
/// `vertices` are `mesh`'s.
#[cfg(all(feature = "teapot", feature = "testing"))]
#[inline(never)]
fn scaled_teapot<const V: usize, R>(
    scene: &TeapotScene,
    k: i32,
    vertices: &[[f32; 3]; V],
    mesh: &crate::mesh::Mesh<'_>,
    f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
) -> Result<R, Error> {
    use crate::primitive::Primitive;
    let scene = scene.scaled_pow2_hook(k)?;
    let s = libm::ldexpf(1.0, k.clamp(-200, 200));
    let moved = vertices.map(|[x, y, z]| [x * s, y * s, z * s]);
    let at = |i: u16| {
        let [x, y, z] = moved.get(usize::from(i)).copied().unwrap_or([0.0; 3]);
        Vec3::new(x, y, z)
    };
    let mut triangles: heapless::Vec<Primitive<Triangle>, 2048> = heapless::Vec::new();
    for &[a, b, c] in mesh.faces() {
        let t = Primitive {
            geometry: Triangle::try_new(at(a), at(b), at(c))?,
            material: mesh.material(),
        };
        triangles.push(t).map_err(|_| Error::CapacityExceeded {
            list: crate::error::List::Triangles,
            capacity: 2048,
        })?;
    }
    let mut bvh: crate::bvh::Bvh<4096, 2048> = crate::bvh::Bvh::new();
    bvh.build(&triangles)?;
    let scaled = [crate::mesh::Mesh::new(
        &moved,
        mesh.faces(),
        mesh.normals(),
        mesh.material(),
        crate::bvh::BakedBvh::new(bvh.nodes(), bvh.order(), bvh.reach()),
    )];
    let view = scene.view().with_meshes(&scaled)?;
    Ok(f(&view, scene.camera()))
}

/// The teapot's scene without its mesh: a checkered floor, the teapot's glazed
/// red, a warm key light and a cool fill light.
#[cfg(feature = "teapot")]
pub fn teapot() -> Result<TeapotScene, Error> {
    let cam = Camera::look_at(
        Vec3::new(2.0, 1.6, 3.0),
        Vec3::new(0.15, 0.45, 0.0),
        Vec3::Y,
        0.1,
        100.0,
    )?;
    let mut s = TeapotScene::new(cam);
    s.set_ambient(Color::splat(0.1))?;
    s.set_background(Color::new(0.55, 0.7, 0.9))?;
    let checker = Texture::Checker {
        a: Color::splat(0.8),
        b: Color::splat(0.25),
        scale: 0.5,
    };
    let floor = s.add_material(Material::matte(Color::WHITE).with_texture(checker)?)?;
    s.add_material(Material::matte(Color::new(0.8, 0.2, 0.12)).with_specular(0.5, 40.0)?)?;
    s.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Y)?, floor)?;
    s.add_light(PointLight::try_new(
        Vec3::new(-2.0, 5.0, 3.0),
        Color::new(1.0, 0.95, 0.9),
        30.0,
    )?)?;
    s.add_light(PointLight::try_new(
        Vec3::new(4.0, 3.0, -1.0),
        Color::new(0.5, 0.6, 0.8),
        10.0,
    )?)?;
    Ok(s)
}

/// The chapter's spheres; `mirror` gives the red sphere a slight and the green one a
/// strong mirror reflectivity.
fn chapter(mirror: bool) -> Result<ChapterScene, Error> {
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.8, 7.0),
        Vec3::new(0.0, 0.9, 0.0),
        Vec3::Y,
        0.1,
        100.0,
    )?;
    let mut s = ChapterScene::new(cam);
    s.set_ambient(Color::splat(0.12))?;
    s.set_background(Color::new(0.08, 0.09, 0.14))?;
    let shiny = |c: Color| Material::matte(c).with_specular(0.4, 48.0);
    let floor = s.add_material(Material::matte(Color::splat(0.75)))?;
    let blue = s.add_material(shiny(Color::new(0.1, 0.25, 0.95))?)?;
    // (reflectivity, diffuse): what the mirror takes, the diffuse term gives back.
    let ((red_kr, red_kd), (green_kr, green_kd)) = if mirror {
        ((0.15, 0.85), (0.8, 0.2))
    } else {
        ((0.0, 1.0), (0.0, 1.0))
    };
    let red = s.add_material(
        shiny(Color::new(0.9, 0.15, 0.1))?
            .with_diffuse(red_kd)?
            .with_reflectivity(red_kr)?,
    )?;
    let green = s.add_material(
        shiny(Color::new(0.15, 0.8, 0.2))?
            .with_diffuse(green_kd)?
            .with_reflectivity(green_kr)?,
    )?;
    let yellow = s.add_material(shiny(Color::new(0.95, 0.8, 0.1))?)?;
    s.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Y)?, floor)?;
    s.add_sphere(Sphere::try_new(Vec3::new(0.0, 1.0, 0.0), 1.0)?, blue)?;
    s.add_sphere(Sphere::try_new(Vec3::new(-2.3, 0.8, 0.4), 0.8)?, red)?;
    s.add_sphere(Sphere::try_new(Vec3::new(2.2, 0.9, -0.3), 0.9)?, green)?;
    s.add_sphere(Sphere::try_new(Vec3::new(0.9, 0.35, 1.9), 0.35)?, yellow)?;
    // The white light above the blue sphere.
    s.add_light(PointLight::try_new(
        Vec3::new(0.0, 7.0, 1.0),
        Color::WHITE,
        40.0,
    )?)?;
    Ok(s)
}

/// The chapter's first picture: direct illumination only, a white light above the
/// blue sphere.
pub fn chapter_direct() -> Result<ChapterScene, Error> {
    chapter(false)
}

/// The chapter's second picture: direct and one level of indirect illumination, with
/// a slightly (red) and a very (green) mirror-like sphere.
pub fn chapter_reflect() -> Result<ChapterScene, Error> {
    chapter(true)
}

/// The chapter's interference example: Young's fringes (`d` = 2 mm,
/// `lambda` = 500 nm, `L` = 3 m, spacing 0.75 mm) on a screen 7 mm high, seen head
/// on. The texture is emitted as is (ambient light 1, no diffuse), so a pixel's value
/// is the texture's, which makes the sampling error measurable.
pub fn interference() -> Result<InterferenceScene, Error> {
    let cam = Camera::try_new(Vec3::new(0.0, 0.0, 0.1), -Vec3::Z, Vec3::Y, 4.0, 0.01, 1.0)?;
    let mut s = InterferenceScene::new(cam);
    s.set_ambient(Color::WHITE)?;
    let fringes = Texture::young(Color::new(0.0, 1.0, 0.6), 2e-3, 500e-9, 3.0)?;
    let screen = s.add_material(
        Material::matte(Color::WHITE)
            .with_texture(fringes)?
            .with_diffuse(0.0)?,
    )?;
    s.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Z)?, screen)?;
    Ok(s)
}

/// Every geometry kind (plane, sphere, triangle, box) and material kind (matte,
/// specular, mirror, glass, checker and fringe textures) in one scene.
pub fn showcase() -> Result<ShowcaseScene, Error> {
    let cam = Camera::look_at(
        Vec3::new(0.5, 2.6, 7.5),
        Vec3::new(0.0, 0.8, 0.0),
        Vec3::Y,
        0.1,
        100.0,
    )?;
    let mut s = ShowcaseScene::new(cam);
    s.set_ambient(Color::splat(0.1))?;
    s.set_background(Color::new(0.55, 0.7, 0.9))?;
    let checker = Texture::Checker {
        a: Color::splat(0.85),
        b: Color::splat(0.15),
        scale: 1.0,
    };
    let floor = s.add_material(
        Material::matte(Color::WHITE)
            .with_texture(checker)?
            .with_reflectivity(0.1)?,
    )?;
    let wall = s.add_material(Material::matte(Color::new(0.8, 0.75, 0.7)))?;
    let glass = s.add_material(
        Material::matte(Color::WHITE)
            .with_diffuse(0.0)?
            .with_ambient(0.0)?
            .with_specular(0.6, 200.0)?
            .with_transparency(0.95, 1.5)?,
    )?;
    let mirror = s.add_material(
        Material::matte(Color::splat(0.9))
            .with_diffuse(0.05)?
            .with_specular(0.5, 300.0)?
            .with_reflectivity(0.9)?,
    )?;
    let plastic =
        s.add_material(Material::matte(Color::new(0.9, 0.35, 0.1)).with_specular(0.5, 32.0)?)?;
    let fringes = Texture::Fringes {
        color: Color::new(1.0, 0.3, 0.8),
        spacing: 0.125,
    };
    let fringed = s.add_material(Material::matte(Color::WHITE).with_texture(fringes)?)?;
    let teal =
        s.add_material(Material::matte(Color::new(0.1, 0.6, 0.6)).with_specular(0.3, 16.0)?)?;
    let boxes = s.add_material(
        Material::matte(Color::new(0.3, 0.3, 0.9))
            .with_specular(0.2, 8.0)?
            .with_reflectivity(0.2)?,
    )?;
    s.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Y)?, floor)?;
    s.add_plane(Plane::try_new(Vec3::new(0.0, 0.0, -4.0), Vec3::Z)?, wall)?;
    s.add_sphere(Sphere::try_new(Vec3::new(0.8, 1.0, 0.9), 1.0)?, glass)?;
    s.add_sphere(Sphere::try_new(Vec3::new(-2.6, 1.1, -1.0), 1.1)?, mirror)?;
    s.add_sphere(Sphere::try_new(Vec3::new(2.3, 0.35, 2.1), 0.35)?, teal)?;
    s.add_box(
        Aabb::try_new(Vec3::new(1.6, 0.0, -1.6), Vec3::new(2.8, 1.2, -0.4))?,
        plastic,
    )?;
    s.add_box(
        Aabb::try_new(Vec3::new(-1.1, 0.0, 1.6), Vec3::new(-0.5, 0.6, 2.2))?,
        boxes,
    )?;
    // A pyramid of four triangles (the base stands on the floor).
    let apex = Vec3::new(-0.6, 1.9, -2.4);
    let base = [
        Vec3::new(-1.5, 0.0, -1.5),
        Vec3::new(0.3, 0.0, -1.5),
        Vec3::new(0.3, 0.0, -3.3),
        Vec3::new(-1.5, 0.0, -3.3),
    ];
    for (i, &a) in base.iter().enumerate() {
        let b = base.get((i + 1) % 4).copied().unwrap_or(a);
        s.add_triangle(Triangle::try_new(a, b, apex)?, fringed)?;
    }
    s.add_light(PointLight::try_new(
        Vec3::new(-3.0, 6.0, 4.0),
        Color::new(1.0, 0.95, 0.9),
        30.0,
    )?)?;
    s.add_light(PointLight::try_new(
        Vec3::new(4.0, 4.0, 3.0),
        Color::new(0.5, 0.6, 0.8),
        12.0,
    )?)?;
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_builds_and_is_named() {
        for &b in Builtin::ALL {
            assert_eq!(Builtin::from_name(b.name()), Some(b));
            assert!(b.with_scene(|_, _| ()).is_ok());
            assert!(b.settings().validate().is_ok());
        }
        assert_eq!(Builtin::from_name("nope"), None);
    }

    /// Every tile of `frame` over `view`, as bytes.
    fn pixels(view: &SceneView<'_>, renderer: &crate::Renderer) -> [u8; 3 * 80 * 60] {
        let mut out = [0; 3 * 80 * 60];
        let mut tile = crate::Tile::<16>::new();
        for ty in 0..4 {
            for tx in 0..5 {
                let coord = crate::TileCoord::new(tx, ty);
                renderer
                    .render_tile(view, coord, &mut tile, &mut ())
                    .unwrap();
                for (y, row) in tile.rows().enumerate() {
                    for (x, p) in row.iter().enumerate() {
                        let i = 3 * ((usize::from(ty) * 16 + y) * 80 + usize::from(tx) * 16 + x);
                        out[i..i + 3].copy_from_slice(&[p.r, p.g, p.b]);
                    }
                }
            }
        }
        out
    }

    /// A built-in scene's static data renders the scene the core builds, byte
    /// for byte, at the scene's own settings; its size is the scene file's.
    #[test]
    fn every_builtin_baked_renders_like_the_built_scene() {
        let vp = crate::Viewport::new(80, 60);
        for &b in Builtin::ALL {
            let (view, renderer) = b.baked().unwrap();
            assert_eq!(*renderer.settings(), b.settings(), "{}", b.name());
            assert_eq!(renderer.viewport(), crate::Viewport::new(320, 240));
            let baked = b
                .with_baked_scene(|v, cam| {
                    let f = crate::Renderer::try_new(cam, vp, b.settings()).unwrap();
                    pixels(v, &f)
                })
                .unwrap();
            assert!(
                core::ptr::eq(view.spheres(), baked_spheres(b)),
                "{}",
                b.name()
            );
            let built = b
                .with_scene(|v, cam| {
                    let f = crate::Renderer::try_new(cam, vp, b.settings()).unwrap();
                    pixels(v, &f)
                })
                .unwrap();
            assert!(baked == built, "{}", b.name());
            assert!(baked.iter().any(|&x| x > 40), "{}: a black image", b.name());
        }
    }

    /// The baked scene's sphere table, where it lies.
    fn baked_spheres(b: Builtin) -> &'static [crate::Primitive<crate::geometry::Sphere>] {
        match b {
            Builtin::ChapterDirect => &baked::chapter_direct::SPHERES,
            Builtin::ChapterReflect => &baked::chapter_reflect::SPHERES,
            Builtin::Interference => &baked::interference::SPHERES,
            Builtin::Showcase => &baked::showcase::SPHERES,
            #[cfg(feature = "teapot")]
            Builtin::Teapot => &baked::teapot::SPHERES,
        }
    }

    #[test]
    fn showcase_uses_every_kind() {
        let s = showcase().unwrap();
        let v = s.view();
        assert!(!v.spheres().is_empty() && !v.planes().is_empty());
        assert!(!v.triangles().is_empty() && !v.boxes().is_empty());
        let m = v.materials();
        assert!(m.iter().any(|m| m.transparency() > 0.0));
        assert!(m.iter().any(|m| m.reflectivity() > 0.5));
        assert!(m.iter().any(|m| m.specular() > 0.0));
        assert!(
            m.iter()
                .any(|m| matches!(m.texture(), Texture::Checker { .. }))
        );
        assert!(
            m.iter()
                .any(|m| matches!(m.texture(), Texture::Fringes { .. }))
        );
    }
}
