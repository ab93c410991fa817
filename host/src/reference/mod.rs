//! The reference renderer: an independent, straightforward whole-image renderer in
//! `f64` with `std` math (no tiles, no fixed capacity, plain `Vec`s; every ray
//! tests every primitive), implementing the core's model and shading from the same
//! [`SceneDesc`]. It is the truth the `f32` core is measured against; it shares with
//! the core only the sub-pixel sample positions ([`tessera_core::Sampler::offset`]).
//!
//! The core skips, per tile, the primitives no ray of the tile can hit (its `cull`
//! module); that culling is conservative and never changes a pixel (the core's
//! tests compare culled and unculled renders byte for byte), so the reference has
//! none and a comparison does not measure it. Neither renderer culls back faces:
//! triangles are hit from both sides.
//!
//! Besides the colours, each pixel gets a [`RefImage::signature`]: a hash of what
//! every ray of every sample hit (primitive kind and index, or nothing; the part
//! of the primitive where its shading jumps at the parts' edges: a box's face, a
//! flat or textured mesh's face; the checker cell) and of every shadow ray's
//! outcome. Neighbours with different signatures straddle a silhouette, a
//! reflected or refracted silhouette, a shadow edge or an edge where the shading
//! jumps. So that every pixel of the frame has its 8 neighbours whatever the
//! frame's shape (one pixel, one row), the pixels of the ring just outside the
//! frame are signed too, by rays through them as through the frame's pixels.

pub mod animation;
pub mod exact;
pub mod geometry;
pub mod image_texture;
pub mod scene;
pub mod shade;
pub mod vec;

use crate::desc::{CameraDesc, DescError, SceneDesc, flush};
use geometry::{Ray, Shape};
use scene::RefScene;
use shade::{Signature, Tracer};
use vec::V3;

/// A reference image: linear `f64` colours and per-pixel signatures, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct RefImage {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Linear RGB of each pixel (mean of its samples), row by row.
    pub pixels: Vec<[f64; 3]>,
    /// Hash of the primitives and shadow outcomes met by each pixel's rays, for
    /// the frame and the ring of pixels just outside it: `(width + 2) x (height
    /// + 2)` of them ([`framed_len`]), row by row from pixel `(-1, -1)`
    /// ([`RefImage::signature_at`]).
    pub signature: Vec<u64>,
    /// How [`RefImage::to_rgb8`] makes the 8 bits (the settings').
    pub encoding: tessera_core::Encoding,
}

/// The 8 bits of the linear value `v` in `encoding`, in `f64`: clamped to
/// `[0, 1]` (NaN gives 0), then `v` (linear) or the sRGB curve of IEC 61966-2-1
/// (srgb) times 255, plus 0.5, truncated: the correctly rounded code the core's
/// `Color::to_rgb8` and `Color::to_srgb8` give from `f32`.
#[must_use]
pub fn encode8(v: f64, encoding: tessera_core::Encoding) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let e = match encoding {
        tessera_core::Encoding::Linear => v,
        tessera_core::Encoding::Srgb if v <= 0.003_130_8 => 12.92 * v,
        tessera_core::Encoding::Srgb => 1.055 * v.powf(1.0 / 2.4) - 0.055,
    };
    (e * 255.0 + 0.5) as u8
}

impl RefImage {
    /// The 8-bit image in its encoding ([`encode8`]: as the core's
    /// `Color::to_rgb8` for linear: clamp to `[0, 1]`, times 255, plus 0.5,
    /// truncate; NaN gives 0).
    #[must_use]
    pub fn to_rgb8(&self) -> image::RgbImage {
        let q = |v: f64| encode8(v, self.encoding);
        image::RgbImage::from_fn(self.width, self.height, |x, y| {
            let p = self.pixels[(y * self.width + x) as usize];
            image::Rgb([q(p[0]), q(p[1]), q(p[2])])
        })
    }

