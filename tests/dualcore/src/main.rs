//! Firmware test image of tessera on both cores of qemu's `mps2-an521` board (the
//! SSE-200 subsystem: two Cortex-M33, run with CPU 0's FPU and DSP on, as on an
//! RP2350): every built-in scene rendered once by CPU 0 alone and once by both CPUs
//! taking tiles from one shared queue, into one shared frame buffer.
//!
//! Start-up: cortex-m-rt starts CPU 0 (its `.data`, `.bss`, FPU). CPU 1 waits in
//! reset (the SSE-200's CPUWAIT bit 1, set at reset) until CPU 0 writes the address
//! of CPU 1's own vector table ([`CORE1_VECTORS`]: its stack, [`core1_reset`], its
//! fault handler) to INITSVTOR1 and clears that bit. CPU 1 then turns its FPU on
//! and waits for frames ([`core1_reset`]).
//!
//! A frame: CPU 0 checks the scene's baked tables (`Builtin::with_baked_scene`),
//! makes the renderer (64x64 pixels, the scene's own settings), resets the tile
//! queue ([`QUEUE`], a `tessera_core::tile::TileQueue`), publishes the scene and the
//! renderer as the [`Job`] and, for two cores, bumps [`POSTED`]; then both CPUs
//! run [`work`]: take a tile from the queue, render it into their own
//! tile buffer, copy it into [`FRAME`] and record which CPU (read from the SSE-200's
//! CPU_IDENTITY register) rendered it, until the queue is empty. CPU 1 then
//! stores the frame's number in [`FINISHED`]; CPU 0 waits for it, writes the frame
//! to the host and prints its line.
//!
//! Protocol (semihosting, files in qemu's working directory):
//! - `quantum cycles=<c> instructions=<n>`: the scheduling quantum (see
//!   [`start_quantum`]);
//! - the frame of scene `s` rendered by `k` cores (1 or 2) goes to
//!   `dualcore-<s>-<k>.rgb`: 64x64 pixels in row-major order, 3 bytes (R, G, B)
//!   each, no header;
//! - one line per frame, in the order rendered (every scene on one core, then every
//!   scene on two): `frame scene=<s> cores=<k> tiles=<n> core0=<tiles> core1=<tiles>
//!   owners=<one digit per tile, row-major: the CPU that rendered it> fnv=<FNV-1a 64
//!   of the frame's bytes, hex>`;
//! - `core1 stack=<peak bytes> of=<bytes>` and `done frames=<n>`, then exit with
//!   success. An error prints `error: ...`, a fault `hard fault: ...`, and qemu exits
//!   with a failure.
//!
//! Instruction counts: each CPU calls the empty marker functions
//! `tessera_profile_begin` and `tessera_profile_end` around its tile loop (taking
//! tiles, rendering them, copying them into the frame); the qemu plugin
//! `tests/profiler/vcpu_count.c` counts each vCPU's instructions between them.
//! SysTick cannot: under `-icount` both CPUs' clocks read one virtual time, which
//! the two CPUs' instructions advance together.
#![no_std]
#![no_main]

// The other firmware image's profiling markers, shared.
#[path = "../../firmware/src/markers.rs"]
mod markers;
// The host-file calls of the other firmware image, shared (this one reads no file).
#[allow(dead_code)]
#[path = "../../firmware/src/semihost.rs"]
mod semihost;
// CPU 0's fault and panic handlers: the firmware test image's (CPU 1 has its own,
// `core1_fault`).
#[path = "../../firmware/src/faults.rs"]
mod faults;

use core::cell::UnsafeCell;
use core::fmt::{self, Write as _};
use core::sync::atomic::{AtomicU8, AtomicU32, Ordering};
use cortex_m_rt::entry;
use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::hprintln;
use semihost::{HostFile, IoError};
use tessera_core::builtin::Builtin;
use tessera_core::tile::TileQueue;
use tessera_core::{Renderer, SceneView, Tile, TileCoord, Viewport};

