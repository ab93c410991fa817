//! A real display driver as client of `Drawing` (an embedded-graphics
//! `Drawable`): `mipidsi`'s ST7789 driver over a
//! recording fake SPI bus, and an emulated ST7789 that decodes the recorded
//! command/data stream into its 240 x 320 RGB565 frame memory (GRAM).
//!
//! Checked: GRAM equals the host image converted with embedded-graphics'
//! `Rgb565::from(Rgb888)` pixel for pixel (and nothing else was written); after the
//! init sequence the driver got exactly one CASET/RASET/RAMWR window per tile, each
//! the tile's rectangle; display errors come back from `draw`. The
//! negative controls show that the comparisons catch a tile shifted by one pixel
//! and a single wrong bit.

use embedded_graphics_core::Drawable;
use embedded_graphics_core::Pixel;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Dimensions, Point};
use embedded_graphics_core::pixelcolor::raw::RawU16;
use embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565, Rgb888};
use embedded_graphics_core::primitives::Rectangle;
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{self, OutputPin};
use embedded_hal::spi::{self, ErrorKind, Operation, SpiDevice};
use image::RgbImage;
use mipidsi::Builder;
use mipidsi::interface::{SpiError, SpiInterface};
use mipidsi::models::ST7789;
use mipidsi::options::{ColorInversion, ColorOrder, Orientation, Rotation};
use std::cell::RefCell;
use std::convert::Infallible;
use std::rc::Rc;
use tessera_core::builtin::Builtin;
use tessera_core::display::Drawing;
use tessera_core::dither::Dither;
use tessera_core::{Renderer, Viewport};

// ---------------------------------------------------------------------------------
// The fake hardware: SPI device, DC pin, reset pin and delay share one event log.
// ---------------------------------------------------------------------------------

/// What the wires saw, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Event {
    /// Bytes clocked out with the DC line low (`dc == false`: command) or high (data).
    Bytes { dc: bool, bytes: Vec<u8> },
    /// The reset line was driven to this level.
    Reset(bool),
    /// The MCU waited this long.
    DelayNs(u64),
}

#[derive(Debug, Default)]
struct Bus {
    dc: bool,
    events: Vec<Event>,
    /// SPI write transfers so far.
    transfers: usize,
    /// The transfer (1-based) that fails, if any.
    fail_on: Option<usize>,
}

type Shared = Rc<RefCell<Bus>>;

/// The bus error of the fake SPI: which transfer failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct BusFault {
    transfer: usize,
}

impl spi::Error for BusFault {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

/// An `SpiDevice` (it owns chip select) that records every byte with the DC level.
struct FakeSpi(Shared);
/// The data/command line.
struct DcPin(Shared);
/// The reset line.
struct RstPin(Shared);
/// A delay that only records.
struct FakeDelay(Shared);

impl spi::ErrorType for FakeSpi {
    type Error = BusFault;
}

impl SpiDevice for FakeSpi {
    fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), BusFault> {
        let mut bus = self.0.borrow_mut();
        for op in operations {
            match op {
                Operation::Write(bytes) => {
                    bus.transfers += 1;
                    if bus.fail_on == Some(bus.transfers) {
                        return Err(BusFault {
                            transfer: bus.transfers,
                        });
                    }
                    let dc = bus.dc;
                    match bus.events.last_mut() {
                        Some(Event::Bytes { dc: d, bytes: b }) if *d == dc => {
                            b.extend_from_slice(bytes);
                        }
                        _ => bus.events.push(Event::Bytes {
                            dc,
                            bytes: bytes.to_vec(),
                        }),
                    }
                }
                Operation::DelayNs(ns) => bus.events.push(Event::DelayNs(u64::from(*ns))),
                _ => panic!("the ST7789 driver only writes"),
            }
        }
        Ok(())
    }
}

impl digital::ErrorType for DcPin {
    type Error = Infallible;
}

impl OutputPin for DcPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.0.borrow_mut().dc = false;
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.0.borrow_mut().dc = true;
        Ok(())
    }
}

impl digital::ErrorType for RstPin {
    type Error = Infallible;
}

