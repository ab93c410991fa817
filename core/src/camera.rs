//! The chapter's camera, viewport and view frustum.
//!
//! Parameters (chapter notation): the camera position `r_cam`, its forward `c_a` and
//! up `c_h` directions, the vertical opening angle `theta` (60 degrees by default),
//! the near and far distances `n` and `f`, and a viewport of `N_L x N_H` pixels.
//! From them, once a frame ([`CameraBasis`]):
//!
//! - `H = 2 n tan(theta / 2)`, `a = N_L / N_H`, `L = a H`;
//! - `u1 = (c_a x c_h) / |c_a x c_h| * L / N_L` (one pixel to the right),
//!   `u2 = (c_a x u1) / |c_a x u1| * H / N_H` (one pixel down);
//! - `r_ini = -N_L/2 u1 - N_H/2 u2` (from the centre of the near plane to the top-left
//!   corner of pixel (0, 0)).
//!
//! The point of pixel `(N_x, N_y)` on the near plane is
//! `r0 = r_cam + n c_a + r_ini + N_x u1 + N_y u2` (the chapter's corner; any sub-pixel
//! offset may be added to `N_x`, `N_y`). The ray starts at `r0`. Its direction is
//! computed in camera space, `normalize(n c_a + r_ini + N_x u1 + N_y u2)`, not as the
//! chapter's `normalize(r0 - r_cam)`: when the camera is far from the origin, `r0` is
//! rounded to the precision of `r_cam` and the difference loses the pixel offsets
//! (several pixels of error at `|r_cam| / n = 1e5` in `f32`).

use crate::error::{Error, Field, flush3, in_range, length, unit};
use crate::math;
use crate::ray::Ray;
use crate::vec::Vec3;

/// The camera: where it is, where it looks, and its view frustum.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Camera {
    position: Vec3,
    forward: Vec3,
    up: Vec3,
    /// The unit right vector, from the inputs as given (see [`right_vector`]).
    right: Vec3,
    fovy_degrees: f32,
    near: f32,
    far: f32,
}

impl Camera {
    /// The chapter's usual vertical opening angle, in degrees.
    pub const DEFAULT_FOVY_DEGREES: f32 = 60.0;

    /// A camera. `forward` and `up` may have any non-zero length (they are
    /// normalised) and need not be perpendicular; `up` may even be parallel to
    /// `forward` (a valid basis is still built, with an arbitrary but deterministic
    /// roll). `fovy_degrees` is the vertical opening angle in `(0, 180)`;
    /// `0 < near < far`, all finite; the position's components and `far` within
    /// [`crate::error::MAX_EXTENT`], `near` at least [`crate::error::MIN_LENGTH`].
    ///
    /// ```
    /// use tessera_core::{Camera, Error, Vec3};
    /// let cam = Camera::try_new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, 0.1, 100.0);
    /// assert!(cam.is_ok());
    /// let bad = Camera::try_new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, 2.0, 1.0);
    /// assert_eq!(bad, Err(Error::NearNotBeforeFar));
    /// ```
    pub fn try_new(
        position: Vec3,
        forward: Vec3,
        up: Vec3,
        fovy_degrees: f32,
        near: f32,
        far: f32,
    ) -> Result<Self, Error> {
        let position = crate::error::position(position, Field::CameraPosition)?;
        let (raw_forward, raw_up) = (flush3(forward), flush3(up));
        let forward = unit(forward, Field::CameraForward)?;
        let up = unit(up, Field::CameraUp)?;
        let right = right_vector(forward, raw_forward, raw_up);
        let fovy_degrees = in_range(
            fovy_degrees,
            0.0,
            180.0,
            Field::FieldOfView,
            "(0, 180) degrees",
        )?;
        if fovy_degrees == 0.0 || fovy_degrees == 180.0 {
            return Err(Error::OutOfRange {
                field: Field::FieldOfView,
                range: "(0, 180) degrees",
            });
        }
        let near = crate::error::finite(near, Field::Near)?;
        let far = crate::error::finite(far, Field::Far)?;
        if near <= 0.0 {
            return Err(Error::NotPositive(Field::Near));
        }
        if near >= far {
            return Err(Error::NearNotBeforeFar);
        }
        // The supported range of scene lengths (see `MIN_LENGTH`, `MAX_EXTENT`).
        let near = length(near, Field::Near)?;
        let far = length(far, Field::Far)?;
        Ok(Self {
            position,
            forward,
            up,
            right,
            fovy_degrees,
            near,
            far,
        })
    }

