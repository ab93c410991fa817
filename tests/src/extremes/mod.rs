//! The numerical-stability battery: each case measures the `f32` core against `f64`
//! (formulas written here, independent of the core, on the f64 reference's plain
//! vector [`V3`]) or an analytic truth, and returns its figures.
//! `tests/tests/extremes.rs` asserts the criteria on them; `src/bin/extremes-report.rs`
//! prints them to `docs/extremes.md`.
//!
//! One module per case (or family of cases), every public item re-exported here:
//! - case 1, `far_sphere`: far spheres;
//! - case 2, `reintersection`: re-intersection of secondary rays;
//! - case 3, `watertight`: watertightness of fans and closed meshes;
//! - case 4, `tiny`: tiny triangles;
//! - case 5, `boxes`: boxes, rays in face planes, along edges, signed zeros;
//! - case 6, `camera`: the camera far from the origin, up close to forward;
//! - cases 7 and 8, `scale`: scale invariance and flush-to-zero;
//! - case 9, `analytic`: the analytic scene;
//! - case 10, `refraction`: refraction near the critical angle;
//! - case 11, `range`: the edges of the supported range;
//! - case 13, `huge`: surfaces far larger than their distance to the camera;
//! - case 14, `subnormal`: subnormal numbers in every kind of scene input.
//!
//! What they share (`support`): the `f64` side of the comparisons, ulps, a seeded
//! generator, rays built exactly. Everything is deterministic: rays come from fixed
//! grids or a seeded SplitMix64.

mod analytic;
mod boxes;
mod camera;
mod far_sphere;
mod huge;
mod range;
mod refraction;
mod reintersection;
mod scale;
mod subnormal;
mod support;
mod tiny;
mod watertight;

pub use analytic::*;
pub use boxes::*;
pub use camera::*;
pub use far_sphere::*;
pub use huge::*;
pub use range::*;
pub use refraction::*;
pub use reintersection::*;
pub use scale::*;
pub use subnormal::*;
pub use support::*;
pub use tiny::*;
pub use watertight::*;
