//! tessera on a board: an STM32F411CEU6 "Black Pill" ray traces a scene file,
//! baked into flash by build.rs (the teapot unless `TESSERA_SCENE` names another),
//! straight onto an ST7789 240x240 SPI panel, with no framebuffer.
//!
//! The chip runs at 100 MHz from its 25 MHz crystal. SPI1 (SCK PA5, MOSI PA7) talks
//! to the panel in mode 3 at 12.5 MHz (the APB2 clock of 100 MHz divided by 8: the
//! fastest step under the ST7789V datasheet's 66 ns serial write cycle, safe over
//! jumper wires), or at 50 MHz with the feature `fast-spi`; DC is PB0, RES PB1,
//! the backlight BLK PB10. The panel is driven by `mipidsi` (model ST7789, colours
//! inverted, as the common 1.3" module needs) through an `embedded-hal-bus`
//! exclusive SPI device without a chip select. Other ST7789 panels (a CS pin,
//! 240x320, 135x240 or 240x280 with an offset) need the changes the README's
//! "Other panels" lists: [`PanelCs`], [`PANEL_SIZE`], [`PANEL_OFFSET`],
//! [`ROTATION`].
//!
//! The picture is drawn progressively (`Drawing::progressive`): first one
//! ray per 4x4 block, each block one `fill_solid`, so a rough picture appears in a
//! small part of the render time; then tile after tile of 16x16 pixels (the
//! scene file's `tile`), each
//! rendered into one `Rgb565` buffer on the stack with 4x4 Bayer dithering and sent
//! in one address window. The on-board LED (PC13, active low) is lit while
//! rendering and off when the picture is complete; on an error it blinks a code
//! forever ([`Failure::blinks`]). Nothing in the render path panics: every error
//! of tessera and of the panel is returned and shown on the LED.
//!
//! With the feature `defmt` (on by default) it also logs over RTT, for a probe
//! (`probe-rs run`): the scene, frame and tile sizes at the start, the time the
//! picture took, and every error with its value ([`log`]); a panic's message goes
//! there too (panic-probe). Without a probe the log costs nothing but its flash
//! (RTT does not wait for a reader until one attaches).
//!
//! With the feature `bench` (off by default) it first times each built-in scene
//! at 240x240 with the cycle counter and prints the figures and each frame's
//! checksum over RTT, then draws its scene as always ([`bench`];
//! docs/bench.md).
#![no_std]
#![no_main]
#![deny(unsafe_code)]

use core::convert::Infallible;
use cortex_m_rt::entry;
use embedded_graphics_core::Drawable;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::pixelcolor::{Rgb565, RgbColor};
use embedded_hal::digital::{ErrorType, OutputPin};
use embedded_hal_bus::spi::{ExclusiveDevice, NoDelay};
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::options::{ColorInversion, Orientation, Rotation};
use mipidsi::{Builder, Display};
use scene::{SCENE, SceneLoops};
use stm32f4xx_hal::gpio::{self, Output, PinState, Speed};
use stm32f4xx_hal::pac;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::{Config, Rcc};
use stm32f4xx_hal::spi::Spi;
use stm32f4xx_hal::timer::SysDelay;
use tessera_core::display::Drawing;
use tessera_core::{Viewport, dither::Dither};

#[cfg(feature = "bench")]
mod bench;
mod log;

/// The scene: its tables (`SCENE`, `MATERIALS`, the meshes...) are statics in
/// flash, written by build.rs from the scene file.
mod scene {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}