    /// A camera at `position` looking at `target`, with the default 60 degree
    /// opening angle.
    pub fn look_at(
        position: Vec3,
        target: Vec3,
        up: Vec3,
        near: f32,
        far: f32,
    ) -> Result<Self, Error> {
        Self::try_new(
            position,
            target - position,
            up,
            Self::DEFAULT_FOVY_DEGREES,
            near,
            far,
        )
    }

    /// Position `r_cam`.
    #[must_use]
    pub fn position(&self) -> Vec3 {
        self.position
    }
    /// Unit forward direction `c_a`.
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        self.forward
    }
    /// Unit up direction `c_h` as given (normalised, not orthogonalised).
    #[must_use]
    pub fn up(&self) -> Vec3 {
        self.up
    }
    /// Vertical opening angle `theta`, degrees.
    #[must_use]
    pub fn fovy_degrees(&self) -> f32 {
        self.fovy_degrees
    }
    /// Near distance `n`.
    #[must_use]
    pub fn near(&self) -> f32 {
        self.near
    }
    /// Far distance `f`.
    #[must_use]
    pub fn far(&self) -> f32 {
        self.far
    }
}

/// The viewport: `N_L x N_H` pixels (width x height).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Viewport {
    /// Width `N_L`, pixels.
    pub width: u16,
    /// Height `N_H`, pixels.
    pub height: u16,
}

impl Viewport {
    /// A viewport of `width x height` pixels (checked when a frame is made).
    #[must_use]
    pub const fn new(width: u16, height: u16) -> Self {
        Self { width, height }
    }
}

/// The per-frame vectors of the chapter: `n c_a`, `u1`, `u2`, `r_ini`, plus the far
/// limit. Built once a frame; a primary ray then costs a few multiply-adds and one
/// square root.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    position: Vec3,
    near_forward: Vec3,
    u1: Vec3,
    u2: Vec3,
    r_ini: Vec3,
    half_width: f32,
    half_height: f32,
    far_over_near_minus_one: f32,
    forward: Vec3,
    near: f32,
    far: f32,
    height: f32,
    width: f32,
    viewport: Viewport,
}

impl CameraBasis {
    /// The basis of `camera` for `viewport`.
    pub fn try_new(camera: &Camera, viewport: Viewport) -> Result<Self, Error> {
        if viewport.width == 0 || viewport.height == 0 {
            return Err(Error::EmptyViewport);
        }
        let (nl, nh) = (f32::from(viewport.width), f32::from(viewport.height));
        let fwd = camera.forward;
        let half_angle = camera.fovy_degrees.to_radians() * 0.5;
        let height = 2.0 * camera.near * math::tan(half_angle);
        let width = (nl / nh) * height;
        let right = camera.right;
        let u1 = right * (width / nl);
        let down = fwd.cross(right).normalize_or(Vec3::ZERO);
        let u2 = down * (height / nh);
        let r_ini = u1 * (-nl * 0.5) - u2 * (nh * 0.5);
        // A near distance so small (or an angle so close to 0) that a pixel is not a
        // normal f32 would give identical rays for neighbouring pixels.
        let pixel = crate::math::min(width / nl, height / nh);
        if !(pixel.is_normal() && height.is_finite() && width.is_finite()) {
            return Err(Error::OutOfRange {
                field: Field::Near,
                range: "a range where one pixel on the near plane is a normal f32 (see docs)",
            });
        }
        Ok(Self {
            position: camera.position,
            near_forward: fwd * camera.near,
            u1,
            u2,
            r_ini,
            half_width: nl * 0.5,
            half_height: nh * 0.5,
            far_over_near_minus_one: (camera.far - camera.near) / camera.near,
            forward: fwd,
            near: camera.near,
            far: camera.far,
            height,
            width,
            viewport,
        })
    }

    /// The primary ray through the point `(x, y)` of the viewport, in pixel units
    /// (`(N_x, N_y)` plus a sub-pixel offset: `(0, 0)` is the top-left corner of the
    /// image), and the time at which it crosses the far plane.
    ///
    /// Returns the ray (origin on the near plane, unit direction) and `t_far`.
    #[must_use]
    pub fn ray(&self, x: f32, y: f32) -> (Ray, f32) {
        let d = self.direction(x, y);
        let len = d.length();
        let dir = d / len;
        let origin = self.position + d;
        (Ray::unit(origin, dir), len * self.far_over_near_minus_one)
    }

