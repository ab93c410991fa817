//! Firmware test image of tessera, for the cores with an FPU that qemu emulates:
//! `mps2-an386` (Cortex-M4F), `mps2-an500` (Cortex-M7), `mps2-an505` (Cortex-M33),
//! `mps3-an547` (Cortex-M55) and `virt` (rv32imafc); and for two without one:
//! Armv6-M (a Cortex-M0/M0+, run on `mps2-an385`'s Cortex-M3) and rv32imc (`virt`
//! without F and D), floating point in software. One source; the core's clock,
//! fault handlers and runtime are chosen by target (`clock`, `faults`: on RISC-V
//! the files under `riscv/`), the memory map by build.rs.
//!
//! Protocol (all I/O over semihosting, files relative to qemu's working directory):
//! 1. reads the run list `tessera-fw.runs` (see [`runs`]; the file names and limits
//!    are in [`protocol`], shared with the host-side harness);
//! 2. prints `calibration instructions=<n> ticks=<t>` (a loop of known length),
//!    and on RISC-V without an FPU (`riscv32imc`) `misa=<hex>` (the CPU's
//!    extensions: bit 5 is F, bit 3 D);
//! 3. for run `i` (counted over non-blank, non-comment lines, from 0) renders the
//!    built-in scene tile after tile, row-major, into a static tile buffer of the
//!    run's size, and writes the frame to `tessera-fw-<i>.rgb`: the image's pixels
//!    in row-major image order, 3 bytes (R, G, B) each, no header (each tile row is
//!    written at its offset with SYS_SEEK);
//! 4. prints `run <i> scene=<name> sampler=<s> depth=<d> tile=<n> size=<w>x<h>
//!    seed=<seed> ticks=<t> instructions=<t*k> pixels=<w*h> stack=<bytes>
//!    base=<bytes> render=<bytes>`, where ticks are clock ticks (SysTick on Arm,
//!    `minstret` on RISC-V) spent inside `render_tile` only, `k` the board's
//!    instructions per tick ([`clock::RATE`]: 40 on mps2-an386), `stack` is the peak stack of the whole firmware during
//!    the run (from the top of RAM), `base` the stack in use when the run started
//!    (the harness) and `render` the peak below the tile loop's stack pointer (what
//!    `render_tile` itself needs);
//!    and after a run of a baked scene (`baked-<name>`) `setup <i> view=<n>
//!    lights=<n> spheres=<n> planes=<n>`: the instructions of a frame's set-up
//!    ([`setup`]);
//! 5. prints `stack peak=<max over runs> available=<bytes> ram=<bytes>` and
//!    `done runs=<n>`, then exits with success.
//!
//! Any error prints `error: ...`, a panic `panic: ...` and a fault `hard fault: ...`,
//! and qemu exits with a failure status.
//!
//! Profiling: each `render_tile` call is bracketed by calls of the empty marker
//! functions `tessera_profile_begin` and `tessera_profile_end` (inside the SysTick
//! reads); the instruction-profiling qemu plugin (`tests/profiler/`) counts between
//! them.
#![no_std]
#![no_main]

#[cfg_attr(target_arch = "riscv32", path = "riscv/clock.rs")]
mod clock;
#[cfg_attr(target_arch = "riscv32", path = "riscv/faults.rs")]
mod faults;
mod markers;
// The tick rates of the other boards are the harness's.
#[allow(dead_code)]
mod protocol;
mod runs;
mod semihost;
mod stack;

use core::fmt::{self, Write as _};
#[cfg(target_arch = "arm")]
use cortex_m_rt::entry;
#[cfg(target_arch = "arm")]
use cortex_m_semihosting::{
    debug::{self, EXIT_FAILURE, EXIT_SUCCESS},
    hprintln,
};
use protocol::{FRAME_PATTERN, FRAME_PREFIX, FRAME_SUFFIX, RUNS_FILE, RUNS_MAX};
#[cfg(target_arch = "riscv32")]
use riscv_rt::entry;
#[cfg(target_arch = "riscv32")]
use riscv_semihosting::{
    debug::{self, EXIT_FAILURE, EXIT_SUCCESS},
    hprintln,
};
use semihost::{HostFile, IoError};
use tessera_core::{Renderer, Tile, TileCoord, Viewport};

/// Iterations of the calibration loop (2 instructions each).
const CALIBRATION_LOOPS: u32 = 2_000_000;

