//! Case 6: the camera far from the origin, and up close to forward (degenerate basis, roll).

use super::{Rng, V3, V3Ext};
use tessera_core::{Camera, Vec3, Viewport, camera::CameraBasis};

/// Camera distances from the origin in case 6.
pub const CAMERA_DISTANCES: [f32; 5] = [0.0, 1e1, 1e3, 1e4, 1e5];
/// Near distances in case 6.
pub const NEARS: [f32; 3] = [0.01, 0.1, 1.0];

/// The camera's per-frame vectors in `f64`, from the user's inputs.
struct RefBasis {
    near_forward: V3,
    u1: V3,
    u2: V3,
    half: (f64, f64),
}

impl RefBasis {
    fn new(forward: V3, up: V3, fovy: f64, near: f64, vp: Viewport) -> Self {
        let f = forward.normalize();
        let up = up.normalize();
        let right = f.cross(up);
        let right = (right - f * f.dot(right)).normalize();
        let down = f.cross(right).normalize();
        let (nl, nh) = (f64::from(vp.width), f64::from(vp.height));
        let height = 2.0 * near * (fovy.to_radians() / 2.0).tan();
        let width = nl / nh * height;
        Self {
            near_forward: f * near,
            u1: right * (width / nl),
            u2: down * (height / nh),
            half: (nl / 2.0, nh / 2.0),
        }
    }
    fn dir(&self, x: f64, y: f64) -> V3 {
        (self.near_forward + self.u1 * (x - self.half.0) + self.u2 * (y - self.half.1)).normalize()
    }
}

/// Figures of case 6 at one camera distance and near distance.
#[derive(Clone, Debug, Default)]
pub struct CameraFar {
    /// `|r_cam|`.
    pub distance: f32,
    /// Near distance.
    pub near: f32,
    /// Rays compared.
    pub rays: usize,
    /// Largest angle between the core's and the `f64` direction, in pixels (over the
    /// angular size of that pixel).
    pub worst_px: f64,
    /// 16x16 tiles checked.
    pub tiles: usize,
    /// Pairs of pixels of a tile with bit-identical rays (origin and direction).
    pub shared_rays: usize,
    /// Pairs of pixels of a tile with bit-identical directions.
    pub shared_dirs: usize,
    /// Tiles where two pixels' origins round to the same point (the position's own
    /// f32 spacing, reported only).
    pub tiles_with_shared_origins: usize,
}

/// One view of case 6: forward, up, vertical angle (degrees), width, height.
type View = ([f64; 3], [f64; 3], f32, u16, u16);

/// The orientations and viewports of case 6.
const VIEWS: [View; 4] = [
    ([-0.3, -0.2, -1.0], [0.0, 1.0, 0.0], 60.0, 64, 48),
    ([1.0, 0.1, 0.05], [0.0, 0.0, 1.0], 90.0, 320, 240),
    ([0.2, -1.0, 0.4], [0.0, 1.0, 0.3], 10.0, 1024, 768),
    ([0.6, 0.64, -0.48], [0.1, 0.2, 1.0], 120.0, 4000, 3000),
];

/// Case 6: primary ray directions of a camera at `distance` from the origin with near
/// distance `near`, against `f64`, in four orientations and viewports (64x48 to
/// 4000x3000; large ones on 24 tiles), and shared rays within 16x16 tiles.
#[must_use]
pub fn camera_far(distance: f32, near: f32) -> CameraFar {
    let mut out = CameraFar {
        distance,
        near,
        ..CameraFar::default()
    };
    let pos = (V3::new(0.6, -0.64, 0.48) * f64::from(distance)).f32();
    let mut rng = Rng::new(0xca3e);
    for (fwd, up, fovy, w, h) in VIEWS {
        let (fwd, up) = (V3::from_array(fwd), V3::from_array(up));
        let vp = Viewport::new(w, h);
        let cam =
            Camera::try_new(pos, fwd.f32(), up.f32(), fovy, near, near * 1e6).expect("camera");
        let basis = CameraBasis::try_new(&cam, vp).expect("basis");
        // The reference starts from the same f32 inputs.
        let rb = RefBasis::new(
            V3::of(fwd.f32()),
            V3::of(up.f32()),
            f64::from(fovy),
            f64::from(near),
            vp,
        );
        for (tx, ty) in tiles(w, h, &mut rng) {
            check_tile(&basis, &rb, (tx, ty), (w, h), &mut out);
        }
    }
    out
}

/// Angles between up and forward in case 6, radians.
pub const UP_ANGLES: [f64; 3] = [0.0, 1e-7, 1e-5];

