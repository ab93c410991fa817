//! Where in a pixel the rays go: the chapter's corner, the centre, a fixed offset,
//! stratified (jittered) k x k, n random positions (anti-aliasing), or the centre
//! with the texture averaged over the pixel's footprint (prefiltered, see the
//! module `prefilter`).
//!
//! Random numbers come from a hash of `(pixel x, pixel y, sample index, seed)`, so a
//! pixel's samples never depend on the tile size, the tile order or the thread count.

use crate::error::{Error, Field};

/// A fixed position inside a pixel, each coordinate in `[0, 1)` (`(0, 0)` = top-left
/// corner, `(0.5, 0.5)` = centre).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SubPixel {
    x: f32,
    y: f32,
}

impl SubPixel {
    /// A sub-pixel position; each coordinate must be finite and in `[0, 1)`.
    pub fn try_new(x: f32, y: f32) -> Result<Self, Error> {
        let (x, y) = (crate::error::flush(x), crate::error::flush(y));
        let ok = |v: f32| (0.0..1.0).contains(&v);
        if ok(x) && ok(y) {
            Ok(Self { x, y })
        } else {
            Err(Error::OutOfRange {
                field: Field::SubPixelOffset,
                range: "[0, 1) on each axis",
            })
        }
    }

    /// A sub-pixel position of baked data (`static` settings written by
    /// `tessera bake`), in a `const` context, not checked here:
    /// [`Sampler::validate`] checks it against [`SubPixel::try_new`], and every
    /// frame validates its sampler.
    #[must_use]
    pub const fn baked(x: f32, y: f32) -> Self {
        Self { x, y }
    }

    /// The `x` offset.
    #[must_use]
    pub fn x(&self) -> f32 {
        self.x
    }
    /// The `y` offset.
    #[must_use]
    pub fn y(&self) -> f32 {
        self.y
    }
}

