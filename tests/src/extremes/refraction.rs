//! Case 10: refraction near the critical angle against Snell's law in `f64`.

use super::{V3, V3Ext};
use tessera_core::testing::refract;

/// Relative indices of case 10.
pub const IORS: [f32; 7] = [1.0, 1.0001, 1.2, 1.33, 1.5, 2.42, 4.0];

/// Half-width of the band around the critical angle where the `f32` decision may
/// differ from `f64`: `|sin^2 t - 1| <= 2^-20` (16 ulps of 1; the rounding of the
/// input vectors and of four operations is a few ulps).
pub const TIR_BAND: f64 = 1.0 / (1u64 << 20) as f64;

/// Figures of case 10.
#[derive(Clone, Debug, Default)]
pub struct Refraction {
    /// Calls of `refract`.
    pub rays: usize,
    /// TIR decisions differing from `f64` outside [`TIR_BAND`].
    pub disagreements: usize,
    /// Decisions differing inside the band (allowed).
    pub band_disagreements: usize,
    /// Largest `|sin^2 t - 1|` among the differing decisions.
    pub widest_disagreement: f64,
    /// Results with a NaN or infinite direction or reflectance, or a reflectance
    /// outside `[0, 1]`.
    pub non_finite: usize,
    /// Largest `| |t| - 1 |` of the refracted directions.
    pub worst_unit: f64,
    /// Largest error of `sin t` against Snell's law in `f64`.
    pub worst_snell: f64,
    /// Refracted directions on the wrong side of the surface.
    pub wrong_side: usize,
}

/// Case 10: for each index, entering and leaving, incidence angles swept over
/// `[0, 90]` degrees and packed around the critical angle (offsets `1e-9` to `1e-1`
/// rad and a few ulps of the input), in an oblique frame; [`refract`] against the
/// geometry of the same `f32` vectors in `f64`.
#[must_use]
pub fn refraction() -> Refraction {
    let mut out = Refraction::default();
    let n64 = V3::new(0.2, 0.9, -0.3).normalize();
    let n32 = n64.f32();
    let (tan, _) = n64.basis();
    let n = V3::of(n32);
    for ior in IORS {
        for entering in [true, false] {
            let mut angles: Vec<f64> = (0..=4000)
                .map(|i| i as f64 / 4000.0 * std::f64::consts::FRAC_PI_2)
                .collect();
            if !entering && ior > 1.0 {
                let crit = (1.0 / f64::from(ior)).asin();
                for e in 0..=16 {
                    let off = 10f64.powf(-1.0 - e as f64 * 0.5);
                    angles.extend([crit - off, crit + off]);
                }
                angles.extend((-200..=200).map(|i| crit + i as f64 * 1e-8));
            }
            for a in angles
                .into_iter()
                .filter(|a| (0.0..=std::f64::consts::FRAC_PI_2).contains(a))
            {
                let d32 = (tan * a.sin() - n64 * a.cos()).f32();
                let cos_i = (-d32.dot(n32)).clamp(0.0, 1.0);
                let got = refract(d32, n32, cos_i, ior, entering);
                out.rays += 1;
                // Truth: the same f32 vectors, in f64.
                let d = V3::of(d32);
                let cos_t_in = -(d.dot(n)) / (d.length() * n.length());
                let eta = if entering {
                    1.0 / f64::from(ior)
                } else {
                    f64::from(ior)
                };
                let sin2_t = eta * eta * (1.0 - cos_t_in * cos_t_in).max(0.0);
                let tir = sin2_t >= 1.0;
                if got.is_none() != tir {
                    let dist = (sin2_t - 1.0).abs();
                    out.widest_disagreement = out.widest_disagreement.max(dist);
                    if dist > TIR_BAND {
                        out.disagreements += 1;
                    } else {
                        out.band_disagreements += 1;
                    }
                }
                if let Some((t, fr)) = got {
                    if !(t.is_finite() && fr.is_finite() && (0.0..=1.0).contains(&fr)) {
                        out.non_finite += 1;
                        continue;
                    }
                    let t = V3::of(t);
                    out.worst_unit = out.worst_unit.max((t.length() - 1.0).abs());
                    if t.dot(n) > 0.0 {
                        out.wrong_side += 1;
                    }
                    if !tir {
                        let tn = t.normalize();
                        let sin_t = (tn - n.normalize() * tn.dot(n.normalize())).length();
                        out.worst_snell = out.worst_snell.max((sin_t - sin2_t.sqrt()).abs());
                    }
                }
            }
        }
    }
    out
}
