//! The pixel loop of one tile (`Pass`): fill, pixel, sample, and the adaptive and sparse fills.

use super::adaptive::{CentrePixel, CentreSample, NEIGHBOURS, Window};
use super::buffer::TilePixel;
use super::renderer::Renderer;
use super::sparse::{
    Grid, Parents, between_coarse_rows, coarse_blend, sparse_blend, sparse_parents,
};
use crate::color::{Color, Rgb8};
use crate::cull::Picks;
use crate::prefilter::Footprint;
use crate::sample::{PixelHash, Sampler, stratified};
use crate::shade::{CameraRay, Observer, RayCounter, Signature, trace_with};
use crate::view::SceneView;

/// What the pixels of one tile share: the renderer, the scene, the tile's
/// candidates (`picks`), the depth rays bounce to and the counter. Its methods
/// are the pixel loop in plain form: a pixel's samples ([`Pass::pixel`]), each a
/// camera ray ([`CameraBasis::ray`]) traced and shaded ([`Pass::sample`]), their
/// mean encoded into the tile's pixel type ([`Pass::fill`]); the loop's
/// instantiations are made in one place, [`Renderer::render_tile_in`]'s `run!`.
pub(super) struct Pass<'a, C> {
    pub(super) renderer: &'a Renderer,
    pub(super) scene: &'a SceneView<'a>,
    pub(super) picks: &'a Picks<'a>,
    pub(super) depth: u8,
    pub(super) count: &'a mut C,
}

impl<'a, C: Observer> Pass<'a, C> {
    #[inline(always)]
    pub(super) fn new(
        renderer: &'a Renderer,
        scene: &'a SceneView<'a>,
        picks: &'a Picks<'a>,
        depth: u8,
        count: &'a mut C,
    ) -> Self {
        Self {
            renderer,
            scene,
            picks,
            depth,
            count,
        }
    }

    /// Fills a tile buffer's first `th` rows of `tw` pixels (`(x0, y0)` to `(x0 +
    /// tw, y0 + th)` of the frame) with each pixel's colour, encoded (`SRGB`); the
    /// rest of the buffer black. Out of line: the loops with and without bounces then each
    /// have their own stack frame, and the larger one (the inlined shader of
    /// the loop without bounces) does not add to the stack of the other. The
    /// rows are a slice: one copy whatever the tile size.
    #[inline(never)]
    pub(super) fn fill<P: TilePixel, const BOUNCES: bool, const SRGB: bool>(
        mut self,
        pixels: &mut [P],
        (x0, y0, tw, th): (u32, u32, usize, usize),
    ) {
        let dither = self.renderer.dither;
        for (j, row) in pixels.chunks_mut(tw.max(1)).enumerate() {
            let live = if j < th { tw } else { 0 };
            let Some((live, rest)) = row.split_at_mut_checked(live) else {
                continue;
            };
            for (i, px) in live.iter_mut().enumerate() {
                let (x, y) = (x0 + i as u32, y0 + j as u32);
                let rgb = encode::<SRGB>(self.pixel::<BOUNCES>(x, y));
                *px = P::from_rgb8(rgb, x, y, dither);
            }
            rest.fill(P::BLACK);
        }
    }

