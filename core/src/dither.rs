//! Ordered (Bayer) dithering of the 8-bit pixels to a panel's fewer bits: 5-6-5,
//! 5-5-5 and 8-bit grey.
//!
//! A panel of 5 bits a channel shows 32 levels: an 8-bit gradient (a floor, a sky)
//! truncated to them is a staircase of bands 8 values wide. Ordered dithering adds
//! to each pixel, before it is quantised, a threshold from an `n x n` Bayer matrix
//! indexed by the pixel's **absolute** position in the frame, so the pattern is the
//! same for every tile size and order (a tile renderer cannot diffuse errors into
//! tiles not yet drawn). On average over the matrix, the level shown is the 8-bit
//! value, exactly: `q = floor(v L / 255 + (r + 1/2) / n^2)` for the level count
//! `L + 1`, the matrix rank `r` of the pixel; integer arithmetic only.
//!
//! [`Dither::None`] rounds to the nearest level, as `embedded-graphics`'
//! `From<Rgb888>` converts (`dither-report` checks the panels are the same).

use crate::color::Rgb8;
use core::fmt;
use core::str::FromStr;

/// How 8-bit channels become a panel's fewer bits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Dither {
    /// The nearest level.
    None,
    /// A 4x4 Bayer matrix (16 thresholds).
    #[default]
    Bayer4,
    /// An 8x8 Bayer matrix (64 thresholds).
    Bayer8,
}

/// The 8x8 Bayer matrix, ranks 0..64; its top-left 4x4 quarter halved (the ranks
/// of even ones) is not the 4x4 matrix, so that one is computed from its own.
const BAYER8: [[u8; 8]; 8] = [
    [0, 32, 8, 40, 2, 34, 10, 42],
    [48, 16, 56, 24, 50, 18, 58, 26],
    [12, 44, 4, 36, 14, 46, 6, 38],
    [60, 28, 52, 20, 62, 30, 54, 22],
    [3, 35, 11, 43, 1, 33, 9, 41],
    [51, 19, 59, 27, 49, 17, 57, 25],
    [15, 47, 7, 39, 13, 45, 5, 37],
    [63, 31, 55, 23, 61, 29, 53, 21],
];

/// The 4x4 Bayer matrix, ranks 0..16.
const BAYER4: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

impl Dither {
    /// Every choice, in the order of [`Dither::name`]s in messages.
    pub const ALL: [Self; 3] = [Self::None, Self::Bayer4, Self::Bayer8];

    /// `none`, `bayer4` or `bayer8`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Bayer4 => "bayer4",
            Self::Bayer8 => "bayer8",
        }
    }

    /// The threshold of pixel `(x, y)` as `(2 r + 1, 2 n^2)`: `(r + 1/2) / n^2`
    /// for the matrix rank `r`; `(1, 2)`, one half, without dithering.
    #[inline]
    fn threshold(self, x: u32, y: u32) -> (u32, u32) {
        let rank = |m: &[u8], n: u32| {
            let i = (y % n) * n + x % n;
            u32::from(m.get(i as usize).copied().unwrap_or(0))
        };
        match self {
            Self::None => (1, 2),
            Self::Bayer4 => (2 * rank(BAYER4.as_flattened(), 4) + 1, 32),
            Self::Bayer8 => (2 * rank(BAYER8.as_flattened(), 8) + 1, 128),
        }
    }

    /// The 8-bit value `v` at pixel `(x, y)` as a level `0..=max` of a channel of
    /// `max + 1` levels (`max` 31 for 5 bits, 63 for 6, 255 for 8; at most 255).
    #[inline]
    #[must_use]
    pub fn level(self, v: u8, max: u8, x: u32, y: u32) -> u8 {
        self.level_of(u32::from(v), 255, max, x, y)
    }

    /// `v / full` (`v <= full`, `full < 2^16`) as a level `0..=max` at `(x, y)`.
    #[inline]
    fn level_of(self, v: u32, full: u32, max: u8, x: u32, y: u32) -> u8 {
        let (t, d) = self.threshold(x, y);
        // floor(v max / full + t / d) = floor((v max d + t full) / (full d)).
        let q = (v * u32::from(max) * d + t * full) / (full * d);
        u8::try_from(q.min(u32::from(max))).unwrap_or(max)
    }

    /// The 5-6-5 levels of `p` at `(x, y)`.
    #[inline]
    #[must_use]
    pub fn rgb565(self, p: Rgb8, x: u32, y: u32) -> (u8, u8, u8) {
        (
            self.level(p.r, 31, x, y),
            self.level(p.g, 63, x, y),
            self.level(p.b, 31, x, y),
        )
    }

    /// The 5-5-5 levels of `p` at `(x, y)`.
    #[inline]
    #[must_use]
    pub fn rgb555(self, p: Rgb8, x: u32, y: u32) -> (u8, u8, u8) {
        (
            self.level(p.r, 31, x, y),
            self.level(p.g, 31, x, y),
            self.level(p.b, 31, x, y),
        )
    }

    /// The 8-bit grey of `p` at `(x, y)`: its luma `(77 r + 150 g + 29 b) / 256`
    /// (BT.601 weights, as `embedded-graphics` converts), kept in 1/256 steps and
    /// dithered to 8 bits.
    #[inline]
    #[must_use]
    pub fn gray8(self, p: Rgb8, x: u32, y: u32) -> u8 {
        let luma = 77 * u32::from(p.r) + 150 * u32::from(p.g) + 29 * u32::from(p.b);
        // luma / 65280 of full scale (255 * 256).
        self.level_of(luma, 255 * 256, 255, x, y)
    }
}