enum FwError {
    Io(IoError, &'static str),
    RunsTooLong(usize),
    Utf8,
    Parse { line: usize, msg: &'static str },
    Core(tessera_core::Error),
    StackOverflow,
    Init(&'static str),
}

impl fmt::Display for FwError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e, file) if e.op == "open" && *file == RUNS_FILE => write!(
                f,
                "cannot open {RUNS_FILE} in qemu's working directory (one run a line: \
                 <scene> <sampler> <depth> <tile 8|16|32> <width> <height> <seed>)"
            ),
            Self::Io(e, file) => write!(f, "semihosting {} failed on {file}", e.op),
            Self::RunsTooLong(n) => write!(f, "{RUNS_FILE} is {n} bytes, at most {RUNS_MAX}"),
            Self::Utf8 => write!(f, "{RUNS_FILE} is not UTF-8"),
            Self::Parse { line, msg } => write!(f, "{RUNS_FILE}:{line}: {msg}"),
            Self::Core(e) => write!(f, "tessera: {e}"),
            Self::StackOverflow => write!(f, "the stack reached the statics"),
            Self::Init(what) => write!(f, "cannot take {what}"),
        }
    }
}

impl From<tessera_core::Error> for FwError {
    fn from(e: tessera_core::Error) -> Self {
        Self::Core(e)
    }
}

/// The tile buffers, one per size, in `.bss`.
struct Tiles {
    t8: &'static mut Tile<8>,
    t16: &'static mut Tile<16>,
    t32: &'static mut Tile<32>,
}

#[entry]
fn main() -> ! {
    let status = match run_all() {
        Ok(()) => EXIT_SUCCESS,
        Err(e) => {
            hprintln!("error: {}", e);
            EXIT_FAILURE
        }
    };
    debug::exit(status);
    loop {
        #[cfg(target_arch = "arm")]
        cortex_m::asm::bkpt();
        #[cfg(target_arch = "riscv32")]
        riscv::asm::wfi();
    }
}

fn run_all() -> Result<(), FwError> {
    #[cfg(target_arch = "arm")]
    {
        let p = cortex_m::Peripherals::take().ok_or(FwError::Init("the core peripherals"))?;
        clock::start(p.SYST);
    }
    #[cfg(target_arch = "riscv32")]
    clock::start();

    let (buf, mut tiles) = statics()?;
    let text = read_runs(buf)?;

    let ticks = clock::calibrate(CALIBRATION_LOOPS);
    hprintln!(
        "calibration instructions={} ticks={}",
        2 * u64::from(CALIBRATION_LOOPS),
        ticks
    );
    #[cfg(all(target_arch = "riscv32", nofpu))]
    hprintln!("misa={:#x}", riscv::register::misa::read().bits());

    let mut index = 0usize;
    let mut peak = 0usize;
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let run = runs::parse(line).map_err(|msg| FwError::Parse { line: n + 1, msg })?;
        let base = stack::in_use();
        stack::paint();
        let (ticks, loop_sp) = render(&run, index, &mut tiles)?;
        let lowest = stack::lowest().ok_or(FwError::StackOverflow)?;
        let used = stack::top() - lowest;
        peak = peak.max(used);
        hprintln!(
            "run {} scene={} sampler={} depth={} tile={} size={}x{} seed={} ticks={} instructions={} pixels={} stack={} base={} render={}",
            index,
            run.scene.name(),
            run.sampler,
            run.depth,
            run.tile,
            run.width,
            run.height,
            run.seed,
            ticks,
            clock::RATE.instructions(ticks),
            u32::from(run.width) * u32::from(run.height),
            used,
            base,
            loop_sp.saturating_sub(lowest)
        );
        if let runs::SceneRef::Baked(b) = run.scene {
            let [view, lights, spheres, planes] = setup(b)?;
            hprintln!(
                "setup {} view={} lights={} spheres={} planes={}",
                index,
                clock::RATE.instructions(view),
                clock::RATE.instructions(lights),
                clock::RATE.instructions(spheres),
                clock::RATE.instructions(planes)
            );
        }
        index += 1;
    }
    hprintln!(
        "stack peak={} available={} ram={}",
        peak,
        stack::top() - stack::limit(),
        stack::ram()
    );
    hprintln!("done runs={}", index);
    Ok(())
}

/// The ticks a frame's set-up takes on the baked scene `b`: its whole view
/// built and checked again with its camera (`BakedScene::view`, what rebuilding
/// the scene each frame costs), then its lights, its spheres and its planes each
/// handed to the view again as a frame's changed list (`SceneView::with_lights`,
/// `with_list`: each checks that list alone).
#[inline(never)]
fn setup(b: tessera_core::builtin::Builtin) -> Result<[u64; 4], FwError> {
    use core::hint::black_box;
    let t0 = clock::now();
    let (times, checked) = b.with_baked_scene(|view, _camera| {
        let t1 = clock::now();
        let lights = black_box(view.with_lights(black_box(view.lights()))).map(|_| ());
        let t2 = clock::now();
        let spheres = black_box(view.with_list(black_box(view.spheres()))).map(|_| ());
        let t3 = clock::now();
        let planes = black_box(view.with_list(black_box(view.planes()))).map(|_| ());
        let t4 = clock::now();
        ([t1, t2, t3, t4], lights.and(spheres).and(planes))
    })?;
    checked?;
    let [t1, t2, t3, t4] = times;
    Ok([t1 - t0, t2 - t1, t3 - t2, t4 - t3])
}

