//! A link-time proof that no panic is reachable from tessera's rendering path on the
//! Cortex-M4F.
//!
//! The image renders every built-in scene ([`Builtin::ALL`]) through the core's
//! public tile API (`Builtin::with_scaled_scene`, `Builtin::with_baked_scene`, `Renderer::try_new`,
//! `Renderer::tile_grid`, `Renderer::render_tile` for 8, 16 and 32 pixel tiles), with
//! every sampler, and writes each pixel to a volatile sink. Its panic handler calls
//! a function that exists nowhere, [`panic_is_reachable`]: the optimiser (fat LTO,
//! opt-level 3, as the firmware test image is built) drops the handler only when no
//! panic is reachable from `main`; otherwise the link fails with
//!
//! ```text
//! rust-lld: error: undefined symbol: tessera_nopanic__a_panic_is_reachable_from_the_render_path
//! ```
//!
//! Every parameter of the renders (scene, sampler and its count or offset, depth,
//! seed, scale, tile size, frame size) is read from [`JOBS`] with volatile loads, so
//! the compiler may not assume any of their values: the proof covers the render
//! path for any settings, not only for the ones in the table. The pixels go to
//! [`SINK`] by volatile stores, so no render is optimised away.
//!
//! The proof can fail: with the line
//! `lit |= [false, true, false][usize::from(tile.width())];` (an index the
//! compiler cannot bound) added after `render_tile` in [`render`], the release
//! build stops at the link with the undefined symbol above, for both backends; so
//! it does with `let _k: u8 = [1u8, 2, 3][usize::from(coord.tx)];` added inside the
//! core's `Renderer::render_tile`; without them, it links.
//!
//! Built in CI by `tests/run-all.sh`, with the exact and the fast-math backend, and
//! run once under qemu (`mps2-an386`, semihosting): it exits with success when every
//! render returned `Ok` and lit some pixel. Only the release build is a proof; a
//! debug build keeps every overflow check and fails to link by design.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use tessera_core::builtin::Builtin;
use tessera_core::testing::BuiltinHooks as _;
use tessera_core::{
    Camera, RenderSettings, Renderer, Sampler, SceneView, Tile, TileCoord, Viewport,
    sample::SubPixel,
};

/// One render. Read with a volatile load: its values are unknown to the compiler.
#[derive(Clone, Copy)]
#[repr(C)]
struct Job {
    /// Index in [`Builtin::ALL`].
    scene: u8,
    /// See [`sampler`].
    sampler: u8,
    /// Reflection/transmission bounces.
    depth: u8,
    /// Tile size: 8, 16, else 32.
    tile: u8,
    /// Rays of the stratified (`k`) and random (`n`) samplers.
    count: u16,
    /// Frame size, pixels.
    width: u16,
    height: u16,
    /// The scene scaled by `2^scale`.
    scale: i32,
    /// Seed of the random samplers.
    seed: u32,
    /// Sub-pixel position of the offset sampler.
    offset: [f32; 2],
    /// sRGB (else linear) output.
    srgb: bool,
    /// The scene from its baked `static` tables (`Builtin::with_baked_scene`:
    /// `BakedScene::view`'s checks), else built in RAM.
    baked: bool,
}

const fn job(scene: u8, sampler: u8, count: u16, depth: u8, tile: u8, scale: i32) -> Job {
    Job {
        srgb: (scene + sampler + tile).is_multiple_of(2),
        scene,
        sampler,
        depth,
        tile,
        count,
        width: 40,
        height: 30,
        scale,
        seed: 7,
        offset: [0.25, 0.75],
        baked: false,
    }
}

/// [`job`] of the scene's baked `static` tables (its own scale).
const fn baked(scene: u8, sampler: u8, count: u16, depth: u8, tile: u8) -> Job {
    Job {
        baked: true,
        ..job(scene, sampler, count, depth, tile, 0)
    }
}

/// The renders: every built-in scene at its own settings, and every sampler, tile
/// size, encoding, a scaled scene and a baked scene somewhere (small frames, so that
/// the run under qemu stays short).
static JOBS: [Job; 11] = [
    job(0, 1, 1, 0, 16, 0), // chapter-direct, centre
    job(1, 1, 1, 1, 16, 0), // chapter-reflect, centre
    job(2, 5, 1, 0, 8, 0),  // interference, prefiltered
    job(3, 1, 1, 5, 32, 0), // showcase, centre
    job(3, 3, 2, 5, 8, 0),  // showcase, stratified 2x2
    job(1, 4, 3, 1, 32, 2), // chapter-reflect x4, random 3
    job(2, 0, 1, 0, 16, 0), // interference, corner
    job(0, 2, 1, 0, 8, -3), // chapter-direct /8, offset
    job(1, 6, 3, 1, 16, 0), // chapter-reflect, adaptive:3
    baked(3, 1, 1, 5, 16),  // showcase from flash, centre
    baked(0, 3, 2, 0, 8),   // chapter-direct from flash, stratified 2x2
];

/// Where every rendered pixel is stored (volatile).
static mut SINK: u32 = 0;