/// The crystal of the Black Pill, in MHz.
const HSE_MHZ: u32 = 25;
/// The system clock, in MHz: the STM32F411's maximum.
const SYSCLK_MHZ: u32 = 100;
/// The SPI clock asked for, in MHz: the ST7789V datasheet's serial write cycle
/// of at least 66 ns (15.2 MHz). SPI1 divides APB2's 100 MHz by a power of two
/// and the HAL takes the fastest rate not above this: 12.5 MHz.
#[cfg(not(feature = "fast-spi"))]
const SPI_MHZ: u32 = 15;
/// The SPI clock asked for with the feature `fast-spi`, in MHz: APB2 (100 MHz)
/// / 2, the fastest SPI1 gives. Beyond the ST7789V datasheet's write cycle,
/// within the ST7789VW's (16 ns); many modules take it over short wires.
#[cfg(feature = "fast-spi")]
const SPI_MHZ: u32 = 50;
/// The panel's width and height in pixels in its own (portrait) orientation, as
/// mipidsi's `display_size` takes them: 240x240 for the 1.3" module; 240x320,
/// 135x240 or 240x280 for the other common ST7789 panels.
const PANEL_SIZE: (u16, u16) = (240, 240);
/// Where the panel's pixels start in the ST7789's 240x320 memory, in the same
/// orientation (mipidsi's `display_offset`): none for 240x240 and 240x320 panels;
/// (52, 40) is usual for 135x240, (0, 20) for 240x280. mipidsi moves it for the
/// other rotations.
const PANEL_OFFSET: (u16, u16) = (0, 0);
/// How the picture is turned on the panel: `Deg0` in the panel's own orientation;
/// `Deg90` and `Deg270` swap its width and height (320x240 on a 240x320 panel).
const ROTATION: Rotation = Rotation::Deg0;
/// The picture's width and height in pixels: [`PANEL_SIZE`], swapped by a
/// quarter turn.
const PICTURE: (u16, u16) = if ROTATION.is_horizontal() {
    PANEL_SIZE
} else {
    (PANEL_SIZE.1, PANEL_SIZE.0)
};
/// The tile size: the scene file's `tile` (8, 16 or 32; 16 for the teapot:
/// 16x16 pixels, 512 bytes of `Rgb565` a tile). Only the buffers depend on it
/// (the tile on the stack, [`SPI_BUFFER`]), not the picture, whose size is the
/// panel's, [`PICTURE`], whatever the scene file's `width` and `height`.
const TILE: usize = scene::TILE;
/// The preview's block: one ray per 4x4 pixels.
const PREVIEW_BLOCK: u32 = 4;
/// mipidsi's SPI buffer: one tile of `Rgb565` (512 bytes for 16x16), so a
/// tile's pixels go out in one SPI write (mipidsi then flushes an empty rest).
const SPI_BUFFER: usize = 2 * TILE * TILE;
/// How long the LED is on and off in a blink of an error code, in ms.
const BLINK_MS: u32 = 200;

/// The SPI bus to the panel: SPI1, full duplex, 8-bit words (MISO unused).
type PanelBus = Spi<pac::SPI1>;
/// The panel's chip select: none on the 1.3" module ([`NoCs`]). A panel with a
/// CS pin: a GPIO output, such as `gpio::PA4<Output>`, made in `main`.
type PanelCs = NoCs;
/// The panel's SPI device: the whole bus, and its chip select.
type PanelSpi = ExclusiveDevice<PanelBus, PanelCs, NoDelay>;
/// The panel: an ST7789 through mipidsi's SPI interface, DC on PB0, RES on PB1.
type Panel<'b> = Display<SpiInterface<'b, PanelSpi, gpio::PB0<Output>>, ST7789, gpio::PB1<Output>>;

/// What stopped the picture; the LED blinks [`Failure::blinks`] times, pauses,
/// and again, forever.
#[derive(Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Failure {
    /// tessera refused the scene, the mesh, the frame or the loops linked (logged
    /// with the feature `defmt`, kept for a debugger).
    Scene(#[allow(dead_code)] tessera_core::Error),
    /// The panel's initialisation failed.
    PanelInit,
    /// A write to the panel failed (SPI or DC pin).
    PanelWrite,
}

impl Failure {
    /// The number of blinks that names this failure: 2 scene, 3 panel
    /// initialisation, 4 panel write.
    fn blinks(&self) -> u32 {
        match self {
            Self::Scene(_) => 2,
            Self::PanelInit => 3,
            Self::PanelWrite => 4,
        }
    }
}

