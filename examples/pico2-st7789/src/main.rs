//! tessera on a Raspberry Pi Pico 2: both Cortex-M33 cores of the RP2350 ray trace
//! an animated scene, frame after frame, onto a Waveshare Pico-LCD-1.3 (ST7789,
//! 240x240), with no framebuffer. The scene is a scene file baked into flash by
//! build.rs (by default `scenes/examples/animated-pico2.toml`: a teapot turning on
//! the spot and a ball bouncing beside it over a checkered floor, lit by two
//! lights; another file with `TESSERA_SCENE`); its meshes are drawn as
//! instances, which its keyframes move.
//!
//! The chip runs at 150 MHz from the board's 12 MHz crystal. SPI1 (SCK GP10, MOSI
//! GP11) talks to the panel in mode 3 at 37.5 MHz (the 150 MHz peripheral clock
//! divided by 4: the fastest the PL022 gives under the ST7789's write limit); CS is
//! GP9, DC GP8, RST GP12, the backlight GP13. The panel is driven by the few
//! commands of [`DmaPanel`]: it sets each tile's address window over SPI, then a
//! DMA channel feeds the tile's bytes to the SPI transmit FIFO while the cores go
//! on rendering.
//!
//! The two cores share the frame through one [`TileQueue`] ([`QUEUE`]): each takes
//! the next tile nobody has taken, so a core whose tiles are cheap takes more of
//! them. Core 1 renders into tile buffers of its own ([`handoff`]) and hands each
//! rendered one to core 0. Core 0 renders too, into two buffers of its own, and owns
//! the SPI bus and the DMA channel: it sends core 1's tiles as they come and its own
//! after each render, so that the transfer of its last tile runs while it renders
//! the next. A buffer is never written while a transfer reads it: core 0 waits for
//! a transfer ([`TileSink::finish`]) before it starts the next one, before it renders
//! into that buffer again and before it gives a buffer back to core 1.
//!
//! **Frames.** The camera, the panel's size and the scene's settings do not change:
//! one [`Renderer`] serves every frame. What changes is where the instances are.
//! Frame `n` of the animation is at `frame_time(n, FPS)` seconds (`n / FPS`, the
//! scene file's `fps`; the host's `tessera render --frame n` is at the same time),
//! whatever time the frame before took to render, and `n` starts again from 0 at
//! the animation's end (`ANIMATION.looped_frames(FPS)`): the animation loops,
//! one frame step a frame, in slow motion when the chip renders fewer frames a second than
//! the file's `fps`. Before each frame core 0 moves the instances to where the
//! animation has them at that time (`ANIMATION.place`, each placement checked;
//! an error stops the firmware as any other, on the LED and in the log) and makes
//! the frame's view of them (`SceneView::with_instances`).
//!
//! **The instances and the two cores.** The instances live in one static in RAM
//! ([`placed`]): the scene's own, copied there once, then moved by core 0 alone
//! before each frame. The frame's view borrows them; core 0 publishes it with the
//! renderer and the frame's label ([`JOB`], then the frame's number, [`FRAME`])
//! only once core 1 has finished the frame before ([`CORE1_DONE`]) and the queue is
//! reset, and it moves the instances again only after that too. So the instances
//! never change while either core renders through a view of them: core 1 reads
//! them only between seeing a frame's number (acquire) and storing it as done
//! (release), and core 0 writes them only after seeing that store (acquire) and
//! before publishing the next number (release).
//!
//! With the feature `fps-label` (on by default) each frame shows the rate of the
//! frame before, timed with the RP2350's timer, in its top left corner: a
//! [`Label`] made once a frame and drawn with embedded-graphics over each tile it
//! crosses, after the tile renders and before it is sent, on both cores
//! ([`label`]).
//!
//! The on-board LED (GP25) changes state after every frame; on an error it blinks a
//! code forever ([`Failure::blinks`]). Nothing in the render path panics: errors of
//! tessera and of the panel link are returned and shown on the LED. With the
//! feature `defmt` (on by default) it also logs over RTT, for a probe: the start,
//! each frame's time, and every error with its value, from either core ([`log`]);
//! a panic's message goes there too (panic-probe).
//!
//! With the feature `bench` (off by default) it first times each built-in scene
//! at 240x240 on one core and on both with the cycle counter and prints the
//! figures and each frame's checksum over RTT, then animates as always
//! ([`bench`]; docs/bench.md).
#![no_std]
#![no_main]

use core::cell::Cell;
use core::convert::Infallible;
use core::hint::spin_loop;
use core::mem;
use core::sync::atomic::{AtomicU32, Ordering};
use critical_section::Mutex;
use embedded_graphics_core::primitives::Rectangle;
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{OutputPin, PinState, StatefulOutputPin};
use embedded_hal::spi::SpiBus;
use hal::Clock;
use hal::dma::{CH0, Channel, DMAExt, ReadTarget, single_buffer};
use hal::fugit::RateExtU32;
use hal::gpio::bank0::{Gpio8, Gpio9, Gpio10, Gpio11, Gpio25};
use hal::gpio::{FunctionSioOutput, FunctionSpi, Pin, PullDown};
use hal::multicore::{Multicore, Stack};
use hal::pac;
use rp235x_hal as hal;
use tessera_core::animation::frame_time;
use tessera_core::display::{Drawing, Rgb565Wire, TileSink, tile_area, wire_bytes};
use tessera_core::tile::TileQueue;
use tessera_core::{Renderer, SceneView, Tile, Viewport};

#[cfg(feature = "bench")]
mod bench;
mod label;
mod log;
#[cfg(not(feature = "flash-only"))]
mod ram;

use label::Label;

/// The scene: its tables (`SCENE`, the meshes and their BVHs, `INSTANCES`,
/// `ANIMATION` and its tracks, `FPS`) are statics in flash, written by build.rs
/// from the scene file. Its numbers are data: a vertex normal of 0.7071068 is
/// not `FRAC_1_SQRT_2` written by hand (clippy's `approx_constant`).
#[allow(clippy::approx_constant)]
mod scene {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}

