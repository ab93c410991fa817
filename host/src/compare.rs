//! Accuracy of the core (f32 tiles) against the reference (f64): PSNR, mean FLIP,
//! the largest difference, and how many pixels agree within 0, 1, 2 LSB outside a
//! 1-pixel band around silhouettes.
//!
//! Silhouettes come from the reference's per-pixel signature (what each sample's ray
//! tree hit, down to a box's or a mesh's face and a checker's cell, and which
//! shadow rays were blocked): a pixel whose signature differs from one of its 8
//! neighbours lies on an edge (of an object, a reflection, a shadow, or where the
//! shading jumps), where a rounding difference may legitimately flip a whole
//! sample. The reference signs the ring of pixels just outside the frame too, so
//! every pixel has its 8 neighbours and the rule is the same on every frame's
//! shape: a pixel on the frame's border (every pixel of a 1x1 or a 64x1 frame)
//! is in the band when an edge passes between it and the pixel beyond the
//! border, as an inner pixel is.

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

    /// The largest difference outside the band, in 8-bit levels.
    #[must_use]
    pub fn max_outside(&self) -> u8 {
        match self.worst_outside.first() {
            Some(w) => w.2,
            None => (0..3).rev().find(|&d| self.outside[d] > 0).unwrap_or(0) as u8,
        }
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

/// Pixels on a silhouette: their signature differs from one of their 8
/// neighbours. `signature` holds the signatures of the `width x height` frame's
/// pixels and of the ring of pixels just outside it, `(width + 2) x (height +
/// 2)` row by row from pixel `(-1, -1)` (the reference's
/// [`RefImage::signature`](crate::reference::RefImage::signature)), so every
/// pixel of the frame has its 8 neighbours; the band is the frame's pixels only.
/// A signature of another length is an error.
pub fn silhouette_band(width: u32, height: u32, signature: &[u64]) -> Result<Vec<bool>, HostError> {
    let want = crate::reference::framed_len(width, height);
    if signature.len() != want {
        return Err(HostError::Measure(format!(
            "a {width}x{height} frame's silhouette band needs {want} signatures (the frame \
             and the ring of pixels around it), got {}",
            signature.len()
        )));
    }
    let (w, h) = (width as usize, height as usize);
    let stride = w + 2;
    let mut band = Vec::with_capacity(w * h);
    for y in 1..=h {
        for x in 1..=w {
            let s = signature[y * stride + x];
            let edge = (y - 1..=y + 1)
                .any(|ny| (x - 1..=x + 1).any(|nx| signature[ny * stride + nx] != s));
            band.push(edge);
        }
    }
    Ok(band)
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
    let (w, h) = reference.dimensions();
    let band = silhouette_band(w, h, signature)?;
    measure_with_band(
        core,
        core_non_finite,
        reference,
        reference_non_finite,
        &band,
    )
}

/// [`measure`] with the silhouette band already made from the signature
/// ([`silhouette_band`]: a byte a pixel where the signature takes eight).
pub fn measure_with_band(
    core: &RgbImage,
    core_non_finite: usize,
    reference: &RgbImage,
    reference_non_finite: usize,
    band: &[bool],
) -> Result<Accuracy, HostError> {
    if core.dimensions() != reference.dimensions() {
        return Err(HostError::Measure(format!(
            "image sizes differ: {:?} vs {:?}",
            core.dimensions(),
            reference.dimensions()
        )));
    }
    let (w, h) = core.dimensions();
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

/// Pixels FLIP measures at a time ([`mean_flip`]): its workspace takes about 60
/// bytes a pixel, so about 60 MB.
const FLIP_BAND_PIXELS: usize = 1 << 20;

/// Mean LDR-FLIP of `test` against `reference` (sRGB 8-bit, the same size), at
/// FLIP's default 67 pixels per degree: `ldr_flip(..).statistics().mean` of the
/// whole images, to the bit, computed a band of rows at a time in bounded memory
/// (about `FLIP_BAND_PIXELS` pixels, whatever the images' size).
pub fn mean_flip(reference: &RgbImage, test: &RgbImage) -> Result<f64, HostError> {
    let (radius, feature_radius) = crate::limits::flip_radii();
    let apron = radius.max(feature_radius) as usize;
    let rows = (FLIP_BAND_PIXELS / (reference.width() as usize).max(1)).max(2 * apron);
    mean_flip_in_bands(reference, test, rows)
}

/// [`mean_flip`] in bands of `rows` rows. A pixel's FLIP error depends only on
/// the pixels within the filters' radii ([`crate::limits::flip_radii`]), and on
/// the image's edges, where the filters clamp: each band is measured with that
/// many rows more above and below (none past the image's edges, as for the
/// whole image) and only its own rows are kept, so every error is the one the
/// whole image gives. They are summed in `f32` in row-major order, as FLIP's
/// statistics do: the same mean.
fn mean_flip_in_bands(
    reference: &RgbImage,
    test: &RgbImage,
    rows: usize,
) -> Result<f64, HostError> {
    if reference.dimensions() != test.dimensions() {
        return Err(HostError::Measure(format!(
            "FLIP: image sizes differ: {:?} vs {:?}",
            reference.dimensions(),
            test.dimensions()
        )));
    }
    let flip = |e: flip_rs::FlipError| HostError::Measure(format!("FLIP: {e}"));
    let (w, h) = (reference.width() as usize, reference.height() as usize);
    let (radius, feature_radius) = crate::limits::flip_radii();
    let apron = radius.max(feature_radius) as usize;
    let mut sum = 0.0_f32;
    let mut top = 0;
    while top < h {
        let bottom = (top + rows.max(1)).min(h);
        let (from, to) = (top.saturating_sub(apron), (bottom + apron).min(h));
        let part = |img: &RgbImage| {
            let bytes = img
                .as_raw()
                .get(from * w * 3..to * w * 3)
                .unwrap_or_default();
            flip_rs::RgbImage::new(w, to - from, bytes.to_vec()).map_err(flip)
        };
        let map = flip_rs::ldr_flip(&part(reference)?, &part(test)?, flip_rs::DEFAULT_PPD)
            .map_err(flip)?;
        let own = map.pixels().get((top - from) * w..(bottom - from) * w);
        for &e in own.unwrap_or_default() {
            sum += e;
        }
        top = bottom;
    }
    Ok(f64::from(sum / (w * h) as f32))
}

/// A heat-map of the differences: black = equal, blue = 1 LSB, green = 2, yellow =
/// 3 or 4, red = 5 or more; equal pixels in the silhouette band
/// ([`silhouette_band`], an error for a signature of the wrong length) are dark
/// grey.
pub fn heatmap(
    core: &RgbImage,
    reference: &RgbImage,
    signature: &[u64],
) -> Result<RgbImage, HostError> {
    let (w, h) = core.dimensions();
    Ok(heatmap_with_band(
        core,
        reference,
        &silhouette_band(w, h, signature)?,
    ))
}

/// [`heatmap`] with the silhouette band already made ([`silhouette_band`]).
#[must_use]
pub fn heatmap_with_band(core: &RgbImage, reference: &RgbImage, band: &[bool]) -> RgbImage {
    let (w, h) = core.dimensions();
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

    /// A `width x height` frame's signatures with its ring, from a function of
    /// the pixel (`-1` to `width`, `height`).
    fn framed(width: u32, height: u32, f: impl Fn(i64, i64) -> u64) -> Vec<u64> {
        let (w, h) = (i64::from(width), i64::from(height));
        (-1..=h)
            .flat_map(|y| (-1..=w).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect()
    }

    #[test]
    fn band_marks_both_sides_of_an_edge() {
        // 4x1: signatures a a b b (and so the ring above and below) -> pixels 1
        // and 2 are on the edge.
        let sig = framed(4, 1, |x, _| if x < 2 { 1 } else { 2 });
        let band = silhouette_band(4, 1, &sig).unwrap();
        assert_eq!(band, vec![false, true, true, false]);
    }

    /// Every pixel has its 8 neighbours, the ring's included: an edge between
    /// the frame's border and the ring puts the border's pixels in the band on
    /// every frame's shape; a uniform neighbourhood none.
    #[test]
    fn band_sees_the_ring_outside_the_frame() {
        // One pixel, an edge through it (its left side and its right side differ).
        let sig = framed(1, 1, |x, _| u64::from(x > 0));
        assert_eq!(silhouette_band(1, 1, &sig).unwrap(), vec![true]);
        assert_eq!(silhouette_band(1, 1, &[7; 9]).unwrap(), vec![false]);
        // One row, a horizontal edge below it: every pixel.
        let sig = framed(64, 1, |_, y| u64::from(y > 0));
        assert_eq!(silhouette_band(64, 1, &sig).unwrap(), vec![true; 64]);
        // A 5x4 frame whose right-hand ring column differs: the last column only.
        let sig = framed(5, 4, |x, _| u64::from(x == 5));
        let band = silhouette_band(5, 4, &sig).unwrap();
        for (i, b) in band.iter().enumerate() {
            assert_eq!(*b, i % 5 == 4, "pixel {i}");
        }
        // A diagonal neighbour counts: only the ring's corner below right differs.
        let sig = framed(3, 2, |x, y| u64::from(x == 3 && y == 2));
        let band = silhouette_band(3, 2, &sig).unwrap();
        assert_eq!(band, vec![false, false, false, false, false, true]);
        let e = silhouette_band(4, 1, &[1, 1, 2, 2])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("4x1") && e.contains("needs 18") && e.contains("got 4"),
            "{e}"
        );
    }

    /// An image of `w x h` with a gradient, a disc and noise (the noise from
    /// `seed`).
    fn pattern(w: u32, h: u32, seed: u32) -> RgbImage {
        let mut s = seed | 1;
        RgbImage::from_fn(w, h, |x, y| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            let (dx, dy) = (x as i64 - i64::from(w) / 2, y as i64 - i64::from(h) / 3);
            let disc = if dx * dx + dy * dy < i64::from(w * h) / 8 {
                90
            } else {
                0
            };
            let g = ((x * 255) / w.max(1)) as u8;
            Rgb([g.wrapping_add(disc), (y * 7) as u8, (s % 4) as u8 + disc])
        })
    }

    /// The banded mean is the whole image's mean, to the bit, for bands of
    /// every height (one row, fewer rows than the filters' radii, more than
    /// the image), on images from one row to many.
    #[test]
    fn flip_in_bands_is_flip_of_the_whole_image() {
        for (w, h) in [(37, 29), (5, 50), (64, 1), (3, 3), (80, 61)] {
            let a = pattern(w, h, 7);
            let mut b = pattern(w, h, 11);
            b.put_pixel(w / 2, h / 2, Rgb([255, 0, 255]));
            let whole = |r: &RgbImage, t: &RgbImage| {
                let f = |i: &RgbImage| {
                    flip_rs::RgbImage::new(w as usize, h as usize, i.as_raw().clone()).unwrap()
                };
                let map = flip_rs::ldr_flip(&f(r), &f(t), flip_rs::DEFAULT_PPD).unwrap();
                f64::from(map.statistics().mean)
            };
            let want = whole(&a, &b);
            assert!(want > 0.0);
            for rows in [1, 2, 5, 9, 13, 30, 1000] {
                let got = mean_flip_in_bands(&a, &b, rows).unwrap();
                assert_eq!(got.to_bits(), want.to_bits(), "{w}x{h}, bands of {rows}");
            }
            assert_eq!(mean_flip(&a, &b).unwrap().to_bits(), want.to_bits());
            assert_eq!(mean_flip(&a, &a).unwrap(), 0.0);
        }
        let e = mean_flip(&pattern(4, 4, 1), &pattern(4, 5, 1)).unwrap_err();
        assert!(e.to_string().contains("sizes differ"), "{e}");
    }

    #[test]
    fn figures_of_known_images() {
        let a = RgbImage::from_pixel(10, 10, Rgb([100, 100, 100]));
        let mut b = a.clone();
        b.put_pixel(3, 3, Rgb([101, 100, 100]));
        b.put_pixel(4, 4, Rgb([100, 103, 100]));
        let sig = vec![7u64; 144];
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
