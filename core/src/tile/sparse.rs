//! The sparse sampler's rule and memory ([`crate::Sampler::Sparse`]): which
//! traced pixels a pixel is interpolated from, when they agree and their mean,
//! and the rows of traced pixels a tile keeps. Its pixel loop is
//! `Pass::fill_sparse` (module `pass`).

use super::adaptive::CentrePixel;
use crate::camera::CameraBasis;
use crate::color::Rgb8;
use crate::cull::Source;
use crate::geometry::{Girth, Kinded};
use crate::kind::{Geometry, each_kind};
use crate::math;
use crate::vec::Vec3;
use crate::view::SceneView;

/// Which traced pixels the sparse sampler may interpolate pixel `(x, y)` from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Parents {
    /// None: a traced pixel (both coordinates even), or one with a neighbour
    /// beyond the frame; its own ray.
    Own,
    /// The two traced pixels either side of it in its row or its column.
    Two([(u32, u32); 2]),
    /// The four traced pixels diagonally around it.
    Four([(u32, u32); 4]),
}

/// The traced neighbours of pixel `(x, y)` in a frame of `(w, h)` pixels
/// ([`Sampler::Sparse`]).
#[inline(always)]
pub(super) fn sparse_parents((x, y): (u32, u32), (w, h): (u32, u32)) -> Parents {
    let (odd_x, odd_y) = (x % 2 == 1, y % 2 == 1);
    // An odd coordinate's neighbours are the even ones either side; the one
    // after it must lie in the frame.
    if odd_x && x + 1 >= w || odd_y && y + 1 >= h {
        return Parents::Own;
    }
    match (odd_x, odd_y) {
        (false, false) => Parents::Own,
        (true, false) => Parents::Two([(x - 1, y), (x + 1, y)]),
        (false, true) => Parents::Two([(x, y - 1), (x, y + 1)]),
        (true, true) => Parents::Four([
            (x - 1, y - 1),
            (x + 1, y - 1),
            (x - 1, y + 1),
            (x + 1, y + 1),
        ]),
    }
}

/// The mean of the 8-bit pixels of `samples` (two or four traced pixels, each
/// channel rounded half up) when they met the same things and each channel
/// spans at most `threshold` over them; `None` otherwise.
#[inline(always)]
pub(super) fn sparse_blend<const K: usize>(
    samples: [&CentrePixel; K],
    threshold: u8,
) -> Option<Rgb8> {
    let (first, rest) = samples.split_first()?;
    let (mut lo, mut hi) = (first.color, first.color);
    let c = first.color;
    let mut sum = [u16::from(c.r), u16::from(c.g), u16::from(c.b)];
    for s in rest {
        if s.sig != first.sig {
            return None;
        }
        let c = s.color;
        lo = Rgb8::new(lo.r.min(c.r), lo.g.min(c.g), lo.b.min(c.b));
        hi = Rgb8::new(hi.r.max(c.r), hi.g.max(c.g), hi.b.max(c.b));
        sum = [
            sum[0] + u16::from(c.r),
            sum[1] + u16::from(c.g),
            sum[2] + u16::from(c.b),
        ];
    }
    if hi.r - lo.r > threshold || hi.g - lo.g > threshold || hi.b - lo.b > threshold {
        return None;
    }
    // K is 2 or 4: the mean rounded half up, by a shift.
    let shift = K.trailing_zeros();
    let mean = |v: u16| ((v + (K as u16 >> 1)) >> shift) as u8;
    Some(Rgb8::new(mean(sum[0]), mean(sum[1]), mean(sum[2])))
}

/// The level-1 pixel of the coarse grid ([`crate::Sampler::Sparse`] with spacing 4):
/// the mean of `samples` (its two or four coarse neighbours) as
/// [`sparse_blend`] takes it, with their signature, when none lies on a
/// texture (a texture's detail between rays four pixels apart is not
/// interpolated); `None` otherwise.
#[inline(always)]
pub(super) fn coarse_blend<const K: usize>(
    samples: [&CentrePixel; K],
    threshold: u8,
) -> Option<CentrePixel> {
    if samples.iter().any(|s| s.textured) {
        return None;
    }
    let color = sparse_blend(samples, threshold)?;
    Some(CentrePixel {
        color,
        sig: samples.first()?.sig,
        textured: false,
    })
}

/// Whether even row `g` of a frame `h` rows high is a level-1 row of the
/// coarse grid with a coarse row on either side (`g - 2` and `g + 2`), whose
/// pixels may be interpolated from them; the frame's last even row when `g +
/// 2` lies beyond it is traced as with spacing 2.
#[inline(always)]
pub(super) fn between_coarse_rows(g: u32, h: u32) -> bool {
    g % 4 == 2 && g + 2 < h
}