/// How a pixel is sampled.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Sampler {
    /// One ray through the top-left corner of the pixel (the chapter's `r0`).
    Corner,
    /// One ray through the centre of the pixel (the default).
    #[default]
    Centre,
    /// One ray through a fixed position in the pixel.
    Offset(SubPixel),
    /// `k x k` rays, one at a random position in each cell of a `k x k` grid
    /// (jittered stratification), `1 <= k <= 64`.
    Stratified(u8),
    /// `n` rays at random positions in the pixel, `1 <= n <= 4096`.
    Random(u16),
    /// One ray through the centre; a texture it hits is averaged exactly over the
    /// pixel's footprint (box-filtered, prefiltered) instead of point-sampled: the
    /// right answer for textures in one evaluation (geometry edges stay aliased).
    Prefiltered,
    /// Adaptive anti-aliasing: one ray through each pixel's centre, its texture
    /// averaged over the pixel as [`Sampler::Prefiltered`] does, then, only where
    /// a pixel needs it, the `k x k` samples of [`Sampler::Stratified`]`(k)` (the
    /// same rays: a refined pixel is the stratified one), `2 <= k <= 64`.
    ///
    /// A pixel is refined when the centre ray of one of its four neighbours in
    /// the frame (above, left, right, below) met something else (another primitive or none, or a shadow where
    /// the pixel's own is lit, by light) or, on untextured surfaces, brought back
    /// an 8-bit colour that differs from the pixel's by more than `threshold` in a
    /// channel (the output's 8 bits: sRGB codes by default, [`crate::Encoding`]). Textured surfaces are left to the prefiltered centre ray (a
    /// texture's colour steps are not edges the samples would improve: refining
    /// Young's fringes by their colour steps makes them worse, a larger FLIP
    /// error than the prefiltered centre ray's). The decision depends only on the centre rays of the
    /// pixel and its neighbours; a tile traces the centre rays of a one-pixel
    /// apron around it, so the image is the same for every tile size, order and
    /// thread count, with three rows of centre samples as its only memory.
    Adaptive {
        /// Samples per side of a refined pixel.
        k: u8,
        /// Largest channel difference (8-bit units of the output's encoding)
        /// between neighbouring centre samples that does not refine them ([`Sampler::ADAPTIVE_THRESHOLD`] by
        /// default).
        threshold: u8,
    },
    /// Sparse sampling, fewer rays than pixels: the ray of [`Sampler::Prefiltered`]
    /// (the centre, its texture averaged over the pixel) through every pixel whose
    /// frame coordinates are both even, a quarter of them; each other pixel is the
    /// mean of its two traced neighbours (a pixel between two of them in a row or
    /// a column) or four (a pixel between four, diagonally) where those met the
    /// same things (the primitive or none, and the shadow of each light) and
    /// agree within `threshold` in each 8-bit channel (the output's 8 bits, as
    /// [`Sampler::Adaptive`] compares them); elsewhere, and where a neighbour
    /// lies beyond the frame, its own prefiltered ray. The mean is taken of the
    /// 8-bit pixels, each channel rounded half up (for neighbours within a few
    /// levels of each other, the mean of their linear colours to within a
    /// level). Shading and textures are interpolated between rays two pixels
    /// apart where they vary slowly (a highlight or a texture's detail narrower
    /// than that may be smoothed or missed); edges, shadows and steps of colour
    /// get their own rays. The decision depends only on the traced pixels, so
    /// the image is the same for every tile size, order and thread count; a
    /// tile traces the even pixels of a one-pixel apron around it, two rows of
    /// them at a time.
    ///
    /// With `spacing` 4, the even pixels are themselves found so from a
    /// coarser grid first: the ray through every pixel whose coordinates are
    /// both multiples of 4, a sixteenth of them; each other even pixel the mean
    /// of its two or four coarse neighbours (4 pixels apart) where those met
    /// the same things, agree within `threshold` and lie on no texture, else
    /// its own ray. The coarse level is taken only where it cannot lose a whole
    /// primitive: when every primitive of the scene is sure to cover, seen
    /// from the camera, a disc of at least twice the spacing across (its
    /// outline then holds a coarse ray), a frame with any other (a flat
    /// triangle or disk that may be seen edge-on, an open cylinder, a mesh)
    /// takes spacing 2. What a spacing of 4 may still smooth or miss is what
    /// spacing 2 may at half the size: detail of shading, texture and
    /// reflections narrower than 4 pixels, and the part of a primitive that
    /// shows less than that (cut by the frame's edge or by what is in front).
    /// A tile then traces the coarse pixels of a three-pixel apron around it.
    Sparse {
        /// Largest channel difference (8-bit units of the output's encoding)
        /// between the traced neighbours of a pixel that still interpolates it
        /// ([`Sampler::SPARSE_THRESHOLD`] by default).
        threshold: u8,
        /// The spacing of the first traced grid: 2 (the default) or 4.
        spacing: u8,
    },
}

impl Sampler {
    /// The colour difference (8-bit units) up to which [`Sampler::Sparse`]
    /// interpolates a pixel when the text form gives none (`sparse`).
    pub const SPARSE_THRESHOLD: u8 = 4;

    /// Sparse sampling with the default threshold.
    #[must_use]
    pub const fn sparse() -> Self {
        Self::sparse_spaced(2)
    }

    /// Sparse sampling with the default threshold from a grid of `spacing`
    /// (2 or 4) pixels.
    #[must_use]
    pub const fn sparse_spaced(spacing: u8) -> Self {
        Self::Sparse {
            threshold: Self::SPARSE_THRESHOLD,
            spacing,
        }
    }

    /// The colour difference (8-bit units) above which [`Sampler::Adaptive`]
    /// refines neighbouring pixels when the text form gives none (`adaptive:K`).
    pub const ADAPTIVE_THRESHOLD: u8 = 64;

    /// Adaptive anti-aliasing with `k x k` samples where needed and the default
    /// threshold.
    #[must_use]
    pub const fn adaptive(k: u8) -> Self {
        Self::Adaptive {
            k,
            threshold: Self::ADAPTIVE_THRESHOLD,
        }
    }

