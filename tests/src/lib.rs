//! Shared helpers of the integration tests: scenes built for tests, a place to
//! write the images a test renders, the numerical-stability battery
//! ([`extremes`]), the firmware test image under qemu
//! ([`firmware`]), its instruction profile ([`profile`], attributed to source
//! functions by [`dwarf`], weighted by the cycle model [`cycles`], its stalls in each board's memory path by
//! [`memory`]), the guarded
//! instruction counts ([`baseline`]), the host's profile under callgrind
//! ([`callgrind`]), the sections of the profile document ([`profile_doc`]), the
//! speed/accuracy trade report ([`trade_report`]), the profile of the chips
//! without an FPU by routine ([`nofpu`]), the random scenes of the property
//! tests ([`random_scene`]), the dual-core firmware image ([`dualcore`]) and the
//! firmware a user copies, built for a scene file and run ([`qemu_example`]).

/// The Rust examples of the repository's README.md, compiled and run by `cargo
/// test -p tessera-tests --doc` (here, not in the core: the core's package reads
/// no file outside its own folder).
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeExamples;

pub mod firmware;

pub mod dualcore;

pub mod readme;

pub mod extremes;

pub mod cycles;

pub mod profile;

pub mod memory;

pub mod dwarf;

pub mod baseline;

pub mod callgrind;

pub mod profile_doc;

pub mod trade_report;

pub mod nofpu;

pub mod random_scene;

pub mod qemu_example;

use std::path::PathBuf;
use tessera_core::{
    Camera, Color, Scene, Vec3, geometry::Sphere, light::Light, material::Material,
};

/// The analytic scene: the camera at the centre of a diffuse sphere of radius `r`,
/// a point light of intensity `intensity` at the same centre, no ambient light.
/// Every visible point is at distance `r` from the light, faces it, and receives
/// `intensity / r^2`: every pixel is `diffuse * color * intensity / r^2`.
pub fn inside_sphere(
    r: f32,
    intensity: f32,
    diffuse: f32,
    color: Color,
) -> Result<
    Scene<tessera_core::capacities!(spheres: 1, materials: 1, lights: 1)>,
    tessera_core::Error,
> {
    inside_sphere_at(
        Vec3::new(0.25, -0.5, 0.75) * r,
        r,
        intensity,
        diffuse,
        color,
    )
}

/// [`inside_sphere`] centred at `center` (anywhere: the far-from-origin cases).
pub fn inside_sphere_at(
    center: Vec3,
    r: f32,
    intensity: f32,
    diffuse: f32,
    color: Color,
) -> Result<
    Scene<tessera_core::capacities!(spheres: 1, materials: 1, lights: 1)>,
    tessera_core::Error,
> {
    let cam = Camera::try_new(
        center,
        Vec3::new(0.3, -0.2, -1.0),
        Vec3::Y,
        75.0,
        r * 0.01,
        r * 10.0,
    )?;
    let mut s = Scene::new(cam);
    let m = s.add_material(Material::matte(color).with_diffuse(diffuse)?)?;
    s.add_sphere(Sphere::try_new(center, r)?, m)?;
    s.add_light(Light::point(center, Color::WHITE, intensity)?)?;
    Ok(s)
}

/// A folder under the target directory for images written by tests (created).
pub fn output_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("target")
        .join("test-images");
    let _ = std::fs::create_dir_all(&dir);
    dir
}

/// The first line of `cmd --version` (for the reports), or `cmd: unknown`.
pub fn tool_version(cmd: &str) -> String {
    std::process::Command::new(cmd)
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .next()
                .map(str::to_string)
        })
        .unwrap_or_else(|| format!("{cmd}: unknown"))
}

/// `n` with a comma every three digits (`1234567` -> `1,234,567`): the host's, so
/// that the reports print figures the way the command's messages do.
pub use tessera_host::limits::thousands;

/// `x` rounded, with [`thousands`] separators (a negative or non-finite figure,
/// which the reports never have, is printed as it is, rounded).
#[must_use]
pub fn thousands_rounded(x: f64) -> String {
    if x.is_finite() && x >= 0.0 {
        thousands(x.round() as u64)
    } else {
        format!("{x:.0}")
    }
}
