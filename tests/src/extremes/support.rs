//! What the cases share: the `f64` side of every comparison (the f64 reference's
//! [`V3`], with the few conversions the battery needs in [`V3Ext`]), ulps, a seeded
//! generator, and the battery's rays, built exactly.

use tessera_core::{Renderer, Vec3, Viewport, trace::Ray};
use tessera_host::compare::{Accuracy, measure};
use tessera_host::desc::SceneDesc;
pub use tessera_host::reference::vec::V3;

/// No distance limit.
pub(crate) const INF: f32 = f32::INFINITY;

/// The offset of the watertightness and re-intersection tests far from the origin.
pub const FAR: Vec3 = Vec3::new(148_376.0, 1234.0, -223_423.0);

/// A point as `(x, y, z)`.
#[must_use]
pub fn show(v: Vec3) -> String {
    format!("({}, {}, {})", v.x, v.y, v.z)
}

/// What the battery needs of the f64 reference's vector beyond its own methods: the
/// way to and from the core's `f32` vectors, a basis, one component replaced.
pub trait V3Ext: Sized {
    /// The exact `f64` value of an `f32` vector.
    fn of(v: Vec3) -> Self;
    /// Rounded to the nearest `f32` vector.
    fn f32(self) -> Vec3;
    /// Two unit vectors completing the unit vector `self` to an orthonormal basis.
    fn basis(self) -> (Self, Self);
    /// `self` with component `i` (0, 1 or 2) set to `x`.
    fn with(self, i: usize, x: f64) -> Self;
}

impl V3Ext for V3 {
    fn of(v: Vec3) -> Self {
        Self::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
    }
    fn f32(self) -> Vec3 {
        Vec3::new(self.x as f32, self.y as f32, self.z as f32)
    }
    fn basis(self) -> (Self, Self) {
        let a = if self.x.abs() < 0.9 {
            Self::new(1.0, 0.0, 0.0)
        } else {
            Self::new(0.0, 1.0, 0.0)
        };
        let e1 = a.cross(self).normalize();
        (e1, self.cross(e1))
    }
    fn with(self, i: usize, x: f64) -> Self {
        match i {
            0 => Self::new(x, self.y, self.z),
            1 => Self::new(self.x, x, self.z),
            _ => Self::new(self.x, self.y, x),
        }
    }
}

/// The spacing of `f32` values at the magnitude of `x` (one ulp).
#[must_use]
pub fn ulp32(x: f64) -> f64 {
    let e = ((x.abs() as f32).to_bits() >> 23) & 0xff;
    2f64.powi(e.max(1) as i32 - 150)
}

/// SplitMix64: a small seeded generator, the same sequence on every machine.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// The next 64 random bits.
    pub fn bits(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.bits() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    /// Uniform on the unit sphere.
    pub fn dir(&mut self) -> V3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        V3::new(r * phi.cos(), r * phi.sin(), z)
    }
    /// An index in `0..n`.
    pub fn index(&mut self, n: usize) -> usize {
        (self.bits() % n as u64) as usize
    }
}

/// The `f32` ray from `o` towards `target` (direction normalised in `f64`, then
/// rounded), or `None` when they coincide.
#[must_use]
pub fn ray_towards(o: Vec3, target: V3) -> Option<Ray> {
    let d = target - V3::of(o);
    (d.length() > 0.0).then(|| exact_ray(o, d.normalize().f32()))
}

/// The ray from `o` along the unit direction `d`, exactly as given: the battery's
/// expectations are computed from these bits, so this asserts that [`Ray::new`]
/// keeps a direction that is unit to `f32` precision (its promise) rather than
/// normalising it again.
#[must_use]
pub fn exact_ray(o: Vec3, d: Vec3) -> Ray {
    let r = Ray::new(o, d).expect("the battery's rays are finite and non-zero");
    assert_eq!(
        (r.origin(), r.dir()),
        (o, d),
        "Ray::new changed a unit direction"
    );
    r
}

/// A description rendered by the core (tiles of 16, as `tessera compare` does) and
/// by the f64 reference, and the one measured against the other.
pub struct Compared {
    /// The core's image.
    pub core: image::RgbImage,
    /// The reference's image.
    pub reference: image::RgbImage,
    /// `tessera compare`'s measure of the core against the reference.
    pub accuracy: Accuracy,
}

/// [`Compared`] of `desc` at `vp` with its own settings; the message of the
/// first renderer that refuses it.
pub fn compared(desc: &SceneDesc, vp: Viewport) -> Result<Compared, String> {
    let settings = desc.settings().map_err(|e| e.to_string())?;
    let scene = desc.to_core().map_err(|e| e.to_string())?;
    let renderer = Renderer::try_new(scene.camera(), vp, settings).map_err(|e| e.to_string())?;
    let (core, non_finite) = scene.with_view(|view| {
        let img =
            tessera_host::render_tiles::<16>(view, &renderer, None).map_err(|e| e.to_string())?;
        let (w, h) = img.dimensions();
        let nf = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| !renderer.pixel_color(view, x, y, &mut ()).is_finite())
            .count();
        Ok::<_, String>((img, nf))
    })?;
    let r = tessera_host::reference::render(desc, vp, &settings).map_err(|e| e.to_string())?;
    let reference = r.to_rgb8();
    let accuracy = measure(&core, non_finite, &reference, r.non_finite(), &r.signature)
        .map_err(|e| e.to_string())?;
    Ok(Compared {
        core,
        reference,
        accuracy,
    })
}
