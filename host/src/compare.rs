//! Accuracy of the core (f32 tiles) against the reference (f64): PSNR, mean FLIP,
//! the largest difference, and how many pixels agree within 0, 1, 2 LSB outside a
//! 1-pixel band around silhouettes.
//!
//! Silhouettes come from the reference's per-pixel signature (what each sample's ray
//! tree hit, and which shadow rays were blocked): a pixel whose signature differs
//! from one of its 8 neighbours lies on an edge (of an object, a reflection or a
//! shadow), where a rounding difference may legitimately flip a whole sample.

use crate::HostError;
use image::{Rgb, RgbImage};
use std::fmt;

/// The accuracy figures of one comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Accuracy {
    /// Pixels compared.
    pub pixels: usize,
    /// Pixels in the silhouette band (excluded from `outside`).
    pub band: usize,
    /// Peak signal-to-noise ratio over all pixels and channels, dB (infinite when
    /// the images are identical).
    pub psnr_db: f64,
    /// Mean LDR-FLIP error (0 = identical, 1 = maximal), over all pixels.
    pub mean_flip: f64,
    /// Largest absolute channel difference, LSB, over all pixels.
    pub max_abs_diff: u8,
    /// Pixels outside the band whose largest channel difference is 0, 1, 2, and more.
    pub outside: [usize; 4],
    /// The same over all pixels.
    pub all: [usize; 4],
    /// Core pixels with a NaN or infinite component.
    pub core_non_finite: usize,
    /// Reference pixels with a NaN or infinite component.
    pub reference_non_finite: usize,
    /// Up to 8 pixels outside the band that differ by more than 2 LSB:
    /// `(x, y, difference)`, largest first (where to look when the bar is missed).
    pub worst_outside: Vec<(u32, u32, u8)>,
}

impl Accuracy {
    /// Share (0 to 1) of the pixels outside the band within `lsb` (0, 1 or 2).
    #[must_use]
    pub fn share_within(&self, lsb: usize) -> f64 {
        share(&self.outside, lsb)
    }

    /// Share of all pixels within `lsb`.
    #[must_use]
    pub fn share_within_all(&self, lsb: usize) -> f64 {
        share(&self.all, lsb)
    }

    /// The project's bar: >= 99.5% of the pixels outside the band within 1 LSB,
    /// 100% within 2 LSB, no NaN or infinity on either side.
    #[must_use]
    pub fn meets_bar(&self) -> bool {
        self.share_within(1) >= 0.995
            && self.share_within(2) >= 1.0
            && self.core_non_finite == 0
            && self.reference_non_finite == 0
    }

    /// What misses the bar (see [`Accuracy::meets_bar`]), for the error message
    /// when it is not met.
    #[must_use]
    pub fn shortfall(&self) -> String {
        let mut missed = Vec::new();
        if self.share_within(1) < 0.995 {
            missed.push(format!(
                "{:.3}% of the pixels outside the band within 1 LSB (needs 99.5%)",
                100.0 * self.share_within(1)
            ));
        }
        if self.share_within(2) < 1.0 {
            missed.push(format!(
                "{} pixel(s) outside the band more than 2 LSB off (needs none)",
                self.outside[3]
            ));
        }
        if self.core_non_finite + self.reference_non_finite > 0 {
            missed.push(format!(
                "NaN/Inf pixels: core {}, reference {} (needs none)",
                self.core_non_finite, self.reference_non_finite
            ));
        }
        if missed.is_empty() {
            "the accuracy bar is met".into()
        } else {
            format!("the accuracy bar is NOT met: {}", missed.join("; "))
        }
    }
}

fn share(h: &[usize; 4], lsb: usize) -> f64 {
    let total: usize = h.iter().sum();
    if total == 0 {
        return 1.0;
    }
    let within: usize = h.iter().take(lsb.min(3) + 1).sum();
    within as f64 / total as f64
}

