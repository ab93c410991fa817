//! Render settings and the tile loops they select: [`RenderSettings`], [`TileLoop`], [`Loops`].

#[cfg(doc)]
use super::Renderer;
use crate::color::Encoding;
use crate::error::Error;
use crate::error::MAX_DEPTH;
use crate::sample::Sampler;
use crate::view::SceneView;

/// How a frame is rendered.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RenderSettings {
    /// Where the rays go in each pixel.
    pub sampler: Sampler,
    /// Reflection/transmission bounces (0 = direct illumination only), at most
    /// [`MAX_DEPTH`].
    pub max_depth: u8,
    /// Seed of the random samplers.
    pub seed: u32,
    /// How the pixels' linear colours become 8 bits (default sRGB, what displays
    /// expect).
    pub encoding: Encoding,
}

impl Default for RenderSettings {
    /// Pixel centres, 3 bounces, seed 0, sRGB.
    fn default() -> Self {
        Self {
            sampler: Sampler::Centre,
            max_depth: 3,
            seed: 0,
            encoding: Encoding::Srgb,
        }
    }
}

impl RenderSettings {
    /// Checks the sampler and the depth.
    pub fn validate(&self) -> Result<(), Error> {
        self.sampler.validate()?;
        if self.max_depth > MAX_DEPTH {
            return Err(Error::DepthTooLarge {
                depth: self.max_depth,
            });
        }
        Ok(())
    }
}

/// One instantiation of a tile's pixel loop: the loop without bounces or with them
/// (mirrors or glass within the frame's depth), in one encoding, or the adaptive
/// or the sparse sampler's loop (which encode each pixel themselves). A frame's tiles all take one
/// ([`Renderer::tile_loop`]); a firmware links those it names ([`Loops`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TileLoop {
    /// No ray bounces; pixels in this encoding.
    Direct(Encoding),
    /// Rays bounce; pixels in this encoding.
    Bounces(Encoding),
    /// The adaptive sampler, without or with bounces.
    Adaptive {
        /// Whether rays bounce.
        bounces: bool,
    },
    /// The sparse sampler, without or with bounces.
    Sparse {
        /// Whether rays bounce.
        bounces: bool,
    },
}

impl TileLoop {
    /// Every tile loop.
    pub const ALL: [Self; 8] = [
        Self::Direct(Encoding::Srgb),
        Self::Direct(Encoding::Linear),
        Self::Bounces(Encoding::Srgb),
        Self::Bounces(Encoding::Linear),
        Self::Adaptive { bounces: false },
        Self::Adaptive { bounces: true },
        Self::Sparse { bounces: false },
        Self::Sparse { bounces: true },
    ];

    /// The loop a frame's tiles take for `scene` with `settings` (what
    /// [`Renderer::tile_loop`] gives, and what `tessera bake` names in a baked
    /// scene's `SceneLoops`): the adaptive or the sparse sampler's, with bounces
    /// when rays reach a mirror or glass within the settings' depth; else the
    /// loop with bounces or without, in the settings' encoding.
    #[must_use]
    pub fn of(settings: &RenderSettings, scene: &SceneView<'_>) -> Self {
        let bounces = scene.depth(settings.max_depth) > 0;
        match (settings.sampler, bounces) {
            (Sampler::Adaptive { .. }, bounces) => Self::Adaptive { bounces },
            (Sampler::Sparse { .. }, bounces) => Self::Sparse { bounces },
            (_, false) => Self::Direct(settings.encoding),
            (_, true) => Self::Bounces(settings.encoding),
        }
    }
}

/// Which tile loops a firmware links ([`Renderer::render_tile_in`],
/// [`crate::display::Drawing::linking`]). The render settings are values, so
/// [`Renderer::render_tile`] links every [`TileLoop`] ([`AllLoops`]); a firmware
/// whose settings are fixed names the ones it needs and the others are left out
/// of the image (the board example's README, `examples/blackpill-st7789`,
/// measures the flash this saves). A render whose settings need a loop left out
/// is refused ([`Error::NotLinked`]), never drawn wrong: the check
/// ([`Renderer::check_loops`]) and the tile's choice of loop ask the same
/// [`Loops::links`].
///
/// ```
/// use tessera_core::{builtin, Encoding, tile::Loops, RenderSettings, Tile, TileCoord, tile::TileLoop, Viewport};
///
/// /// Direct light only, sRGB, no adaptive sampling.
/// enum DirectSrgb {}
/// impl Loops for DirectSrgb {
///     fn links(tile_loop: TileLoop) -> bool {
///         tile_loop == TileLoop::Direct(Encoding::Srgb)
///     }
/// }
///
/// let scene = builtin::chapter_direct()?;
/// let settings = RenderSettings { max_depth: 0, ..RenderSettings::default() };
/// let renderer = scene.renderer(Viewport::new(32, 32), settings)?;
/// let mut tile = Tile::<16>::new();
/// renderer.render_tile_in::<DirectSrgb, 16, _, _>(&scene.view(), TileCoord::new(0, 0), &mut tile, &mut ())?;
/// # Ok::<(), tessera_core::Error>(())
/// ```
pub trait Loops {
    /// Whether this set links `tile_loop`. Asked with constants where the loops
    /// are instantiated, so a loop it refuses is not compiled in: keep it a plain
    /// comparison (`==`, `matches!`).
    fn links(tile_loop: TileLoop) -> bool;
}

/// Every tile loop: what [`Renderer::render_tile`] links.
#[derive(Clone, Copy, Debug)]
pub enum AllLoops {}

impl Loops for AllLoops {
    #[inline(always)]
    fn links(_: TileLoop) -> bool {
        true
    }
}

/// Whether `L` links a loop with bounces (`bounces`) or without, in some form:
/// what the one-ray preview ([`Renderer::preview_color`]) needs.
#[inline(always)]
pub(super) fn links_any<L: Loops>(bounces: bool) -> bool {
    use Encoding::{Linear, Srgb};
    if bounces {
        L::links(TileLoop::Bounces(Srgb))
            || L::links(TileLoop::Bounces(Linear))
            || L::links(TileLoop::Adaptive { bounces: true })
            || L::links(TileLoop::Sparse { bounces: true })
    } else {
        L::links(TileLoop::Direct(Srgb))
            || L::links(TileLoop::Direct(Linear))
            || L::links(TileLoop::Adaptive { bounces: false })
            || L::links(TileLoop::Sparse { bounces: false })
    }
}