/// Takes the run-list buffer and the tile buffers (once). Not inlined: the values
/// are built on the stack before they are moved to `.bss`, and that frame must not
/// stay under the renders.
#[inline(never)]
fn statics() -> Result<(&'static mut [u8; RUNS_MAX], Tiles), FwError> {
    #[cfg(target_arch = "arm")]
    use cortex_m::singleton;
    #[cfg(target_arch = "riscv32")]
    use riscv::singleton;
    let buf = singleton!(: [u8; RUNS_MAX] = [0; RUNS_MAX]);
    let t8 = singleton!(: Tile<8> = Tile::new());
    let t16 = singleton!(: Tile<16> = Tile::new());
    let t32 = singleton!(: Tile<32> = Tile::new());
    match (buf, t8, t16, t32) {
        (Some(buf), Some(t8), Some(t16), Some(t32)) => Ok((buf, Tiles { t8, t16, t32 })),
        _ => Err(FwError::Init("the static buffers")),
    }
}

/// Reads the whole run list into `buf`.
fn read_runs(buf: &'static mut [u8; RUNS_MAX]) -> Result<&'static str, FwError> {
    let io = |e| FwError::Io(e, RUNS_FILE);
    let f = HostFile::open_read(RUNS_FILE).map_err(io)?;
    let len = f.len().map_err(io)?;
    let dst = buf.get_mut(..len).ok_or(FwError::RunsTooLong(len))?;
    f.read_exact(dst).map_err(io)?;
    core::str::from_utf8(dst).map_err(|_| FwError::Utf8)
}

/// Renders run `index` with the tile buffer of its size; returns the ticks spent
/// in `render_tile` and the stack pointer of the tile loop.
fn render(run: &runs::Run, index: usize, tiles: &mut Tiles) -> Result<(u64, usize), FwError> {
    let mut name = heapless::String::<32>::new();
    let _ = write!(name, "{FRAME_PREFIX}{index}{FRAME_SUFFIX}");
    let out = HostFile::create(&name).map_err(|e| FwError::Io(e, FRAME_PATTERN))?;
    match run.tile {
        8 => render_tiles(run, &out, tiles.t8),
        16 => render_tiles(run, &out, tiles.t16),
        _ => render_tiles(run, &out, tiles.t32),
    }
}

/// Not inlined, so that the scene (built on the stack by `with_scene`) and the
/// renderer's frames sit below the harness's frame: `stack - base` in the result
/// line is what tessera itself needs.
#[inline(never)]
fn render_tiles<const N: usize>(
    run: &runs::Run,
    out: &HostFile,
    tile: &mut Tile<N>,
) -> Result<(u64, usize), FwError> {
    run.scene.with_scaled_scene(run.scale, |view, camera| {
        let renderer =
            Renderer::try_new(camera, Viewport::new(run.width, run.height), run.settings())?;
        let (across, down) = renderer.tile_grid(N);
        let mut ticks = 0;
        let loop_sp = stack::sp();
        for ty in 0..down {
            for tx in 0..across {
                let t0 = clock::now();
                markers::tessera_profile_begin();
                let rendered = renderer.render_tile(view, TileCoord::new(tx, ty), tile, &mut ());
                markers::tessera_profile_end();
                ticks += clock::now() - t0;
                rendered?;
                write_tile(out, tile, run.width)?;
            }
        }
        Ok((ticks, loop_sp))
    })?
}

/// Writes each row of `tile` at its place in the row-major RGB image.
fn write_tile<const N: usize>(out: &HostFile, tile: &Tile<N>, width: u16) -> Result<(), FwError> {
    let io = |e| FwError::Io(e, FRAME_PATTERN);
    let (x0, y0) = tile.origin();
    let (x0, y0) = (x0 as usize, y0 as usize);
    let mut bytes = [0u8; 3 * 32];
    for (j, row) in tile.rows().enumerate() {
        let mut n = 0;
        for (dst, p) in bytes.chunks_exact_mut(3).zip(row) {
            dst.copy_from_slice(&[p.r, p.g, p.b]);
            n += 3;
        }
        out.seek(((y0 + j) * usize::from(width) + x0) * 3)
            .map_err(io)?;
        out.write_all(bytes.get(..n).unwrap_or(&[])).map_err(io)?;
    }
    Ok(())
}