    /// Checks the sample count.
    pub fn validate(&self) -> Result<(), Error> {
        match *self {
            Self::Stratified(k) if k == 0 || k > 64 => Err(Error::BadSampleCount),
            Self::Adaptive { k, .. } if !(2..=64).contains(&k) => Err(Error::BadSampleCount),
            Self::Random(n) if n == 0 || n > 4096 => Err(Error::BadSampleCount),
            Self::Sparse { spacing, .. } if spacing != 2 && spacing != 4 => Err(Error::BadSpacing),
            // A baked offset (SubPixel::baked) is what try_new makes of it.
            Self::Offset(p) if SubPixel::try_new(p.x, p.y)? != p => Err(Error::OutOfRange {
                field: Field::SubPixelOffset,
                range: "[0, 1) on each axis, subnormal numbers as 0",
            }),
            _ => Ok(()),
        }
    }

    /// Camera rays per pixel; for [`Sampler::Adaptive`], the most a pixel takes
    /// (its centre ray and `k x k` samples; most pixels take one); for
    /// [`Sampler::Sparse`] also the most (a pixel takes one ray or none).
    #[must_use]
    pub fn count(&self) -> u32 {
        match *self {
            Self::Corner
            | Self::Centre
            | Self::Offset(_)
            | Self::Prefiltered
            | Self::Sparse { .. } => 1,
            Self::Stratified(k) => u32::from(k) * u32::from(k),
            Self::Adaptive { k, .. } => u32::from(k) * u32::from(k) + 1,
            Self::Random(n) => u32::from(n),
        }
    }

    /// Offset `(dx, dy)` in `[0, 1)^2` of sample `index` of pixel `(px, py)`
    /// (for [`Sampler::Adaptive`], of its refined samples, the stratified ones).
    #[must_use]
    pub fn offset(&self, px: u32, py: u32, index: u32, seed: u32) -> (f32, f32) {
        match *self {
            Self::Corner => (0.0, 0.0),
            Self::Centre | Self::Prefiltered | Self::Sparse { .. } => (0.5, 0.5),
            Self::Offset(s) => (s.x, s.y),
            Self::Stratified(k) | Self::Adaptive { k, .. } => {
                let k = u32::from(k.max(1));
                let cell = (index % k, index / k);
                stratified(PixelHash::new(px, py, seed), index, cell, stratum(k))
            }
            Self::Random(_) => random_pair(px, py, index, seed),
        }
    }
}

/// The text form of every sampler, as scene files and the command line write it:
/// `corner`, `centre`, `prefiltered`, `offset:X,Y`, `stratified:K`, `random:N`,
/// `adaptive:K` (the default threshold) or `adaptive:K,T`, `sparse` (the default
/// threshold) or `sparse:T`, and `sparse:T,S` for a first grid of spacing `S`
/// (2 or 4; `sparse:T,2` is written `sparse:T`).
/// [`Sampler::from_str`](core::str::FromStr::from_str) reads it back (and `center`).
impl core::fmt::Display for Sampler {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Self::Corner => f.write_str("corner"),
            Self::Centre => f.write_str("centre"),
            Self::Prefiltered => f.write_str("prefiltered"),
            Self::Offset(o) => write!(f, "offset:{},{}", o.x, o.y),
            Self::Stratified(k) => write!(f, "stratified:{k}"),
            Self::Random(n) => write!(f, "random:{n}"),
            Self::Adaptive { k, threshold } if threshold == Self::ADAPTIVE_THRESHOLD => {
                write!(f, "adaptive:{k}")
            }
            Self::Adaptive { k, threshold } => write!(f, "adaptive:{k},{threshold}"),
            Self::Sparse {
                threshold,
                spacing: 2,
            } if threshold == Self::SPARSE_THRESHOLD => f.write_str("sparse"),
            Self::Sparse {
                threshold,
                spacing: 2,
            } => write!(f, "sparse:{threshold}"),
            Self::Sparse { threshold, spacing } => write!(f, "sparse:{threshold},{spacing}"),
        }
    }
}

impl core::str::FromStr for Sampler {
    type Err = Error;