    /// The signature of pixel `(x, y)`, `-1` to `width` and `height` (the ring
    /// outside the frame included); `None` beyond them.
    #[must_use]
    pub fn signature_at(&self, x: i64, y: i64) -> Option<u64> {
        let (w, h) = (i64::from(self.width), i64::from(self.height));
        if x < -1 || y < -1 || x > w || y > h {
            return None;
        }
        self.signature
            .get(((y + 1) * (w + 2) + x + 1) as usize)
            .copied()
    }

    /// How many pixels have a NaN or infinite component.
    #[must_use]
    pub fn non_finite(&self) -> usize {
        self.pixels
            .iter()
            .filter(|p| p.iter().any(|v| !v.is_finite()))
            .count()
    }
}

/// The camera's per-frame vectors in `f64` (chapter notation: `n c_a`, `u1`, `u2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefCamera {
    position: V3,
    near_forward: V3,
    u1: V3,
    u2: V3,
    half_width: f64,
    half_height: f64,
    far_over_near_minus_one: f64,
}

impl RefCamera {
    /// The camera of a description (assumed validated) for a viewport.
    pub fn new(c: &CameraDesc, viewport: tessera_core::Viewport) -> Result<Self, DescError> {
        let position = V3::from_array(c.position);
        let forward = match (c.forward, c.look_at) {
            (Some(f), None) => V3::from_array(f),
            // The difference too follows the rule for subnormal numbers, as the
            // core's camera reads its forward direction.
            (None, Some(t)) => {
                let f = V3::from_array(t) - position;
                V3::new(flush(f.x), flush(f.y), flush(f.z))
            }
            _ => {
                return Err(DescError {
                    item: "camera".into(),
                    message: "give exactly one of `forward` and `look_at`".into(),
                });
            }
        };
        let fwd = forward.normalize();
        let up = V3::from_array(c.up);
        let (nl, nh) = (f64::from(viewport.width), f64::from(viewport.height));
        let height = 2.0 * c.near * (c.fovy.to_radians() / 2.0).tan();
        let width = nl / nh * height;
        let right = right_vector(fwd, forward, up);
        let down = fwd.cross(right).normalize();
        Ok(Self {
            position,
            near_forward: fwd * c.near,
            u1: right * (width / nl),
            u2: down * (height / nh),
            half_width: nl / 2.0,
            half_height: nh / 2.0,
            far_over_near_minus_one: (c.far - c.near) / c.near,
        })
    }

    /// The primary ray through viewport point `(x, y)` (pixel units, `(0, 0)` the
    /// top-left corner): origin on the near plane, unit direction, and the time at
    /// which it reaches the far plane.
    #[must_use]
    pub fn ray(&self, x: f64, y: f64) -> (Ray, f64) {
        let d =
            self.near_forward + self.u1 * (x - self.half_width) + self.u2 * (y - self.half_height);
        let len = d.length();
        let ray = Ray {
            origin: self.position + d,
            dir: d * (1.0 / len),
        };
        (ray, len * self.far_over_near_minus_one)
    }
}

/// `normalize(forward x up)` (the inputs as given: the direction does not depend on
/// their lengths) after one Gram-Schmidt step against the unit `fwd`; only
/// when `up` is exactly parallel to `fwd` (a zero cross product, as in the core) does
/// the world axis least aligned with `fwd` replace it.
fn right_vector(fwd: V3, forward: V3, up: V3) -> V3 {
    let mut right = forward.cross(up);
    if right.length() == 0.0 {
        let a = fwd.abs();
        let axis = if a.x <= a.y && a.x <= a.z {
            V3::X
        } else if a.y <= a.z {
            V3::Y
        } else {
            V3::Z
        };
        right = fwd.cross(axis);
    }
    let right = right.normalize();
    (right - fwd * fwd.dot(right)).normalize()
}

