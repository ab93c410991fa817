//! The adaptive sampler's centre samples and their sliding window of rows.

use crate::color::{Color, Encoding, Rgb8};

/// The neighbours a pixel is compared with, as `(dx, dy)`: above, left, right,
/// below. (The diagonal ones too would trace many more camera rays for hardly
/// a smaller error: an edge that crosses a pixel crosses the line to one of
/// these four.)
pub(super) const NEIGHBOURS: [(i32, i32); 4] = [(0, -1), (-1, 0), (1, 0), (0, 1)];

/// A centre sample of the adaptive sampler: the linear colour and the signature
/// of its ray tree (see `shade::Signed`).
#[derive(Clone, Copy)]
pub(super) struct CentreSample {
    pub(super) color: Color,
    pub(super) sig: u32,
    pub(super) textured: bool,
}

impl CentreSample {
    /// What the decision needs of it.
    #[inline(always)]
    pub(super) fn encoded(&self, encoding: Encoding) -> CentrePixel {
        CentrePixel {
            color: encoding.encode(self.color),
            sig: self.sig,
            textured: self.textured,
        }
    }
}

/// What the adaptive sampler compares of two neighbouring centre samples: the
/// 8-bit pixel and the signature.
#[derive(Clone, Copy, Default)]
pub(super) struct CentrePixel {
    pub(super) color: Rgb8,
    pub(super) sig: u32,
    pub(super) textured: bool,
}

impl CentrePixel {
    /// Whether the two pixels straddle an edge: their rays met different things,
    /// or a channel differs by more than `threshold`.
    #[inline(always)]
    pub(super) fn differs(self, other: Self, threshold: u8) -> bool {
        let (a, b) = (self.color, other.color);
        self.sig != other.sig
            || !self.textured
                && (a.r.abs_diff(b.r) > threshold
                    || a.g.abs_diff(b.g) > threshold
                    || a.b.abs_diff(b.b) > threshold)
    }
}

/// Three rows of centre samples, each `N + 2` wide (the tile's columns and the
/// apron's on either side): row `r` of the tile (`-1` to `N`) is kept in slot
/// `(r + 1) mod 3`, column `i` (`-1` to `N`) in `left`, `mid[i]` or `right`.
pub(super) struct Window<const N: usize> {
    pub(super) rows: [Row<N>; 3],
}

/// One row of a [`Window`].
#[derive(Clone, Copy)]
pub(super) struct Row<const N: usize> {
    pub(super) left: CentrePixel,
    pub(super) mid: [CentrePixel; N],
    pub(super) right: CentrePixel,
}

impl<const N: usize> Window<N> {
    pub(super) fn new() -> Self {
        let row = Row {
            left: CentrePixel::default(),
            mid: [CentrePixel::default(); N],
            right: CentrePixel::default(),
        };
        Self { rows: [row; 3] }
    }

    /// The place of column `i` of row `r` (always `Some`: the slot is `< 3`).
    #[inline(always)]
    pub(super) fn at(&mut self, r: i64, i: i64) -> Option<&mut CentrePixel> {
        let row = self.rows.get_mut((r + 1).rem_euclid(3) as usize)?;
        Some(match usize::try_from(i) {
            Err(_) => &mut row.left,
            Ok(i) => match row.mid.get_mut(i) {
                Some(p) => p,
                None => &mut row.right,
            },
        })
    }

    #[inline(always)]
    pub(super) fn set(&mut self, r: i64, i: i64, p: CentrePixel) {
        if let Some(at) = self.at(r, i) {
            *at = p;
        }
    }

    #[inline(always)]
    pub(super) fn get(&mut self, r: i64, i: i64) -> CentrePixel {
        self.at(r, i).map(|p| *p).unwrap_or_default()
    }
}