/// The frame's size, pixels.
const WIDTH: u16 = 64;
/// See [`WIDTH`].
const HEIGHT: u16 = 64;
/// The tile size.
const N: usize = 16;
/// The frame's tiles across ...
const ACROSS: u16 = WIDTH.div_ceil(N as u16);
/// ... and down.
const DOWN: u16 = HEIGHT.div_ceil(N as u16);
/// Tiles of the frame.
const TILES: usize = ACROSS as usize * DOWN as usize;
/// Bytes of the frame.
const FRAME_BYTES: usize = WIDTH as usize * HEIGHT as usize * 3;
/// CPU 1's stack, bytes.
const CORE1_STACK_BYTES: usize = 16 * 1024;
/// What CPU 1's stack is painted with before it starts.
const STACK_PATTERN: u32 = 0xDEAD_C0DE;

/// The SSE-200's system control registers (secure alias; `hw/misc/iotkit-sysctl.c`
/// in qemu): INITSVTOR1, CPU 1's initial secure vector table address, taken at its
/// next reset ...
const INITSVTOR1: *mut u32 = 0x5002_1114 as *mut u32;
/// ... and CPUWAIT, one bit per CPU held in reset (reset value 0b10: CPU 1 waits);
/// clearing CPU 1's bit powers it up from INITSVTOR1's table.
const CPUWAIT: *mut u32 = 0x5002_1118 as *mut u32;
/// The SSE-200's per-CPU CPU_IDENTITY register: reads as the CPU's number.
const CPU_IDENTITY: *const u32 = 0x4001_F000 as *const u32;
/// The Coprocessor Access Control Register (SCB): CP10 and CP11 give the FPU.
const CPACR: *mut u32 = 0xE000_ED88 as *mut u32;
/// SysTick's control and status, reload and current value registers.
const SYST_CSR: *mut u32 = 0xE000_E010 as *mut u32;
/// See [`SYST_CSR`].
const SYST_RVR: *mut u32 = 0xE000_E014 as *mut u32;
/// See [`SYST_CSR`].
const SYST_CVR: *mut u32 = 0xE000_E018 as *mut u32;
/// SysTick's period on CPU 0, processor clock cycles: the scheduling quantum (see
/// [`start_quantum`]).
const QUANTUM_CYCLES: u32 = 200;
/// Guest instructions per processor clock cycle on `mps2-an521` under `-icount
/// shift=0` (one instruction a nanosecond, a 20 MHz clock).
const INSTRUCTIONS_PER_CYCLE: u32 = 50;

/// The built-in scenes rendered (the teapot's mesh and BVH are flash data).
const SCENES: [Builtin; 5] = [
    Builtin::ChapterDirect,
    Builtin::ChapterReflect,
    Builtin::Interference,
    Builtin::Showcase,
    Builtin::Teapot,
];

/// A static written by one CPU while the other does not look (see each one's rule).
#[repr(transparent)]
struct Shared<T>(UnsafeCell<T>);

// SAFETY: each `Shared` static below states who may touch it when; the handshake
// through `POSTED` and `FINISHED` (release/acquire) orders the accesses.
unsafe impl<T> Sync for Shared<T> {}

impl<T> Shared<T> {
    const fn new(v: T) -> Self {
        Self(UnsafeCell::new(v))
    }
    const fn get(&self) -> *mut T {
        self.0.get()
    }
}

/// A frame's work, shared by both CPUs: the scene and the renderer.
struct Job {
    view: SceneView<'static>,
    renderer: Renderer,
}

/// The frame's tiles, each handed out once to whichever CPU asks first (one
/// `fetch_add` a tile); CPU 0 resets it before each frame, while CPU 1 waits.
static QUEUE: TileQueue = TileQueue::new(ACROSS, DOWN);