impl fmt::Display for Dither {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A dithering name that is not `none`, `bayer4` or `bayer8`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UnknownDither;

impl fmt::Display for UnknownDither {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("expected a dithering: none, bayer4 or bayer8")
    }
}

impl core::error::Error for UnknownDither {}

impl FromStr for Dither {
    type Err = UnknownDither;
    fn from_str(s: &str) -> Result<Self, UnknownDither> {
        Self::ALL
            .into_iter()
            .find(|d| d.name().eq_ignore_ascii_case(s.trim()))
            .ok_or(UnknownDither)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each matrix holds every rank once.
    #[test]
    fn the_matrices_are_permutations() {
        let mut seen = [false; 64];
        for &r in BAYER8.as_flattened() {
            assert!(!seen[usize::from(r)]);
            seen[usize::from(r)] = true;
        }
        let mut seen = [false; 16];
        for &r in BAYER4.as_flattened() {
            assert!(!seen[usize::from(r)]);
            seen[usize::from(r)] = true;
        }
    }

    /// Over one matrix, the mean level shown is the 8-bit value (to within the
    /// matrix's resolution), for every value and channel width; black and white
    /// stay black and white everywhere; without dithering it is the nearest level.
    #[test]
    fn the_mean_level_is_the_value() {
        for d in [Dither::Bayer4, Dither::Bayer8] {
            let n = if d == Dither::Bayer4 { 4 } else { 8 };
            for max in [31u8, 63, 255] {
                for v in 0..=255u8 {
                    let mut sum = 0u32;
                    for y in 0..n {
                        for x in 0..n {
                            let q = d.level(v, max, x + 16, y + 40);
                            sum += u32::from(q);
                        }
                    }
                    let mean = f64::from(sum) / f64::from(n * n);
                    let want = f64::from(v) * f64::from(max) / 255.0;
                    assert!(
                        (mean - want).abs() <= 0.5 / f64::from(n * n) + 1e-9,
                        "{d} max {max} v {v}: mean {mean}, want {want}"
                    );
                }
                assert_eq!(d.level(0, max, 3, 5), 0);
                assert_eq!(d.level(255, max, 3, 5), max);
            }
        }
        for v in 0..=255u8 {
            let want = (f64::from(v) * 31.0 / 255.0).round() as u8;
            assert_eq!(Dither::None.level(v, 31, 7, 9), want, "{v}");
        }
    }

    /// The threshold is a function of the absolute position, periodic with the
    /// matrix: the same pixel gets the same level whatever tile it is drawn in.
    #[test]
    fn the_pattern_depends_on_the_absolute_position_only() {
        let p = Rgb8::new(100, 37, 201);
        for (x, y) in [(0, 0), (5, 9), (123, 77)] {
            assert_eq!(
                Dither::Bayer8.rgb565(p, x, y),
                Dither::Bayer8.rgb565(p, x + 8, y + 16)
            );
            assert_eq!(
                Dither::Bayer4.rgb555(p, x, y),
                Dither::Bayer4.rgb555(p, x + 4, y + 4)
            );
        }
        // Neighbours differ somewhere for a value between two levels.
        let mid = Rgb8::new(4, 2, 4);
        let levels: std::vec::Vec<_> = (0..4).map(|x| Dither::Bayer4.rgb565(mid, x, 0)).collect();
        assert!(levels.iter().any(|l| *l != levels[0]), "{levels:?}");
    }

    #[test]
    fn grey_is_the_dithered_luma() {
        for v in [0u8, 1, 100, 254, 255] {
            let p = Rgb8::new(v, v, v);
            assert_eq!(Dither::None.gray8(p, 0, 0), v);
        }
        let names: std::vec::Vec<_> = Dither::ALL.iter().map(|d| d.name()).collect();
        assert_eq!(names, ["none", "bayer4", "bayer8"]);
        assert_eq!("Bayer8".parse(), Ok(Dither::Bayer8));
        assert_eq!("floyd".parse::<Dither>(), Err(UnknownDither));
    }

    extern crate std;
}