impl From<tessera_core::Error> for Failure {
    fn from(e: tessera_core::Error) -> Self {
        Self::Scene(e)
    }
}

/// The absent chip select of the 1.3" module (its CS is tied low on the board):
/// an output pin that does nothing.
struct NoCs;

impl ErrorType for NoCs {
    type Error = Infallible;
}

impl OutputPin for NoCs {
    /// Nothing to drive.
    fn set_low(&mut self) -> Result<(), Infallible> {
        Ok(())
    }

    /// Nothing to drive.
    fn set_high(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// The pins of the panel besides the SPI bus.
struct PanelPins {
    /// Chip select ([`PanelCs`]): none here.
    cs: PanelCs,
    /// Data/command select (PB0).
    dc: gpio::PB0<Output>,
    /// Reset, active low (PB1).
    rst: gpio::PB1<Output>,
    /// Backlight, on when high (PB10).
    blk: gpio::PB10<Output>,
}

/// Sets up the clocks and pins, draws the scene, then shows the outcome on the
/// LED forever.
#[entry]
fn main() -> ! {
    let (Some(dp), Some(mut cp)) = (pac::Peripherals::take(), pac::CorePeripherals::take()) else {
        halt();
    };
    // Above 84 MHz the F411's regulator must be in scale 1 (PWR_CR.VOS; the reset
    // value is scale 2, up to 84 MHz); the HAL only sets the flash wait states.
    // VOS is written while the PLL is off, as the reference manual asks; PWR's
    // clock first.
    dp.RCC.apb1enr().modify(|_, w| w.pwren().set_bit());
    dp.PWR.cr().modify(|_, w| w.vos().scale1());
    let mut rcc = dp
        .RCC
        .freeze(Config::hse(HSE_MHZ.MHz()).sysclk(SYSCLK_MHZ.MHz()));
    let mut delay = cp.SYST.delay(&rcc.clocks);
    log::start_clock(&mut cp.DCB, &mut cp.DWT);
    #[cfg(feature = "bench")]
    bench::run(&mut cp.DCB, &mut cp.DWT);
    let gpioa = dp.GPIOA.split(&mut rcc);
    let gpiob = dp.GPIOB.split(&mut rcc);
    let gpioc = dp.GPIOC.split(&mut rcc);
    // PC13 sinks the LED's current: high is off, low is lit.
    let mut led = gpioc.pc13.into_push_pull_output_in_state(PinState::High);
    let bus = panel_bus(dp.SPI1, gpioa.pa5, gpioa.pa7, &mut rcc);
    let pins = PanelPins {
        cs: NoCs,
        dc: gpiob.pb0.into_push_pull_output(),
        rst: gpiob.pb1.into_push_pull_output_in_state(PinState::High),
        blk: gpiob.pb10.into_push_pull_output(),
    };
    let mut buffer = [0u8; SPI_BUFFER];
    led.set_low();
    match show_scene(bus, pins, &mut buffer, &mut delay) {
        Ok(()) => {
            led.set_high();
            halt()
        }
        Err(failure) => {
            log::failed(&failure);
            blink_forever(&mut led, &mut delay, failure.blinks())
        }
    }
}

/// SPI1 in mode 3 at [`SPI_MHZ`] on SCK PA5 and MOSI PA7 (very high speed
/// outputs, for the 50 MHz edges of `fast-spi`); MISO is not connected.
fn panel_bus(spi1: pac::SPI1, sck: gpio::PA5, mosi: gpio::PA7, rcc: &mut Rcc) -> PanelBus {
    let sck = sck.into_alternate::<5>().speed(Speed::VeryHigh);
    let mosi = mosi.into_alternate::<5>().speed(Speed::VeryHigh);
    spi1.spi(
        (Some(sck), pac::SPI1::NoMiso, Some(mosi)),
        embedded_hal::spi::MODE_3,
        SPI_MHZ.MHz(),
        rcc,
    )
}

/// Initialises the panel, clears it to black, turns the backlight on and draws
/// the scene on it.
fn show_scene(
    bus: PanelBus,
    mut pins: PanelPins,
    buffer: &mut [u8],
    delay: &mut SysDelay,
) -> Result<(), Failure> {
    let mut panel = init_panel(bus, pins.cs, pins.dc, pins.rst, buffer, delay)?;
    // The panel's memory holds noise after a reset: clear it before lighting it.
    panel
        .clear(Rgb565::BLACK)
        .map_err(|e| log::panel_error(Failure::PanelWrite, &e))?;
    pins.blk.set_high();
    draw_scene(&mut panel)
}

/// The ST7789 panel of [`PANEL_SIZE`] at [`PANEL_OFFSET`] on `bus` (selected by
/// `cs`), turned by [`ROTATION`], reset through `rst` and initialised with
/// inverted colours (the 1.3" module's panel shows the complement otherwise).
fn init_panel<'b>(
    bus: PanelBus,
    cs: PanelCs,
    dc: gpio::PB0<Output>,
    rst: gpio::PB1<Output>,
    buffer: &'b mut [u8],
    delay: &mut SysDelay,
) -> Result<Panel<'b>, Failure> {
    let Ok(spi) = ExclusiveDevice::new_no_delay(bus, cs);
    Builder::new(ST7789, SpiInterface::new(spi, dc, buffer))
        .display_size(PANEL_SIZE.0, PANEL_SIZE.1)
        .display_offset(PANEL_OFFSET.0, PANEL_OFFSET.1)
        .orientation(Orientation::new().rotate(ROTATION))
        .invert_colors(ColorInversion::Inverted)
        .reset_pin(rst)
        .init(delay)
        .map_err(|e| log::panel_error(Failure::PanelInit, &e))
}

