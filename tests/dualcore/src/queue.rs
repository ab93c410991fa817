//! The frame's tiles handed out once each across cores: a stand-in with the API of
//! `tessera::tile::TileQueue` (not yet in the core), to be replaced by it.

use core::sync::atomic::{AtomicU32, Ordering};
use tessera::TileCoord;

/// Hands out each tile of an `across x down` grid exactly once, row-major, to
/// whichever core asks next.
pub struct TileQueue {
    next: AtomicU32,
    across: u16,
    down: u16,
}

impl TileQueue {
    /// A queue of the `across x down` tiles of a frame.
    pub const fn new(across: u16, down: u16) -> Self {
        Self {
            next: AtomicU32::new(0),
            across,
            down,
        }
    }

    /// The next tile nobody has taken, or `None` when all are taken.
    pub fn next(&self) -> Option<TileCoord> {
        let i = self.next.fetch_add(1, Ordering::Relaxed);
        let across = u32::from(self.across);
        if across == 0 || i >= across * u32::from(self.down) {
            return None;
        }
        Some(TileCoord::new((i % across) as u16, (i / across) as u16))
    }
}