/// The Pico 2's crystal, in Hz.
const XTAL_HZ: u32 = 12_000_000;
/// The SPI clock asked for, in Hz: the ST7789's write limit (a 16 ns serial clock
/// cycle). The PL022 divides the 150 MHz peripheral clock by an even prescaler
/// times an integer, and the HAL takes the fastest rate not above this: 37.5 MHz.
const SPI_HZ: u32 = 62_500_000;
/// The SPI mode: 3 (clock idle high, data taken on the rising edge, as the ST7789
/// reads it). In mode 0 the PL022 pulses its frame signal between words, which
/// leaves a gap after every byte; in mode 3 a DMA transfer goes out back to back.
const SPI_MODE: embedded_hal::spi::Mode = embedded_hal::spi::MODE_3;
/// The picture's width and height in pixels: the whole 1.3" panel.
const PICTURE: (u16, u16) = (240, 240);
/// The tile size: 16x16 pixels, 512 bytes of `Rgb565Wire` a tile.
const TILE: usize = 16;
/// The frame's tiles across and down ([`Renderer::tile_grid`] of [`PICTURE`]).
const GRID: (u16, u16) = (
    PICTURE.0.div_ceil(TILE as u16),
    PICTURE.1.div_ceil(TILE as u16),
);
/// How many instances the scene has: the room of the RAM copy that moves them.
const INSTANCE_COUNT: usize = scene::INSTANCES.len();
/// Core 1's stack, in 32-bit words: 8 KiB. `render_tile` needs about 2.3 KiB on
/// the Cortex-M33 for the built-in scenes and about 4 KiB for instanced teapots
/// (the peak of a whole firmware on the Cortex-M4F; both measured under qemu,
/// docs/chip-cost.md); core 1's own frames hold the frame's job (a renderer, a
/// view, a label), no tile.
const CORE1_STACK_WORDS: usize = 2048;
/// How long the LED is on and off in a blink of an error code, in ms.
const BLINK_MS: u32 = 200;

/// Tells the RP2350's boot ROM that this is a secure Arm executable. The ROM
/// starts an image only if it finds such a block in the first 4 KiB of flash:
/// memory.x places `.start_block` right after the vector table.
#[unsafe(link_section = ".start_block")]
#[used]
static IMAGE_DEF: hal::block::ImageDef = hal::block::ImageDef::secure_exe();

/// What `picotool info` shows of the image.
#[unsafe(link_section = ".bi_entries")]
#[used]
static PICOTOOL_ENTRIES: [hal::binary_info::EntryAddr; 4] = [
    hal::binary_info::rp_cargo_bin_name!(),
    hal::binary_info::rp_cargo_version!(),
    hal::binary_info::rp_program_description!(
        c"tessera: ray traced frames on both cores, sent to an ST7789 by DMA"
    ),
    hal::binary_info::rp_program_build_attribute!(),
];

/// The frame's tiles, handed out to both cores one at a time.
static QUEUE: TileQueue = TileQueue::new(GRID.0, GRID.1);
/// The number of the frame being rendered (from 1; 0 before the first), stored by
/// core 0 (release) after [`JOB`] and [`QUEUE`]'s reset: core 1 starts a
/// frame when it sees a new number (acquire).
static FRAME: AtomicU32 = AtomicU32::new(0);
/// The last frame for which core 1 has stopped taking tiles and handed over every
/// tile it rendered (stored with release after its last hand-over).
static CORE1_DONE: AtomicU32 = AtomicU32::new(0);
/// The renderer, view and label of the frame [`FRAME`] names: plain data, copied
/// out by core 1 (the view borrows the instances of [`placed`], which stay put
/// until core 1 has stored the frame in [`CORE1_DONE`]).
static JOB: Mutex<Cell<Option<FrameJob>>> = Mutex::new(Cell::new(None));
/// Core 1's stack (in `.bss`; core 0's is SRAM8 and SRAM9, memory.x). The HAL
/// puts its lowest address in core 1's MSPLIM: an overflow faults.
static CORE1_STACK: Stack<CORE1_STACK_WORDS> = Stack::new();

/// The tile buffers core 1 renders into and core 0 sends from.
///
/// Each buffer is in one of three states, and each state has one owner: `FREE`
/// (core 1 may render into it), `READY` (rendered, waiting for core 0) and
/// `SENDING` (core 0's DMA reads it). Only core 1 moves a buffer from `FREE` to
/// `READY` ([`Producer::render`]), only core 0 from `READY` to `SENDING`
/// ([`Consumer::take`]) and back to `FREE` ([`Consumer::release`]), and there is
/// one [`Producer`] and one [`Consumer`] ([`split`]). The tile's bytes are
/// written before the release store of `READY` and read after the acquire load
/// that sees it, and core 1 renders into a buffer only after an acquire load of
/// `FREE` that sees core 0's release store: every access to a tile happens while
/// its owner holds it.
mod handoff {
    use super::TILE;
    use core::cell::UnsafeCell;
    use core::sync::atomic::{AtomicBool, AtomicU8, Ordering};
    use tessera_core::Tile;
    use tessera_core::display::Rgb565Wire;

    /// Core 1 may render into the buffer.
    const FREE: u8 = 0;
    /// Rendered, for core 0 to send.
    const READY: u8 = 1;
    /// Core 0's DMA is sending it.
    const SENDING: u8 = 2;
    /// How many buffers core 1 has: while core 0 renders a tile of its own, core 1
    /// can render this many before it waits for core 0 to send them (cheap tiles,
    /// of background only, take little time).
    pub const COUNT: usize = 4;