/// Renders `desc` at `viewport` with `settings` in `f64`. First rejects exactly
/// what the core rejects (`desc.to_core()` and the core's frame check, results
/// discarded), then renders from the description's own values, read by the rule
/// for subnormal numbers ([`SceneDesc::flush_subnormals`]).
pub fn render(
    desc: &SceneDesc,
    viewport: tessera_core::Viewport,
    settings: &tessera_core::RenderSettings,
) -> Result<RefImage, DescError> {
    let core = desc.to_core()?;
    core.lists()
        .renderer(viewport, *settings)
        .map_err(|e| DescError {
            item: "render".into(),
            message: e.to_string(),
        })?;
    drop(core);
    // The rule for subnormal numbers, as the core applies it to its f32 numbers:
    // a scene file's are read by it already, a description built in code not.
    let mut desc = desc.clone();
    desc.flush_subnormals();
    let desc = &desc;
    let camera = RefCamera::new(&desc.camera, viewport)?;
    let scene = RefScene::from_desc(desc)?;
    let tracer = Tracer {
        scene: &scene,
        max_depth: settings.max_depth,
    };
    let (width, height) = (u32::from(viewport.width), u32::from(viewport.height));
    if let tessera_core::Sampler::Adaptive { k, threshold } = settings.sampler {
        return Ok(adaptive(
            &tracer,
            &camera,
            (width, height),
            settings,
            k,
            threshold,
        ));
    }
    if let tessera_core::Sampler::Sparse { threshold, spacing } = settings.sampler {
        let coarse = spacing == 4 && coarse_fits(&camera, &scene);
        return Ok(sparse(
            &tracer,
            &camera,
            (width, height),
            settings,
            (threshold, coarse),
        ));
    }
    // Every pixel of the frame and of the ring around it (signatures only).
    let mut pixels = Vec::with_capacity((width * height) as usize);
    let mut signature = Vec::with_capacity(framed_len(width, height));
    for (x, y) in framed(width, height) {
        let mut sig = Signature::default();
        let color = if settings.sampler == tessera_core::Sampler::Prefiltered {
            prefiltered(&tracer, &camera, (x, y), &mut sig)
        } else {
            mean(
                &tracer,
                &camera,
                settings.sampler,
                settings.seed,
                (x, y),
                &mut sig,
            )
        };
        if inside((width, height), (x, y)) {
            pixels.push(color.to_array());
        }
        signature.push(sig.0);
    }
    Ok(RefImage {
        width,
        height,
        pixels,
        signature,
        encoding: settings.encoding,
    })
}

/// How many signatures a `width x height` frame has: its pixels' and those of
/// the ring of pixels just outside it, `(width + 2) x (height + 2)`.
#[must_use]
pub fn framed_len(width: u32, height: u32) -> usize {
    (width as usize + 2) * (height as usize + 2)
}

/// The pixels of a `width x height` frame and of the ring just outside it, row
/// by row from `(-1, -1)` to `(width, height)`: the order of
/// [`RefImage::signature`].
fn framed(width: u32, height: u32) -> impl Iterator<Item = (i64, i64)> {
    let (w, h) = (i64::from(width), i64::from(height));
    (-1..=h).flat_map(move |y| (-1..=w).map(move |x| (x, y)))
}

/// Whether pixel `(x, y)` is in the `width x height` frame (not on its ring).
fn inside((width, height): (u32, u32), (x, y): (i64, i64)) -> bool {
    x >= 0 && y >= 0 && x < i64::from(width) && y < i64::from(height)
}

/// The colour of pixel `(x, y)`'s prefiltered centre ray in `f64` (its
/// texture averaged over the footprint of the pixel's corner rays), its ray
/// tree signed into `sig`.
fn prefiltered(
    tracer: &Tracer<'_>,
    camera: &RefCamera,
    (x, y): (i64, i64),
    sig: &mut Signature,
) -> V3 {
    let (px, py) = (x as f64, y as f64);
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
        .map(|(dx, dy)| camera.ray(px + dx, py + dy).0);
    let (ray, t_far) = camera.ray(px + 0.5, py + 0.5);
    tracer.trace_camera_prefiltered(&ray, t_far, &corners, sig)
}