impl fmt::Display for Accuracy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let pct = |x: f64| 100.0 * x;
        writeln!(f, "pixels                 {}", self.pixels)?;
        writeln!(
            f,
            "silhouette band        {} ({:.2}%)",
            self.band,
            pct(self.band as f64 / self.pixels.max(1) as f64)
        )?;
        writeln!(f, "PSNR                   {:.2} dB", self.psnr_db)?;
        writeln!(f, "mean FLIP              {:.6}", self.mean_flip)?;
        writeln!(f, "max abs difference     {} LSB", self.max_abs_diff)?;
        writeln!(
            f,
            "outside band: within 0 / 1 / 2 LSB, more: {:.3}% / {:.3}% / {:.3}%, {} px",
            pct(self.share_within(0)),
            pct(self.share_within(1)),
            pct(self.share_within(2)),
            self.outside[3]
        )?;
        writeln!(
            f,
            "all pixels:   within 0 / 1 / 2 LSB, more: {:.3}% / {:.3}% / {:.3}%, {} px",
            pct(self.share_within_all(0)),
            pct(self.share_within_all(1)),
            pct(self.share_within_all(2)),
            self.all[3]
        )?;
        writeln!(
            f,
            "NaN/Inf pixels         core {}, reference {}",
            self.core_non_finite, self.reference_non_finite
        )?;
        if !self.worst_outside.is_empty() {
            let list: Vec<String> = self
                .worst_outside
                .iter()
                .map(|(x, y, d)| format!("({x}, {y}) {d} LSB"))
                .collect();
            writeln!(f, "worst outside band     {}", list.join(", "))?;
        }
        write!(
            f,
            "bar (>= 99.5% within 1 LSB, 100% within 2 LSB outside the band, 0 NaN): {}",
            if self.meets_bar() { "met" } else { "NOT met" }
        )
    }
}

/// Pixels on a silhouette: their signature differs from one of their 8 neighbours.
#[must_use]
pub fn silhouette_band(width: u32, height: u32, signature: &[u64]) -> Vec<bool> {
    let (w, h) = (width as i64, height as i64);
    let at = |x: i64, y: i64| signature.get((y * w + x) as usize).copied();
    let mut band = vec![false; signature.len()];
    for y in 0..h {
        for x in 0..w {
            let s = at(x, y);
            let mut edge = false;
            for (dx, dy) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let (nx, ny) = (x + dx, y + dy);
                if nx >= 0 && ny >= 0 && nx < w && ny < h && at(nx, ny) != s {
                    edge = true;
                }
            }
            if let Some(b) = band.get_mut((y * w + x) as usize) {
                *b = edge;
            }
        }
    }
    band
}

/// Largest absolute channel difference of two pixels.
fn diff(a: &Rgb<u8>, b: &Rgb<u8>) -> u8 {
    a.0.iter()
        .zip(b.0.iter())
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

/// Measures `core` against `reference` (same size), with the reference's signature.
pub fn measure(
    core: &RgbImage,
    core_non_finite: usize,
    reference: &RgbImage,
    reference_non_finite: usize,
    signature: &[u64],
) -> Result<Accuracy, HostError> {
    if core.dimensions() != reference.dimensions() {
        return Err(HostError::Measure(format!(
            "image sizes differ: {:?} vs {:?}",
            core.dimensions(),
            reference.dimensions()
        )));
    }
    let (w, h) = core.dimensions();
    let band = silhouette_band(w, h, signature);
    let mut outside = [0usize; 4];
    let mut all = [0usize; 4];
    let mut max_abs_diff = 0u8;
    let mut worst = Vec::new();
    let mut sq = 0.0f64;
    for (i, (a, b)) in core.pixels().zip(reference.pixels()).enumerate() {
        let d = diff(a, b);
        max_abs_diff = max_abs_diff.max(d);
        let bin = usize::from(d.min(3));
        all[bin] += 1;
        if !band.get(i).copied().unwrap_or(false) {
            outside[bin] += 1;
            if d > 2 {
                worst.push(((i % w as usize) as u32, (i / w as usize) as u32, d));
            }
        }
        for (x, y) in a.0.iter().zip(b.0.iter()) {
            let e = f64::from(*x) - f64::from(*y);
            sq += e * e;
        }
    }
    let n = (w as usize * h as usize).max(1);
    let mse = sq / (3 * n) as f64;
    let psnr_db = if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0 * 255.0 / mse).log10()
    };
    Ok(Accuracy {
        pixels: n,
        band: band.iter().filter(|b| **b).count(),
        psnr_db,
        mean_flip: mean_flip(reference, core)?,
        max_abs_diff,
        outside,
        all,
        core_non_finite,
        reference_non_finite,
        worst_outside: {
            worst.sort_by_key(|w| std::cmp::Reverse(w.2));
            worst.truncate(8);
            worst
        },
    })
}