    /// A tile buffer of core 1's and its state.
    struct Slot {
        state: AtomicU8,
        tile: UnsafeCell<Tile<TILE, Rgb565Wire>>,
    }

    // SAFETY: the tile is only reached through `Producer` and `Consumer`, which
    // touch it only in the states they own (the module's documentation).
    unsafe impl Sync for Slot {}

    /// Core 1's buffers (520 bytes each).
    static BUFFERS: [Slot; COUNT] = [const {
        Slot {
            state: AtomicU8::new(FREE),
            tile: UnsafeCell::new(Tile::blank()),
        }
    }; COUNT];
    /// Whether [`split`] has been called.
    static SPLIT: AtomicBool = AtomicBool::new(false);

    /// Core 1's end: renders into free buffers and hands them over.
    pub struct Producer(());
    /// Core 0's end: takes the rendered buffers and gives them back.
    pub struct Consumer(());

    /// The two ends, once (`None` after the first call).
    pub fn split() -> Option<(Producer, Consumer)> {
        (!SPLIT.swap(true, Ordering::AcqRel)).then_some((Producer(()), Consumer(())))
    }

    impl Producer {
        /// Waits for a free buffer, gives it to `render` and, if that returns
        /// true, hands it to core 0 (else the buffer stays free).
        pub fn render(&mut self, render: impl FnOnce(&mut Tile<TILE, Rgb565Wire>) -> bool) {
            loop {
                for slot in &BUFFERS {
                    if slot.state.load(Ordering::Acquire) == FREE {
                        // SAFETY: the buffer is FREE, a state only the (one)
                        // producer leaves, so core 0 neither reads it nor sends
                        // it until the store of READY below; the acquire load
                        // ordered core 0's last reads before this write.
                        let tile = unsafe { &mut *slot.tile.get() };
                        if render(tile) {
                            slot.state.store(READY, Ordering::Release);
                        }
                        return;
                    }
                }
                core::hint::spin_loop();
            }
        }
    }

    impl Consumer {
        /// A buffer core 1 has rendered, now core 0's (`SENDING`) until
        /// [`Consumer::release`]: its index and its tile.
        pub fn take(&mut self) -> Option<(usize, &Tile<TILE, Rgb565Wire>)> {
            BUFFERS.iter().enumerate().find_map(|(i, slot)| {
                if slot.state.load(Ordering::Acquire) != READY {
                    return None;
                }
                slot.state.store(SENDING, Ordering::Relaxed);
                // SAFETY: the buffer was READY (acquire: core 1's writes are
                // visible) and is now SENDING; core 1 writes only FREE buffers,
                // and only `release`, which needs `&mut self` and so ends this
                // borrow first, frees it.
                Some((i, unsafe { &*slot.tile.get() }))
            })
        }

        /// Gives buffer `i` back to core 1. Call it only once nothing reads the
        /// buffer any more (its transfer finished): core 1 may write it at once.
        pub fn release(&mut self, i: usize) {
            if let Some(slot) = BUFFERS.get(i) {
                // Only a buffer taken by `take`: never one core 1 is filling.
                if slot.state.load(Ordering::Relaxed) == SENDING {
                    slot.state.store(FREE, Ordering::Release);
                }
            }
        }
    }
}

/// The frame's instances: the scene's copied into RAM once, then moved by the
/// animation before each frame; both cores read them through the frame's view.
///
/// They live in one static ([`Placer`]'s slot) and have one writer, the one
/// [`Placer`] (core 0's), which moves them only in [`Placer::place`], an `unsafe
/// fn` whose caller promises that no view of them is in use meanwhile. Core 0
/// keeps that promise by the frame protocol (`crate::animate`): it places a
/// frame's instances before it publishes the frame (the view in `crate::JOB`,
/// then the number in `crate::FRAME`, release), and the next frame's only after
/// core 1 has stored the frame as done (`crate::CORE1_DONE`, release; core 0's
/// acquire load sees it before `crate::draw_frame` returns), with its own view of
/// the frame before gone. Core 1 reads through the view only between its acquire
/// load of the frame's number and its release store of it as done. So every
/// write to the instances happens before every read of them through the next
/// view, and every read through a view happens before the next write.
mod placed {
    use super::{INSTANCE_COUNT, scene};
    use core::cell::UnsafeCell;
    use core::ptr::NonNull;
    use core::sync::atomic::{AtomicBool, Ordering};
    use tessera_core::instance::{Instances, Placement};
    use tessera_core::{Error, SceneView};

    /// The instances, in RAM (about 180 bytes each).
    type Moving = Instances<'static, INSTANCE_COUNT>;

    /// Where the instances live: `None` until [`Placer::new`] copies the
    /// scene's there.
    struct Slot(UnsafeCell<Option<Moving>>);

    // SAFETY: the slot is reached only through the one `Placer`, which writes it
    // in `new` (before any view of it exists) and in `place` (whose caller
    // promises that no view of it is in use on either core), and through the
    // views `place` returns, which only read it (the module's documentation).
    unsafe impl Sync for Slot {}

    /// The instances both cores read through the frame's view.
    static SLOT: Slot = Slot(UnsafeCell::new(None));
    /// Whether [`Placer::new`] has made the one placer.
    static MADE: AtomicBool = AtomicBool::new(false);

    /// Core 0's handle on the instances: the only one that moves them.
    pub struct Placer {
        /// The scene's view, with its instances where the scene file has them.
        view: SceneView<'static>,
        /// Each instance's placement in the scene file, which the animation's
        /// tracks change channel by channel.
        rest: [Placement; INSTANCE_COUNT],
        /// The instances in [`SLOT`].
        moving: NonNull<Moving>,
    }