    /// [`Pass::fill`] for the adaptive sampler: the centre rays of the tile and of
    /// a one-pixel apron around it (where the frame has pixels), row after row,
    /// then each pixel either its centre colour or, where it differs from a
    /// neighbour's ([`CentrePixel::differs`]), its stratified samples. Rows are decided
    /// as soon as the row below them is traced: three rows of centre samples are
    /// kept ([`Window`]), not the tile's.
    #[inline(never)]
    pub(super) fn fill_adaptive<const N: usize, P: TilePixel, const BOUNCES: bool>(
        mut self,
        pixels: &mut [P],
        (x0, y0, tw, th): (u32, u32, usize, usize),
        threshold: u8,
    ) where
        C: RayCounter,
    {
        let (vp, settings, dither) = (
            self.renderer.viewport(),
            self.renderer.settings,
            self.renderer.dither,
        );
        let (w, h) = (i64::from(vp.width), i64::from(vp.height));
        let (x0i, y0i) = (i64::from(x0), i64::from(y0));
        let mut window = Window::<N>::new();
        // Row `r` of the tile (-1 and `th`: the apron) into the window.
        let trace_row = |pass: &mut Self, r: i64, window: &mut Window<N>| {
            let y = y0i + r;
            if !(0..h).contains(&y) {
                return;
            }
            for i in -1..=tw as i64 {
                let x = x0i + i;
                if (0..w).contains(&x) {
                    let c = pass.centre::<BOUNCES>(x as u32, y as u32);
                    window.set(r, i, c.encoded(settings.encoding));
                }
            }
        };
        trace_row(&mut self, -1, &mut window);
        trace_row(&mut self, 0, &mut window);
        for (j, row) in pixels.chunks_mut(tw.max(1)).enumerate() {
            let live = if j < th { tw } else { 0 };
            let Some((live, rest)) = row.split_at_mut_checked(live) else {
                continue;
            };
            let r = j as i64;
            if !live.is_empty() {
                trace_row(&mut self, r + 1, &mut window);
            }
            for (i, px) in live.iter_mut().enumerate() {
                let (x, y) = (x0i + i as i64, y0i + r);
                let own = window.get(r, i as i64);
                let mut refine = false;
                for (dx, dy) in NEIGHBOURS {
                    let (nx, ny) = (x + i64::from(dx), y + i64::from(dy));
                    if (0..w).contains(&nx) && (0..h).contains(&ny) {
                        let n = window.get(r + i64::from(dy), i as i64 + i64::from(dx));
                        refine |= own.differs(n, threshold);
                    }
                }
                let rgb = if refine {
                    settings
                        .encoding
                        .encode(self.pixel::<BOUNCES>(x as u32, y as u32))
                } else {
                    own.color
                };
                *px = P::from_rgb8(rgb, x as u32, y as u32, dither);
            }
            rest.fill(P::BLACK);
        }
    }

    /// [`Pass::fill`] for the sparse sampler: row after row, the traced pixels
    /// (both coordinates even, [`Sampler::Sparse`]) of the rows the row needs
    /// (its own when even, the one above and the one below when odd), over the
    /// tile's columns and the apron's, kept a few rows at a time ([`Grid`],
    /// [`Pass::grid_row`]); then each pixel its traced colour, the mean of its
    /// traced neighbours ([`sparse_blend`]), or its own ray. With `coarse`,
    /// the even pixels come from the grid of spacing 4 first.
    ///
    /// Out of line and small: its cells are on its own frame, not on that of
    /// the tile loop that calls it, whose other loops then do not carry them.
    #[inline(never)]
    pub(super) fn fill_sparse<const N: usize, P: TilePixel, const BOUNCES: bool>(
        self,
        pixels: &mut [P],
        area: (u32, u32, usize, usize),
        (threshold, coarse): (u8, bool),
    ) where
        C: RayCounter,
    {
        // A row of the grid holds at most N / 2 + 5 traced pixels (N / 2 + 1
        // for a tile of a multiple of 4): from 30 on, three fit in 2 N (as
        // for a tile of 32, whose two rows of spacing 2 take as much);
        // below, three rows of N from 10, of 10 below. Each branch's cells are
        // its own: the other, dead for this N, takes no stack.
        if N >= 30 {
            let mut flat = [[CentrePixel::default(); N]; 2];
            let (a, rest) = flat.as_flattened_mut().split_at_mut(2 * N / 3);
            let (b, c) = rest.split_at_mut(2 * N / 3);
            let grid = Grid::new([a, b, c]);
            return self.fill_sparse_in::<P, BOUNCES>(pixels, area, (threshold, coarse), grid);
        }
        let mut big = [[CentrePixel::default(); N]; 3];
        let mut small = [[CentrePixel::default(); 10]; 3];
        let ([b0, b1, b2], [s0, s1, s2]) = (&mut big, &mut small);
        let cells: [&mut [CentrePixel]; 3] = if N >= 10 { [b0, b1, b2] } else { [s0, s1, s2] };
        self.fill_sparse_in::<P, BOUNCES>(pixels, area, (threshold, coarse), Grid::new(cells));
    }