/// The current frame's job: written by CPU 0 only while CPU 1 waits (before it
/// bumps [`POSTED`], after CPU 1 stored the previous frame in [`FINISHED`]); read
/// by both between.
static JOB: Shared<Option<Job>> = Shared::new(None);
/// Frames posted to CPU 1 (a count; CPU 1 works on a frame when it changes).
static POSTED: AtomicU32 = AtomicU32::new(0);
/// The last frame CPU 1 finished (its [`POSTED`] number).
static FINISHED: AtomicU32 = AtomicU32::new(0);
/// Set by CPU 1 when its tile loop failed (a render error or a tile taken twice).
static CORE1_FAILED: AtomicU32 = AtomicU32::new(0);
/// The frame, 8-bit RGB, row-major: each CPU writes only the tiles the queue gave
/// it; CPU 0 reads it once CPU 1 has finished the frame.
static FRAME: Shared<[u8; FRAME_BYTES]> = Shared::new([0; FRAME_BYTES]);
/// Per tile (row-major), 1 + the number of the CPU that rendered it; 0: none yet.
static OWNERS: [AtomicU8; TILES] = [const { AtomicU8::new(0) }; TILES];
/// CPU 0's tile buffer (only CPU 0 touches it).
static TILE0: Shared<Tile<N>> = Shared::new(Tile::new());
/// CPU 1's tile buffer (only CPU 1 touches it).
static TILE1: Shared<Tile<N>> = Shared::new(Tile::new());
/// CPU 1's stack: painted by CPU 0 before CPU 1 starts, then CPU 1's alone
/// (CPU 0 reads it back at the end, while CPU 1 waits).
static CORE1_STACK: Shared<[u32; CORE1_STACK_BYTES / 4]> = Shared::new([0; CORE1_STACK_BYTES / 4]);

/// An exception handler of CPU 1.
type Handler = unsafe extern "C" fn() -> !;

/// CPU 1's vector table: initial stack pointer, reset, then the 14 system
/// exceptions (all faults go to one handler; CPU 1 enables no interrupt). Aligned
/// to 128 bytes, as VTOR needs.
#[repr(C, align(128))]
struct Vectors {
    stack_top: *const u32,
    reset: Handler,
    exceptions: [Handler; 14],
}

// SAFETY: read-only data (a pointer and function pointers), read by the hardware.
unsafe impl Sync for Vectors {}

/// CPU 1's vector table (in flash).
static CORE1_VECTORS: Vectors = Vectors {
    // One past the stack's last word (`Shared` is transparent: the array's address).
    stack_top: (&raw const CORE1_STACK)
        .cast::<u32>()
        .wrapping_add(CORE1_STACK_BYTES / 4),
    reset: core1_reset,
    exceptions: [core1_fault; 14],
};

enum FwError {
    Core(tessera_core::Error),
    Io(IoError, &'static str),
    TwiceRendered(u8),
    Missing,
    Core1Failed,
    Core1Stack,
    NotCpu0(u32),
    Grid,
}

impl fmt::Display for FwError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Core(e) => write!(f, "tessera: {e}"),
            Self::Io(e, what) => write!(f, "semihosting {} failed on {what}", e.op),
            Self::TwiceRendered(core) => write!(f, "CPU {core} got a tile already rendered"),
            Self::Missing => write!(f, "a tile of the frame was not rendered"),
            Self::Core1Failed => write!(f, "CPU 1's tile loop failed"),
            Self::Core1Stack => write!(f, "CPU 1's stack overflowed"),
            Self::NotCpu0(id) => write!(f, "main runs on CPU {id}, not CPU 0"),
            Self::Grid => write!(f, "the frame is not {ACROSS}x{DOWN} tiles"),
        }
    }
}

impl From<tessera_core::Error> for FwError {
    fn from(e: tessera_core::Error) -> Self {
        Self::Core(e)
    }
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
        cortex_m::asm::bkpt();
    }
}

fn run_all() -> Result<(), FwError> {
    let id = cpu_id();
    if id != 0 {
        return Err(FwError::NotCpu0(id));
    }
    start_quantum();
    hprintln!(
        "quantum cycles={} instructions={}",
        QUANTUM_CYCLES,
        QUANTUM_CYCLES * INSTRUCTIONS_PER_CYCLE
    );
    let mut frames = 0;
    for b in SCENES {
        frame(b, 1)?;
        frames += 1;
    }
    start_core1();
    for b in SCENES {
        frame(b, 2)?;
        frames += 1;
    }
    // CPU 1 waits for a frame that never comes: its stack is quiet.
    let used = core1_stack_used();
    hprintln!("core1 stack={} of={}", used, CORE1_STACK_BYTES);
    if used >= CORE1_STACK_BYTES {
        return Err(FwError::Core1Stack);
    }
    hprintln!("done frames={}", frames);
    Ok(())
}