/// Figures of case 6, up against forward.
#[derive(Clone, Debug, Default)]
pub struct UpForward {
    /// Cameras built.
    pub cameras: usize,
    /// Cameras with a NaN or infinite vector or ray.
    pub non_finite: usize,
    /// Largest `|e_i . e_j|` among the unit right, down and forward vectors.
    pub worst_dot: f64,
    /// Largest `| |u1| / (L / N_L) - 1 |`, `| |u2| / (H / N_H) - 1 |`, `| |c_a| - 1 |`.
    pub worst_length: f64,
}

/// Case 6, degenerate up: forward along axes and oblique directions, up at each of
/// [`UP_ANGLES`] from forward (and from minus forward), the basis must be finite and
/// orthonormal within `1e-6`.
#[must_use]
pub fn up_forward() -> UpForward {
    let mut out = UpForward::default();
    let forwards = [
        V3::new(0.0, 0.0, 1.0),
        V3::new(0.0, -1.0, 0.0),
        V3::new(1.0, 0.0, 0.0),
        V3::new(0.3, 0.4, 0.5),
        V3::new(-0.7, 0.1, 0.2),
        V3::new(0.577, -0.577, 0.578),
    ];
    for f in forwards {
        let f = f.normalize();
        let (p, q) = f.basis();
        for angle in UP_ANGLES {
            for side in [1.0, -1.0] {
                for axis in [p, q, (p + q).normalize()] {
                    let up = (f * angle.cos() + axis * angle.sin()) * side;
                    let cam = Camera::try_new(Vec3::ZERO, f.f32(), up.f32(), 60.0, 0.1, 10.0)
                        .expect("camera");
                    let basis = CameraBasis::try_new(&cam, Viewport::new(64, 48)).expect("basis");
                    out.cameras += 1;
                    let rays = [(0.0, 0.0), (32.0, 24.0), (64.0, 48.0), (0.5, 47.5)]
                        .map(|(x, y)| basis.ray(x, y).0);
                    if !(basis.u1().is_finite()
                        && basis.u2().is_finite()
                        && basis.r_ini().is_finite()
                        && rays
                            .iter()
                            .all(|r| r.origin().is_finite() && r.dir().is_finite()))
                    {
                        out.non_finite += 1;
                        continue;
                    }
                    let (u1, u2, fw) = (
                        V3::of(basis.u1()),
                        V3::of(basis.u2()),
                        V3::of(cam.forward()),
                    );
                    let (e1, e2) = (u1.normalize(), u2.normalize());
                    for d in [e1.dot(e2), e1.dot(fw), e2.dot(fw)] {
                        out.worst_dot = out.worst_dot.max(d.abs());
                    }
                    let px = f64::from(basis.width()) / 64.0;
                    let py = f64::from(basis.height()) / 48.0;
                    for l in [
                        u1.length() / px - 1.0,
                        u2.length() / py - 1.0,
                        fw.length() - 1.0,
                    ] {
                        out.worst_length = out.worst_length.max(l.abs());
                    }
                }
            }
        }
    }
    out
}

/// Angles between up and forward in the roll part of case 6, radians.
pub const ROLL_ANGLES: [f64; 5] = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3];

/// Figures of case 6, the roll set by an up nearly parallel to forward.
#[derive(Clone, Debug, Default)]
pub struct UpRoll {
    /// Cameras built.
    pub cameras: usize,
    /// Rays compared (corners, edge midpoints and centre of each viewport).
    pub rays: usize,
    /// Largest distance between the core's and the `f64` direction, in pixels.
    pub worst_px: f64,
    /// The angle (radians) at which `worst_px` was found.
    pub worst_angle: f64,
}

