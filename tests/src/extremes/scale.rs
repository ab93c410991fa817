//! Cases 7 and 8: scale invariance of the built-in scenes (`2^k`), and flush-to-zero.

use image::RgbImage;
use tessera_core::Geometry;
use tessera_core::kind::Kind;
use tessera_core::{Renderer, Viewport};
use tessera_host::desc::{SceneDesc, TextureDesc};
use tessera_host::kinds::{HostKind, Listed, Number, each_kind};

/// The built-in scene descriptions of case 7.
#[must_use]
pub fn builtins() -> Vec<(&'static str, SceneDesc)> {
    tessera_core::builtin::Builtin::ALL
        .iter()
        .map(|&b| (b.name(), tessera_host::file::builtin_desc(b)))
        .collect()
}

/// `desc` with every length times `2^k` and every light intensity times `4^k`, so
/// that the image is unchanged in exact arithmetic. Texture coordinates in world
/// units (planes) scale too, so a texture used by planes has its scale divided (its
/// fringe spacing or wavelength multiplied) by `2^k`; other shapes' uv are
/// scale-free. Every product is exact in `f64`, and the `f32` values the core gets
/// are exactly the unscaled ones times `2^k` while they stay normal.
///
/// # Panics
/// If a textured material is used by a plane and by another kind of shape.
#[must_use]
pub fn scaled(desc: &SceneDesc, k: i32) -> SceneDesc {
    let s = 2f64.powi(k);
    let v = |a: [f64; 3]| a.map(|x| x * s);
    let mut d = desc.clone();
    d.camera.position = v(d.camera.position);
    d.camera.look_at = d.camera.look_at.map(v);
    d.camera.near *= s;
    d.camera.far *= s;
    each_kind!(|G| {
        for x in G::descs_mut(&mut d) {
            G::numbers(x, &mut |_, what, xs| {
                if what != Number::Direction {
                    xs.iter_mut().for_each(|x| *x *= s);
                }
            });
        }
    });
    for m in &mut d.meshes {
        for f in &mut m.faces {
            *f = f.map(v);
        }
    }
    for x in &mut d.lights {
        // A sun's light does not fall off with distance: it stays as it is.
        if x.direction.is_none() {
            x.position = v(x.position);
            x.intensity *= s * s;
        }
    }
    for m in &mut d.materials {
        let on_planes = desc.planes.iter().any(|p| p.material == m.name);
        let mut elsewhere = desc
            .meshes
            .iter()
            .any(|p| p.material.as_ref() == Some(&m.name));
        each_kind!(|G| {
            if G::KIND != Kind::Plane {
                elsewhere |= G::descs(desc).iter().any(|p| G::material(p) == m.name);
            }
        });
        let Some(t) = &mut m.texture else { continue };
        assert!(
            !(on_planes && elsewhere),
            "material {} on planes and other shapes",
            m.name
        );
        if on_planes {
            match t {
                TextureDesc::Checker { scale, .. } => *scale /= s,
                TextureDesc::Fringes { spacing, .. } => *spacing *= s,
                TextureDesc::Young { wavelength, .. } => *wavelength *= s,
                // An image on a plane is in world units too: not scaled here (the
                // scaled scenes have none).
                TextureDesc::Image { file, .. } => panic!("image {file} on a plane"),
            }
        }
    }
    d
}

/// A rendered image and how many of its pixels had a NaN or infinite linear colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Rendered {
    /// The 8-bit image.
    pub image: RgbImage,
    /// Pixels whose linear colour is not finite.
    pub non_finite: usize,
}

/// Renders a description with the core (`Renderer::pixel_color`, as a tile does) at
/// `vp` with the description's own settings; the core's error if it refuses it.
pub fn render_desc(desc: &SceneDesc, vp: Viewport) -> Result<Rendered, String> {
    let settings = desc.settings().map_err(|e| e.to_string())?;
    let scene = desc.to_core().map_err(|e| e.to_string())?;
    let renderer = Renderer::try_new(scene.camera(), vp, settings).map_err(|e| e.to_string())?;
    let mut non_finite = 0;
    let image = scene.with_view(|view| {
        RgbImage::from_fn(u32::from(vp.width), u32::from(vp.height), |x, y| {
            let c = renderer.pixel_color(view, x, y, &mut ());
            non_finite += usize::from(!c.is_finite());
            let p = c.to_rgb8();
            image::Rgb([p.r, p.g, p.b])
        })
    });
    Ok(Rendered { image, non_finite })
}

/// The viewport of cases 7 and 8.
pub const SCALE_VIEWPORT: Viewport = Viewport::new(64, 48);

/// Figures of case 7 for one scene: the range of `k` over which the image is
/// bit-identical to `k = 0`, and what happens just beyond it on each side.
#[derive(Clone, Debug, Default)]
pub struct ScaleRange {
    /// The scene.
    pub name: String,
    /// Smallest `k` of the identical run around 0.
    pub lo: i32,
    /// Largest `k` of the identical run around 0.
    pub hi: i32,
    /// At `lo - 1`: `"rejected: <error>"`, `"N pixels differ"`, or `"not tried"`.
    pub below: String,
    /// At `hi + 1`.
    pub above: String,
}