impl OutputPin for RstPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.0.borrow_mut().events.push(Event::Reset(false));
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.0.borrow_mut().events.push(Event::Reset(true));
        Ok(())
    }
}

impl DelayNs for FakeDelay {
    fn delay_ns(&mut self, ns: u32) {
        self.0
            .borrow_mut()
            .events
            .push(Event::DelayNs(u64::from(ns)));
    }
}

// ---------------------------------------------------------------------------------
// The emulated ST7789.
// ---------------------------------------------------------------------------------

const GRAM_W: usize = 240;
const GRAM_H: usize = 320;

const SWRESET: u8 = 0x01;
const SLPOUT: u8 = 0x11;
const NORON: u8 = 0x13;
const INVOFF: u8 = 0x20;
const INVON: u8 = 0x21;
const DISPON: u8 = 0x29;
const CASET: u8 = 0x2A;
const RASET: u8 = 0x2B;
const RAMWR: u8 = 0x2C;
const MADCTL: u8 = 0x36;
const COLMOD: u8 = 0x3A;
const RAMWRC: u8 = 0x3C;

/// One memory write: the address window it was given and how many pixels came.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Window {
    /// CASET start/end (inclusive), in the controller's address space.
    cols: (u16, u16),
    /// RASET start/end (inclusive).
    rows: (u16, u16),
    /// The window's rectangle in GRAM (`x0, y0, x1, y1`, inclusive), through MADCTL.
    gram: (usize, usize, usize, usize),
    pixels: usize,
}

/// The controller's state after the whole stream.
struct Panel {
    /// Frame memory, row-major, `None` where nothing was written.
    gram: Vec<Option<u16>>,
    madctl: u8,
    colmod: Option<u8>,
    inverted: Option<bool>,
    awake: bool,
    display_on: bool,
    /// Every command, in order.
    commands: Vec<u8>,
    /// One entry per RAMWR, in order.
    windows: Vec<Window>,
}

/// The decoder: command/parameter state, address window and write pointer.
struct Controller {
    panel: Panel,
    cmd: Option<u8>,
    params: Vec<u8>,
    cols: (u16, u16),
    rows: (u16, u16),
    /// Write pointer (column, row) in address space.
    ptr: (u16, u16),
    /// First byte of a half-received 16-bit pixel.
    high: Option<u8>,
    reset_done: bool,
    since_reset_ns: u64,
    since_slpout_ns: Option<u64>,
}

impl Controller {
    fn new() -> Self {
        Self {
            panel: Panel {
                gram: vec![None; GRAM_W * GRAM_H],
                madctl: 0,
                colmod: None,
                inverted: None,
                awake: false,
                display_on: false,
                commands: Vec::new(),
                windows: Vec::new(),
            },
            cmd: None,
            params: Vec::new(),
            cols: (0, GRAM_W as u16 - 1),
            rows: (0, GRAM_H as u16 - 1),
            ptr: (0, 0),
            high: None,
            reset_done: false,
            since_reset_ns: 0,
            since_slpout_ns: None,
        }
    }

    /// Address (column, row) to GRAM (x, y), as MADCTL's MY/MX/MV bits say: MV
    /// exchanges the column and row counters, then MX mirrors the 240 GRAM columns
    /// and MY the 320 GRAM rows.
    fn to_gram(&self, col: u16, row: u16) -> (usize, usize) {
        let m = self.panel.madctl;
        let (mut x, mut y) = if m & 0x20 != 0 {
            (usize::from(row), usize::from(col))
        } else {
            (usize::from(col), usize::from(row))
        };
        assert!(
            x < GRAM_W && y < GRAM_H,
            "address ({col}, {row}) outside GRAM"
        );
        if m & 0x40 != 0 {
            x = GRAM_W - 1 - x;
        }
        if m & 0x80 != 0 {
            y = GRAM_H - 1 - y;
        }
        (x, y)
    }