    impl Placer {
        /// Checks the scene's animation against `view`'s instances and copies
        /// them into RAM; `None` on a second call (there is one placer).
        ///
        /// # Errors
        /// The animation's ([`tessera_core::animation::Animation::check`]: its
        /// times, its values, its tracks' instances) and
        /// [`Error::CapacityExceeded`] if `view` has more instances than the
        /// scene baked.
        pub fn new(view: SceneView<'static>) -> Result<Option<Self>, Error> {
            if MADE.swap(true, Ordering::AcqRel) {
                return Ok(None);
            }
            scene::ANIMATION.check(view.instance_count())?;
            let copy = Instances::of(&view)?;
            // SAFETY: `MADE` was false: this is the one placer being made, so no
            // view of the slot exists yet and nothing else reaches it.
            let slot = unsafe { &mut *SLOT.0.get() };
            Ok(Some(Self {
                view,
                rest: scene::INSTANCES.map(|p| p.instance().placement),
                moving: NonNull::from(slot.insert(copy)),
            }))
        }

        /// Moves the instances to where the animation has them at `t` seconds
        /// and returns the frame's view of them. The view reads the instances in
        /// place: it shows this frame's placements until the next call.
        ///
        /// # Safety
        /// No view an earlier call returned is in use, or will be used again,
        /// on either core: core 1 has stored the frame of the last one as done
        /// (`crate::CORE1_DONE`) and core 0 has seen it with an acquire load,
        /// or core 1 renders nothing; core 0's own copy of it is no longer used.
        ///
        /// # Errors
        /// As [`tessera_core::animation::Animation::place`] (a placement the
        /// core refuses) and [`SceneView::with_instances`]. The instances may
        /// then be partly moved: the caller stops.
        pub unsafe fn place(&mut self, t: f32) -> Result<SceneView<'static>, Error> {
            // SAFETY: `moving` points into `SLOT`, a static; this placer is its
            // only writer (`&mut self`), and the caller promises that no view
            // reads it while it changes.
            let moving = unsafe { self.moving.as_mut() };
            scene::ANIMATION.place(t, &self.rest, moving)?;
            // SAFETY: from here to the next `place` the instances are only read,
            // through the view returned (on both cores); `SLOT` lives for the
            // whole run, so the borrow is `'static` as long as the next `place`'s
            // caller keeps its promise that this view is no longer used.
            let moving: &'static Moving = unsafe { self.moving.as_ref() };
            self.view.with_instances(moving)
        }
    }
}

/// The SPI bus to the panel: SPI1, 8-bit words, transmit only (MOSI GP11, SCK GP10).
type PanelSpi = hal::spi::Spi<
    hal::spi::Enabled,
    pac::SPI1,
    (
        Pin<Gpio11, FunctionSpi, PullDown>,
        Pin<Gpio10, FunctionSpi, PullDown>,
    ),
    8,
>;
/// The DMA channel that feeds the panel.
type PanelDma = Channel<CH0>;
/// A push-pull output pin.
type Output<I> = Pin<I, FunctionSioOutput, PullDown>;

/// ST7789 commands (Sitronix ST7789VW datasheet, section 9).
mod st7789 {
    /// Sleep out; the controller needs 120 ms before sleep in, 5 ms before the next
    /// command.
    pub const SLPOUT: u8 = 0x11;
    /// Normal display mode on.
    pub const NORON: u8 = 0x13;
    /// Display inversion on: the Pico-LCD-1.3's IPS panel shows the complement of
    /// every colour without it (Waveshare's demo sends it too).
    pub const INVON: u8 = 0x21;
    /// Display on.
    pub const DISPON: u8 = 0x29;
    /// Column address set: first and last column, each high byte first.
    pub const CASET: u8 = 0x2A;
    /// Row address set: first and last row.
    pub const RASET: u8 = 0x2B;
    /// Memory write: the pixels of the window follow.
    pub const RAMWR: u8 = 0x2C;
    /// Memory data access control: the orientation.
    pub const MADCTL: u8 = 0x36;
    /// Interface pixel format.
    pub const COLMOD: u8 = 0x3A;
    /// MADCTL as Waveshare's demo sets it for the board held with its buttons to
    /// the right: row/column exchange, column order and vertical refresh order
    /// reversed (MV | MX | ML). The picture then fills the controller's memory from
    /// its origin: no offset.
    pub const LANDSCAPE: u8 = 0x70;
    /// COLMOD: 16 bits a pixel (RGB565), for the RGB and the serial interface.
    pub const RGB565: u8 = 0x55;

    /// The panel's registers as Waveshare's demo code for the Pico-LCD-1.3 sets
    /// them, each command with its parameters (the ST7789V datasheet's names).
    /// Those that differ from the controller's reset values: VCOMS (VCOM 0.725 V
    /// against 0.9 V), VRHS (VRH 4.45 V against 4.1 V) and both gamma curves;
    /// the rest are the reset values, written as the demo writes them.
    pub const PANEL: [(u8, &[u8]); 11] = [
        // PORCTRL: back and front porch 12 lines each, separate porch control
        // off, idle and partial modes' porches 3 and 3 (reset values).
        (0xB2, &[0x0C, 0x0C, 0x00, 0x33, 0x33]),
        // GCTRL: VGH 13.26 V, VGL -10.43 V (reset value).
        (0xB7, &[0x35]),
        // VCOMS: VCOM 0.725 V (reset 0x20, 0.9 V).
        (0xBB, &[0x19]),
        // LCMCTRL (reset value).
        (0xC0, &[0x2C]),
        // VDVVRHEN: VDV and VRH from the commands below (reset value).
        (0xC2, &[0x01]),
        // VRHS: VRH 4.45 V (reset 0x0B, 4.1 V).
        (0xC3, &[0x12]),
        // VDVS: VDV 0 V (reset value).
        (0xC4, &[0x20]),
        // FRCTRL2: 60 frames a second in normal mode (reset value).
        (0xC6, &[0x0F]),
        // PWCTRL1: AVDD 6.8 V, AVCL -4.8 V, VDS 2.3 V (reset value).
        (0xD0, &[0xA4, 0xA1]),
        // PVGAMCTRL: the positive gamma curve.
        (
            0xE0,
            &[
                0xD0, 0x04, 0x0D, 0x11, 0x13, 0x2B, 0x3F, 0x54, 0x4C, 0x18, 0x0D, 0x0B, 0x1F, 0x23,
            ],
        ),
        // NVGAMCTRL: the negative gamma curve.
        (
            0xE1,
            &[
                0xD0, 0x04, 0x0C, 0x11, 0x13, 0x2C, 0x3F, 0x44, 0x51, 0x2F, 0x1F, 0x1F, 0x20, 0x23,
            ],
        ),
    ];
}