/// Ray traces the scene onto `display` with the README's API: the whole scene
/// baked in flash by build.rs (what `tessera bake` writes of the scene file: no
/// byte of it in RAM), its frame of [`PICTURE`] (240x240) with the scene file's
/// own settings (for the teapot centre sampling, depth 0, sRGB: what `tessera
/// render teapot` uses), drawn progressively (a preview of one ray per 4x4
/// block, then the [`TILE`]-sized tiles, Bayer 4x4 dithered).
///
/// It links only the tile loops the scene needs (`SceneLoops`, which the baker
/// writes: for the teapot direct light, sRGB, no adaptive or sparse sampler); the
/// others are left out of the image (`tessera_core::tile::Loops`; the README gives
/// the flash this saves), and settings that needed one would be refused by
/// `linking`, not drawn wrong.
fn draw_scene<D>(display: &mut D) -> Result<(), Failure>
where
    D: DrawTarget<Color = Rgb565>,
    D::Error: log::Value,
{
    let view = SCENE.view()?;
    let renderer = SCENE.renderer_at(Viewport::new(PICTURE.0, PICTURE.1), SCENE.settings())?;
    log::drawing(&renderer, TILE, PREVIEW_BLOCK);
    let started = log::now();
    Drawing::<Rgb565, TILE>::new(&renderer, &view)
        .dithered(Dither::Bayer4)
        .progressive(PREVIEW_BLOCK)
        .linking::<SceneLoops>()?
        .draw(display)
        .map_err(|e| log::panel_error(Failure::PanelWrite, &e))?;
    log::drawn(started);
    Ok(())
}

/// Blinks `led` (active low) `count` times, pauses, and again, forever.
fn blink_forever(led: &mut gpio::PC13<Output>, delay: &mut SysDelay, count: u32) -> ! {
    loop {
        for _ in 0..count {
            led.set_low();
            delay.delay_ms(BLINK_MS);
            led.set_high();
            delay.delay_ms(BLINK_MS);
        }
        delay.delay_ms(4 * BLINK_MS);
    }
}

/// Spins forever (the picture stays on the panel).
fn halt() -> ! {
    loop {
        core::hint::spin_loop();
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