    fn run(events: &[Event]) -> Panel {
        let mut c = Self::new();
        for e in events {
            match e {
                Event::Reset(level) => c.reset_line(*level),
                Event::DelayNs(ns) => {
                    c.since_reset_ns += ns;
                    if let Some(t) = c.since_slpout_ns.as_mut() {
                        *t += ns;
                    }
                }
                Event::Bytes { dc: false, bytes } => {
                    for &b in bytes {
                        c.command(b);
                    }
                }
                Event::Bytes { dc: true, bytes } => {
                    for &b in bytes {
                        c.data(b);
                    }
                }
            }
        }
        c.finish();
        c.panel
    }

    fn reset_line(&mut self, level: bool) {
        if level {
            assert!(
                self.since_reset_ns >= 10_000,
                "reset pulse shorter than 10 us"
            );
            self.reset_done = true;
        }
        self.since_reset_ns = 0;
    }

    fn command(&mut self, b: u8) {
        self.finish();
        assert!(self.reset_done, "command {b:#04x} before the reset");
        if let Some(t) = self.since_slpout_ns {
            assert!(t >= 5_000_000, "command {b:#04x} within 5 ms of SLPOUT");
            self.since_slpout_ns = None;
        }
        self.panel.commands.push(b);
        match b {
            RAMWR => {
                self.ptr = (self.cols.0, self.rows.0);
                self.start_window();
            }
            RAMWRC => self.start_window(),
            SLPOUT => {
                assert!(
                    self.since_reset_ns >= 120_000_000,
                    "SLPOUT within 120 ms of the reset"
                );
                self.panel.awake = true;
                self.since_slpout_ns = Some(0);
            }
            SWRESET | NORON | INVOFF | INVON | DISPON | CASET | RASET | MADCTL | COLMOD => {}
            other => panic!("unexpected command {other:#04x}"),
        }
        self.cmd = Some(b);
    }

    fn start_window(&mut self) {
        assert_eq!(self.panel.colmod, Some(0x55), "RAMWR before 16-bit COLMOD");
        assert!(self.panel.awake && self.panel.display_on);
        let (a, b) = (
            self.to_gram(self.cols.0, self.rows.0),
            self.to_gram(self.cols.1, self.rows.1),
        );
        self.panel.windows.push(Window {
            cols: self.cols,
            rows: self.rows,
            gram: (a.0.min(b.0), a.1.min(b.1), a.0.max(b.0), a.1.max(b.1)),
            pixels: 0,
        });
        self.high = None;
    }

    fn data(&mut self, b: u8) {
        match self.cmd {
            Some(RAMWR | RAMWRC) => match self.high.take() {
                None => self.high = Some(b),
                Some(hi) => self.pixel(u16::from_be_bytes([hi, b])),
            },
            Some(_) => self.params.push(b),
            None => panic!("data byte {b:#04x} without a command"),
        }
    }

    /// One pixel at the write pointer; the pointer runs along the column range,
    /// then to the next row, and wraps to the window's start after its last pixel.
    fn pixel(&mut self, value: u16) {
        let (x, y) = self.to_gram(self.ptr.0, self.ptr.1);
        self.panel.gram[y * GRAM_W + x] = Some(value);
        if let Some(w) = self.panel.windows.last_mut() {
            w.pixels += 1;
        }
        if self.ptr.0 >= self.cols.1 {
            self.ptr.0 = self.cols.0;
            self.ptr.1 = if self.ptr.1 >= self.rows.1 {
                self.rows.0
            } else {
                self.ptr.1 + 1
            };
        } else {
            self.ptr.0 += 1;
        }
    }