/// What scaling by `2^k` does: `None` when the image is identical to `base`.
fn scale_outcome(desc: &SceneDesc, k: i32, base: &Rendered) -> Option<String> {
    match render_desc(&scaled(desc, k), SCALE_VIEWPORT) {
        Err(e) => Some(format!("rejected: {e}")),
        Ok(r) if r == *base => None,
        Ok(r) => {
            let n = r
                .image
                .pixels()
                .zip(base.image.pixels())
                .filter(|(a, b)| a != b)
                .count();
            Some(format!("{n} pixels differ, {} non-finite", r.non_finite))
        }
    }
}

/// Case 7 for one scene: scans `k` outwards from 0 up to `|k| = limit`.
#[must_use]
pub fn scale_range(name: &str, desc: &SceneDesc, limit: i32) -> ScaleRange {
    let base = render_desc(desc, SCALE_VIEWPORT).expect("base render");
    let mut out = ScaleRange {
        name: name.into(),
        below: "not tried".into(),
        above: "not tried".into(),
        ..ScaleRange::default()
    };
    for k in 1..=limit {
        if let Some(why) = scale_outcome(desc, k, &base) {
            out.above = why;
            break;
        }
        out.hi = k;
    }
    for k in 1..=limit {
        if let Some(why) = scale_outcome(desc, -k, &base) {
            out.below = why;
            break;
        }
        out.lo = -k;
    }
    out
}

/// The range of `k` for which validation accepts the scene scaled by `2^k`
/// (scanned outwards from 0, up to `|k| = 200`).
#[must_use]
pub fn validated_range(desc: &SceneDesc) -> (i32, i32) {
    let ok = |k: i32| {
        let d = scaled(desc, k);
        match (d.to_core(), d.settings()) {
            (Ok(scene), Ok(settings)) => scene.lists().renderer(SCALE_VIEWPORT, settings).is_ok(),
            _ => false,
        }
    };
    let hi = (1..=200).take_while(|&k| ok(k)).last().unwrap_or(0);
    let lo = (1..=200).take_while(|&k| ok(-k)).last().map_or(0, |k| -k);
    (lo, hi)
}

/// The `k` in `ks` for which the scaled scene's image differs from `k = 0`.
#[must_use]
pub fn scale_mismatches(desc: &SceneDesc, ks: impl IntoIterator<Item = i32>) -> Vec<(i32, String)> {
    let base = render_desc(desc, SCALE_VIEWPORT).expect("base render");
    ks.into_iter()
        .filter_map(|k| scale_outcome(desc, k, &base).map(|w| (k, w)))
        .collect()
}

/// Runs `f` with denormals flushed to zero (MXCSR FTZ and DAZ set) on this thread,
/// restoring the previous MXCSR afterwards, even if `f` panics.
#[cfg(target_arch = "x86_64")]
pub fn with_flush_to_zero<R>(f: impl FnOnce() -> R) -> R {
    #[allow(deprecated, unsafe_code)]
    mod csr {
        use core::arch::x86_64::{_mm_getcsr, _mm_setcsr};
        /// FTZ (bit 15) and DAZ (bit 6).
        const FTZ_DAZ: u32 = 0x8040;
        pub struct Guard(u32);
        impl Guard {
            pub fn set() -> Self {
                // SAFETY: reading MXCSR and setting two of its mode bits only changes
                // how this thread rounds tiny results; no memory is involved.
                let old = unsafe { _mm_getcsr() };
                unsafe { _mm_setcsr(old | FTZ_DAZ) };
                Self(old)
            }
        }
        impl Drop for Guard {
            fn drop(&mut self) {
                // SAFETY: restores the value read in `set`.
                unsafe { _mm_setcsr(self.0) };
            }
        }
    }
    let _guard = csr::Guard::set();
    f()
}

/// True when denormals are currently flushed on this thread (checked by computing
/// one).
#[must_use]
pub fn denormals_flushed() -> bool {
    let tiny = std::hint::black_box(f32::MIN_POSITIVE);
    std::hint::black_box(tiny * 0.5) == 0.0
}

/// Figures of case 8 for one scene at one scale.
#[derive(Clone, Debug, Default)]
pub struct Flushed {
    /// The scene.
    pub name: String,
    /// Scale exponent.
    pub k: i32,
    /// Pixels differing from the render with denormals.
    pub differing: usize,
    /// Non-finite pixels with denormals flushed.
    pub non_finite: usize,
}

/// Case 8 for one scene at `2^k`: the render with denormals flushed against the
/// normal one (x86_64 only; elsewhere the two renders are the same code).
#[must_use]
pub fn flushed(name: &str, desc: &SceneDesc, k: i32) -> Flushed {
    let d = scaled(desc, k);
    let normal = render_desc(&d, SCALE_VIEWPORT).expect("render");
    #[cfg(target_arch = "x86_64")]
    let ftz = with_flush_to_zero(|| {
        assert!(denormals_flushed(), "FTZ did not take effect");
        render_desc(&d, SCALE_VIEWPORT)
    })
    .expect("render");
    #[cfg(not(target_arch = "x86_64"))]
    let ftz = normal.clone();
    Flushed {
        name: name.into(),
        k,
        differing: ftz
            .image
            .pixels()
            .zip(normal.image.pixels())
            .filter(|(a, b)| a != b)
            .count(),
        non_finite: ftz.non_finite,
    }
}
