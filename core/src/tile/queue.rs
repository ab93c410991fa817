//! Sharing a frame's tiles between cores: [`TileQueue`] (atomic) and [`Interleave`].

#[cfg(doc)]
use super::Renderer;
use super::buffer::TileCoord;

/// Hands out a frame's tiles to several cores, each tile once: each core loops
/// `while let Some(c) = queue.next() { renderer.render_tile(.., c, &mut its_tile,
/// ..)?; /* send it */ }` with its own tile buffer, and a core that finishes its
/// tile early takes the next one, so the cores stay busy to the end of the frame
/// whatever each tile costs. Which core renders a tile changes none of its pixels
/// (a tile is a function of the scene, the renderer and its coordinate), so the
/// image is the one core's, byte for byte. Tiles go out row after row of tiles.
///
/// One load and one `fetch_add` a tile on an `AtomicU32` (cores with atomic read-modify-write:
/// Armv7-M, Armv8-M Mainline, RISC-V with the A extension); on cores without it
/// (Armv6-M, rv32imc) use [`Interleave`]. A `static` queue is shared by both
/// cores of a dual-core part (RP2350); [`TileQueue::reset`] starts the next frame
/// once every core has stopped taking tiles.
#[cfg(target_has_atomic = "32")]
#[derive(Debug)]
pub struct TileQueue {
    pub(super) next: core::sync::atomic::AtomicU32,
    pub(super) across: u16,
    pub(super) down: u16,
}

#[cfg(target_has_atomic = "32")]
impl TileQueue {
    /// The queue of a frame of `across x down` tiles ([`Renderer::tile_grid`]).
    #[must_use]
    pub const fn new(across: u16, down: u16) -> Self {
        Self {
            next: core::sync::atomic::AtomicU32::new(0),
            across,
            down,
        }
    }

    /// The next tile nobody has taken, or `None` when every tile is taken (and
    /// ever after, however often it is asked).
    pub fn next(&self) -> Option<TileCoord> {
        use core::sync::atomic::Ordering;
        let total = u32::from(self.across) * u32::from(self.down);
        // Relaxed: the counter orders nothing else; the pixels a core writes are
        // its own until it hands them over by other means. Once past the end it
        // is left there (a load first, so that it cannot wrap after 2^32 asks).
        if self.next.load(Ordering::Relaxed) >= total {
            return None;
        }
        let k = self.next.fetch_add(1, Ordering::Relaxed);
        (k < total).then(|| tile_at(k, self.across))
    }

    /// Starts the frame over: every tile is handed out again. Call it when no core
    /// is taking tiles. The store is relaxed: the other cores see it once the
    /// caller hands them the new frame with a release that they acquire (the
    /// handshake that tells them a frame is ready); a core that looks earlier
    /// finds the queue empty, which costs it the frame's tiles, not pixels.
    pub fn reset(&self) {
        self.next.store(0, core::sync::atomic::Ordering::Relaxed);
    }
}

/// Tile `k` of a frame `across` tiles wide, row after row.
pub(super) fn tile_at(k: u32, across: u16) -> TileCoord {
    let across = u32::from(across).max(1);
    // Both fit in u16: k < across * down, each at most u16::MAX.
    TileCoord::new(
        u16::try_from(k % across).unwrap_or(u16::MAX),
        u16::try_from(k / across).unwrap_or(u16::MAX),
    )
}

/// A frame's tiles shared by `cores` cores without atomics: core `core` takes
/// tiles `core`, `core + cores`, `core + 2 cores`, ... row after row (for cores
/// without atomic read-modify-write, where [`TileQueue`] is not available). Each
/// tile goes to one core; the image is one core's, byte for byte. The split is
/// fixed, so a core whose tiles cost more finishes later.
#[derive(Clone, Debug)]
pub struct Interleave {
    pub(super) k: u32,
    pub(super) step: u32,
    pub(super) total: u32,
    pub(super) across: u16,
}

impl Interleave {
    /// The tiles of core `core` (0-based) of `cores` in a frame of `across x
    /// down` tiles; none when `core >= cores`.
    #[must_use]
    pub fn new(core: u32, cores: u32, across: u16, down: u16) -> Self {
        let total = u32::from(across) * u32::from(down);
        Self {
            k: if core < cores { core } else { total },
            step: cores.max(1),
            total,
            across,
        }
    }
}

impl Iterator for Interleave {
    type Item = TileCoord;
    fn next(&mut self) -> Option<TileCoord> {
        if self.k >= self.total {
            return None;
        }
        let c = tile_at(self.k, self.across);
        self.k = self.k.saturating_add(self.step);
        Some(c)
    }
}