/// Case 6, roll: `up` at each of [`ROLL_ANGLES`] from forward (several forwards and
/// directions of the tilt, 640x480 and 64x48 viewports, 60 and 100 degrees), the
/// primary rays' directions against an `f64` basis built from the same `f32`
/// inputs. For example forward (0.3, 0.4, 0.5), up (0.300002, 0.4, 0.4999988),
/// 640x480: a plain `f32` cross product rolls it by 3.9 pixels at the corners.
#[must_use]
pub fn up_roll() -> UpRoll {
    let mut out = UpRoll::default();
    let forwards = [
        V3::new(0.3, 0.4, 0.5),
        V3::new(0.0, 0.0, -1.0),
        V3::new(-0.7, 0.1, 0.2),
        V3::new(1.0, 1e-3, -2e-3),
    ];
    let mut cases: Vec<(Vec3, Vec3)> = vec![(
        Vec3::new(0.3, 0.4, 0.5),
        Vec3::new(0.300_002, 0.4, 0.499_998_8),
    )];
    for f in forwards {
        let fu = f.normalize();
        let (p, q) = fu.basis();
        for angle in ROLL_ANGLES {
            for axis in [p, q, (p - q * 0.3).normalize()] {
                let up = fu * angle.cos() + axis * angle.sin();
                cases.push((f.f32(), (up * 2.5).f32()));
            }
        }
    }
    for (fwd, up) in cases {
        for (fovy, w, h) in [(60.0f32, 640u16, 480u16), (100.0, 64, 48)] {
            let vp = Viewport::new(w, h);
            let cam = Camera::try_new(Vec3::ZERO, fwd, up, fovy, 0.1, 100.0).expect("camera");
            let basis = CameraBasis::try_new(&cam, vp).expect("basis");
            let rb = RefBasis::new(V3::of(fwd), V3::of(up), f64::from(fovy), 0.1, vp);
            let angle = V3::of(fwd)
                .normalize()
                .cross(V3::of(up).normalize())
                .length()
                .asin();
            out.cameras += 1;
            let (fw, fh) = (f64::from(w), f64::from(h));
            for (x, y) in [
                (0.0, 0.0),
                (fw, 0.0),
                (0.0, fh),
                (fw, fh),
                (fw / 2.0, 0.0),
                (0.0, fh / 2.0),
                (fw / 2.0, fh / 2.0),
            ] {
                let (ray, _) = basis.ray(x as f32, y as f32);
                let d = V3::of(ray.dir()).normalize();
                let truth = rb.dir(x, y);
                let (cx, cy) = (x.clamp(0.5, fw - 0.5), y.clamp(0.5, fh - 0.5));
                let pixel = (rb.dir(cx + 0.5, cy) - rb.dir(cx - 0.5, cy))
                    .length()
                    .min((rb.dir(cx, cy + 0.5) - rb.dir(cx, cy - 0.5)).length());
                out.rays += 1;
                let px = (d - truth).length() / pixel;
                if px > out.worst_px {
                    out.worst_px = px;
                    out.worst_angle = angle;
                }
            }
        }
    }
    out
}

/// The 16x16 tiles of case 6 in a `w x h` viewport: all of them up to 300, else the
/// four corners, the centre and 19 random ones.
fn tiles(w: u16, h: u16, rng: &mut Rng) -> Vec<(u16, u16)> {
    let (across, down) = (w.div_ceil(16), h.div_ceil(16));
    if u32::from(across) * u32::from(down) <= 300 {
        (0..down)
            .flat_map(|ty| (0..across).map(move |tx| (tx, ty)))
            .collect()
    } else {
        let mut t = vec![
            (0, 0),
            (across - 1, 0),
            (0, down - 1),
            (across - 1, down - 1),
        ];
        t.push((across / 2, down / 2));
        t.extend((0..19).map(|_| {
            (
                rng.index(usize::from(across)) as u16,
                rng.index(usize::from(down)) as u16,
            )
        }));
        t
    }
}

/// One tile of case 6: every pixel's ray direction against `f64`, and the rays,
/// directions and origins shared between its pixels.
fn check_tile(
    basis: &CameraBasis,
    rb: &RefBasis,
    (tx, ty): (u16, u16),
    (w, h): (u16, u16),
    out: &mut CameraFar,
) {
    out.tiles += 1;
    let mut rays = std::collections::HashSet::new();
    let mut dirs = std::collections::HashSet::new();
    let mut origins = std::collections::HashSet::new();
    let mut n = 0;
    for y in ty * 16..((ty + 1) * 16).min(h) {
        for x in tx * 16..((tx + 1) * 16).min(w) {
            let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
            let (ray, _) = basis.ray(px as f32, py as f32);
            let d = V3::of(ray.dir()).normalize();
            let truth = rb.dir(px, py);
            let pixel = (rb.dir(px + 0.5, py) - rb.dir(px - 0.5, py))
                .length()
                .min((rb.dir(px, py + 0.5) - rb.dir(px, py - 0.5)).length());
            out.rays += 1;
            out.worst_px = out.worst_px.max((d - truth).length() / pixel);
            let bits = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
            rays.insert((bits(ray.origin()), bits(ray.dir())));
            dirs.insert(bits(ray.dir()));
            origins.insert(bits(ray.origin()));
            n += 1;
        }
    }
    out.shared_rays += n - rays.len();
    out.shared_dirs += n - dirs.len();
    out.tiles_with_shared_origins += usize::from(origins.len() < n);
}