    /// [`Pass::fill_sparse`] in the rows of `grid`: one copy whatever the tile
    /// size.
    #[inline(never)]
    pub(super) fn fill_sparse_in<P: TilePixel, const BOUNCES: bool>(
        mut self,
        pixels: &mut [P],
        (x0, y0, tw, th): (u32, u32, usize, usize),
        (threshold, coarse): (u8, bool),
        mut grid: Grid<'_>,
    ) where
        C: RayCounter,
    {
        let (vp, encoding, dither) = (
            self.renderer.viewport(),
            self.renderer.settings.encoding,
            self.renderer.dither,
        );
        let frame = (u32::from(vp.width), u32::from(vp.height));
        let columns = sparse_columns(x0, tw, frame.0, coarse);
        for (j, row) in pixels.chunks_mut(tw.max(1)).enumerate() {
            let live = if j < th { tw } else { 0 };
            let Some((live, rest)) = row.split_at_mut_checked(live) else {
                continue;
            };
            let y = y0 + j as u32;
            if !live.is_empty() {
                for g in [y & !1, (y | 1) + 1] {
                    if g < frame.1 && (g == y || y % 2 == 1) && !grid.holds(g) {
                        // A level-1 row's coarse rows first.
                        if coarse && between_coarse_rows(g, frame.1) {
                            for r in [g - 2, g + 2] {
                                if !grid.holds(r) {
                                    self.grid_row::<BOUNCES>(
                                        &mut grid,
                                        r,
                                        columns,
                                        (threshold, coarse),
                                    );
                                }
                            }
                        }
                        self.grid_row::<BOUNCES>(&mut grid, g, columns, (threshold, coarse));
                    }
                }
            }
            // The traced rows this row takes its pixels from: its own (even), or
            // the one above and, but on the frame's last row, the one below (odd).
            let odd_y = y % 2 == 1;
            let rows = match (grid.row(y & !1), grid.row(y + 1)) {
                (Some(u), _) if !odd_y => Some((u, u)),
                (Some(u), Some(l)) => Some((u, l)),
                // The frame's last row, odd: no row below.
                _ => None,
            };
            for (i, px) in live.iter_mut().enumerate() {
                let x = x0 + i as u32;
                let k = ((x - columns.lo) / 2) as usize;
                let odd_x = x % 2 == 1;
                let mean = match rows {
                    // A neighbour beyond the frame.
                    _ if odd_x && x + 1 >= frame.0 => None,
                    None => None,
                    Some((u, l)) => match (odd_x, odd_y) {
                        (false, false) => Some(u.at(k).color),
                        (true, false) => sparse_blend([u.at(k), u.at(k + 1)], threshold),
                        (false, true) => sparse_blend([u.at(k), l.at(k)], threshold),
                        (true, true) => {
                            sparse_blend([u.at(k), u.at(k + 1), l.at(k), l.at(k + 1)], threshold)
                        }
                    },
                };
                let rgb = match mean {
                    Some(rgb) => rgb,
                    // Its own ray, the prefiltered one (no signature needed).
                    None => encoding.encode(self.pixel::<BOUNCES>(x, y)),
                };
                *px = P::from_rgb8(rgb, x, y, dither);
            }
            rest.fill(P::BLACK);
        }
    }

    /// Traces even row `g` of the frame into `grid` over `columns`
    /// ([`sparse_columns`]): with spacing 2 (or on a frame's row with no
    /// coarse row below it) every even pixel's ray; with `coarse`, the coarse
    /// pixels' rays (both coordinates multiples of 4) and each other even
    /// pixel of the tile's columns the mean of its coarse neighbours
    /// ([`coarse_blend`]) or its own ray; a row between two coarse rows takes
    /// them from `grid` (traced before it). Out of line: one copy for the
    /// three calls of the tile loop.
    #[inline(never)]
    fn grid_row<const BOUNCES: bool>(
        &mut self,
        grid: &mut Grid<'_>,
        g: u32,
        columns: SparseColumns,
        (threshold, coarse): (u8, bool),
    ) where
        C: RayCounter,
    {
        let vp = self.renderer.viewport();
        let (w, h) = (u32::from(vp.width), u32::from(vp.height));
        let encoding = self.renderer.settings.encoding;
        let level1_row = coarse && between_coarse_rows(g, h);
        grid.slot_for(g);
        let (Some(row), up, down) = grid.rows_at(g, g.wrapping_sub(2), g + 2) else {
            return;
        };
        // The columns the tile needs, `k` counted from the row's first.
        let needed = (columns.first..=columns.last)
            .step_by(2)
            .enumerate()
            .map(|(k, gx)| (k + ((columns.first - columns.lo) / 2) as usize, gx));
        if !coarse || g % 4 == 2 && !level1_row {
            // Spacing 2, or a level-1 row with no coarse row below: every
            // needed pixel's ray.
            for (k, gx) in needed {
                row.set(k, self.centre::<BOUNCES>(gx, g).encoded(encoding));
            }
            return;
        }
        let coarse_row = g.is_multiple_of(4);
        if coarse_row {
            // The coarse pixels first: the others between them take them.
            for (k, gx) in (columns.lo..=columns.hi).step_by(2).enumerate() {
                if gx.is_multiple_of(4) {
                    row.set(k, self.centre::<BOUNCES>(gx, g).encoded(encoding));
                }
            }
        }
        for (k, gx) in needed {
            let coarse_x = gx.is_multiple_of(4);
            if coarse_row && coarse_x {
                continue;
            }
            // A level-1 pixel: between two coarse pixels of its row, its
            // column, or four diagonally; its own ray where one lies beyond
            // the frame.
            let blend = match (up, down) {
                _ if !coarse_x && gx + 2 >= w => None,
                _ if coarse_row => coarse_blend([row.at(k - 1), row.at(k + 1)], threshold),
                (Some(u), Some(l)) if coarse_x => coarse_blend([u.at(k), l.at(k)], threshold),
                (Some(u), Some(l)) => coarse_blend(
                    [u.at(k - 1), u.at(k + 1), l.at(k - 1), l.at(k + 1)],
                    threshold,
                ),
                _ => None,
            };
            let s = blend.unwrap_or_else(|| self.centre::<BOUNCES>(gx, g).encoded(encoding));
            row.set(k, s);
        }
    }