    /// Applies the pending command's parameters.
    fn finish(&mut self) {
        let p = std::mem::take(&mut self.params);
        let Some(cmd) = self.cmd.take() else { return };
        let range = |p: &[u8]| {
            assert_eq!(p.len(), 4, "{cmd:#04x} takes 4 parameter bytes");
            let (s, e) = (
                u16::from_be_bytes([p[0], p[1]]),
                u16::from_be_bytes([p[2], p[3]]),
            );
            assert!(s <= e, "{cmd:#04x}: start {s} after end {e}");
            (s, e)
        };
        match cmd {
            CASET => self.cols = range(&p),
            RASET => self.rows = range(&p),
            MADCTL => {
                assert_eq!(p.len(), 1);
                self.panel.madctl = p[0];
            }
            COLMOD => {
                assert_eq!(p.len(), 1);
                self.panel.colmod = Some(p[0]);
            }
            INVON | INVOFF => self.panel.inverted = Some(cmd == INVON),
            DISPON => self.panel.display_on = true,
            RAMWR | RAMWRC => assert!(self.high.is_none(), "half a pixel at the end"),
            _ => {}
        }
        if !matches!(cmd, RAMWR | RAMWRC) {
            assert!(
                p.is_empty() || matches!(cmd, CASET | RASET | MADCTL | COLMOD),
                "{cmd:#04x} got parameters {p:?}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------
// The comparisons, used by the positive tests and the negative controls alike.
// ---------------------------------------------------------------------------------

/// A GRAM pixel that differs from what the image says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Mismatch {
    /// GRAM coordinates.
    gram: (usize, usize),
    /// The image pixel that belongs there (`None`: nothing belongs there).
    image: Option<(u32, u32)>,
    want: Option<u16>,
    got: Option<u16>,
}

/// Every GRAM pixel that is not the image's pixel converted to RGB565 (the 16-bit
/// value as the ST7789 stores it: R in the top 5 bits, sent high byte first), and
/// every written GRAM pixel where no image pixel belongs. `place` says where image
/// pixel `(x, y)` belongs in GRAM for the panel's orientation.
fn mismatches(
    panel: &Panel,
    img: &RgbImage,
    place: &dyn Fn(u32, u32) -> (usize, usize),
) -> Vec<Mismatch> {
    let mut expected: Vec<Option<(u32, u32, u16)>> = vec![None; GRAM_W * GRAM_H];
    for (x, y, p) in img.enumerate_pixels() {
        let want = Rgb565::from(Rgb888::new(p[0], p[1], p[2])).into_storage();
        let (gx, gy) = place(x, y);
        expected[gy * GRAM_W + gx] = Some((x, y, want));
    }
    let mut out = Vec::new();
    for (i, (e, &got)) in expected.iter().zip(&panel.gram).enumerate() {
        let want = e.map(|(_, _, v)| v);
        if want != got {
            out.push(Mismatch {
                gram: (i % GRAM_W, i / GRAM_W),
                image: e.map(|(x, y, _)| (x, y)),
                want,
                got,
            });
        }
    }
    out
}

/// What is wrong with the windows the driver sent: the commands after the init must
/// be CASET, RASET, RAMWR once per tile, in row-major tile order, each window the
/// tile's rectangle (placed in GRAM like its pixels) and filled exactly once.
fn window_errors(
    panel: &Panel,
    img: &RgbImage,
    n: u32,
    place: &dyn Fn(u32, u32) -> (usize, usize),
) -> Vec<String> {
    let mut errors = Vec::new();
    let first = panel
        .commands
        .iter()
        .position(|&c| c == CASET)
        .unwrap_or(panel.commands.len());
    let (across, down) = (img.width().div_ceil(n), img.height().div_ceil(n));
    let tiles = (across * down) as usize;
    let after_init = &panel.commands[first..];
    let want: Vec<u8> = [CASET, RASET, RAMWR].repeat(tiles);
    if after_init != want.as_slice() {
        errors.push(format!(
            "{} commands after init, want {} (3 per tile)",
            after_init.len(),
            want.len()
        ));
    }
    if panel.windows.len() != tiles {
        errors.push(format!("{} windows for {tiles} tiles", panel.windows.len()));
    }
    for (i, w) in panel.windows.iter().enumerate().take(tiles) {
        let (tx, ty) = (i as u32 % across, i as u32 / across);
        let (x0, y0) = (tx * n, ty * n);
        let (x1, y1) = (
            (x0 + n).min(img.width()) - 1,
            (y0 + n).min(img.height()) - 1,
        );
        let (a, b) = (place(x0, y0), place(x1, y1));
        let rect = (a.0.min(b.0), a.1.min(b.1), a.0.max(b.0), a.1.max(b.1));
        if w.gram != rect {
            errors.push(format!("tile {i}: window {:?}, want {rect:?}", w.gram));
        }
        let area = ((x1 - x0 + 1) * (y1 - y0 + 1)) as usize;
        if w.pixels != area {
            errors.push(format!("tile {i}: {} pixels, want {area}", w.pixels));
        }
    }
    errors
}

// ---------------------------------------------------------------------------------
// Panels, a tampering wrapper, and the run.
// ---------------------------------------------------------------------------------

/// How the ST7789 is built: the panel part of its 240 x 320 GRAM, orientation and
/// colour options, and where an image pixel should land in GRAM.
struct Setup {
    size: (u16, u16),
    offset: (u16, u16),
    orientation: Orientation,
    order: ColorOrder,
    invert: ColorInversion,
    /// The MADCTL byte a correct driver sends for this setup.
    madctl: u8,
    place: fn(u32, u32) -> (usize, usize),
}

/// A bare 240 x 320 ST7789, upright: image pixel (x, y) at GRAM (x, y).
const PORTRAIT: Setup = Setup {
    size: (240, 320),
    offset: (0, 0),
    orientation: Orientation::new(),
    order: ColorOrder::Rgb,
    invert: ColorInversion::Normal,
    madctl: 0x00,
    place: |x, y| (x as usize, y as usize),
};

/// The same panel turned upside down, with BGR subpixels: pixel (x, y) at GRAM
/// (239 - x, 319 - y); MY | MX | BGR.
const UPSIDE_DOWN_BGR: Setup = Setup {
    size: (240, 320),
    offset: (0, 0),
    orientation: Orientation::new().rotate(Rotation::Deg180),
    order: ColorOrder::Bgr,
    invert: ColorInversion::Normal,
    madctl: 0xC8,
    place: |x, y| (239 - x as usize, 319 - y as usize),
};

/// A 1.14" 135 x 240 IPS module (visible at GRAM columns 52..187, rows 40..280),
/// used in landscape (240 x 135): the image is turned a quarter onto the glass,
/// its top row along GRAM column 186, its left column along GRAM row 40; MV | MX.
const LANDSCAPE_135: Setup = Setup {
    size: (135, 240),
    offset: (52, 40),
    orientation: Orientation::new().rotate(Rotation::Deg90),
    order: ColorOrder::Rgb,
    invert: ColorInversion::Inverted,
    madctl: 0x60,
    place: |x, y| (52 + 134 - y as usize, 40 + x as usize),
};

/// What the wrapper does to the tiles on their way to the driver.
#[derive(Clone, Copy, Debug)]
enum Tamper {
    /// Moves tile `k`'s rectangle one pixel to the right.
    ShiftTile(usize),
    /// Flips the lowest bit of pixel `i` of tile `k`.
    FlipBit { tile: usize, pixel: usize },
}

/// A `DrawTarget` that passes everything on to `inner`, tampering as told.
struct Tampered<'a, D> {
    inner: &'a mut D,
    tamper: Tamper,
    fills: usize,
}

impl<D: DrawTarget<Color = Rgb565>> Dimensions for Tampered<'_, D> {
    fn bounding_box(&self) -> Rectangle {
        self.inner.bounding_box()
    }
}

impl<D: DrawTarget<Color = Rgb565>> DrawTarget for Tampered<'_, D> {
    type Color = Rgb565;
    type Error = D::Error;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, px: I) -> Result<(), D::Error> {
        self.inner.draw_iter(px)
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), D::Error> {
        let k = self.fills;
        self.fills += 1;
        match self.tamper {
            Tamper::ShiftTile(t) if t == k => {
                let moved = Rectangle::new(area.top_left + Point::new(1, 0), area.size);
                self.inner.fill_contiguous(&moved, colors)
            }
            Tamper::FlipBit { tile, pixel } if tile == k => {
                let colors = colors.into_iter().enumerate().map(|(i, c)| {
                    if i == pixel {
                        Rgb565::from(RawU16::new(c.into_storage() ^ 1))
                    } else {
                        c
                    }
                });
                self.inner.fill_contiguous(area, colors)
            }
            _ => self.inner.fill_contiguous(area, colors),
        }
    }
}