/// Renders `b` with `cores` CPUs (1: CPU 0 alone, CPU 1 not involved; 2: both),
/// writes the frame to the host and prints its line.
fn frame(b: Builtin, cores: u32) -> Result<(), FwError> {
    let (view, renderer) = b.with_baked_scene(|view, camera| {
        let vp = Viewport::new(WIDTH, HEIGHT);
        Renderer::try_new(camera, vp, b.settings()).map(|r| (*view, r))
    })??;
    if renderer.tile_grid(N) != (ACROSS, DOWN) {
        return Err(FwError::Grid);
    }
    QUEUE.reset();
    for o in &OWNERS {
        o.store(0, Ordering::Relaxed);
    }
    // SAFETY: CPU 1 is waiting (not started, or it finished the previous frame:
    // `FINISHED` was acquired below), so nothing reads the job while it changes.
    unsafe {
        *JOB.get() = Some(Job { view, renderer });
    }
    let posted = if cores == 2 {
        let n = POSTED.fetch_add(1, Ordering::Release) + 1;
        cortex_m::asm::sev();
        // Lets qemu run CPU 1 now (see `start_quantum`): a hint, no effect on a
        // chip.
        // SAFETY: YIELD touches no register or memory.
        unsafe { core::arch::asm!("yield", options(nomem, nostack, preserves_flags)) };
        Some(n)
    } else {
        None
    };
    // SAFETY: the job stays as written until this frame is over (only this
    // function writes it, before posting); CPU 1 reads it too, shared.
    let job = unsafe { (*JOB.get()).as_ref() };
    // SAFETY: only CPU 0 uses `TILE0`.
    let tile = unsafe { &mut *TILE0.get() };
    let mine = match job {
        Some(job) => work(cpu_id() as u8, job, tile),
        None => Ok(0),
    };
    if let Some(n) = posted {
        while FINISHED.load(Ordering::Acquire) != n {
            cortex_m::asm::wfe();
        }
    }
    mine?;
    if CORE1_FAILED.load(Ordering::Acquire) != 0 {
        return Err(FwError::Core1Failed);
    }
    let mut owners = [b'?'; TILES];
    let mut count = [0u32; 2];
    for (o, c) in OWNERS.iter().zip(&mut owners) {
        let core = o
            .load(Ordering::Acquire)
            .checked_sub(1)
            .ok_or(FwError::Missing)?;
        *c = b'0' + core;
        if let Some(n) = count.get_mut(usize::from(core)) {
            *n += 1;
        }
    }
    // SAFETY: both CPUs are done with the frame (CPU 1's writes were released by
    // its `FINISHED` store, acquired above).
    let pixels: &[u8; FRAME_BYTES] = unsafe { &*FRAME.get() };
    let mut name = Name::new();
    let _ = write!(name, "dualcore-{}-{}.rgb", b.name(), cores);
    let io = |e| FwError::Io(e, "the frame file");
    let out = HostFile::create(name.as_str()).map_err(io)?;
    out.write_all(pixels).map_err(io)?;
    drop(out);
    hprintln!(
        "frame scene={} cores={} tiles={} core0={} core1={} owners={} fnv={:016x}",
        b.name(),
        cores,
        TILES,
        count[0],
        count[1],
        core::str::from_utf8(&owners).unwrap_or("?"),
        fnv1a64(pixels)
    );
    Ok(())
}

/// One CPU's share of a frame: tiles from [`QUEUE`] until it is empty, each
/// rendered into `tile`, copied into [`FRAME`] and recorded in [`OWNERS`]. Returns
/// how many tiles this CPU rendered. Between the two profiling markers: the
/// plugin counts this loop's instructions on each CPU. The same code on both
/// CPUs; not inlined, so that the markers bracket the same instructions.
#[inline(never)]
fn work(core: u8, job: &Job, tile: &mut Tile<N>) -> Result<u32, FwError> {
    markers::tessera_profile_begin();
    let mut done = 0;
    let result = loop {
        let Some(coord) = QUEUE.next() else {
            break Ok(done);
        };
        if let Err(e) = job.renderer.render_tile(&job.view, coord, tile, &mut ()) {
            break Err(FwError::Core(e));
        }
        copy_into_frame(tile);
        if let Err(e) = record(core, coord) {
            break Err(e);
        }
        done += 1;
    };
    markers::tessera_profile_end();
    result
}