/// The radius, in pixels, of the disc every primitive's outline must be sure
/// to cover for the coarse grid: twice the spacing across, wider than the
/// spacing times `sqrt(2)` that a disc needs to hold a point of a grid of
/// that spacing.
const COARSE_RADIUS: f32 = 4.0;

/// Whether the sparse sampler may start from the grid of spacing 4 in `scene`
/// seen through `basis`: whether every primitive's outline is sure to hold a
/// pixel of that grid ([`crate::Sampler::Sparse`]). A ball inside a primitive, of
/// radius `r` and centre at distance `d` from the camera, lying wholly
/// between the camera's plane and its far plane, has an outline (an ellipse)
/// whose smaller half-axis is at least `f r / d` pixels, `f` the distance
/// from the camera to the near plane in pixels; a ball that holds the camera
/// fills the view; a primitive wholly behind the camera or beyond the far
/// plane (the ball about the inner one's centre that holds it) is not seen. Any other
/// primitive (its ball across the camera's plane or the far plane, flat or
/// thin where seen), or a mesh or an instance: spacing 2. Computed in `f32`
/// with a margin of `2^-10`, far above its roundings; a NaN fails every
/// comparison, and gives spacing 2.
pub(super) fn coarse_fits(basis: &CameraBasis, scene: &SceneView<'_>) -> bool {
    let mut tops = false;
    scene.each_top(|_, _| tops = true);
    if tops {
        return false;
    }
    let (forward, near, far) = basis.depth_axis();
    let pixel = math::max(basis.u1().length(), basis.u2().length());
    let eye = basis.position();
    let margin = 1.0 + 1.0 / 1024.0;
    // The ball that holds the primitive wholly behind the camera or beyond
    // the far plane, with room for its roundings: never seen. A NaN fails.
    let unseen = |center: Vec3, reach: f32| {
        let to = center - eye;
        let (along, slack) = (to.dot(forward), reach * margin + to.length() / 1024.0);
        along + slack < 0.0 || along - slack > far
    };
    // A ball inside the primitive: holding the camera, or wholly between the
    // camera's plane and the far plane and `f r / d` pixels or more.
    let wide = |center: Vec3, radius: f32| {
        let to = center - eye;
        let (d, along) = (to.length(), to.dot(forward));
        d * margin < radius
            || along > radius * margin
                && along + radius < far
                && near * radius >= COARSE_RADIUS * pixel * d * margin
    };
    let primitives = scene.primitives;
    let mut fits = true;
    each_kind!(|G| {
        for p in G::of(&primitives) {
            let g = &p.geometry;
            fits &= match g.girth() {
                Girth::HalfSpace => true,
                Girth::Thin => false,
                Girth::Ball {
                    center,
                    radius,
                    reach,
                } => wide(center, radius) || unseen(center, reach),
            };
        }
    });
    fits
}

/// Three rows of the sparse sampler's traced pixels (even rows), each over the
/// even columns from the grid's first on: at most `N / 2 + 5` of them for a
/// tile of `N`, in the cells the tile loop lends ([`Grid::new`]), so that the
/// loop has one copy whatever the tile size. Spacing 2 keeps two rows (its own
/// or the two around an odd row); spacing 4 also the two coarse rows around a
/// level-1 row.
pub(super) struct Grid<'a> {
    rows: [GridRow<'a>; 3],
}

/// One row of a [`Grid`]: its `y` (`u32::MAX` before it is traced).
pub(super) struct GridRow<'a> {
    y: u32,
    cells: &'a mut [CentrePixel],
}

/// The pixel [`GridRow::at`] gives beyond a row (never asked for).
const NONE: CentrePixel = CentrePixel {
    color: Rgb8::new(0, 0, 0),
    sig: 0,
    textured: false,
};

impl GridRow<'_> {
    /// The traced pixel of the `k`-th even column from the grid's first.
    #[inline(always)]
    pub(super) fn at(&self, k: usize) -> &CentrePixel {
        self.cells.get(k).unwrap_or(&NONE)
    }

    #[inline(always)]
    pub(super) fn set(&mut self, k: usize, s: CentrePixel) {
        if let Some(at) = self.cells.get_mut(k) {
            *at = s;
        }
    }
}

