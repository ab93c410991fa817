//! The prefiltered sampler ([`crate::Sampler::Prefiltered`]) in one place: a
//! camera ray carries its pixel's footprint ([`Footprint`]); where it hits a
//! textured surface, the four corner rays of the pixel give the footprint's uv box
//! on that surface ([`uv_box`]), and the texture is averaged exactly over the box
//! (`Texture::eval_box`, a box filter) instead of evaluated at one point. The tile
//! loop creates the footprint (`Pass::pixel` in `tile`), the hit resolution uses it (see
//! `trace::resolve`).

use crate::camera::CameraBasis;
use crate::geometry::Shape;
use crate::math;
use crate::ray::Ray;

/// A camera ray's pixel, for the prefiltered sampler: the four corner rays are
/// only built when the ray hits a textured surface.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Footprint<'a> {
    basis: &'a CameraBasis,
    x: f32,
    y: f32,
}

impl<'a> Footprint<'a> {
    /// The footprint of pixel `(x, y)` (its top-left corner) of `basis`.
    #[must_use]
    pub(crate) fn new(basis: &'a CameraBasis, x: f32, y: f32) -> Self {
        Self { basis, x, y }
    }

    /// The rays through the pixel's four corners.
    #[must_use]
    pub(crate) fn corners(&self) -> [Ray; 4] {
        [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
            .map(|(dx, dy)| self.basis.ray(self.x + dx, self.y + dy).0)
    }
}

/// The uv bounding box of a pixel's footprint on `shape`: where the rays through the
/// pixel's four corners meet the same shape. `None` (point sampling instead) when a
/// corner ray misses it, or when the box spans more than half the uv range of a
/// wrapping parametrisation (a sphere's seam). `map` takes the shape's own uv to
/// the texture's (a mesh's vertex uvs, interpolated; `centre` is already mapped).
/// Out of line: only the prefiltered sampler comes here, and its four rays would
/// weigh on every caller's frame.
#[inline(never)]
pub(crate) fn uv_box<G: Shape>(
    shape: &G,
    footprint: &Footprint<'_>,
    centre: [f32; 2],
    map: impl Fn([f32; 2]) -> [f32; 2],
) -> Option<([f32; 2], [f32; 2])> {
    let (mut lo, mut hi) = (centre, centre);
    for r in &footprint.corners() {
        let c = shape.intersect(r, f32::INFINITY)?;
        let [u, v] = map(shape.uv(&shape.surface(r, &c), &c));
        lo = [math::min(lo[0], u), math::min(lo[1], v)];
        hi = [math::max(hi[0], u), math::max(hi[1], v)];
    }
    // A footprint that wraps (sphere seam) is not a box of the texture.
    if shape.uv_wraps() && (hi[0] - lo[0] > 0.5 || hi[1] - lo[1] > 0.5) {
        return None;
    }
    Some((lo, hi))
}