    /// The sparse sampler's linear colour of pixel `(x, y)` on its own: the rule
    /// of [`Pass::fill_sparse`], its traced neighbours traced here.
    pub(super) fn sparse_pixel(&mut self, x: u32, y: u32, (threshold, coarse): (u8, bool)) -> Color
    where
        C: RayCounter,
    {
        let vp = self.renderer.viewport();
        let frame = (u32::from(vp.width), u32::from(vp.height));
        let even = |pass: &mut Self, at: (u32, u32)| {
            let coarse = coarse.then(|| pass.coarse_mean(at, threshold)).flatten();
            coarse.unwrap_or_else(|| pass.traced(at))
        };
        let blended = match sparse_parents((x, y), frame) {
            // An even pixel: its own ray, or the mean of its coarse neighbours.
            Parents::Own if x.is_multiple_of(2) && y.is_multiple_of(2) && coarse => {
                self.coarse_mean((x, y), threshold).map(|c| c.color)
            }
            Parents::Own => None,
            Parents::Two(at) => sparse_blend(at.map(|a| even(self, a)).each_ref(), threshold),
            Parents::Four(at) => sparse_blend(at.map(|a| even(self, a)).each_ref(), threshold),
        };
        match blended {
            Some(rgb) => self.renderer.settings.encoding.decode(rgb),
            None => self.pixel::<true>(x, y),
        }
    }

    /// The 8-bit pixel and signature of even pixel `(x, y)`'s own ray.
    fn traced(&mut self, (x, y): (u32, u32)) -> CentrePixel
    where
        C: RayCounter,
    {
        let encoding = self.renderer.settings.encoding;
        self.centre::<true>(x, y).encoded(encoding)
    }

    /// Even pixel `(x, y)` as [`Pass::grid_row`] interpolates it from the
    /// coarse grid (`None`: a coarse pixel, or one that takes its own ray).
    fn coarse_mean(&mut self, (x, y): (u32, u32), threshold: u8) -> Option<CentrePixel>
    where
        C: RayCounter,
    {
        let vp = self.renderer.viewport();
        // The even pixels are a frame of half the size, whose own even pixels
        // are the coarse ones.
        let half = (
            u32::from(vp.width).div_ceil(2),
            u32::from(vp.height).div_ceil(2),
        );
        let twice = |(a, b): (u32, u32)| (2 * a, 2 * b);
        match sparse_parents((x / 2, y / 2), half) {
            Parents::Own => None,
            Parents::Two(at) => {
                coarse_blend(at.map(|a| self.traced(twice(a))).each_ref(), threshold)
            }
            Parents::Four(at) => {
                coarse_blend(at.map(|a| self.traced(twice(a))).each_ref(), threshold)
            }
        }
    }