/// Why the panel link failed.
#[derive(Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum PanelError {
    /// The SPI bus and the DMA channel were not where the link keeps them (cannot
    /// happen: each state change puts them back).
    LinkLost,
    /// A tile's window lies beyond the controller's 16-bit addresses.
    Window,
}

/// Where the SPI bus and the DMA channel are: with the panel between transfers,
/// or inside the transfer in flight.
enum Link {
    /// No transfer: commands may be written.
    Idle(PanelDma, PanelSpi),
    /// A tile's bytes are going out by DMA.
    Sending(single_buffer::Transfer<PanelDma, TileBytes, PanelSpi>),
    /// Only while the state changes.
    Lost,
}

/// The bytes of a tile ([`wire_bytes`]) as a DMA source: their address and count.
struct TileBytes {
    address: u32,
    count: u32,
}

// SAFETY: a `TileBytes` is made only by `DmaPanel::start` from the `bytes` that
// `TileSink::start` receives, and the transfer that reads them is waited for in
// `DmaPanel::finish` (and by `start` before it makes the next). `TileSink::start`'s
// callers promise (it is an `unsafe fn`) to keep those bytes unwritten and in
// place until `finish` returns: tessera's `Drawing::send` does, and so does this
// firmware's own sender (`Sender`). The
// address and count never change.
unsafe impl ReadTarget for TileBytes {
    type ReceivedWord = u8;

    fn rx_treq() -> Option<u8> {
        // Memory: the transfer is paced by the SPI's transmit request.
        None
    }

    fn rx_address_count(&self) -> (u32, u32) {
        (self.address, self.count)
    }

    fn rx_increment(&self) -> bool {
        true
    }
}

/// The ST7789 on SPI1 with a DMA channel: commands by blocking writes, each tile's
/// pixels by DMA ([`TileSink`]).
struct DmaPanel {
    link: Link,
    /// Data/command select (GP8): low for a command byte, high for its parameters
    /// and for pixels.
    dc: Output<Gpio8>,
    /// Chip select (GP9), active low.
    cs: Output<Gpio9>,
}

impl DmaPanel {
    /// Selects the controller and writes `command` and its `params` (the bus must
    /// be idle); the controller stays selected.
    fn command(&mut self, command: u8, params: &[u8]) -> Result<(), PanelError> {
        let Link::Idle(_, spi) = &mut self.link else {
            return Err(PanelError::LinkLost);
        };
        let Ok(()) = self.cs.set_low();
        let Ok(()) = self.dc.set_low();
        let Ok(()) = spi.write(&[command]);
        // The controller reads DC with the command's last bit: that bit is out
        // before DC changes.
        let Ok(()) = spi.flush();
        let Ok(()) = self.dc.set_high();
        let Ok(()) = spi.write(params);
        let Ok(()) = spi.flush();
        Ok(())
    }

    /// Ends the controller's selection.
    fn deselect(&mut self) {
        let Ok(()) = self.cs.set_high();
    }

    /// Resets the controller through `rst` and sets it up: awake, landscape as
    /// Waveshare's demo, RGB565, the panel's registers as Waveshare's demo for
    /// the Pico-LCD-1.3 sets them (porch, gate, VCOM, power and gamma: see
    /// [`st7789::PANEL`]), colours inverted (the IPS panel), display on. Its
    /// memory still holds noise: the backlight is turned on after the first
    /// frame.
    fn init(
        &mut self,
        rst: &mut impl OutputPin,
        delay: &mut impl DelayNs,
    ) -> Result<(), PanelError> {
        let _ = rst.set_low();
        delay.delay_ms(10);
        let _ = rst.set_high();
        delay.delay_ms(120);
        let before: [(u8, &[u8], u32); 3] = [
            (st7789::SLPOUT, &[], 120),
            (st7789::MADCTL, &[st7789::LANDSCAPE], 0),
            (st7789::COLMOD, &[st7789::RGB565], 0),
        ];
        let panel = st7789::PANEL.map(|(command, params)| (command, params, 0));
        let after: [(u8, &[u8], u32); 3] = [
            (st7789::INVON, &[], 0),
            (st7789::NORON, &[], 0),
            (st7789::DISPON, &[], 20),
        ];
        for (command, params, wait_ms) in before.into_iter().chain(panel).chain(after) {
            self.command(command, params)?;
            self.deselect();
            delay.delay_ms(wait_ms);
        }
        Ok(())
    }
}

/// The first and last address of `len` pixels from `start`, as CASET and RASET
/// take them (each high byte first).
fn span(start: i32, len: u32) -> Result<[u8; 4], PanelError> {
    let first = u16::try_from(start).map_err(|_| PanelError::Window)?;
    let len = u16::try_from(len).map_err(|_| PanelError::Window)?;
    let last = first
        .checked_add(len.saturating_sub(1))
        .ok_or(PanelError::Window)?;
    let ([f0, f1], [l0, l1]) = (first.to_be_bytes(), last.to_be_bytes());
    Ok([f0, f1, l0, l1])
}

impl TileSink for DmaPanel {
    type Error = PanelError;