/// Mean LDR-FLIP of `test` against `reference` (sRGB 8-bit), at FLIP's default
/// 67 pixels per degree.
pub fn mean_flip(reference: &RgbImage, test: &RgbImage) -> Result<f64, HostError> {
    let (w, h) = reference.dimensions();
    let to_flip = |img: &RgbImage| {
        flip_rs::RgbImage::new(w as usize, h as usize, img.as_raw().clone())
            .map_err(|e| HostError::Measure(format!("FLIP: {e}")))
    };
    let map = flip_rs::ldr_flip(&to_flip(reference)?, &to_flip(test)?, flip_rs::DEFAULT_PPD)
        .map_err(|e| HostError::Measure(format!("FLIP: {e}")))?;
    Ok(f64::from(map.statistics().mean))
}

/// A heat-map of the differences: black = equal, blue = 1 LSB, green = 2, yellow =
/// 3 or 4, red = 5 or more; equal pixels in the silhouette band are dark grey.
#[must_use]
pub fn heatmap(core: &RgbImage, reference: &RgbImage, signature: &[u64]) -> RgbImage {
    let (w, h) = core.dimensions();
    let band = silhouette_band(w, h, signature);
    let mut out = RgbImage::new(w, h);
    for (i, ((a, b), o)) in core
        .pixels()
        .zip(reference.pixels())
        .zip(out.pixels_mut())
        .enumerate()
    {
        *o = match diff(a, b) {
            0 if band.get(i).copied().unwrap_or(false) => Rgb([40, 40, 40]),
            0 => Rgb([0, 0, 0]),
            1 => Rgb([40, 80, 255]),
            2 => Rgb([0, 200, 60]),
            3 | 4 => Rgb([255, 220, 0]),
            _ => Rgb([255, 30, 30]),
        };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_marks_both_sides_of_an_edge() {
        // 4x1: signatures a a b b -> pixels 1 and 2 are on the edge.
        let band = silhouette_band(4, 1, &[1, 1, 2, 2]);
        assert_eq!(band, vec![false, true, true, false]);
    }

    #[test]
    fn figures_of_known_images() {
        let a = RgbImage::from_pixel(10, 10, Rgb([100, 100, 100]));
        let mut b = a.clone();
        b.put_pixel(3, 3, Rgb([101, 100, 100]));
        b.put_pixel(4, 4, Rgb([100, 103, 100]));
        let sig = vec![7u64; 100];
        let acc = measure(&b, 0, &a, 0, &sig).unwrap();
        assert_eq!(acc.outside, [98, 1, 0, 1]);
        assert_eq!(acc.max_abs_diff, 3);
        // MSE = (1 + 9) / 300.
        let psnr = 10.0 * (255.0f64 * 255.0 / (10.0 / 300.0)).log10();
        assert!((acc.psnr_db - psnr).abs() < 1e-9);
        assert!(!acc.meets_bar());
        let same = measure(&a, 0, &a, 0, &sig).unwrap();
        assert!(same.psnr_db.is_infinite() && same.mean_flip == 0.0 && same.meets_bar());
        let nan = measure(&a, 1, &a, 0, &sig).unwrap();
        assert!(!nan.meets_bar());
    }
}