    /// The colour of pixel `(x, y)`: the mean of its samples, each one call of
    /// [`Renderer::sample`]. The single-sample samplers trace one ray and return
    /// its colour (`(0 + c) * 1 = c`); the stratified and random samplers hash the
    /// pixel once and the sample index per sample.
    #[inline(always)]
    pub(super) fn pixel<const BOUNCES: bool>(&mut self, x: u32, y: u32) -> Color {
        let r = self.renderer;
        let (px, py) = (x as f32, y as f32);
        // One ray: no loop, no average (`(0 + c) * 1 = c`).
        if let Some((dx, dy)) = r.single {
            let footprint = matches!(
                r.settings.sampler,
                Sampler::Prefiltered | Sampler::Sparse { .. }
            )
            .then(|| Footprint::new(&r.basis, px, py));
            let (at, footprint) = ((px + dx, py + dy), footprint.as_ref());
            return r.sample::<C, BOUNCES>(
                self.scene, self.picks, self.depth, at, footprint, self.count,
            );
        }
        let hash = PixelHash::new(x, y, r.settings.seed);
        let mut sum = Color::BLACK;
        // The stratified sampler's cell (cx, cy) of sample i = cy k + cx.
        let (mut cx, mut cy) = (0u32, 0u32);
        for i in 0..r.samples {
            let (dx, dy) = match r.settings.sampler {
                Sampler::Stratified(k) | Sampler::Adaptive { k, .. } => {
                    let d = stratified(hash, i, (cx, cy), r.stratum);
                    cx += 1;
                    if cx == u32::from(k) {
                        (cx, cy) = (0, cy + 1);
                    }
                    d
                }
                _ => hash.pair(i),
            };
            let at = (px + dx, py + dy);
            sum += r.sample::<C, BOUNCES>(self.scene, self.picks, self.depth, at, None, self.count);
        }
        sum * r.inv_count
    }

    /// The adaptive sampler's centre sample of pixel `(x, y)`: its colour and the
    /// signature of its ray tree.
    #[inline(always)]
    pub(super) fn centre<const BOUNCES: bool>(&mut self, x: u32, y: u32) -> CentreSample
    where
        C: RayCounter,
    {
        let mut signed = Signature::new(&mut *self.count);
        let (px, py) = (x as f32, y as f32);
        let footprint = Footprint::new(&self.renderer.basis, px, py);
        let at = (px + 0.5, py + 0.5);
        let (scene, picks, depth) = (self.scene, self.picks, self.depth);
        let color = self.renderer.sample::<_, BOUNCES>(
            scene,
            picks,
            depth,
            at,
            Some(&footprint),
            &mut signed,
        );
        CentreSample {
            color,
            sig: signed.hash,
            textured: signed.textured,
        }
    }
}

impl Renderer {
    /// The colour the camera ray through the viewport point `at` brings back: the
    /// pixel loop's one call per sample. Out of line: inlined, the pixel loop's
    /// registers spill around the shader.
    #[inline(never)]
    pub(super) fn sample<C: Observer, const BOUNCES: bool>(
        &self,
        scene: &SceneView<'_>,
        picks: &Picks<'_>,
        depth: u8,
        (x, y): (f32, f32),
        footprint: Option<&Footprint<'_>>,
        count: &mut C,
    ) -> Color {
        let (ray, t_max) = self.basis.ray(x, y);
        let cam = CameraRay {
            ray,
            t_max,
            footprint,
        };
        trace_with::<C, BOUNCES>(scene, cam, depth, picks, count)
    }
}

/// `c` in 8 bits, sRGB-encoded or linear (a tile loop's constant).
#[inline(always)]
pub(super) fn encode<const SRGB: bool>(c: Color) -> Rgb8 {
    if SRGB { c.to_srgb8() } else { c.to_rgb8() }
}

/// The even columns a sparse tile's rows hold: from `lo` to `hi`, of which the
/// tile's pixels need those from `first` to `last` (the even columns from
/// `x0 - 1` to `x0 + tw` within the frame); with spacing 4, `lo` and `hi`
/// reach out to the coarse columns around those (within the frame).
#[derive(Clone, Copy)]
pub(super) struct SparseColumns {
    pub(super) lo: u32,
    pub(super) first: u32,
    pub(super) last: u32,
    pub(super) hi: u32,
}

/// The [`SparseColumns`] of a tile of `tw` columns from `x0` in a frame `w`
/// wide.
#[inline(always)]
pub(super) fn sparse_columns(x0: u32, tw: usize, w: u32, coarse: bool) -> SparseColumns {
    let first = x0 & !1;
    let last = (x0 + tw as u32).min(w.saturating_sub(1)) & !1;
    if coarse {
        SparseColumns {
            lo: first & !3,
            first,
            last,
            hi: ((last + 2) & !3).min(w.saturating_sub(1) & !1),
        }
    } else {
        SparseColumns {
            lo: first,
            first,
            last,
            hi: last,
        }
    }
}
