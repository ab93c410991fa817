//! Scenes of the extremes battery that the firmware test image renders too
//! (feature `testing`): the chip must give the host's bits on them, and the chip
//! report measures what they cost. Each is also measured on the host against the
//! f64 reference (`docs/extremes.md`, cases 13 and 14).

use crate::error::Error;
use crate::{
    Camera, Color, Scene, SceneView, Vec3, geometry::Aabb, geometry::Plane, geometry::Sphere,
    geometry::Triangle, light::Light, material::Material, texture::Texture,
};

/// A scene of the extremes battery, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extreme {
    /// Case 13: a ground of two triangles `2^25` (3.4e7) wide seen from 2 units,
    /// a ball and its shadow on it.
    HugeGround,
    /// Case 13: the ground as a sphere of radius `2^25` whose top is `y = 0`.
    HugeSphere,
    /// [`Extreme::HugeGround`] 32 units wide: what the huge one costs more.
    SmallGround,
    /// [`Extreme::HugeSphere`] of radius 16: what the huge one costs more.
    SmallSphere,
    /// [`Extreme::HugeGround`] 1,024 units wide, 256 times its distance: large,
    /// but below where the `f64` paths take over (`geometry::wide::REACH`).
    MediumGround,
    /// [`Extreme::HugeSphere`] of radius 512.
    MediumSphere,
    /// Case 14: the camera `1e-45` (a subnormal) off the vertical through its
    /// target, looking straight down: without the rule for subnormal numbers, a
    /// subnormal would decide its roll.
    SubnormalCamera,
    /// Case 14: subnormal numbers in every kind a scene takes (positions,
    /// directions, colours, intensities, weights), read as zeros.
    SubnormalInputs,
}

impl Extreme {
    /// Every scene.
    pub const ALL: [Self; 8] = [
        Self::HugeGround,
        Self::HugeSphere,
        Self::SmallGround,
        Self::SmallSphere,
        Self::MediumGround,
        Self::MediumSphere,
        Self::SubnormalCamera,
        Self::SubnormalInputs,
    ];

    /// Its name in run lists and reports.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::HugeGround => "huge-ground",
            Self::HugeSphere => "huge-sphere",
            Self::SmallGround => "small-ground",
            Self::SmallSphere => "small-sphere",
            Self::MediumGround => "medium-ground",
            Self::MediumSphere => "medium-sphere",
            Self::SubnormalCamera => "subnormal-camera",
            Self::SubnormalInputs => "subnormal-inputs",
        }
    }

    /// The scene of a name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|e| e.name() == name)
    }

    /// `f` of the scene's view and camera.
    ///
    /// # Errors
    /// The scene's construction error (none: a test checks each builds).
    pub fn with_scene<R>(self, f: impl FnOnce(&SceneView<'_>, &Camera) -> R) -> Result<R, Error> {
        let s = match self {
            Self::HugeGround => ground(HUGE, false)?,
            Self::HugeSphere => ground(HUGE, true)?,
            Self::SmallGround => ground(16.0, false)?,
            Self::SmallSphere => ground(16.0, true)?,
            Self::MediumGround => ground(512.0, false)?,
            Self::MediumSphere => ground(512.0, true)?,
            Self::SubnormalCamera => subnormal_camera(TINY)?,
            Self::SubnormalInputs => subnormal_inputs(TINY)?,
        };
        Ok(f(&s.view(), s.camera()))
    }
}

/// One scene type for all (each type of scene is code of its own in a firmware).
type ExtremeScene = Scene<
    crate::capacities!(spheres: 2, planes: 1, triangles: 2, boxes: 1, materials: 3, lights: 2),
>;

/// The smallest subnormal `f32`.
const TINY: f32 = 1e-45;

/// The half-size of the huge grounds: `2^25`.
const HUGE: f32 = (1u32 << 25) as f32;

/// Case 13's ground (two triangles or a sphere) `2 s` across, seen from 2 units
/// above, with a mirror ball, its shadow and one light.
fn ground(s: f32, sphere: bool) -> Result<ExtremeScene, Error> {
    let cam = Camera::look_at(Vec3::new(0.3, 2.0, 6.1), Vec3::ZERO, Vec3::Y, 0.1, 100.0)?;
    let mut scene = Scene::new(cam);
    scene.set_ambient(Color::splat(0.1))?;
    scene.set_background(Color::new(0.1, 0.2, 0.5))?;
    let ground = scene.add_material(Material::matte(Color::splat(0.7)).with_specular(0.3, 1.0)?)?;
    let ball = Material::matte(Color::new(0.9, 0.2, 0.1)).with_reflectivity(0.3)?;
    let ball = scene.add_material(ball)?;
    scene.add_sphere(Sphere::try_new(Vec3::new(0.0, 0.75, 0.0), 0.5)?, ball)?;
    scene.add_light(Light::point(Vec3::new(2.0, 6.0, 4.0), Color::WHITE, 40.0)?)?;
    if sphere {
        scene.add_sphere(Sphere::try_new(Vec3::new(0.0, -s, 0.0), s)?, ground)?;
    } else {
        let v = |x: f32, z: f32| Vec3::new(x, 0.0, z);
        scene.add_triangle(Triangle::try_new(v(-s, -s), v(s, -s), v(s, s))?, ground)?;
        scene.add_triangle(Triangle::try_new(v(-s, -s), v(s, s), v(-s, s))?, ground)?;
    }
    Ok(scene)
}