/// Everything one run produced.
struct Run {
    img: RgbImage,
    panel: Panel,
    /// `Drawable::draw`'s answer.
    drawn: Result<(), SpiError<BusFault, Infallible>>,
    /// SPI transfers of the init sequence, and in all.
    init_transfers: usize,
    transfers: usize,
}

/// Renders `scene` at `w x h` on the host, and through `Drawing` with tiles of `N`
/// onto mipidsi's ST7789 over the fake bus (through a `Tampered` wrapper if
/// `tamper` is given; the bus fails `fail_after` transfers after the init if given);
/// then decodes the bus into the emulated panel.
fn run<const N: usize>(
    scene: Builtin,
    (w, h): (u16, u16),
    setup: &Setup,
    tamper: Option<Tamper>,
    fail_after: Option<usize>,
) -> Run {
    let bus: Shared = Rc::default();
    let mut buffer = [0u8; 64];
    let di = SpiInterface::new(FakeSpi(bus.clone()), DcPin(bus.clone()), &mut buffer);
    let mut display = Builder::new(ST7789, di)
        .display_size(setup.size.0, setup.size.1)
        .display_offset(setup.offset.0, setup.offset.1)
        .orientation(setup.orientation)
        .color_order(setup.order)
        .invert_colors(setup.invert)
        .reset_pin(RstPin(bus.clone()))
        .init(&mut FakeDelay(bus.clone()))
        .expect("display init");
    let init_transfers = bus.borrow().transfers;
    bus.borrow_mut().fail_on = fail_after.map(|n| init_transfers + n);

    let settings = scene.settings();
    let viewport = Viewport::new(w, h);
    let (img, drawn) = scene
        .with_scene(|view, camera| {
            let img = tessera_host::render(view, camera, viewport, settings, N).expect("host");
            let renderer = Renderer::try_new(camera, viewport, settings).expect("frame");
            let picture = Drawing::<_, N>::new(&renderer, view).dithered(Dither::None);
            let drawn = match tamper {
                None => picture.draw(&mut display),
                Some(tamper) => {
                    let mut wrapped = Tampered {
                        inner: &mut display,
                        tamper,
                        fills: 0,
                    };
                    picture.draw(&mut wrapped)
                }
            };
            (img, drawn)
        })
        .expect("scene");
    drop(display);
    let bus = bus.borrow();
    Run {
        img,
        panel: Controller::run(&bus.events),
        drawn,
        init_transfers,
        transfers: bus.transfers,
    }
}