/// Notes that CPU `core` rendered the tile at `coord`; an error if some CPU did
/// already (the queue handed it out twice).
fn record(core: u8, coord: TileCoord) -> Result<(), FwError> {
    let across = usize::from(WIDTH).div_ceil(N);
    let i = usize::from(coord.ty) * across + usize::from(coord.tx);
    let slot = OWNERS.get(i).ok_or(FwError::Missing)?;
    match slot.swap(core + 1, Ordering::Release) {
        0 => Ok(()),
        _ => Err(FwError::TwiceRendered(core)),
    }
}

/// Copies `tile`'s pixels to their place in [`FRAME`].
fn copy_into_frame(tile: &Tile<N>) {
    let (x0, y0) = tile.origin();
    let (x0, y0) = (x0 as usize, y0 as usize);
    let frame = FRAME.get().cast::<u8>();
    for (j, row) in tile.rows().enumerate() {
        let start = ((y0 + j) * usize::from(WIDTH) + x0) * 3;
        for (i, p) in row.iter().enumerate() {
            let at = start + 3 * i;
            if at + 3 > FRAME_BYTES {
                return;
            }
            // SAFETY: `at..at + 3` lies in the frame (checked above), inside this
            // tile's rectangle, which the queue gave to this CPU alone: no other
            // CPU writes or reads these bytes during the frame.
            unsafe {
                frame.add(at).write(p.r);
                frame.add(at + 1).write(p.g);
                frame.add(at + 2).write(p.b);
            }
        }
    }
}

/// Starts CPU 0's SysTick, without its interrupt, with a period of
/// [`QUANTUM_CYCLES`] (10,000 instructions): a timer of qemu's virtual clock, so
/// that the two vCPUs take turns in short steps, as two cores at one clock run side
/// by side. It changes no instruction the CPUs execute.
///
/// Under `-icount` qemu runs the vCPUs in turn on one thread, each until the next
/// deadline of the virtual clock's timers or until it gives up its turn (YIELD, and
/// WFE, which qemu treats as YIELD). qemu 7.2 gives the first vCPU of a round the
/// whole budget to that deadline, which can starve the others (a known problem,
/// fixed after 7.2 by splitting the budget: "accel/tcg/tcg-accel-ops-rr: ensure
/// fairness with icount", Jamie Iles, April 2023). Without a timer of the guest's
/// the next deadline is the round-robin kick, 100 ms (100 million instructions)
/// away: CPU 0 renders every tile of each frame before CPU 1 runs (measured: CPU 1
/// renders no tile). With this timer, measured on qemu 7.2: a vCPU that waits in a
/// YIELD loop gets no turn while the other runs to deadlines, but two vCPUs that
/// both render alternate exactly 10,000 instructions each (the plugin's `shared`
/// counts check it in the test). So CPU 0 also yields once after posting a frame
/// ([`frame`]): CPU 1 then sees the frame and starts.
fn start_quantum() {
    // SAFETY: SysTick's registers of this CPU; nothing else uses SysTick, and its
    // interrupt stays off (TICKINT clear): ENABLE and CLKSOURCE (processor clock).
    unsafe {
        SYST_RVR.write_volatile(QUANTUM_CYCLES - 1);
        SYST_CVR.write_volatile(0);
        SYST_CSR.write_volatile(0b101);
    }
}

/// The number of the CPU running this (the SSE-200's CPU_IDENTITY register).
fn cpu_id() -> u32 {
    // SAFETY: CPU_IDENTITY is a read-only device register of each CPU's private
    // region; reading it has no effect.
    unsafe { CPU_IDENTITY.read_volatile() }
}