/// Case 14's camera: straight above its target but for `t` in z, over a
/// checkered floor with a ball.
fn subnormal_camera(t: f32) -> Result<ExtremeScene, Error> {
    let cam = Camera::look_at(Vec3::new(0.0, 2.0, t), Vec3::ZERO, Vec3::Y, 0.1, 100.0)?;
    let mut scene = Scene::new(cam);
    scene.set_ambient(Color::splat(0.1))?;
    let checker = Texture::Checker {
        a: Color::WHITE,
        b: Color::splat(0.1),
        scale: 2.0,
    };
    let floor = scene.add_material(Material::matte(Color::WHITE).with_texture(checker)?)?;
    let ball = scene.add_material(Material::matte(Color::new(0.2, 0.4, 0.9)))?;
    scene.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Y)?, floor)?;
    scene.add_sphere(Sphere::try_new(Vec3::new(0.3, 0.5, 0.2), 0.5)?, ball)?;
    scene.add_light(Light::point(Vec3::new(1.0, 4.0, 2.0), Color::WHITE, 20.0)?)?;
    Ok(scene)
}

/// Every kind of number with `t` (a subnormal, or 0) in it.
fn subnormal_inputs(t: f32) -> Result<ExtremeScene, Error> {
    let cam = Camera::try_new(
        Vec3::new(t, 1.5, 6.0),
        Vec3::new(-t, -0.25, -1.0),
        Vec3::new(t, 1.0, -t),
        60.0,
        0.1,
        100.0,
    )?;
    let mut scene = Scene::new(cam);
    scene.set_ambient(Color::new(0.1, t, 0.1))?;
    scene.set_background(Color::new(t, 0.1, 0.3))?;
    let checker = Texture::Checker {
        a: Color::new(0.9, t, 0.9),
        b: Color::new(t, 0.2, 0.2),
        scale: 1.0,
    };
    let floor = Material::matte(Color::WHITE)
        .with_texture(checker)?
        .with_reflectivity(t)?;
    let floor = scene.add_material(floor)?;
    let red =
        scene.add_material(Material::matte(Color::new(0.9, t, 0.1)).with_specular(t, 8.0)?)?;
    let glass = Material::matte(Color::new(0.8, 0.9, t)).with_transparency(0.5, 1.0 + t)?;
    let glass = scene.add_material(glass)?;
    scene.add_plane(
        Plane::try_new(Vec3::new(t, 0.0, -t), Vec3::new(-t, 1.0, t))?,
        floor,
    )?;
    scene.add_sphere(Sphere::try_new(Vec3::new(-t, 0.6, 0.0), 0.6)?, red)?;
    scene.add_triangle(
        Triangle::try_new(
            Vec3::new(1.0, t, -1.0),
            Vec3::new(2.5, -t, -1.0),
            Vec3::new(1.8, 1.5, -t),
        )?,
        glass,
    )?;
    scene.add_box(
        Aabb::try_new(Vec3::new(-2.5, -t, -1.5), Vec3::new(-1.5, 1.0, t - 0.5))?,
        red,
    )?;
    scene.add_light(Light::point(
        Vec3::new(2.0, 5.0, t),
        Color::new(1.0, t, 1.0),
        30.0,
    )?)?;
    scene.add_light(Light::point(Vec3::new(-3.0, 4.0, 2.0), Color::WHITE, t)?)?;
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{RenderSettings, Renderer, Viewport};

    extern crate std;
    use std::vec::Vec as StdVec;

    /// A 24x18 render of a scene.
    fn render<C: crate::Capacities>(s: &Scene<C>) -> StdVec<[u8; 3]> {
        let view = s.view();
        let renderer =
            Renderer::try_new(s.camera(), Viewport::new(24, 18), RenderSettings::default())
                .unwrap();
        (0..18u32)
            .flat_map(|y| (0..24u32).map(move |x| (x, y)))
            .map(|(x, y)| {
                let c = renderer.pixel_color(&view, x, y, &mut ()).to_srgb8();
                [c.r, c.g, c.b]
            })
            .collect()
    }

    #[test]
    fn every_scene_builds_and_subnormals_render_as_zeros() {
        for e in Extreme::ALL {
            assert_eq!(Extreme::from_name(e.name()), Some(e));
            assert!(
                e.with_scene(|v, _| v.primitives.spheres.len()).is_ok(),
                "{e:?}"
            );
        }
        for t in [TINY, -TINY, 1e-40, 1.1e-38] {
            let z = 0f32.copysign(t);
            assert_eq!(
                render(&subnormal_camera(t).unwrap()),
                render(&subnormal_camera(z).unwrap())
            );
            assert_eq!(
                render(&subnormal_inputs(t.abs()).unwrap()),
                render(&subnormal_inputs(0.0).unwrap())
            );
        }
    }
}