    /// The unnormalised direction of the primary ray through `(x, y)`: from the
    /// camera to that point of the near plane.
    #[inline]
    pub(crate) fn direction(&self, x: f32, y: f32) -> Vec3 {
        // n c_a + r_ini + x u1 + y u2, summed as n c_a + (x - N_L/2) u1 + (y - N_H/2) u2:
        // the same vector, without the cancellation of r_ini against x u1 (x - N_L/2
        // is exact for pixel coordinates).
        self.near_forward + self.u1 * (x - self.half_width) + self.u2 * (y - self.half_height)
    }

    /// The camera position `r_cam`.
    pub(crate) fn position(&self) -> Vec3 {
        self.position
    }

    /// The unit forward direction `c_a` and the near and far distances.
    pub(crate) fn depth_axis(&self) -> (Vec3, f32, f32) {
        (self.forward, self.near, self.far)
    }

    /// `u1`: one pixel to the right on the near plane.
    #[must_use]
    pub fn u1(&self) -> Vec3 {
        self.u1
    }
    /// `u2`: one pixel down on the near plane.
    #[must_use]
    pub fn u2(&self) -> Vec3 {
        self.u2
    }
    /// `r_ini`: from the centre of the near plane to the top-left corner of pixel (0, 0).
    #[must_use]
    pub fn r_ini(&self) -> Vec3 {
        self.r_ini
    }
    /// `H`, the height of the near plane.
    #[must_use]
    pub fn height(&self) -> f32 {
        self.height
    }
    /// `L`, the width of the near plane.
    #[must_use]
    pub fn width(&self) -> f32 {
        self.width
    }
    /// The viewport.
    #[must_use]
    pub fn viewport(&self) -> Viewport {
        self.viewport
    }
}

/// The unit "right" vector `c_a x c_h / |c_a x c_h|`, made exactly perpendicular to
/// the unit forward `fwd` by one Gram-Schmidt step.
///
/// The cross product is taken of the inputs as given (`forward`, `up`: its
/// direction does not depend on their lengths, so they are only scaled by powers of
/// two, exactly), each component by Kahan's difference of products with a fused
/// multiply-add (within 2 ulps): no cancellation, so `up` a microradian from
/// `forward` sets the roll as exactly as `up` at right angles (a plain `f32` cross
/// of the normalised vectors rolls the picture by pixels when `up` is that close).
/// Only when the inputs are exactly parallel (the cross product is exactly zero)
/// does the world axis least aligned with `forward` stand in for `up`: a valid
/// orthonormal basis, deterministic roll.
fn right_vector(fwd: Vec3, forward: Vec3, up: Vec3) -> Vec3 {
    let mut right = pow2_scaled(forward).cross_accurate(pow2_scaled(up));
    if right == Vec3::ZERO || !right.is_finite() {
        let a = fwd.abs();
        let axis = if a.x <= a.y && a.x <= a.z {
            Vec3::X
        } else if a.y <= a.z {
            Vec3::Y
        } else {
            Vec3::Z
        };
        right = fwd.cross(axis);
    }
    let right = right.normalize_or(Vec3::X);
    let right = right - fwd * fwd.dot(right);
    right.normalize_or(Vec3::X)
}