    /// Sets the controller's window to `area`, then starts the DMA transfer of
    /// `bytes` to the SPI transmit FIFO and returns (after waiting for a transfer
    /// still in flight, if any: one at a time).
    unsafe fn start(&mut self, area: Rectangle, bytes: &[u8]) -> Result<(), PanelError> {
        self.finish()?;
        if bytes.is_empty() {
            return Ok(());
        }
        let columns = span(area.top_left.x, area.size.width)?;
        let rows = span(area.top_left.y, area.size.height)?;
        self.command(st7789::CASET, &columns)?;
        self.command(st7789::RASET, &rows)?;
        self.command(st7789::RAMWR, &[])?;
        // Still selected, DC high: the pixels follow.
        let (dma, spi) = match mem::replace(&mut self.link, Link::Lost) {
            Link::Idle(dma, spi) => (dma, spi),
            // Not reached (`command` needed the link idle); put it back all the
            // same: a transfer is never dropped while it runs.
            other => {
                self.link = other;
                return Err(PanelError::LinkLost);
            }
        };
        let from = TileBytes {
            // The RP2350's addresses are 32 bits; a tile is at most 131,072 bytes.
            address: bytes.as_ptr() as u32,
            count: u32::try_from(bytes.len()).unwrap_or(0),
        };
        self.link = Link::Sending(single_buffer::Config::new(dma, from, spi).start());
        Ok(())
    }

    /// Waits for the transfer in flight, then for the SPI to shift its last bytes
    /// out, empties the receive FIFO (the bytes clocked in meanwhile, ignored) and
    /// deselects the controller. Nothing to do when no transfer is in flight.
    fn finish(&mut self) -> Result<(), PanelError> {
        match mem::replace(&mut self.link, Link::Lost) {
            Link::Sending(transfer) => {
                let (dma, _, mut spi) = transfer.wait();
                let Ok(()) = spi.flush();
                while embedded_hal_nb::spi::FullDuplex::<u8>::read(&mut spi).is_ok() {}
                self.deselect();
                self.link = Link::Idle(dma, spi);
                Ok(())
            }
            idle @ Link::Idle(..) => {
                self.link = idle;
                Ok(())
            }
            Link::Lost => Err(PanelError::LinkLost),
        }
    }
}

/// Which buffer the DMA transfer in flight reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Held {
    /// Core 0's buffer `k`.
    Own(usize),
    /// Core 1's buffer `i` ([`handoff`]).
    Core1(usize),
}

/// Core 0's side of the panel: at most one transfer in flight, and whose buffer
/// it reads.
struct Sender {
    panel: DmaPanel,
    from_core1: handoff::Consumer,
    in_flight: Option<Held>,
}

impl Sender {
    /// Waits for the transfer in flight, if any; then its buffer may be written
    /// again (a buffer of core 1's goes back to it).
    fn finish(&mut self) -> Result<(), PanelError> {
        let held = self.in_flight.take();
        self.panel.finish()?;
        if let Some(Held::Core1(i)) = held {
            self.from_core1.release(i);
        }
        Ok(())
    }

    /// Starts sending `tile`, which `held` names, once the transfer before it is
    /// done.
    fn start(&mut self, held: Held, tile: &Tile<TILE, Rgb565Wire>) -> Result<(), PanelError> {
        self.finish()?;
        // SAFETY: `held` names `tile`'s buffer, and no buffer is written while
        // it is held: core 0 renders into its own only after the `finish` that
        // ends its transfer, and core 1's go back to core 1 only in `finish`.
        unsafe { self.panel.start(tile_area(tile), wire_bytes(tile))? };
        self.in_flight = Some(held);
        Ok(())
    }

    /// Waits for the transfer in flight, then sends every tile core 1 has handed
    /// over, one after the other (each waits for the one before); the last one's
    /// transfer is left running.
    fn send_core1_tiles(&mut self) -> Result<(), PanelError> {
        loop {
            self.finish()?;
            let Some((i, tile)) = self.from_core1.take() else {
                return Ok(());
            };
            // SAFETY: core 1's buffer `i` stays with core 0, unwritten, until
            // the `finish` that releases it.
            unsafe { self.panel.start(tile_area(tile), wire_bytes(tile))? };
            self.in_flight = Some(Held::Core1(i));
        }
    }
}