/// The positive check: init as configured, GRAM equals the image, one window a tile.
fn check<const N: usize>(scene: Builtin, size: (u16, u16), setup: &Setup) {
    let r = run::<N>(scene, size, setup, None, None);
    r.drawn.expect("draw");
    assert_eq!(
        (r.img.width(), r.img.height()),
        (u32::from(size.0), u32::from(size.1))
    );
    let p = &r.panel;
    assert_eq!(p.madctl, setup.madctl, "MADCTL");
    assert_eq!(p.colmod, Some(0x55), "COLMOD: 16 bits a pixel");
    assert_eq!(
        p.inverted,
        Some(matches!(setup.invert, ColorInversion::Inverted))
    );
    assert!(p.awake && p.display_on);
    assert_eq!(
        &p.commands[..p.commands.iter().position(|&c| c == CASET).unwrap()],
        &[
            SLPOUT,
            MADCTL,
            if p.inverted == Some(true) {
                INVON
            } else {
                INVOFF
            },
            COLMOD,
            NORON,
            DISPON
        ],
        "init sequence (hardware reset, so no SWRESET)"
    );
    assert!(r.init_transfers > 0 && r.transfers > r.init_transfers);

    let bad = mismatches(p, &r.img, &setup.place);
    assert!(
        bad.is_empty(),
        "{} GRAM pixels differ, first {:?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
    let wrong = window_errors(p, &r.img, N as u32, &setup.place);
    assert!(wrong.is_empty(), "{wrong:#?}");
    // The image is not flat: the comparison had something to catch.
    let first = r.img.get_pixel(0, 0);
    assert!(r.img.pixels().any(|p| p != first));
}

#[test]
fn chapter_reflect_240x135_tile16_on_a_landscape_135x240_module() {
    check::<16>(Builtin::ChapterReflect, (240, 135), &LANDSCAPE_135);
}

#[test]
fn chapter_reflect_240x135_tile8_on_a_landscape_135x240_module() {
    check::<8>(Builtin::ChapterReflect, (240, 135), &LANDSCAPE_135);
}

#[test]
fn showcase_100x75_tile16_portrait() {
    check::<16>(Builtin::Showcase, (100, 75), &PORTRAIT);
}

#[test]
fn showcase_100x75_tile8_upside_down_bgr() {
    check::<8>(Builtin::Showcase, (100, 75), &UPSIDE_DOWN_BGR);
}

#[test]
fn negative_control_a_tile_shifted_by_one_pixel_is_caught() {
    // Tile 1 of 100 x 75 in 16 x 16 tiles: columns 16..32 of the top row.
    let r = run::<16>(
        Builtin::Showcase,
        (100, 75),
        &PORTRAIT,
        Some(Tamper::ShiftTile(1)),
        None,
    );
    r.drawn.expect("draw");
    let bad = mismatches(&r.panel, &r.img, &PORTRAIT.place);
    // Column 16 of the top tile row is never written...
    assert!(
        (0..16).all(|y| bad.iter().any(|m| m.gram == (16, y) && m.got.is_none())),
        "{bad:?}"
    );
    // ... and every mismatch lies in the shifted tile's rows and columns 16..=32.
    assert!(
        bad.iter()
            .all(|m| (16..=32).contains(&m.gram.0) && m.gram.1 < 16),
        "{bad:?}"
    );
    let wrong = window_errors(&r.panel, &r.img, 16, &PORTRAIT.place);
    assert_eq!(
        wrong,
        ["tile 1: window (17, 0, 32, 15), want (16, 0, 31, 15)"]
    );
}

#[test]
fn negative_control_one_flipped_bit_is_caught() {
    // Pixel 5 of row 2 of tile 3 (tile (3, 0)): image pixel (53, 2).
    let r = run::<16>(
        Builtin::ChapterReflect,
        (240, 135),
        &LANDSCAPE_135,
        Some(Tamper::FlipBit {
            tile: 3,
            pixel: 2 * 16 + 5,
        }),
        None,
    );
    r.drawn.expect("draw");
    let bad = mismatches(&r.panel, &r.img, &LANDSCAPE_135.place);
    assert_eq!(bad.len(), 1, "{bad:?}");
    let m = bad[0];
    assert_eq!(m.image, Some((53, 2)));
    assert_eq!(m.gram, (LANDSCAPE_135.place)(53, 2));
    assert_eq!(m.want.zip(m.got).map(|(a, b)| a ^ b), Some(1));
    // The windows were right: only the pixel comparison sees this one.
    assert!(window_errors(&r.panel, &r.img, 16, &LANDSCAPE_135.place).is_empty());
}

#[test]
fn a_bus_error_comes_back_from_draw_and_stops_it() {
    // A tile is 2 transfers each for CASET, RASET and RAMWR (command byte, then
    // parameters, empty for RAMWR) and its pixels, 32 a transfer from the 64-byte
    // buffer: tile 0 is transfers 1..=15, tile 1's pixels start at 22, so the 25th
    // transfer after the init is in the middle of tile 1's pixels.
    let r = run::<16>(
        Builtin::ChapterReflect,
        (240, 135),
        &LANDSCAPE_135,
        None,
        Some(25),
    );
    let fail_on = r.init_transfers + 25;
    match r.drawn {
        Err(SpiError::Spi(BusFault { transfer })) => {
            assert_eq!(transfer, fail_on);
        }
        other => panic!("want a display error, got {other:?}"),
    }
    // Nothing was sent after the failed transfer: the draw stopped there.
    assert_eq!(r.transfers, fail_on);
    // Tile 0 arrived whole, tile 1 in part, nothing after.
    let sizes: Vec<usize> = r.panel.windows.iter().map(|w| w.pixels).collect();
    assert_eq!(sizes.len(), 2, "{sizes:?}");
    assert_eq!(sizes[0], 256);
    assert!(sizes[1] > 0 && sizes[1] < 256, "{sizes:?}");
}