/// The mean colour of pixel `(x, y)`'s samples by `sampler` in `f64`, their
/// ray trees signed into `sig`. A pixel of the ring outside the frame (a
/// coordinate -1) takes the sampler's offsets of its coordinates modulo 2^32.
fn mean(
    tracer: &Tracer<'_>,
    camera: &RefCamera,
    sampler: tessera_core::Sampler,
    seed: u32,
    (x, y): (i64, i64),
    sig: &mut Signature,
) -> V3 {
    let count = sampler.count();
    let mut sum = V3::ZERO;
    for i in 0..count {
        let (dx, dy) = sampler.offset(x as u32, y as u32, i, seed);
        let (ray, t_far) = camera.ray(x as f64 + f64::from(dx), y as f64 + f64::from(dy));
        sum = sum + tracer.trace_camera(&ray, t_far, sig);
    }
    sum * (1.0 / f64::from(count))
}

/// What [`centre`] gives of a pixel.
type Centre = (V3, Signature, u64, bool, [u8; 3]);

/// The signature of pixel `(x, y)`'s prefiltered centre ray: what the adaptive
/// and sparse samplers' pixels of the ring outside the frame are signed with.
fn centre_signature(tracer: &Tracer<'_>, camera: &RefCamera, (x, y): (i64, i64)) -> u64 {
    let mut sig = Signature::default();
    prefiltered(tracer, camera, (x, y), &mut sig);
    sig.0
}

/// A pixel's prefiltered centre ray in `f64`, as the adaptive and sparse
/// samplers trace it: its colour, signature, what its camera ray met (the
/// primitive and the shadow of each light), whether on a textured surface, and
/// its 8-bit channels.
fn centre(
    tracer: &Tracer<'_>,
    camera: &RefCamera,
    (x, y): (u32, u32),
    encoding: tessera_core::Encoding,
) -> Centre {
    let mut sig = Signature::default();
    let color = prefiltered(tracer, camera, (x.into(), y.into()), &mut sig);
    let (ray, t_far) = camera.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
    let (probe, textured) = tracer.camera_probe(&ray, t_far);
    let bytes = color.to_array().map(|v| encode8(v, encoding));
    (color, sig, probe, textured, bytes)
}

/// Whether the sparse sampler of spacing 4 starts from its coarse grid: every
/// object is a sphere, a box or a closed cylinder whose largest inner ball
/// (the sphere; the ball touching the box's nearest faces; the one at the
/// cylinder's middle touching its side or caps) is sure to show as a disc of
/// radius at least 4 pixels, or a plane; any object wholly behind the camera
/// or beyond the far plane is never seen. A ball shows so when it holds the
/// camera, or lies wholly between the camera's plane and the far plane with
/// `near r >= 4 pixel d` (`d` the distance
/// of its centre, `pixel` a pixel's side on the near plane): the smaller
/// half-axis of its outline is `near tan(asin(r / d)) / pixel >= near r / (d
/// pixel)` pixels.
fn coarse_fits(camera: &RefCamera, scene: &RefScene) -> bool {
    let near = camera.near_forward.length();
    let forward = camera.near_forward * (1.0 / near);
    let far = near * (camera.far_over_near_minus_one + 1.0);
    let pixel = camera.u1.length().max(camera.u2.length());
    let shows = |center: V3, r: f64| {
        let to = center - camera.position;
        let (d, a) = (to.length(), to.dot(forward));
        d < r || a > r && a + r < far && near * r >= 4.0 * pixel * d
    };
    // The ball of radius `reach` about `center`, which holds the object,
    // wholly behind the camera or beyond the far plane: never seen.
    let unseen = |center: V3, reach: f64| {
        let a = (center - camera.position).dot(forward);
        a + reach < 0.0 || a - reach > far
    };
    scene.objects.iter().all(|o| match o.shape {
        Shape::Sphere { center, radius } => shows(center, radius) || unseen(center, radius),
        Shape::Box { min, max } => {
            let (c, half) = ((min + max) * 0.5, (max - min) * 0.5);
            shows(c, half.x.min(half.y).min(half.z)) || unseen(c, half.length())
        }
        Shape::Cylinder {
            base,
            top,
            radius,
            capped,
        } => {
            let (c, half) = ((base + top) * 0.5, (top - base).length() * 0.5);
            capped && (shows(c, radius.min(half)) || unseen(c, radius.hypot(half)))
        }
        Shape::Plane { .. } => true,
        Shape::Triangle { .. } | Shape::Disk { .. } => false,
    })
}

