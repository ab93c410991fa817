//! The pixel loop of one tile (`Pass`): fill, pixel, sample, and the adaptive and sparse fills.

use super::adaptive::{CentrePixel, CentreSample, NEIGHBOURS, Window};
use super::buffer::TilePixel;
use super::renderer::Renderer;
use super::sparse::{Grid, Parents, sparse_blend, sparse_parents};
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
    /// tile's columns and the apron's, kept two rows at a time ([`Grid`]); then
    /// each pixel its traced colour, the mean of its traced neighbours
    /// ([`sparse_blend`]), or its own ray.
    ///
    /// Out of line and small: its cells are on its own frame, not on that of
    /// the tile loop that calls it, whose other loops then do not carry them.
    #[inline(never)]
    pub(super) fn fill_sparse<const N: usize, P: TilePixel, const BOUNCES: bool>(
        self,
        pixels: &mut [P],
        area: (u32, u32, usize, usize),
        threshold: u8,
    ) where
        C: RayCounter,
    {
        // A row of the grid holds at most N / 2 + 2 traced pixels: N of them
        // from 4 on, 4 below.
        let mut big = [[CentrePixel::default(); N]; 2];
        let mut small = [[CentrePixel::default(); 4]; 2];
        let ([b0, b1], [s0, s1]) = (&mut big, &mut small);
        let cells: [&mut [CentrePixel]; 2] = if N >= 4 { [b0, b1] } else { [s0, s1] };
        self.fill_sparse_in::<P, BOUNCES>(pixels, area, threshold, Grid::new(cells));
    }

    /// [`Pass::fill_sparse`] in the rows of `grid`: one copy whatever the tile
    /// size.
    #[inline(never)]
    pub(super) fn fill_sparse_in<P: TilePixel, const BOUNCES: bool>(
        mut self,
        pixels: &mut [P],
        (x0, y0, tw, th): (u32, u32, usize, usize),
        threshold: u8,
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
        // The even columns of [x0 - 1, x0 + tw] within the frame.
        let columns = (x0 & !1, (x0 + tw as u32).min(frame.0.saturating_sub(1)));
        for (j, row) in pixels.chunks_mut(tw.max(1)).enumerate() {
            let live = if j < th { tw } else { 0 };
            let Some((live, rest)) = row.split_at_mut_checked(live) else {
                continue;
            };
            let y = y0 + j as u32;
            if !live.is_empty() {
                for g in [y & !1, (y | 1) + 1] {
                    if g < frame.1 && (g == y || y % 2 == 1) && !grid.holds(g) {
                        let slot = grid.slot_for(g);
                        for (k, gx) in (columns.0..=columns.1).step_by(2).enumerate() {
                            let c = self.centre::<BOUNCES>(gx, g);
                            slot.set(k, c.encoded(encoding));
                        }
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
                let k = ((x - columns.0) / 2) as usize;
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

    /// The sparse sampler's linear colour of pixel `(x, y)` on its own: the rule
    /// of [`Pass::fill_sparse`], its traced neighbours traced here.
    pub(super) fn sparse_pixel(&mut self, x: u32, y: u32, threshold: u8) -> Color
    where
        C: RayCounter,
    {
        let vp = self.renderer.viewport();
        let frame = (u32::from(vp.width), u32::from(vp.height));
        let encoding = self.renderer.settings.encoding;
        let traced =
            |pass: &mut Self, (gx, gy): (u32, u32)| pass.centre::<true>(gx, gy).encoded(encoding);
        let blended = match sparse_parents((x, y), frame) {
            Parents::Own => None,
            Parents::Two(at) => sparse_blend(at.map(|a| traced(self, a)).each_ref(), threshold),
            Parents::Four(at) => sparse_blend(at.map(|a| traced(self, a)).each_ref(), threshold),
        };
        match blended {
            Some(rgb) => encoding.decode(rgb),
            None => self.pixel::<true>(x, y),
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