/// Paints CPU 1's stack, points INITSVTOR1 at CPU 1's vector table and releases
/// CPU 1 from reset (CPUWAIT bit 1).
fn start_core1() {
    let stack = CORE1_STACK.get().cast::<u32>();
    for i in 0..CORE1_STACK_BYTES / 4 {
        // SAFETY: inside CPU 1's stack, which nothing uses before CPU 1 starts.
        unsafe { stack.add(i).write_volatile(STACK_PATTERN) };
    }
    let vectors = (&raw const CORE1_VECTORS) as u32;
    // SAFETY: the SSE-200's system control registers, secure alias, written from
    // the secure state; CPU 1 reads its table at the reset the CPUWAIT write
    // causes, after this write.
    unsafe {
        INITSVTOR1.write_volatile(vectors);
        cortex_m::asm::dsb();
        let wait = CPUWAIT.read_volatile();
        CPUWAIT.write_volatile(wait & !0b10);
    }
    cortex_m::asm::dsb();
}

/// Bytes of CPU 1's stack it ever used: from the lowest word that lost the
/// pattern to the top.
fn core1_stack_used() -> usize {
    let stack = CORE1_STACK.get().cast::<u32>();
    let words = CORE1_STACK_BYTES / 4;
    // SAFETY: inside CPU 1's stack; CPU 1 waits for a frame (its stack below its
    // waiting frame is not written), read word by word.
    let untouched = (0..words)
        .take_while(|&i| unsafe { stack.add(i).read_volatile() } == STACK_PATTERN)
        .count();
    (words - untouched) * 4
}

/// CPU 1's reset handler: turns its FPU on, then renders each posted frame's
/// share and reports it finished, forever.
unsafe extern "C" fn core1_reset() -> ! {
    // SAFETY: CPACR of this CPU's SCB; CP10 and CP11 full access, then the
    // barriers that make the FPU usable from the next instruction. No floating
    // point instruction runs before this (a plain function, no FP arguments).
    unsafe {
        CPACR.write_volatile(CPACR.read_volatile() | (0b1111 << 20));
    }
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
    core1_loop()
}

/// CPU 1's main loop (FPU on).
#[inline(never)]
fn core1_loop() -> ! {
    let core = cpu_id() as u8;
    let mut seen = 0;
    loop {
        let n = loop {
            let n = POSTED.load(Ordering::Acquire);
            if n != seen {
                break n;
            }
            cortex_m::asm::wfe();
        };
        seen = n;
        // SAFETY: CPU 0 wrote the job before posting frame `n` (acquired above)
        // and does not change it until this CPU stores `n` in FINISHED; only
        // this CPU uses `TILE1`.
        let (job, tile) = unsafe { ((*JOB.get()).as_ref(), &mut *TILE1.get()) };
        let ok = match job {
            Some(job) => work(core, job, tile).is_ok(),
            None => false,
        };
        if !ok {
            CORE1_FAILED.store(1, Ordering::Release);
        }
        FINISHED.store(n, Ordering::Release);
        cortex_m::asm::sev();
    }
}

/// CPU 1's handler of every fault and exception: reports over semihosting (a
/// fixed message, without the console lock CPU 0's `hprintln!` takes) and exits
/// qemu with a failure.
unsafe extern "C" fn core1_fault() -> ! {
    let msg = b"hard fault: on CPU 1\n\0";
    // SAFETY: SYS_WRITE0 reads the NUL-terminated string, a static.
    unsafe {
        cortex_m_semihosting::syscall!(WRITE0, msg.as_ptr());
    }
    debug::exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::bkpt();
    }
}

/// FNV-1a, 64 bits.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// A short file name, on the stack.
struct Name {
    buf: [u8; 48],
    len: usize,
}

impl Name {
    const fn new() -> Self {
        Self {
            buf: [0; 48],
            len: 0,
        }
    }
    fn as_str(&self) -> &str {
        core::str::from_utf8(self.buf.get(..self.len).unwrap_or(&[])).unwrap_or("")
    }
}

impl fmt::Write for Name {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        let dst = self.buf.get_mut(self.len..end).ok_or(fmt::Error)?;
        dst.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}