/// The sparse sampler in `f64`: the prefiltered centre ray of every pixel
/// whose coordinates are both even; each other pixel the mean of the 8-bit
/// pixels of its two or four traced neighbours (in its row or column, or
/// diagonally) when they met the same things and each 8-bit channel spans at
/// most `threshold` over them, else (and when a neighbour lies beyond the
/// frame) its own prefiltered centre ray. With `coarse` (spacing 4, where
/// [`coarse_fits`]), the even pixels are found so first from those whose
/// coordinates are both multiples of 4, a mean taken only of neighbours on no
/// texture. The pixels of the ring outside the frame are signed by their own
/// centre ray.
fn sparse(
    tracer: &Tracer<'_>,
    camera: &RefCamera,
    (width, height): (u32, u32),
    settings: &tessera_core::RenderSettings,
    (threshold, coarse): (u8, bool),
) -> RefImage {
    let e = settings.encoding;
    let (w, h) = (i64::from(width), i64::from(height));
    // The pixels `(x, y)` of a frame `(w, h)` that pixel `(x, y)` is the mean
    // of: its row's two either side (odd x), its column's (odd y) or the four
    // diagonal ones (both odd); none for a pixel with both even or with a
    // neighbour beyond the frame.
    let near = |x: u32, y: u32, (w, h): (u32, u32)| -> Vec<(u32, u32)> {
        let beyond = x % 2 == 1 && x + 1 >= w || y % 2 == 1 && y + 1 >= h;
        match (x % 2, y % 2) {
            _ if beyond => vec![],
            (1, 0) => vec![(x - 1, y), (x + 1, y)],
            (0, 1) => vec![(x, y - 1), (x, y + 1)],
            (1, 1) => vec![
                (x - 1, y - 1),
                (x + 1, y - 1),
                (x - 1, y + 1),
                (x + 1, y + 1),
            ],
            _ => vec![],
        }
    };
    // The mean of `n`'s 8-bit pixels, rounded half up, with the first's
    // signature and what it met, when they met the same things (and with
    // `flat` lie on no texture) and each channel spans at most `threshold`.
    let blend = |n: &[&Centre], flat: bool| -> Option<Centre> {
        let first = *n.first()?;
        let agree = n.iter().all(|s| s.2 == first.2 && !(flat && s.3))
            && (0..3).all(|c| {
                let (lo, hi) = n
                    .iter()
                    .fold((u8::MAX, 0), |(lo, hi), s| (lo.min(s.4[c]), hi.max(s.4[c])));
                hi - lo <= threshold
            });
        // In linear terms: the smallest value the encoding writes as it.
        agree.then(|| {
            let k = n.len() as u32;
            let mean = |c: usize| {
                let sum: u32 = n.iter().map(|s| u32::from(s.4[c])).sum();
                ((sum + k / 2) / k) as u8
            };
            let bytes = [mean(0), mean(1), mean(2)];
            let p = tessera_core::color::Rgb8::new(bytes[0], bytes[1], bytes[2]);
            let c = e.decode(p);
            let c = V3::new(f64::from(c.r), f64::from(c.g), f64::from(c.b));
            (c, first.1, first.2, false, bytes)
        })
    };
    // The even pixels, `grid[y / 2][x / 2]`: with `coarse`, the coarse ones
    // traced and the others interpolated from them where they can be, as the
    // even pixels of a frame of half the size.
    let half = (width.div_ceil(2), height.div_ceil(2));
    let mut grid: Vec<Vec<Option<Centre>>> = (0..half.1)
        .map(|gy| {
            (0..half.0)
                .map(|gx| {
                    let coarse_px = gx % 2 == 0 && gy % 2 == 0;
                    (!coarse || coarse_px).then(|| centre(tracer, camera, (2 * gx, 2 * gy), e))
                })
                .collect()
        })
        .collect();
    if coarse {
        for gy in 0..half.1 {
            for gx in 0..half.0 {
                if grid[gy as usize][gx as usize].is_some() {
                    continue;
                }
                let parents: Vec<&Centre> = near(gx, gy, half)
                    .iter()
                    .filter_map(|&(px, py)| grid[py as usize][px as usize].as_ref())
                    .collect();
                let value = blend(&parents, true)
                    .unwrap_or_else(|| centre(tracer, camera, (2 * gx, 2 * gy), e));
                grid[gy as usize][gx as usize] = Some(value);
            }
        }
    }
    let traced = |x: u32, y: u32| -> Option<&Centre> {
        if !x.is_multiple_of(2) || !y.is_multiple_of(2) {
            return None;
        }
        grid.get((y / 2) as usize)?.get((x / 2) as usize)?.as_ref()
    };
    let ring = |x: i64, y: i64| centre_signature(tracer, camera, (x, y));
    let mut pixels = Vec::with_capacity((width * height) as usize);
    let mut signature = Vec::with_capacity(framed_len(width, height));
    signature.extend((-1..=w).map(|x| ring(x, -1)));
    for y in 0..height {
        signature.push(ring(-1, i64::from(y)));
        for x in 0..width {
            let parents: Option<Vec<&Centre>> = near(x, y, (width, height))
                .iter()
                .map(|&(x, y)| traced(x, y))
                .collect();
            let mean = parents.and_then(|n| blend(&n, false));
            let (color, sig) = match (traced(x, y), mean) {
                (Some(t), _) => (t.0, t.1),
                (None, Some(b)) => (b.0, b.1),
                (None, None) => {
                    let mut sig = Signature::default();
                    let c = prefiltered(tracer, camera, (x.into(), y.into()), &mut sig);
                    (c, sig)
                }
            };
            pixels.push(color.to_array());
            signature.push(sig.0);
        }
        signature.push(ring(w, i64::from(y)));
    }
    signature.extend((-1..=w).map(|x| ring(x, h)));
    RefImage {
        width,
        height,
        pixels,
        signature,
        encoding: e,
    }
}