    /// Parses the text form of [`Sampler`]'s `Display` (spaces around numbers are
    /// allowed) and validates it.
    ///
    /// # Errors
    ///
    /// [`Error::UnknownSampler`] for text that is none of the forms,
    /// [`Error::BadSampleCount`] for a count out of range, and the sub-pixel
    /// offset's range error for `offset:X,Y` outside `[0, 1)`.
    fn from_str(s: &str) -> Result<Self, Error> {
        let number = |t: &str| t.trim().parse().map_err(|_| Error::UnknownSampler);
        // A count or a threshold is digits alone: no sign (`+4` as `-0` is refused).
        fn digits<T: core::str::FromStr>(t: &str, err: Error) -> Result<T, Error> {
            let t = t.trim();
            if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) {
                return Err(err);
            }
            t.parse().map_err(|_| err)
        }
        let sampler = match s.split_once(':') {
            None => match s {
                "corner" => Self::Corner,
                "centre" | "center" => Self::Centre,
                "prefiltered" => Self::Prefiltered,
                "sparse" => Self::sparse(),
                _ => return Err(Error::UnknownSampler),
            },
            Some(("sparse", rest)) => {
                let (t, spacing) = match rest.split_once(',') {
                    Some((t, s)) => (t, digits(s, Error::BadSpacing)?),
                    None => (rest, 2),
                };
                Self::Sparse {
                    threshold: digits(t, Error::BadThreshold)?,
                    spacing,
                }
            }
            Some(("stratified", k)) => Self::Stratified(digits(k, Error::BadSampleCount)?),
            Some(("random", n)) => Self::Random(digits(n, Error::BadSampleCount)?),
            Some(("adaptive", rest)) => {
                let (k, threshold) = match rest.split_once(',') {
                    Some((k, t)) => (k, Some(t)),
                    None => (rest, None),
                };
                let k = digits(k, Error::BadSampleCount)?;
                let threshold = match threshold {
                    Some(t) => digits(t, Error::BadThreshold)?,
                    None => Self::ADAPTIVE_THRESHOLD,
                };
                Self::Adaptive { k, threshold }
            }
            Some(("offset", xy)) => {
                let (x, y) = xy.split_once(',').ok_or(Error::UnknownSampler)?;
                Self::Offset(SubPixel::try_new(number(x)?, number(y)?)?)
            }
            Some(_) => return Err(Error::UnknownSampler),
        };
        sampler.validate()?;
        Ok(sampler)
    }
}

/// The cell size `1 / k` of the stratified sampler with `k x k` cells.
#[inline]
pub(crate) fn stratum(k: u32) -> f32 {
    1.0 / k as f32
}

/// The offset of stratified sample `index` of the pixel hashed as `hash`, in cell
/// `(cx, cy)` (`index = cy k + cx`) of size `inv = 1 / k`: a random position in the
/// cell. The one definition, used by [`Sampler::offset`] and by the tile loop (which
/// hashes the pixel once and steps through the cells without dividing).
#[inline]
pub(crate) fn stratified(
    hash: PixelHash,
    index: u32,
    (cx, cy): (u32, u32),
    inv: f32,
) -> (f32, f32) {
    let (jx, jy) = hash.pair(index);
    (
        below_one((cx as f32 + jx) * inv),
        below_one((cy as f32 + jy) * inv),
    )
}

/// Clamps a rounded-up `1.0` back into `[0, 1)`.
#[inline]
fn below_one(v: f32) -> f32 {
    crate::math::min(v, 1.0 - f32::EPSILON / 2.0)
}