/// The sampler numbered `n` (0 corner, 1 centre, 2 offset, 3 stratified, 4 random,
/// 6 adaptive, else prefiltered).
fn sampler(n: u8, count: u16, offset: [f32; 2]) -> Result<Sampler, tessera_core::Error> {
    Ok(match n {
        6 => Sampler::adaptive(u8::try_from(count).unwrap_or(u8::MAX)),
        0 => Sampler::Corner,
        1 => Sampler::Centre,
        2 => Sampler::Offset(SubPixel::try_new(offset[0], offset[1])?),
        3 => Sampler::Stratified(u8::try_from(count).unwrap_or(u8::MAX)),
        4 => Sampler::Random(count),
        _ => Sampler::Prefiltered,
    })
}

/// What the renders gave: a core error, or no lit pixel at all.
enum Failure {
    Core,
    UnknownScene,
    Black,
}

impl From<tessera_core::Error> for Failure {
    fn from(_: tessera_core::Error) -> Self {
        Self::Core
    }
}

#[entry]
fn main() -> ! {
    let status = match render_all() {
        Ok(()) => EXIT_SUCCESS,
        Err(_) => EXIT_FAILURE,
    };
    debug::exit(status);
    loop {
        cortex_m::asm::wfi();
    }
}

/// Renders every job; `Ok` when every render succeeded and some pixel was lit.
fn render_all() -> Result<(), Failure> {
    let mut lit = false;
    for slot in &JOBS {
        // SAFETY: `slot` is a reference to an initialised, aligned `Job` in a
        // static; the volatile load only hides its value from the optimiser.
        let j = unsafe { core::ptr::read_volatile(slot) };
        let scene = *Builtin::ALL
            .get(usize::from(j.scene))
            .ok_or(Failure::UnknownScene)?;
        let settings = RenderSettings {
            sampler: sampler(j.sampler, j.count, j.offset)?,
            max_depth: j.depth,
            seed: j.seed,
            // Hidden like the rest: both encodings' loops are linked and proved.
            encoding: if j.srgb {
                tessera_core::Encoding::Srgb
            } else {
                tessera_core::Encoding::Linear
            },
        };
        let viewport = Viewport::new(j.width, j.height);
        lit |= match j.tile {
            8 => render(scene, &j, viewport, settings, &mut Tile::<8>::new()),
            16 => render(scene, &j, viewport, settings, &mut Tile::<16>::new()),
            _ => render(scene, &j, viewport, settings, &mut Tile::<32>::new()),
        }?;
    }
    if lit { Ok(()) } else { Err(Failure::Black) }
}

/// Renders one frame tile after tile into `tile`; true when some pixel is not black.
fn render<const N: usize>(
    scene: Builtin,
    job: &Job,
    viewport: Viewport,
    settings: RenderSettings,
    tile: &mut Tile<N>,
) -> Result<bool, Failure> {
    // Mutable where the instances' closure below calls it.
    #[allow(unused_mut)]
    let mut draw = |view: &SceneView<'_>, camera: &Camera| {
        let renderer = Renderer::try_new(camera, viewport, settings)?;
        let (across, down) = renderer.tile_grid(N);
        let mut lit = false;
        for ty in 0..down {
            for tx in 0..across {
                renderer.render_tile(view, TileCoord::new(tx, ty), tile, &mut ())?;
                for p in tile.pixels() {
                    lit |= (p.r | p.g | p.b) != 0;
                    let word = u32::from_le_bytes([p.r, p.g, p.b, 0]);
                    // SAFETY: a volatile store to a static that nothing else
                    // references (single thread, no interrupt uses it).
                    unsafe { core::ptr::write_volatile(&raw mut SINK, word) };
                }
            }
        }
        Ok::<bool, Failure>(lit)
    };
    // With the feature `instances`: a scene with meshes is drawn through
    // instances of them too (placed by the job's hidden numbers), so that the
    // instance search and its hits are linked and proved.
    #[cfg(feature = "instances")]
    let draw = |view: &SceneView<'_>, camera: &Camera| {
        if view.meshes().is_empty() {
            return draw(view, camera);
        }
        let mut placed: tessera_core::instance::Instances<'_, 2> =
            tessera_core::instance::Instances::new(view);
        let k = 1.0 + job.offset[0];
        let turn = job.offset[1];
        for (i, x) in [-0.5f32, 0.5].into_iter().enumerate() {
            let at = tessera_core::instance::Placement::new(
                [0.0, turn, 0.0, 1.0],
                [0.5 * k, 0.5, -0.5 * k],
                [x, 0.0, 0.0],
            );
            let mesh = u16::try_from(i % view.meshes().len()).unwrap_or(0);
            placed.push(tessera_core::instance::Instance::new(mesh, at))?;
        }
        draw(&view.with_instances(&placed)?, camera)
    };
    if job.baked {
        scene.with_baked_scene(draw)?
    } else {
        scene.with_scaled_scene(job.scale, draw)?
    }
}

/// The panic handler: a call of a function that no object defines. It survives the
/// optimiser only if some panic is reachable, and then the link fails naming it.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    // SAFETY: never executed: a program in which this call survives does not link.
    unsafe { panic_is_reachable() }
}

unsafe extern "Rust" {
    /// Defined nowhere (see the crate documentation).
    #[link_name = "tessera_nopanic__a_panic_is_reachable_from_the_render_path"]
    fn panic_is_reachable() -> !;
}