/// The adaptive sampler in `f64`: every pixel's prefiltered centre ray first,
/// then, for each pixel whose centre differs from one of its four neighbours'
/// (another camera-hit signature, or on untextured hits an 8-bit channel more
/// than `threshold` apart), the `k x k` stratified samples instead. The pixels
/// of the ring outside the frame are signed by their own centre ray.
fn adaptive(
    tracer: &Tracer<'_>,
    camera: &RefCamera,
    (width, height): (u32, u32),
    settings: &tessera_core::RenderSettings,
    k: u8,
    threshold: u8,
) -> RefImage {
    let mut centres = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            centres.push(centre(tracer, camera, (x, y), settings.encoding));
        }
    }
    let at = |x: i64, y: i64| {
        (x >= 0 && y >= 0 && x < i64::from(width) && y < i64::from(height))
            .then(|| &centres[(y * i64::from(width) + x) as usize])
    };
    let stratified = tessera_core::Sampler::Stratified(k);
    let mut pixels = Vec::with_capacity(centres.len());
    let mut signature = Vec::with_capacity(framed_len(width, height));
    for (xi, yi) in framed(width, height) {
        let Some(&(color, sig, probe, textured, bytes)) = at(xi, yi) else {
            signature.push(centre_signature(tracer, camera, (xi, yi)));
            continue;
        };
        let refine = [(0, -1), (-1, 0), (1, 0), (0, 1)]
            .into_iter()
            .filter_map(|(dx, dy)| at(xi + dx, yi + dy))
            .any(|n| {
                n.2 != probe
                    || !textured
                        && bytes
                            .iter()
                            .zip(&n.4)
                            .any(|(a, b)| a.abs_diff(*b) > threshold)
            });
        if !refine {
            pixels.push(color.to_array());
            signature.push(sig.0);
            continue;
        }
        let mut sig = Signature::default();
        let color = mean(
            tracer,
            camera,
            stratified,
            settings.seed,
            (xi, yi),
            &mut sig,
        );
        pixels.push(color.to_array());
        signature.push(sig.0);
    }
    RefImage {
        width,
        height,
        pixels,
        signature,
        encoding: settings.encoding,
    }
}

#[cfg(test)]
mod tests;