/// What stopped the animation; the LED blinks [`Failure::blinks`] times, pauses,
/// and again, forever.
#[derive(Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Failure {
    /// tessera refused the scene, a camera, a frame or the loops linked (logged
    /// with the feature `defmt`, kept for a debugger).
    Scene(#[allow(dead_code)] tessera_core::Error),
    /// The panel link failed (logged with the feature `defmt`, kept for a
    /// debugger).
    Panel(#[allow(dead_code)] PanelError),
}

impl Failure {
    /// The number of blinks that names this failure: 2 scene, 3 panel.
    fn blinks(&self) -> u32 {
        match self {
            Self::Scene(_) => 2,
            Self::Panel(_) => 3,
        }
    }
}

impl From<tessera_core::Error> for Failure {
    fn from(e: tessera_core::Error) -> Self {
        Self::Scene(e)
    }
}

impl From<PanelError> for Failure {
    fn from(e: PanelError) -> Self {
        Self::Panel(e)
    }
}

/// What core 0 hands core 1 for a frame ([`JOB`]): the renderer, the frame's
/// view (the instances where the frame has them) and its label, so that both
/// cores render the same frame and draw the same text on their tiles. Plain
/// `Copy` data; the view borrows the instances of [`placed`], which do not
/// change until core 1 is done with the frame ([`CORE1_DONE`]).
#[derive(Clone, Copy)]
struct FrameJob {
    renderer: Renderer,
    view: SceneView<'static>,
    label: Label,
}

/// The renderer of every frame: the scene's camera at the panel's size with the
/// scene's own settings (for the default scene: centre sampling, no bounce,
/// sRGB; 4x4 Bayer dithering to RGB565, the renderer's default).
fn renderer() -> Result<Renderer, tessera_core::Error> {
    scene::SCENE.renderer_at(Viewport::new(PICTURE.0, PICTURE.1), scene::SCENE.settings())
}

/// Core 1: renders tiles of each new frame from the queue into its buffers and
/// hands them to core 0, then says it is done with the frame. It reads the frame's
/// view (and so the instances) only between its acquire load of the frame's
/// number and its release store of it in [`CORE1_DONE`].
fn core1_main(mut tiles: handoff::Producer) -> ! {
    #[cfg(feature = "bench")]
    bench::serve();
    let mut seen = 0;
    loop {
        let frame = FRAME.load(Ordering::Acquire);
        if frame == seen {
            spin_loop();
            continue;
        }
        seen = frame;
        if let Some(job) = critical_section::with(|cs| JOB.borrow(cs).get()) {
            while let Some(coord) = QUEUE.next() {
                tiles.render(|tile| {
                    let rendered = job
                        .renderer
                        .render_tile_in::<scene::SceneLoops, TILE, _, _>(
                            &job.view,
                            coord,
                            tile,
                            &mut (),
                        );
                    match rendered {
                        Ok(()) => {
                            job.label.draw(tile);
                            true
                        }
                        Err(e) => {
                            log::tile_failed(1, coord, e);
                            false
                        }
                    }
                });
            }
        }
        CORE1_DONE.store(frame, Ordering::Release);
    }
}

/// Core 0's frame with core 1: publishes the frame, then renders and sends tiles
/// with [`render_and_send`] until core 1 is done and every tile is sent. Returns
/// how many tiles core 0 rendered; on `Ok`, core 1 has stored `frame` in
/// [`CORE1_DONE`] and core 0 has seen it (acquire): core 1 no longer reads the
/// frame's view.
fn draw_frame(sender: &mut Sender, job: &FrameJob, frame: u32) -> Result<u32, PanelError> {
    // Core 1 stopped taking tiles at the end of the frame before (CORE1_DONE),
    // and no longer reads its view.
    QUEUE.reset();
    critical_section::with(|cs| JOB.borrow(cs).set(Some(*job)));
    FRAME.store(frame, Ordering::Release);
    // Core 0's two buffers, on its stack: no transfer may outlive them, so the
    // last one is waited for here whatever `render_and_send` returned.
    let mut own = [Tile::<TILE, Rgb565Wire>::blank(), Tile::blank()];
    let drawn = render_and_send(sender, &mut own, job, frame);
    let finished = sender.finish();
    let core0_tiles = drawn?;
    finished?;
    Ok(core0_tiles)
}

/// Renders tiles from the queue into `own` (alternately), draws the frame's label
/// over each, and sends them, sending core 1's as they come, until core 1 is done
/// with `frame` and every tile it rendered has been started; the last transfer
/// may still run. Returns how many tiles core 0 rendered.
fn render_and_send(
    sender: &mut Sender,
    own: &mut [Tile<TILE, Rgb565Wire>; 2],
    job: &FrameJob,
    frame: u32,
) -> Result<u32, PanelError> {
    let mut k = 0;
    let mut rendered_here = 0;
    loop {
        if let Some(coord) = QUEUE.next() {
            let [a, b] = &mut *own;
            let tile = if k == 0 { a } else { b };
            if sender.in_flight == Some(Held::Own(k)) {
                sender.finish()?;
            }
            let rendered = match job
                .renderer
                .render_tile_in::<scene::SceneLoops, TILE, _, _>(&job.view, coord, tile, &mut ())
            {
                Ok(()) => {
                    job.label.draw(tile);
                    true
                }
                Err(e) => {
                    log::tile_failed(0, coord, e);
                    false
                }
            };
            // Core 1's tiles first, then this one: its transfer then runs while
            // the next tile renders, and no buffer of core 1's is held meanwhile.
            sender.send_core1_tiles()?;
            if rendered {
                sender.start(Held::Own(k), tile)?;
                k ^= 1;
                rendered_here += 1;
            }
        } else if CORE1_DONE.load(Ordering::Acquire) == frame {
            // Everything core 1 handed over is visible now: send the rest.
            sender.send_core1_tiles()?;
            return Ok(rendered_here);
        } else {
            // No tile left to take: send core 1's last ones as they come.
            sender.send_core1_tiles()?;
            spin_loop();
        }
    }
}

/// Renders frame after frame of the animation onto the panel through `renderer`
/// (its tile loops checked), the instances moved by `placer` before each, with
/// core 1 if it started, else with core 0 alone (`Drawing::send_overlaid`), each
/// with the rate of the frame before ([`Label`], timed by `timer`). Returns only
/// on an error.
fn animate(
    sender: &mut Sender,
    renderer: Renderer,
    placer: &mut placed::Placer,
    two_cores: bool,
    timer: hal::Timer<hal::timer::CopyableTimer0>,
    backlight: &mut impl OutputPin,
    led: &mut impl StatefulOutputPin,
) -> Result<Infallible, Failure> {
    let tiles = u32::from(GRID.0) * u32::from(GRID.1);
    // One pass: for the default scene, two seconds at 12 frames a second, 24
    // frames, the 25th (at the end) the next pass's first.
    let per_loop = scene::ANIMATION.looped_frames(scene::FPS);
    let mut frame: u32 = 0;
    // The frame of the animation this frame shows: 0 to `per_loop - 1`.
    let mut step: u32 = 0;
    // The start of the frame before (µs) and how many tiles core 0 rendered of it.
    let mut before: Option<(u64, u32)> = None;
    loop {
        frame = frame.wrapping_add(1).max(1);
        let now = timer.get_counter().ticks();
        let period = before.map(|(start, core0_tiles)| {
            let period = now.wrapping_sub(start);
            log::frame(frame.wrapping_sub(1), period, core0_tiles, tiles);
            period
        });
        // SAFETY: no view of the instances is in use: core 1 is done with the
        // frame before (`draw_frame` returned `Ok` only once it saw core 1 store
        // that frame in CORE1_DONE, acquire; an error ends this loop for good),
        // or core 1 does not render; core 0's job of the frame before went out
        // of scope at the end of the last pass of this loop.
        let view = unsafe { placer.place(frame_time(step, scene::FPS)) }?;
        step = if step + 1 >= per_loop { 0 } else { step + 1 };
        let job = FrameJob {
            renderer,
            view,
            label: Label::new(period),
        };
        let core0_tiles = if two_cores {
            draw_frame(sender, &job, frame)?
        } else {
            Drawing::<Rgb565Wire, TILE>::new(&job.renderer, &job.view)
                .linking::<scene::SceneLoops>()?
                .send_overlaid(&mut sender.panel, |tile| job.label.draw(tile))?;
            tiles
        };
        before = Some((now, core0_tiles));
        if frame == 1 {
            // The panel's memory is the first frame now, no longer noise.
            let _ = backlight.set_high();
        }
        let _ = led.toggle();
    }
}

/// Sets up the clocks, the panel and core 1, then animates; on an error, blinks
/// its code on the LED forever.
#[hal::entry]
fn main() -> ! {
    let Some(mut pac) = pac::Peripherals::take() else {
        halt()
    };
    let mut watchdog = hal::Watchdog::new(pac.WATCHDOG);
    let clocks = match hal::clocks::init_clocks_and_plls(
        XTAL_HZ,
        pac.XOSC,
        pac.CLOCKS,
        pac.PLL_SYS,
        pac.PLL_USB,
        &mut pac.RESETS,
        &mut watchdog,
    ) {
        Ok(clocks) => clocks,
        Err(e) => {
            log::clocks_failed(&e);
            halt()
        }
    };
    let mut timer = hal::Timer::new_timer0(pac.TIMER0, &mut pac.RESETS, &clocks);
    let mut sio = hal::Sio::new(pac.SIO);
    let pins = hal::gpio::Pins::new(
        pac.IO_BANK0,
        pac.PADS_BANK0,
        sio.gpio_bank0,
        &mut pac.RESETS,
    );
    let mut led: Output<Gpio25> = pins.gpio25.into_push_pull_output();
    let mut backlight = pins.gpio13.into_push_pull_output_in_state(PinState::Low);
    let mut rst = pins.gpio12.into_push_pull_output_in_state(PinState::High);
    let spi = hal::Spi::<_, _, _, 8>::new(
        pac.SPI1,
        (
            pins.gpio11.into_function::<FunctionSpi>(),
            pins.gpio10.into_function::<FunctionSpi>(),
        ),
    )
    .init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        SPI_HZ.Hz(),
        SPI_MODE,
    );
    let dma = pac.DMA.split(&mut pac.RESETS);
    let mut panel = DmaPanel {
        link: Link::Idle(dma.ch0, spi),
        dc: pins.gpio8.into_push_pull_output_in_state(PinState::High),
        cs: pins.gpio9.into_push_pull_output_in_state(PinState::High),
    };
    let Some((producer, consumer)) = handoff::split() else {
        halt()
    };
    let outcome = panel
        .init(&mut rst, &mut timer)
        .map_err(Failure::from)
        .and_then(|()| {
            let view = scene::SCENE.view()?;
            let renderer = renderer()?;
            // Once: the tile loops linked serve the renderer's settings and the
            // scene's materials, which every frame shares, so that no tile meets
            // `Error::NotLinked`.
            renderer.check_loops::<scene::SceneLoops>(&view)?;
            // There is one placer: this is the only call.
            let Some(placer) = placed::Placer::new(view)? else {
                halt()
            };
            Ok((renderer, placer))
        })
        .and_then(|(renderer, mut placer)| {
            // Core 1 with its own stack; if it does not start, core 0 renders alone.
            let mut mc = Multicore::new(&mut pac.PSM, &mut pac.PPB, &mut sio.fifo);
            let two_cores = match (mc.cores().get_mut(1), CORE1_STACK.take()) {
                (Some(core1), Some(stack)) => {
                    match core1.spawn(stack, move || core1_main(producer)) {
                        Ok(()) => true,
                        Err(e) => {
                            log::core1_not_started(&e);
                            false
                        }
                    }
                }
                _ => false,
            };
            #[cfg(feature = "bench")]
            bench::run(two_cores, clocks.system_clock.freq().to_Hz());
            log::started(two_cores, scene::ANIMATION.looped_frames(scene::FPS));
            let mut sender = Sender {
                panel,
                from_core1: consumer,
                in_flight: None,
            };
            animate(
                &mut sender,
                renderer,
                &mut placer,
                two_cores,
                timer,
                &mut backlight,
                &mut led,
            )
        });
    match outcome {
        Ok(never) => match never {},
        Err(failure) => {
            log::failed(&failure);
            blink_forever(&mut led, &mut timer, failure.blinks())
        }
    }
}

/// Blinks `led` `count` times, pauses, and again, forever.
fn blink_forever(led: &mut impl OutputPin, delay: &mut impl DelayNs, count: u32) -> ! {
    loop {
        for _ in 0..count {
            let _ = led.set_high();
            delay.delay_ms(BLINK_MS);
            let _ = led.set_low();
            delay.delay_ms(BLINK_MS);
        }
        delay.delay_ms(4 * BLINK_MS);
    }
}

/// Spins forever.
fn halt() -> ! {
    loop {
        spin_loop();
    }
}

/// Halts on a panic (none is expected: the render path returns its errors). With
/// the feature `defmt`, panic-probe's handler instead: it logs the message, then
/// stops the core on a `HardFault` (which halts it too, without a probe).
#[cfg(not(feature = "defmt"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    cortex_m::interrupt::disable();
    halt()
}