/// `v` (finite, non-zero) times a power of two that brings its largest component
/// near 1: exact, so its direction is unchanged, and products of two components
/// neither overflow nor underflow.
fn pow2_scaled(v: Vec3) -> Vec3 {
    let m = v.abs().max_element();
    // The binary exponent of `m` (-127 for a subnormal: scaled by 2^126 it is
    // still at least 2^-23).
    let e = ((m.to_bits() >> 23) & 0xff) as i32 - 127;
    let k = -e;
    let pow2 = |i: i32| f32::from_bits(((127 + i) as u32) << 23);
    // Two factors, each within [2^-64, 2^64]: |k| <= 127.
    v * pow2(k / 2) * pow2(k - k / 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
        (a - b).length() <= tol
    }

    /// The chapter's formulas on a worked example computed by hand:
    /// r_cam = 0, c_a = -z, c_h = +y, theta = 90 deg, n = 1, viewport 4 x 2.
    /// H = 2 * 1 * tan(45 deg) = 2, a = 2, L = 4; u1 = (1, 0, 0) * 4/4 = (1, 0, 0);
    /// u2 = (-z x x) * 2/2 = (0, -1, 0); r_ini = -2 u1 - 1 u2 = (-2, 1, 0).
    #[test]
    fn worked_example_matches_hand_computation() {
        let cam = Camera::try_new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 90.0, 1.0, 10.0).unwrap();
        let b = CameraBasis::try_new(&cam, Viewport::new(4, 2)).unwrap();
        assert!((b.height() - 2.0).abs() < 1e-6);
        assert!((b.width() - 4.0).abs() < 1e-6);
        assert!(close(b.u1(), Vec3::new(1.0, 0.0, 0.0), 1e-6));
        assert!(close(b.u2(), Vec3::new(0.0, -1.0, 0.0), 1e-6));
        assert!(close(b.r_ini(), Vec3::new(-2.0, 1.0, 0.0), 1e-6));

        // Pixel (0, 0), corner: r0 = (0,0,-1) + (-2, 1, 0) = (-2, 1, -1);
        // v = (-2, 1, -1) / sqrt(6).
        let (r, t_far) = b.ray(0.0, 0.0);
        assert!(close(r.origin, Vec3::new(-2.0, 1.0, -1.0), 1e-6));
        let s6 = 6f32.sqrt();
        assert!(close(
            r.dir,
            Vec3::new(-2.0 / s6, 1.0 / s6, -1.0 / s6),
            1e-6
        ));
        // Far plane at z = -10: from r0, t = (10 - 1) * sqrt(6) / 1.
        assert!((t_far - 9.0 * s6).abs() < 1e-5);
        assert!((r.at(t_far).z + 10.0).abs() < 1e-5);

        // Centre of the centre pixel region: (N_L/2, N_H/2) = (2, 1) is the image
        // centre, straight ahead.
        let (r, _) = b.ray(2.0, 1.0);
        assert_eq!(r.dir, -Vec3::Z);
        assert_eq!(r.origin, Vec3::new(0.0, 0.0, -1.0));
        // The centre pixel of a 5 x 3 viewport, (2, 1), sampled at its centre
        // (2.5, 1.5) = (N_L/2, N_H/2): straight ahead.
        let b53 = CameraBasis::try_new(&cam, Viewport::new(5, 3)).unwrap();
        let (r, _) = b53.ray(2.0 + 0.5, 1.0 + 0.5);
        assert_eq!(r.dir, -Vec3::Z);
        // Centre of pixel (1, 0): (1.5, 0.5) -> d = (-0.5, 0.5, -1).
        let (r, _) = b.ray(1.5, 0.5);
        let s = 1.5f32.sqrt();
        assert!(close(r.dir, Vec3::new(-0.5 / s, 0.5 / s, -1.0 / s), 1e-6));
    }

    #[test]
    fn default_sixty_degrees_gives_the_chapter_height() {
        let cam = Camera::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y, 0.5, 10.0).unwrap();
        let b = CameraBasis::try_new(&cam, Viewport::new(320, 240)).unwrap();
        let h = 2.0 * 0.5 * (30f64.to_radians()).tan();
        assert!((b.height() as f64 - h).abs() < 1e-6);
        assert!((b.width() as f64 - h * 320.0 / 240.0).abs() < 1e-6);
    }

    #[test]
    fn far_camera_keeps_pixel_directions() {
        // |r_cam| / n = 1e5: directions must not depend on the position at all.
        let near = Camera::try_new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, 1.0, 1e7).unwrap();
        let far =
            Camera::try_new(Vec3::new(1e5, -1e5, 3e4), -Vec3::Z, Vec3::Y, 60.0, 1.0, 1e7).unwrap();
        let vp = Viewport::new(64, 64);
        let (a, b) = (
            CameraBasis::try_new(&near, vp).unwrap(),
            CameraBasis::try_new(&far, vp).unwrap(),
        );
        for (x, y) in [(0.5, 0.5), (31.5, 7.5), (63.5, 63.5)] {
            assert_eq!(a.ray(x, y).0.dir, b.ray(x, y).0.dir);
        }
    }

    #[test]
    fn up_parallel_to_forward_still_gives_an_orthonormal_basis() {
        for (fwd, up) in [
            (-Vec3::Y, -Vec3::Y),
            (-Vec3::Y, Vec3::Y),
            (Vec3::new(0.3, 0.4, 0.5), Vec3::new(0.3, 0.4, 0.5)),
            (Vec3::Z, Vec3::new(1e-7, 0.0, 1.0)),
            (Vec3::Z, Vec3::new(1e-5, 0.0, 1.0)),
        ] {
            let cam = Camera::try_new(Vec3::ZERO, fwd, up, 60.0, 0.1, 10.0).unwrap();
            let b = CameraBasis::try_new(&cam, Viewport::new(10, 10)).unwrap();
            let (e1, e2, f) = (
                b.u1().normalize_or(Vec3::ZERO),
                b.u2().normalize_or(Vec3::ZERO),
                cam.forward(),
            );
            for (p, q) in [(e1, e2), (e1, f), (e2, f)] {
                assert!(p.dot(q).abs() <= 1e-6, "{fwd:?} {up:?}");
            }
            for v in [e1, e2] {
                assert!((v.length() - 1.0).abs() <= 1e-6);
            }
        }
    }

    #[test]
    fn invalid_cameras_are_rejected() {
        let ok = |p, f, u, a, n, fa| Camera::try_new(p, f, u, a, n, fa);
        let (o, z, y) = (Vec3::ZERO, -Vec3::Z, Vec3::Y);
        let nan = Vec3::new(f32::NAN, 0.0, 0.0);
        assert_eq!(
            ok(nan, z, y, 60.0, 0.1, 1.0),
            Err(Error::NotFinite(Field::CameraPosition))
        );
        assert_eq!(
            ok(o, Vec3::ZERO, y, 60.0, 0.1, 1.0),
            Err(Error::ZeroLength(Field::CameraForward))
        );
        assert_eq!(
            ok(o, z, Vec3::ZERO, 60.0, 0.1, 1.0),
            Err(Error::ZeroLength(Field::CameraUp))
        );
        assert_eq!(
            ok(o, nan, y, 60.0, 0.1, 1.0),
            Err(Error::NotFinite(Field::CameraForward))
        );
        for a in [0.0, 180.0, -5.0, 200.0] {
            assert!(matches!(
                ok(o, z, y, a, 0.1, 1.0),
                Err(Error::OutOfRange {
                    field: Field::FieldOfView,
                    ..
                })
            ));
        }
        assert_eq!(
            ok(o, z, y, f32::NAN, 0.1, 1.0),
            Err(Error::NotFinite(Field::FieldOfView))
        );
        assert_eq!(
            ok(o, z, y, 60.0, 0.0, 1.0),
            Err(Error::NotPositive(Field::Near))
        );
        assert_eq!(
            ok(o, z, y, 60.0, -1.0, 1.0),
            Err(Error::NotPositive(Field::Near))
        );
        assert_eq!(ok(o, z, y, 60.0, 1.0, 1.0), Err(Error::NearNotBeforeFar));
        assert_eq!(
            ok(o, z, y, 60.0, 0.1, f32::INFINITY),
            Err(Error::NotFinite(Field::Far))
        );
        let cam = ok(o, z, y, 60.0, 0.1, 1.0).unwrap();
        assert_eq!(
            CameraBasis::try_new(&cam, Viewport::new(0, 5)),
            Err(Error::EmptyViewport)
        );
        assert_eq!(
            CameraBasis::try_new(&cam, Viewport::new(5, 0)),
            Err(Error::EmptyViewport)
        );
        assert!(matches!(
            ok(o, z, y, 60.0, 1e-37, 1.0),
            Err(Error::OutOfRange {
                field: Field::Near,
                ..
            })
        ));
        // A subnormal near distance is read as zero (`error::flush`).
        assert_eq!(
            ok(o, z, y, 60.0, 1e-38, 1.0),
            Err(Error::NotPositive(Field::Near))
        );
        assert!(matches!(
            ok(o, z, y, 60.0, 0.1, 1e19),
            Err(Error::OutOfRange {
                field: Field::Far,
                ..
            })
        ));
        // A valid near distance but an opening so small that a pixel is not a
        // normal f32.
        let narrow = ok(o, z, y, 1e-30, crate::error::MIN_LENGTH, 1.0).unwrap();
        assert!(CameraBasis::try_new(&narrow, Viewport::new(1000, 1000)).is_err());
    }
}