/// A 32-bit integer hash with good avalanche (Wellons' "lowbias32").
#[inline]
#[must_use]
pub(crate) fn mix(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Two uniform numbers in `[0, 1)` for a pixel's sample.
#[must_use]
pub(crate) fn random_pair(px: u32, py: u32, index: u32, seed: u32) -> (f32, f32) {
    PixelHash::new(px, py, seed).pair(index)
}

/// The hash of a pixel's samples (every input changes every output bit), split:
/// the part that depends on the pixel and the seed only, computed once
/// per pixel rather than once per sample.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PixelHash(u32);

impl PixelHash {
    /// The pixel `(px, py)` with `seed`.
    #[inline]
    pub(crate) fn new(px: u32, py: u32, seed: u32) -> Self {
        let h = mix(seed ^ 0x9e37_79b9);
        let h = mix(h ^ px);
        let h = mix(h.wrapping_add(0x85eb_ca6b) ^ py);
        Self(h.wrapping_add(0xc2b2_ae35))
    }

    /// The hash of sample `index` of this pixel.
    #[inline]
    pub(crate) fn sample(self, index: u32) -> u32 {
        mix(self.0 ^ index)
    }

    /// [`random_pair`] of sample `index`.
    #[inline]
    pub(crate) fn pair(self, index: u32) -> (f32, f32) {
        let h = self.sample(index);
        (unit(h), unit(mix(h ^ 0x68e3_1da4)))
    }
}

/// The top 24 bits of `h` as a float in `[0, 1)` (exactly representable).
#[inline]
fn unit(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samplers_print_and_parse_back() {
        use core::fmt::Write;
        let offset = Sampler::Offset(SubPixel::try_new(0.25, 0.1).unwrap());
        for (sampler, text) in [
            (Sampler::Corner, "corner"),
            (Sampler::Centre, "centre"),
            (Sampler::Prefiltered, "prefiltered"),
            (offset, "offset:0.25,0.1"),
            (Sampler::Stratified(3), "stratified:3"),
            (Sampler::Random(16), "random:16"),
            (Sampler::adaptive(4), "adaptive:4"),
            (Sampler::Adaptive { k: 3, threshold: 0 }, "adaptive:3,0"),
            (Sampler::sparse(), "sparse"),
            (
                Sampler::Sparse {
                    threshold: 0,
                    spacing: 2,
                },
                "sparse:0",
            ),
            (Sampler::sparse_spaced(4), "sparse:4,4"),
            (
                Sampler::Sparse {
                    threshold: 9,
                    spacing: 4,
                },
                "sparse:9,4",
            ),
        ] {
            let mut shown = heapless::String::<32>::new();
            write!(shown, "{sampler}").unwrap();
            assert_eq!(shown.as_str(), text);
            assert_eq!(text.parse::<Sampler>(), Ok(sampler), "{text}");
        }
        assert_eq!("center".parse(), Ok(Sampler::Centre));
        assert_eq!("random: 7".parse(), Ok(Sampler::Random(7)));
        assert_eq!("offset: 0.5 , 0".parse::<Sampler>().unwrap().count(), 1);
        assert_eq!(
            "adaptive: 5 , 255".parse(),
            Ok(Sampler::Adaptive {
                k: 5,
                threshold: 255
            })
        );
        assert_eq!(Sampler::adaptive(4).count(), 17);
        assert_eq!(
            "sparse: 255".parse(),
            Ok(Sampler::Sparse {
                threshold: 255,
                spacing: 2
            })
        );
        assert_eq!(
            "sparse:4,2".parse(),
            Ok(Sampler::sparse()),
            "spacing 2 prints as `sparse`"
        );
        assert_eq!(Sampler::sparse_spaced(4).count(), 1);
        assert_eq!(
            "sparse:4".parse(),
            Ok(Sampler::sparse()),
            "the default threshold prints as `sparse`"
        );
        assert_eq!(Sampler::sparse().count(), 1);
    }

    #[test]
    fn bad_sampler_text_says_what_is_wrong() {
        for text in [
            "",
            "gauss",
            "centre:2",
            "offset:0.5",
            "offset:a,0",
            "Corner",
            "Sparse",
        ] {
            assert_eq!(
                text.parse::<Sampler>(),
                Err(Error::UnknownSampler),
                "{text:?}"
            );
        }
        for text in [
            "stratified:0",
            "stratified:65",
            "stratified:x",
            "random:0",
            "random:5000",
            "adaptive:1",
            "adaptive:65",
            "adaptive:",
            "adaptive:x,3",
            // A sign, either one, is refused on every count.
            "stratified:+4",
            "stratified:-0",
            "random:+1",
            "adaptive:+4",
            "adaptive:-0,3",
        ] {
            assert_eq!(
                text.parse::<Sampler>(),
                Err(Error::BadSampleCount),
                "{text:?}"
            );
        }
        for text in [
            "adaptive:4,256",
            "adaptive:4,-1",
            "adaptive:4,",
            "adaptive:4,0.5",
            "sparse:256",
            "sparse:-1",
            "sparse:",
            "sparse:x",
            // ... and on every threshold.
            "sparse:+4",
            "sparse:-0",
            "sparse: +4 ",
            "adaptive:4,+3",
            "adaptive:4,-0",
        ] {
            assert_eq!(
                text.parse::<Sampler>(),
                Err(Error::BadThreshold),
                "{text:?}"
            );
        }
        for text in [
            "sparse:4,3",
            "sparse:4,8",
            "sparse:4,",
            "sparse:4,x",
            "sparse:4,+4",
        ] {
            assert_eq!(text.parse::<Sampler>(), Err(Error::BadSpacing), "{text:?}");
        }
        assert!(matches!(
            "offset:1,0".parse::<Sampler>(),
            Err(Error::OutOfRange {
                field: Field::SubPixelOffset,
                ..
            })
        ));
    }

    #[test]
    fn fixed_samplers() {
        assert_eq!(Sampler::Corner.offset(3, 4, 0, 1), (0.0, 0.0));
        assert_eq!(Sampler::Centre.offset(3, 4, 0, 1), (0.5, 0.5));
        let s = SubPixel::try_new(0.25, 0.75).unwrap();
        assert_eq!(Sampler::Offset(s).offset(9, 9, 0, 0), (0.25, 0.75));
        assert!(SubPixel::try_new(1.0, 0.0).is_err());
        assert!(SubPixel::try_new(f32::NAN, 0.0).is_err());
        assert!(SubPixel::try_new(-0.1, 0.0).is_err());
    }

    #[test]
    fn stratified_puts_one_sample_in_each_cell() {
        let k = 4u8;
        let s = Sampler::Stratified(k);
        assert_eq!(s.count(), 16);
        let mut seen = [false; 16];
        for i in 0..16 {
            let (x, y) = s.offset(17, 5, i, 42);
            assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
            let cell = (y * 4.0) as usize * 4 + (x * 4.0) as usize;
            assert!(!seen[cell], "two samples in cell {cell}");
            seen[cell] = true;
        }
    }

    #[test]
    fn random_is_deterministic_and_uniform() {
        let s = Sampler::Random(8);
        assert_eq!(s.offset(1, 2, 3, 4), s.offset(1, 2, 3, 4));
        assert_ne!(s.offset(1, 2, 3, 4), s.offset(1, 2, 3, 5));
        assert_ne!(s.offset(1, 2, 3, 4), s.offset(2, 1, 3, 4));
        // Mean and a 10-bin histogram over many pixels.
        let mut bins = [0u32; 10];
        let mut sum = 0.0f64;
        let n = 100_000u32;
        for i in 0..n {
            let (x, y) = s.offset(i % 317, i / 317, i % 8, 7);
            sum += f64::from(x) + f64::from(y);
            bins[(x * 10.0) as usize] += 1;
        }
        assert!((sum / f64::from(2 * n) - 0.5).abs() < 0.005);
        for b in bins {
            assert!((9_500..10_500).contains(&b), "{bins:?}");
        }
    }

    #[test]
    fn bad_counts_are_rejected() {
        assert_eq!(
            Sampler::Stratified(0).validate(),
            Err(Error::BadSampleCount)
        );
        assert_eq!(
            Sampler::Stratified(65).validate(),
            Err(Error::BadSampleCount)
        );
        assert_eq!(Sampler::Random(0).validate(), Err(Error::BadSampleCount));
        assert_eq!(Sampler::Random(4097).validate(), Err(Error::BadSampleCount));
        assert!(Sampler::Random(4096).validate().is_ok());
    }
}