impl<'a> Grid<'a> {
    /// Three rows in `cells`, each at least `N / 2 + 5` long for tiles of `N`.
    pub(super) fn new(cells: [&'a mut [CentrePixel]; 3]) -> Self {
        Self {
            rows: cells.map(|cells| GridRow { y: u32::MAX, cells }),
        }
    }

    /// Whether row `y` is kept.
    #[inline(always)]
    pub(super) fn holds(&self, y: u32) -> bool {
        self.rows.iter().any(|r| r.y == y)
    }

    /// Gives row `y` a slot to be traced into ([`Grid::rows_at`]): a free
    /// one, else the one of the topmost row kept (rows are asked for from the
    /// top down; a row interpolated from two others is asked for after them,
    /// which are then the two lowest).
    #[inline(always)]
    pub(super) fn slot_for(&mut self, y: u32) {
        let [a, b, c] = &mut self.rows;
        let older =
            |p: &GridRow<'_>, q: &GridRow<'_>| p.y == u32::MAX || q.y != u32::MAX && p.y < q.y;
        let ab = if older(a, b) { a } else { b };
        let oldest = if older(ab, c) { ab } else { c };
        oldest.y = y;
    }

    /// Row `y`, if it is kept.
    #[inline(always)]
    pub(super) fn row(&self, y: u32) -> Option<&GridRow<'a>> {
        self.rows.iter().find(|r| r.y == y)
    }

    /// Row `y` to write and rows `a` and `b` to read, those of them kept.
    #[inline(always)]
    pub(super) fn rows_at(
        &mut self,
        y: u32,
        a: u32,
        b: u32,
    ) -> (
        Option<&mut GridRow<'a>>,
        Option<&GridRow<'a>>,
        Option<&GridRow<'a>>,
    ) {
        let (mut w, mut ra, mut rb) = (None, None, None);
        for r in &mut self.rows {
            if r.y == y {
                w = Some(r);
            } else if r.y == a {
                ra = Some(&*r);
            } else if r.y == b {
                rb = Some(&*r);
            }
        }
        (w, ra, rb)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn px(r: u8, g: u8, b: u8, sig: u32) -> CentrePixel {
        CentrePixel {
            color: Rgb8::new(r, g, b),
            sig,
            textured: false,
        }
    }

    #[test]
    fn a_traced_pixel_takes_8_bytes_of_a_row() {
        // Three rows in 2 N cells from tiles of 30, of N below: the 16 N and
        // 24 N bytes the tile module's doc gives.
        assert_eq!(core::mem::size_of::<CentrePixel>(), 8);
    }

    #[test]
    fn a_pixel_takes_the_traced_pixels_around_it_within_the_frame() {
        let frame = (6, 5);
        assert_eq!(sparse_parents((2, 4), frame), Parents::Own);
        assert_eq!(
            sparse_parents((3, 2), frame),
            Parents::Two([(2, 2), (4, 2)])
        );
        assert_eq!(
            sparse_parents((2, 3), frame),
            Parents::Two([(2, 2), (2, 4)])
        );
        assert_eq!(
            sparse_parents((1, 1), frame),
            Parents::Four([(0, 0), (2, 0), (0, 2), (2, 2)])
        );
        // The last column (x = 5) has no neighbour at x = 6: its own ray; the
        // last row (y = 4) is even: traced.
        assert_eq!(sparse_parents((5, 2), frame), Parents::Own);
        assert_eq!(sparse_parents((5, 3), frame), Parents::Own);
        assert_eq!(
            sparse_parents((3, 4), frame),
            Parents::Two([(2, 4), (4, 4)])
        );
        // An even height: the last row is odd, with no row below.
        assert_eq!(sparse_parents((2, 3), (6, 4)), Parents::Own);
    }

    #[test]
    fn the_mean_rounds_half_up_and_the_threshold_is_inclusive() {
        let (a, b) = (px(10, 20, 30, 7), px(13, 20, 31, 7));
        // (10 + 13) / 2 = 11.5 -> 12; (30 + 31) / 2 = 30.5 -> 31.
        assert_eq!(sparse_blend([&a, &b], 3), Some(Rgb8::new(12, 20, 31)));
        assert_eq!(sparse_blend([&a, &b], 2), None);
        let (c, d) = (px(10, 21, 30, 7), px(13, 20, 30, 7));
        // Means 11.5 -> 12, 20.25 -> 20, 30.25 -> 30.
        assert_eq!(
            sparse_blend([&a, &b, &c, &d], 3),
            Some(Rgb8::new(12, 20, 30))
        );
        // Another signature (another primitive or shadow): never blended.
        let e = px(10, 20, 30, 8);
        assert_eq!(sparse_blend([&a, &e], 255), None);
        assert_eq!(sparse_blend([&a, &b, &c, &e], 255), None);
    }
}
