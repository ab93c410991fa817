//! Host side of tessera: renders frames tile by tile with the core, assembles the
//! tiles into an [`image::RgbImage`] or streams them into a PNG a row of tiles at a
//! time ([`render_png`]), and writes files without ever leaving a half-written file
//! behind ([`output`]). What each command may ask for is bounded ([`limits`]).

pub mod compare;
pub mod desc;
pub mod file;
pub mod reference;
pub mod simulate;
pub mod trade;

use image::RgbImage;
use std::fmt;
use std::io::{Seek, Write};
use std::path::Path;
use tessera::{Camera, Frame, RayCount, RenderSettings, SceneView, Tile, TileCoord, Viewport};

/// The tile sizes the host can render with (the core fixes the size at compile
/// time; the host instantiates these three).
pub const TILE_SIZES: [usize; 3] = [8, 16, 32];

/// What can go wrong on the host.
#[derive(Debug)]
pub enum HostError {
    /// The core refused the scene, camera or settings.
    Core(tessera::Error),
    /// A tile size other than 8, 16 or 32.
    TileSize(usize),
    /// Writing the output failed.
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// A step with an output's temporary file failed (see [`output`]).
    Temp {
        /// The output file, as the user named it.
        target: String,
        /// The file that could not be created, written or renamed.
        temp: String,
        /// What was being done.
        step: TempStep,
        /// Why.
        source: std::io::Error,
    },
    /// An output that must not be written: not a regular file, the input, ...
    Refused {
        /// The output, as the user named it.
        path: String,
        /// Why.
        reason: String,
    },
    /// A request beyond a documented limit (see [`limits`]), refused before any work.
    Limit(String),
    /// Writing failed on a stream that does not know its file's name (the caller
    /// names it: [`output::Pending::error`]).
    Write(std::io::Error),
    /// Several steps failed (an all-or-nothing write that could not be undone).
    Files(String),
    /// Encoding the PNG failed.
    Encode(String),
    /// The thread pool could not be built.
    Threads(String),
}

/// The step of writing an output through its temporary file that failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TempStep {
    /// Creating the temporary file (next to the output).
    Create,
    /// Writing it (or flushing it to the disk).
    Write,
    /// Renaming it onto the output.
    Rename,
    /// Keeping a copy of the old output while several files are replaced.
    Backup,
}

impl fmt::Display for HostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Core(e) => write!(f, "{e}"),
            Self::TileSize(n) => write!(f, "tile size {n} is not one of 8, 16, 32"),
            Self::Io { path, source } => write!(f, "cannot write {path}: {source}"),
            Self::Temp {
                target,
                temp,
                step,
                source,
            } => {
                let what = match step {
                    TempStep::Create => "creating the temporary file",
                    TempStep::Write => "writing the temporary file",
                    TempStep::Rename => "renaming onto it the temporary file",
                    TempStep::Backup => "keeping a copy of the old file as",
                };
                write!(f, "cannot write {target}: {what} {temp} failed: {source}")
            }
            Self::Refused { path, reason } => write!(f, "refusing to write {path}: {reason}"),
            Self::Limit(e) | Self::Files(e) => f.write_str(e),
            Self::Write(e) => write!(f, "cannot write the output: {e}"),
            Self::Encode(e) => write!(f, "cannot encode the PNG: {e}"),
            Self::Threads(e) => write!(f, "cannot start the render threads: {e}"),
        }
    }
}

impl std::error::Error for HostError {}

impl From<tessera::Error> for HostError {
    fn from(e: tessera::Error) -> Self {
        Self::Core(e)
    }
}

/// Renders the whole frame tile by tile with tiles of `N x N`, in the order given
/// by `order` (a permutation of the tile indices, row-major; `None` = row-major).
pub fn render_tiles<const N: usize>(
    scene: &SceneView<'_>,
    frame: &Frame,
    order: Option<&[usize]>,
) -> Result<RgbImage, HostError> {
    let vp = frame.viewport();
    let mut img = RgbImage::new(u32::from(vp.width), u32::from(vp.height));
    let (across, down) = frame.tile_grid(N);
    let count = usize::from(across) * usize::from(down);
    let row_major: Vec<usize> = (0..count).collect();
    let order = order.unwrap_or(&row_major);
    let mut tile = Tile::<N>::new();
    for &i in order {
        let coord = TileCoord::new(
            (i % usize::from(across)) as u16,
            (i / usize::from(across)) as u16,
        );
        frame.render_tile(scene, coord, &mut tile)?;
        place(&mut img, &tile);
    }
    Ok(img)
}

/// Copies a rendered tile into its place in the image, row by row.
pub fn place<const N: usize>(img: &mut RgbImage, tile: &Tile<N>) {
    let width = img.width() as usize;
    place_in(img, width, 0, tile);
}

/// Copies a rendered tile into `buf`, an RGB buffer `width` pixels wide whose first
/// row is row `top` of the frame. Rows outside the buffer are skipped.
fn place_in<const N: usize>(buf: &mut [u8], width: usize, top: usize, tile: &Tile<N>) {
    let (x0, y0) = tile.origin();
    let (x0, y0) = (x0 as usize, y0 as usize);
    for (j, row) in tile.rows().enumerate() {
        let Some(y) = (y0 + j).checked_sub(top) else {
            continue;
        };
        let start = (y * width + x0) * 3;
        // Inside the buffer whenever the tile comes from a frame of its size.
        let Some(dst) = buf.get_mut(start..start + row.len() * 3) else {
            continue;
        };
        for (d, p) in dst.chunks_exact_mut(3).zip(row) {
            d.copy_from_slice(&[p.r, p.g, p.b]);
        }
    }
}

/// Renders tile `i` (row-major) of `frame`, counting its rays.
fn one_tile<const N: usize>(
    scene: &SceneView<'_>,
    frame: &Frame,
    across: usize,
    i: usize,
) -> Result<(Tile<N>, RayCount), tessera::Error> {
    let coord = TileCoord::new((i % across) as u16, (i / across) as u16);
    let mut tile = Tile::<N>::new();
    let mut rays = RayCount::default();
    frame.render_tile_counted(scene, coord, &mut tile, &mut rays)?;
    Ok((tile, rays))
}

/// Renders tiles `tiles` (row-major indices, `across` tiles a row) of `frame` on
/// the current rayon pool, in order, calling `on_tile` after each (for progress).
fn tiles_parallel<const N: usize>(
    scene: &SceneView<'_>,
    frame: &Frame,
    across: usize,
    tiles: std::ops::Range<usize>,
    on_tile: &(dyn Fn() + Sync),
) -> Result<Vec<(Tile<N>, RayCount)>, tessera::Error> {
    use rayon::prelude::*;
    tiles
        .into_par_iter()
        .map(|i| {
            let t = one_tile::<N>(scene, frame, across, i)?;
            on_tile();
            Ok(t)
        })
        .collect()
}

/// Renders every tile of `frame` with tiles of `N x N` on the current rayon pool,
/// calling `on_tile` after each tile (for progress), and assembles the image. The
/// bytes do not depend on the number of threads: a pixel depends only on its
/// coordinates, and each tile is placed where it belongs.
pub fn render_parallel<const N: usize>(
    scene: &SceneView<'_>,
    frame: &Frame,
    on_tile: &(dyn Fn() + Sync),
) -> Result<(RgbImage, RayCount), HostError> {
    let vp = frame.viewport();
    let (across, down) = frame.tile_grid(N);
    let across = usize::from(across);
    let count = across * usize::from(down);
    let tiles = tiles_parallel::<N>(scene, frame, across, 0..count, on_tile)?;
    let mut img = RgbImage::new(u32::from(vp.width), u32::from(vp.height));
    let mut rays = RayCount::default();
    for (tile, r) in &tiles {
        place(&mut img, tile);
        rays.add(r);
    }
    Ok((img, rays))
}

/// A pool of `threads` threads (0 = one per core), at most [`limits::MAX_THREADS`].
fn pool(threads: usize) -> Result<rayon::ThreadPool, HostError> {
    limits::threads(threads).map_err(HostError::Limit)?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| HostError::Threads(e.to_string()))
}

/// [`render_parallel`] for a tile size chosen at run time (8, 16 or 32), on a pool
/// of `threads` threads (0 = one per core, at most [`limits::MAX_THREADS`]).
pub fn render_with(
    scene: &SceneView<'_>,
    frame: &Frame,
    tile: usize,
    threads: usize,
    on_tile: &(dyn Fn() + Sync),
) -> Result<(RgbImage, RayCount), HostError> {
    pool(threads)?.install(|| match tile {
        8 => render_parallel::<8>(scene, frame, on_tile),
        16 => render_parallel::<16>(scene, frame, on_tile),
        32 => render_parallel::<32>(scene, frame, on_tile),
        n => Err(HostError::TileSize(n)),
    })
}

/// Renders `frame` with tiles of `tile` pixels (8, 16 or 32) on `threads` threads
/// (0 = one per core) and streams it into `out` as a PNG, one row of tiles at a
/// time: the memory taken is a band of rows of tiles as wide as the frame (enough
/// rows to keep the threads busy), never the whole image, so any frame the core
/// accepts renders in bounded memory. The bytes are those of [`write_png`] for the
/// same image. Calls `on_tile` after each tile; returns the rays cast and `out`.
/// Write errors come back as [`HostError::Write`].
pub fn render_png<W: Write + Seek + Send>(
    scene: &SceneView<'_>,
    frame: &Frame,
    tile: usize,
    threads: usize,
    on_tile: &(dyn Fn() + Sync),
    out: W,
) -> Result<(RayCount, W), HostError> {
    let pool = pool(threads)?;
    let threads = pool.current_num_threads();
    pool.install(|| match tile {
        8 => stream::<8, W>(scene, frame, threads, on_tile, out),
        16 => stream::<16, W>(scene, frame, threads, on_tile, out),
        32 => stream::<32, W>(scene, frame, threads, on_tile, out),
        n => Err(HostError::TileSize(n)),
    })
}

/// Rows of tiles rendered together: one, or as many as give every thread four
/// tiles when a row of tiles is short.
fn band_rows(across: usize, down: usize, threads: usize) -> usize {
    (4 * threads.max(1))
        .div_ceil(across.max(1))
        .clamp(1, down.max(1))
}

fn stream<const N: usize, W: Write + Seek + Send>(
    scene: &SceneView<'_>,
    frame: &Frame,
    threads: usize,
    on_tile: &(dyn Fn() + Sync),
    out: W,
) -> Result<(RayCount, W), HostError> {
    let vp = frame.viewport();
    let (width, height) = (usize::from(vp.width), usize::from(vp.height));
    let (across, down) = frame.tile_grid(N);
    let (across, down) = (usize::from(across), usize::from(down));
    let group = band_rows(across, down, threads);
    let mut png = png::PngStream::new(out, u32::from(vp.width), u32::from(vp.height))
        .map_err(HostError::Write)?;
    let mut band = vec![0u8; width * 3 * N * group];
    let mut rays = RayCount::default();
    for first in (0..down).step_by(group) {
        let rows = group.min(down - first);
        let band_tiles = first * across..(first + rows) * across;
        let tiles = tiles_parallel::<N>(scene, frame, across, band_tiles, on_tile)?;
        let top = first * N;
        for (tile, r) in &tiles {
            place_in(&mut band, width, top, tile);
            rays.add(r);
        }
        let visible = ((first + rows) * N).min(height) - top;
        for row in band.chunks_exact(width * 3).take(visible) {
            png.write_row(row).map_err(HostError::Write)?;
        }
    }
    let out = png.finish().map_err(HostError::Write)?;
    Ok((rays, out))
}

/// Renders `scene` seen by `camera` at `viewport` with `settings`, in tiles of
/// `tile` pixels (8, 16 or 32), one after the other on this thread.
pub fn render(
    scene: &SceneView<'_>,
    camera: &Camera,
    viewport: Viewport,
    settings: RenderSettings,
    tile: usize,
) -> Result<RgbImage, HostError> {
    let frame = Frame::try_new(camera, viewport, settings)?;
    match tile {
        8 => render_tiles::<8>(scene, &frame, None),
        16 => render_tiles::<16>(scene, &frame, None),
        32 => render_tiles::<32>(scene, &frame, None),
        n => Err(HostError::TileSize(n)),
    }
}

/// Encodes `img` as a PNG into `out` (see [`png::PngStream`]).
pub fn encode_png<W: Write + Seek>(img: &RgbImage, out: W) -> std::io::Result<W> {
    let mut png = png::PngStream::new(out, img.width(), img.height())?;
    let row = img.width() as usize * 3;
    if row > 0 {
        for r in img.as_raw().chunks_exact(row) {
            png.write_row(r)?;
        }
    }
    png.finish()
}

/// Writes `img` as a PNG at `path` atomically (see [`output`]).
pub fn write_png(img: &RgbImage, path: &Path) -> Result<(), HostError> {
    output::write_with(path, &[], |f| {
        encode_png(img, f).map(|_| ()).map_err(HostError::Write)
    })
}

/// Writes `bytes` at `path` atomically: they go to a temporary file in the same
/// folder, which is then renamed over `path`. An existing file at `path` is either
/// replaced whole or left untouched, and no temporary file is left behind (see
/// [`output`] for what is refused and how symbolic links are followed).
pub fn write_atomic(bytes: &[u8], path: &Path) -> Result<(), HostError> {
    output::write_with(path, &[], |f| f.write_all(bytes).map_err(HostError::Write))
}

pub mod png {
    //! A PNG encoder fed one row at a time: 8-bit RGB, the Paeth filter on every
    //! row, and the `png` crate's fast compression (fdeflate), one `write_data` call
    //! per filtered row as `png::Writer::write_image_data` makes them. So a file is
    //! byte for byte what `image`'s `PngEncoder` with `CompressionType::Fast` and
    //! `FilterType::Paeth` writes for the whole image (tested), with one exception:
    //! when fast compression makes an image larger than stored blocks would (noise,
    //! tiny images), that encoder starts again with stored blocks. The stream does
    //! the same for images up to [`KEEP_RAW`] bytes (it keeps them until the end);
    //! a larger one keeps its compressed data, a few percent larger than stored,
    //! with the same pixels.
    //!
    //! Why Paeth and fast compression: measured on the four built-in scenes at
    //! 320x240 against the adaptive filter (which tries all five filters per row):
    //! files within 1 % (27,059 vs 27,175 bytes on chapter-direct, 2,553 vs 2,523 on
    //! interference, 62,050 vs 61,472 on showcase) for 0.65 M fewer of the 42.7 M
    //! instructions of a whole chapter-reflect run (callgrind). Up and Average cost
    //! less still but give files 1.3-1.6 times larger (Average 58 times on
    //! interference), Sub triples smooth images such as docs/interference.png.
    //!
    //! The compressed data goes into one IDAT chunk (split at 2^31 - 1 bytes, as the
    //! `png` crate splits it) whose length is written when the chunk ends, so the
    //! output must be seekable; the memory taken is two rows (and up to [`KEEP_RAW`]
    //! bytes for a small image).

    use std::cell::RefCell;
    use std::io::{self, Seek, SeekFrom, Write};
    use std::rc::Rc;

    const SIGNATURE: [u8; 8] = [137, 80, 78, 71, 13, 10, 26, 10];

    /// The largest IDAT chunk the `png` crate writes.
    pub const MAX_CHUNK: u64 = (u32::MAX >> 1) as u64;

    /// The compressor's output, drained into the file after every row. (fdeflate
    /// unwraps some of its writes, so it writes into memory, which cannot fail,
    /// and the file's errors are returned here.)
    #[derive(Clone, Default)]
    struct Shared(Rc<RefCell<Vec<u8>>>);

    impl Write for Shared {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.0.borrow_mut().extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    /// The IDAT chunk being written: where its length goes, its length, its CRC.
    struct Chunk {
        at: u64,
        len: u64,
        crc: crc32fast::Hasher,
    }

    /// A PNG being written row by row; see the module documentation.
    pub struct PngStream<W: Write + Seek> {
        out: W,
        zlib: Option<fdeflate::Compressor<Shared>>,
        compressed: Shared,
        chunk: Option<Chunk>,
        max_chunk: u64,
        prev: Vec<u8>,
        current: Vec<u8>,
        rows_left: u32,
        /// The rows as given, while the image is small enough ([`KEEP_RAW`]):
        /// needed if fast compression turns out larger than stored blocks.
        raw: Option<Vec<u8>>,
    }

    /// Up to this many bytes of rows the stream keeps the rows and the compressed
    /// data in memory, and at the end makes the same choice as the whole-image
    /// encoder between the compressed data and stored blocks; past it, the rows
    /// are dropped and the compressed data goes to the output as it comes.
    pub const KEEP_RAW: usize = 1 << 20;

    fn invalid(msg: String) -> io::Error {
        io::Error::new(io::ErrorKind::InvalidInput, msg)
    }

    fn write_chunk(w: &mut impl Write, kind: &[u8; 4], data: &[u8]) -> io::Result<()> {
        let len = u32::try_from(data.len()).map_err(|_| invalid("chunk too long".into()))?;
        w.write_all(&len.to_be_bytes())?;
        w.write_all(kind)?;
        w.write_all(data)?;
        let mut crc = crc32fast::Hasher::new();
        crc.update(kind);
        crc.update(data);
        w.write_all(&crc.finalize().to_be_bytes())
    }

    impl<W: Write + Seek> PngStream<W> {
        /// Writes the signature and the header of a `width x height` RGB image.
        pub fn new(out: W, width: u32, height: u32) -> io::Result<Self> {
            Self::with_max_chunk(out, width, height, MAX_CHUNK)
        }

        /// [`PngStream::new`] with IDAT chunks of at most `max_chunk` bytes.
        pub fn with_max_chunk(
            mut out: W,
            width: u32,
            height: u32,
            max_chunk: u64,
        ) -> io::Result<Self> {
            if width == 0 || height == 0 || max_chunk == 0 || max_chunk > MAX_CHUNK {
                return Err(invalid(format!(
                    "a PNG of {width}x{height} pixels in chunks of {max_chunk} bytes"
                )));
            }
            let row = usize::try_from(width)
                .ok()
                .and_then(|w| w.checked_mul(3))
                .ok_or_else(|| invalid(format!("a PNG {width} pixels wide")))?;
            out.write_all(&SIGNATURE)?;
            let mut ihdr = [0u8; 13];
            ihdr[..4].copy_from_slice(&width.to_be_bytes());
            ihdr[4..8].copy_from_slice(&height.to_be_bytes());
            ihdr[8] = 8; // bits per channel
            ihdr[9] = 2; // RGB; compression, filter method, interlace: 0
            write_chunk(&mut out, b"IHDR", &ihdr)?;
            let compressed = Shared::default();
            let zlib = fdeflate::Compressor::new(compressed.clone())?;
            let stream = Self {
                out,
                zlib: Some(zlib),
                compressed,
                chunk: None,
                max_chunk,
                prev: vec![0; row],
                current: vec![0; row + 1],
                rows_left: height,
                raw: Some(Vec::new()),
            };
            Ok(stream)
        }

        /// Filters, compresses and writes the next row (`3 x width` bytes).
        pub fn write_row(&mut self, row: &[u8]) -> io::Result<()> {
            if row.len() != self.prev.len() || self.rows_left == 0 {
                return Err(invalid(format!(
                    "a row of {} bytes ({} rows left, {} bytes each)",
                    row.len(),
                    self.rows_left,
                    self.prev.len()
                )));
            }
            let Some(zlib) = self.zlib.as_mut() else {
                return Err(invalid("the PNG is finished".into()));
            };
            paeth_row(&self.prev, row, &mut self.current);
            zlib.write_data(&self.current)?;
            self.prev.copy_from_slice(row);
            self.rows_left -= 1;
            if let Some(raw) = self.raw.as_mut() {
                if raw.len() + row.len() <= KEEP_RAW {
                    raw.extend_from_slice(row);
                    return Ok(());
                }
                self.raw = None;
            }
            self.drain()
        }

        /// Ends the compressed data and the file, and returns the output.
        pub fn finish(mut self) -> io::Result<W> {
            if self.rows_left != 0 {
                return Err(invalid(format!("{} rows missing", self.rows_left)));
            }
            if let Some(zlib) = self.zlib.take() {
                zlib.finish()?;
            }
            if let Some(raw) = self.raw.take() {
                let row = self.prev.len();
                let stored_size = fdeflate::StoredOnlyCompressor::<()>::compressed_size(
                    (row + 1) * (raw.len() / row.max(1)),
                );
                if self.compressed.0.borrow().len() > stored_size {
                    // As `png` does: unfiltered rows in stored blocks.
                    let mut stored =
                        fdeflate::StoredOnlyCompressor::new(io::Cursor::new(Vec::new()))?;
                    for line in raw.chunks_exact(row.max(1)) {
                        stored.write_data(&[0])?;
                        stored.write_data(line)?;
                    }
                    *self.compressed.0.borrow_mut() = stored.finish()?.into_inner();
                }
            }
            self.drain()?;
            self.close_chunk()?;
            write_chunk(&mut self.out, b"IEND", &[])?;
            self.out.flush()?;
            Ok(self.out)
        }

        /// Moves the compressed bytes into IDAT chunks.
        fn drain(&mut self) -> io::Result<()> {
            let bytes = std::mem::take(&mut *self.compressed.0.borrow_mut());
            let mut rest = bytes.as_slice();
            while !rest.is_empty() {
                if self.chunk.as_ref().is_some_and(|c| c.len >= self.max_chunk) {
                    self.close_chunk()?;
                }
                let chunk = match self.chunk.as_mut() {
                    Some(c) => c,
                    None => {
                        let at = self.out.stream_position()?;
                        self.out.write_all(&[0, 0, 0, 0])?;
                        self.out.write_all(b"IDAT")?;
                        let mut crc = crc32fast::Hasher::new();
                        crc.update(b"IDAT");
                        self.chunk.insert(Chunk { at, len: 0, crc })
                    }
                };
                let room = usize::try_from(self.max_chunk - chunk.len).unwrap_or(usize::MAX);
                let (now, later) = rest.split_at(rest.len().min(room));
                self.out.write_all(now)?;
                chunk.crc.update(now);
                chunk.len += now.len() as u64;
                rest = later;
            }
            Ok(())
        }

        /// Writes the open chunk's CRC and, at its start, its length.
        fn close_chunk(&mut self) -> io::Result<()> {
            let Some(chunk) = self.chunk.take() else {
                return Ok(());
            };
            self.out.write_all(&chunk.crc.finalize().to_be_bytes())?;
            let end = self.out.stream_position()?;
            let len = u32::try_from(chunk.len).map_err(|_| invalid("chunk too long".into()))?;
            self.out.seek(SeekFrom::Start(chunk.at))?;
            self.out.write_all(&len.to_be_bytes())?;
            self.out.seek(SeekFrom::Start(end))?;
            Ok(())
        }
    }

    /// The Paeth predictor of PNG.
    fn paeth(a: u8, b: u8, c: u8) -> u8 {
        let (ia, ib, ic) = (i16::from(a), i16::from(b), i16::from(c));
        let pa = (ib - ic).abs();
        let pb = (ia - ic).abs();
        let pc = (ia + ib - 2 * ic).abs();
        if pa <= pb && pa <= pc {
            a
        } else if pb <= pc {
            b
        } else {
            c
        }
    }

    /// `out` = the Paeth filter type (4) and `row` filtered against `prev`.
    fn paeth_row(prev: &[u8], row: &[u8], out: &mut [u8]) {
        let Some((kind, out)) = out.split_first_mut() else {
            return;
        };
        *kind = 4;
        for (i, o) in out.iter_mut().enumerate().take(row.len()) {
            let (a, c) = if i >= 3 {
                (row[i - 3], prev[i - 3])
            } else {
                (0, 0)
            };
            *o = row[i].wrapping_sub(paeth(a, prev[i], c));
        }
    }
}

pub mod output {
    //! Output files, written so that a failure or an interruption never leaves a
    //! half-written file or a stray temporary file, and never replaces what the
    //! user did not name.
    //!
    //! - Each output is written to a temporary file in the folder of the file it
    //!   replaces, named `.tessera-PID-N.tmp` (short whatever the output's name),
    //!   then renamed onto it: an existing file is replaced whole or left untouched.
    //! - An output is checked before any work ([`Target::check`]): an existing
    //!   output that is not a regular file (a folder, a device, a FIFO, a socket) is
    //!   refused, and so is the input scene file (compared by identity: device and
    //!   inode, so another path or a hard link to it is caught).
    //! - A symbolic link is followed (through a chain of links, also a dangling one):
    //!   the file it names is written and the link stays. A link to a folder is
    //!   refused like the folder.
    //! - Several outputs ([`commit`]) are all or nothing: every temporary file is
    //!   written first, then all are renamed; if a rename fails the outputs already
    //!   replaced get their old contents back (kept as hard links, or copies, until
    //!   the end) and no temporary file remains.
    //! - With [`clean_up_on_signals`], SIGINT, SIGTERM and SIGHUP remove the
    //!   temporary files before the process dies of the signal, and SIGXFSZ (a file
    //!   size limit, `ulimit -f`) makes the write fail with an error, which removes
    //!   them too.

    use super::{HostError, TempStep};
    use std::fs::{self, File, OpenOptions};
    use std::io::{self, BufWriter, Seek, SeekFrom, Write};
    use std::path::{Path, PathBuf};
    use std::sync::atomic::{AtomicU64, Ordering};
    use std::sync::{Mutex, MutexGuard, PoisonError};

    /// The temporary files that exist now (removed on a signal).
    static TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
    /// The number of the next temporary file of this process.
    static NEXT: AtomicU64 = AtomicU64::new(0);

    fn temps() -> MutexGuard<'static, Vec<PathBuf>> {
        TEMPS.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Removes the temporary files, then lets SIGINT, SIGTERM and SIGHUP end the
    /// process as they would have; SIGXFSZ turns into a write error (`File too
    /// large`). The signal handler only wakes a thread (signal-hook's self-pipe),
    /// which does the work outside the handler: it takes the lock of the list of
    /// temporary files (so a rename in progress finishes first, and no later one
    /// starts), removes them and re-raises the signal with its default action.
    #[cfg(unix)]
    pub fn clean_up_on_signals() -> Result<(), HostError> {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};
        let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP, SIGXFSZ])
            .map_err(|e| HostError::Files(format!("cannot handle signals: {e}")))?;
        std::thread::Builder::new()
            .name("tessera-signals".into())
            .spawn(move || {
                for signal in signals.forever() {
                    if signal == SIGXFSZ {
                        continue;
                    }
                    let mut list = temps();
                    for p in list.drain(..) {
                        let _ = fs::remove_file(p);
                    }
                    // Dies of the signal (the lock stays taken until then).
                    let _ = signal_hook::low_level::emulate_default_handler(signal);
                    std::process::exit(128 + signal);
                }
            })
            .map_err(|e| HostError::Files(format!("cannot handle signals: {e}")))?;
        Ok(())
    }

    /// Without Unix signals there is nothing to install.
    #[cfg(not(unix))]
    pub fn clean_up_on_signals() -> Result<(), HostError> {
        Ok(())
    }

    /// An output checked before any work is done: the file that will be written.
    #[derive(Clone, Debug, PartialEq, Eq)]
    pub struct Target {
        shown: PathBuf,
        file: PathBuf,
    }

    fn refused(path: &Path, reason: impl Into<String>) -> HostError {
        HostError::Refused {
            path: path.display().to_string(),
            reason: reason.into(),
        }
    }

    /// What a file that is not a regular file is.
    fn kind(t: &fs::FileType) -> &'static str {
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            if t.is_char_device() {
                return "a character device";
            }
            if t.is_block_device() {
                return "a block device";
            }
            if t.is_fifo() {
                return "a FIFO (named pipe)";
            }
            if t.is_socket() {
                return "a socket";
            }
        }
        if t.is_dir() {
            "a folder"
        } else {
            "not a regular file"
        }
    }

    /// Whether two metadata describe the same file.
    fn same_file(a: &fs::Metadata, a_path: &Path, b: &Path) -> bool {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            let _ = a_path;
            fs::metadata(b).is_ok_and(|m| m.dev() == a.dev() && m.ino() == a.ino())
        }
        #[cfg(not(unix))]
        {
            let _ = a;
            match (fs::canonicalize(a_path), fs::canonicalize(b)) {
                (Ok(x), Ok(y)) => x == y,
                _ => false,
            }
        }
    }

    impl Target {
        /// Checks that `path` may be written, following symbolic links, without
        /// touching anything: refused if it is empty, an existing folder, device,
        /// FIFO or socket (also through a link), or one of `inputs`.
        pub fn check(path: &Path, inputs: &[&Path]) -> Result<Self, HostError> {
            if path.as_os_str().is_empty() {
                return Err(refused(path, "the file name is empty"));
            }
            let mut file = path.to_path_buf();
            let mut links = 0;
            let meta = loop {
                match fs::symlink_metadata(&file) {
                    Ok(m) if m.file_type().is_symlink() => {
                        links += 1;
                        if links > 40 {
                            return Err(refused(path, "too many levels of symbolic links"));
                        }
                        let to = fs::read_link(&file).map_err(|source| HostError::Io {
                            path: file.display().to_string(),
                            source,
                        })?;
                        file = match file.parent() {
                            Some(dir) if to.is_relative() => dir.join(to),
                            _ => to,
                        };
                    }
                    Ok(m) => break Some(m),
                    Err(e) if e.kind() == io::ErrorKind::NotFound => break None,
                    Err(source) => {
                        return Err(HostError::Io {
                            path: file.display().to_string(),
                            source,
                        });
                    }
                }
            };
            let through = if file == path {
                String::new()
            } else {
                format!(" (the symbolic link's target {})", file.display())
            };
            if let Some(m) = &meta {
                if !m.is_file() {
                    return Err(refused(
                        path,
                        format!(
                            "it is {}{through}, not a regular file",
                            kind(&m.file_type())
                        ),
                    ));
                }
                if let Some(input) = inputs.iter().find(|i| same_file(m, &file, i)) {
                    return Err(refused(
                        path,
                        format!(
                            "it is the input scene file {}{through}; choose another output",
                            input.display()
                        ),
                    ));
                }
            }
            Ok(Self {
                shown: path.to_path_buf(),
                file,
            })
        }

        /// [`Target::check`] for several outputs, which must be different files.
        pub fn check_all(paths: &[PathBuf], inputs: &[&Path]) -> Result<Vec<Self>, HostError> {
            let mut out: Vec<Self> = Vec::with_capacity(paths.len());
            for p in paths {
                let t = Self::check(p, inputs)?;
                if let Some(first) = out.iter().find(|o| o.file == t.file) {
                    return Err(refused(
                        p,
                        format!("{} names the same file", first.shown.display()),
                    ));
                }
                out.push(t);
            }
            Ok(out)
        }

        /// The output as the user named it.
        #[must_use]
        pub fn path(&self) -> &Path {
            &self.shown
        }

        /// The file that will be written (after following symbolic links).
        #[must_use]
        pub fn file(&self) -> &Path {
            &self.file
        }

        fn folder(&self) -> PathBuf {
            match self.file.parent() {
                Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
                _ => PathBuf::from("."),
            }
        }

        fn error(&self, step: TempStep, temp: &Path, source: io::Error) -> HostError {
            HostError::Temp {
                target: self.shown.display().to_string(),
                temp: temp.display().to_string(),
                step,
                source,
            }
        }
    }

    /// A new file next to `target` with a short name of its own (never an existing
    /// one), in the list of temporary files while `list` is held.
    fn create_temp(
        target: &Target,
        list: &mut Vec<PathBuf>,
        suffix: &str,
    ) -> Result<(PathBuf, File), HostError> {
        let dir = target.folder();
        let pid = std::process::id();
        let mut last = None;
        for _ in 0..100 {
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let temp = dir.join(format!(".tessera-{pid}-{n}.{suffix}"));
            match OpenOptions::new().write(true).create_new(true).open(&temp) {
                Ok(f) => {
                    list.push(temp.clone());
                    return Ok((temp, f));
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = Some(e),
                Err(e) => return Err(target.error(TempStep::Create, &temp, e)),
            }
        }
        let temp = dir.join(format!(".tessera-{pid}-N.{suffix}"));
        Err(target.error(
            TempStep::Create,
            &temp,
            last.unwrap_or_else(|| io::Error::other("no free name")),
        ))
    }

    fn forget(list: &mut Vec<PathBuf>, p: &Path) {
        list.retain(|q| q != p);
    }

    /// An output being written: its temporary file, removed when this is dropped
    /// unless [`commit`] renamed it onto the output. Write into it with
    /// [`Write`]/[`Seek`]; the first write error is kept and reported, naming the
    /// temporary file, by [`Pending::finish`] (or [`Pending::error`]).
    pub struct Pending {
        target: Target,
        temp: PathBuf,
        file: Option<BufWriter<File>>,
        failed: Option<io::Error>,
        done: bool,
    }

    impl Pending {
        /// Creates the temporary file for `target` (with the permissions of the
        /// file it will replace, if any).
        pub fn create(target: Target) -> Result<Self, HostError> {
            let (temp, file) = create_temp(&target, &mut temps(), "tmp")?;
            let pending = Self {
                target,
                temp,
                file: Some(BufWriter::with_capacity(1 << 16, file)),
                failed: None,
                done: false,
            };
            if let Ok(m) = fs::metadata(&pending.target.file) {
                let _ = fs::set_permissions(&pending.temp, m.permissions());
            }
            Ok(pending)
        }

        /// The output.
        #[must_use]
        pub fn target(&self) -> &Target {
            &self.target
        }

        /// The temporary file.
        #[must_use]
        pub fn temp(&self) -> &Path {
            &self.temp
        }

        /// `e`, or the write error this file met first (which caused it), naming
        /// the temporary file.
        pub fn error(&mut self, e: HostError) -> HostError {
            match (self.failed.take(), e) {
                (Some(source), _) | (None, HostError::Write(source)) => {
                    self.target.error(TempStep::Write, &self.temp, source)
                }
                (None, e) => e,
            }
        }

        /// Flushes the file to the disk and closes it.
        pub fn finish(&mut self) -> Result<(), HostError> {
            if let Some(source) = self.failed.take() {
                return Err(self.target.error(TempStep::Write, &self.temp, source));
            }
            let Some(file) = self.file.take() else {
                return Ok(());
            };
            file.into_inner()
                .map_err(io::IntoInnerError::into_error)
                .and_then(|f| f.sync_all())
                .map_err(|e| self.target.error(TempStep::Write, &self.temp, e))
        }

        fn io<T>(
            &mut self,
            op: impl FnOnce(&mut BufWriter<File>) -> io::Result<T>,
        ) -> io::Result<T> {
            if let Some(e) = &self.failed {
                return Err(io::Error::new(e.kind(), e.to_string()));
            }
            let Some(file) = self.file.as_mut() else {
                return Err(io::Error::other("the file is already closed"));
            };
            op(file).inspect_err(|e| self.failed = Some(io::Error::new(e.kind(), e.to_string())))
        }
    }

    impl Write for Pending {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.io(|f| f.write(buf))
        }
        fn flush(&mut self) -> io::Result<()> {
            self.io(Write::flush)
        }
    }

    impl Seek for Pending {
        fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
            self.io(|f| f.seek(pos))
        }
    }

    impl Drop for Pending {
        fn drop(&mut self) {
            if !self.done {
                self.file = None;
                let mut list = temps();
                let _ = fs::remove_file(&self.temp);
                forget(&mut list, &self.temp);
            }
        }
    }

    /// Finishes every file and renames each onto its output, all or nothing: on
    /// any failure no output is changed (those already renamed get their old
    /// contents back) and every temporary file is removed.
    pub fn commit(mut files: Vec<Pending>) -> Result<(), HostError> {
        for f in &mut files {
            f.finish()?;
        }
        let mut list = temps();
        let result = rename_all(&mut files, &mut list);
        drop(list);
        result
    }

    fn rename_all(files: &mut [Pending], list: &mut Vec<PathBuf>) -> Result<(), HostError> {
        if let [one] = files {
            fs::rename(&one.temp, &one.target.file)
                .map_err(|e| one.target.error(TempStep::Rename, &one.temp, e))?;
            one.done = true;
            forget(list, &one.temp);
            return Ok(());
        }
        // The old contents of the outputs that exist, to put back on a failure.
        let mut backups: Vec<Option<PathBuf>> = Vec::with_capacity(files.len());
        let mut failure = None;
        for f in files.iter() {
            if failure.is_some() || !f.target.file.is_file() {
                backups.push(None);
                continue;
            }
            match create_temp(&f.target, list, "old") {
                Ok((b, file)) => {
                    drop(file);
                    let kept = fs::remove_file(&b)
                        .and_then(|()| fs::hard_link(&f.target.file, &b))
                        .or_else(|_| fs::copy(&f.target.file, &b).map(|_| ()));
                    if let Err(e) = kept {
                        failure = Some(f.target.error(TempStep::Backup, &b, e));
                    }
                    backups.push(Some(b));
                }
                Err(e) => {
                    failure = Some(e);
                    backups.push(None);
                }
            }
        }
        let mut renamed = 0;
        if failure.is_none() {
            for f in files.iter() {
                if let Err(e) = fs::rename(&f.temp, &f.target.file) {
                    failure = Some(f.target.error(TempStep::Rename, &f.temp, e));
                    break;
                }
                renamed += 1;
            }
        }
        let mut problems = Vec::new();
        if failure.is_some() {
            // Put back what was replaced.
            for (f, b) in files.iter().zip(&backups).take(renamed) {
                let undone = match b {
                    Some(b) => fs::rename(b, &f.target.file),
                    None => fs::remove_file(&f.target.file),
                };
                if let Err(e) = undone {
                    problems.push(match b {
                        Some(b) => format!(
                            "restoring {} from {} failed ({e}): the old contents are in {}",
                            f.target.shown.display(),
                            b.display(),
                            b.display()
                        ),
                        None => {
                            format!("removing the new {} failed: {e}", f.target.shown.display())
                        }
                    });
                }
            }
        } else {
            for f in files.iter_mut() {
                f.done = true;
                forget(list, &f.temp);
            }
        }
        for b in backups.iter().flatten() {
            if problems.iter().all(|p| !p.contains(&*b.to_string_lossy())) {
                let _ = fs::remove_file(b);
            }
            forget(list, b);
        }
        match failure {
            None => Ok(()),
            Some(e) if problems.is_empty() => Err(e),
            Some(e) => Err(HostError::Files(format!("{e}; {}", problems.join("; ")))),
        }
    }

    /// Checks `path` (see [`Target::check`]), writes it through a temporary file
    /// with `write`, and renames it onto `path`.
    pub fn write_with(
        path: &Path,
        inputs: &[&Path],
        write: impl FnOnce(&mut Pending) -> Result<(), HostError>,
    ) -> Result<(), HostError> {
        let mut pending = Pending::create(Target::check(path, inputs)?)?;
        if let Err(e) = write(&mut pending) {
            return Err(pending.error(e));
        }
        commit(vec![pending])
    }
}

pub mod limits {
    //! What each command may be asked for, checked before any work starts; a
    //! request beyond a limit is refused with the figure it would need.
    //!
    //! - Render threads: at most [`MAX_THREADS`] (0 = one per core).
    //! - `render`: no size limit: it streams the PNG a row of tiles at a time, in
    //!   memory proportional to the width (see [`crate::render_png`]).
    //! - `compare` and `trade`: at most [`flip_pixels`] pixels (about 28.5 million,
    //!   e.g. 5,300 x 5,300): FLIP refuses more than 2^34 filter operations at its
    //!   default 67 pixels per degree. They keep whole images (about 120 bytes a
    //!   pixel: 3.4 GB at that size). `trade` runs at most [`MAX_RUNS`] timed runs.
    //! - `simulate`: the simulated panel keeps whole frames: at most
    //!   [`MEMORY_LIMIT`] bytes, counted as [`SIMULATE_BYTES_PER_PIXEL`] per pixel
    //!   for the frame being drawn and 3 more per pixel of each frame kept for
    //!   `--window`; an orbit has at most [`MAX_ORBIT_FRAMES`] frames.

    use super::HostError;
    use tessera::Viewport;

    /// The most render threads.
    pub const MAX_THREADS: usize = 256;
    /// The most memory a command may plan to take (4 GiB).
    pub const MEMORY_LIMIT: u64 = 4 << 30;
    /// Memory per pixel of the frame `simulate` draws: the panel's buffer, its RGB
    /// picture, the copy handed back, and the GIF encoder's RGBA copy and indices.
    pub const SIMULATE_BYTES_PER_PIXEL: u64 = 16;
    /// The most frames of an orbit (one per tenth of a degree).
    pub const MAX_ORBIT_FRAMES: u32 = 3600;
    /// The most timed runs per setting of `trade`.
    pub const MAX_RUNS: usize = 1000;

    /// `n` with thousands separators.
    #[must_use]
    pub fn thousands(n: u64) -> String {
        let digits = n.to_string();
        let mut out = String::new();
        for (i, c) in digits.chars().enumerate() {
            if i > 0 && (digits.len() - i) % 3 == 0 {
                out.push(',');
            }
            out.push(c);
        }
        out
    }

    /// A byte count for people: `1.5 GiB`, `300.0 MiB`, `12 bytes`.
    #[must_use]
    pub fn bytes(n: u64) -> String {
        const UNITS: [(&str, u64); 4] = [
            ("TiB", 1 << 40),
            ("GiB", 1 << 30),
            ("MiB", 1 << 20),
            ("KiB", 1 << 10),
        ];
        UNITS.iter().find(|(_, u)| n >= *u).map_or_else(
            || format!("{n} bytes"),
            |(name, u)| format!("{:.1} {name}", n as f64 / *u as f64),
        )
    }

    /// Checks a thread count (0 = one per core).
    pub fn threads(n: usize) -> Result<usize, String> {
        if n > MAX_THREADS {
            return Err(format!(
                "{n} render threads is more than the {MAX_THREADS} allowed (0 = one per core, {} here)",
                std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
            ));
        }
        Ok(n)
    }

    /// The most pixels FLIP measures at the default pixels per degree: its filter
    /// work, `pixels x (16 x spatial taps + 14 x feature taps)`, is at most 2^34
    /// (flip-rs computes the taps in f32 as here).
    #[must_use]
    pub fn flip_pixels() -> u64 {
        use std::f32::consts::PI;
        let ppd = flip_rs::DEFAULT_PPD;
        let radius = (3.0 * (0.04 / (2.0 * (PI * PI))).sqrt() * ppd).ceil();
        let feature_radius = (3.0 * (0.5 * 0.082 * ppd)).ceil();
        let spatial = 2 * radius as u64 + 1;
        let feature = 2 * feature_radius as u64 + 1;
        (1u64 << 34) / (16 * spatial + 14 * feature)
    }

    fn pixels(vp: Viewport) -> u64 {
        u64::from(vp.width) * u64::from(vp.height)
    }

    /// Checks that `command` (compare, trade) can measure a `vp` image with FLIP.
    pub fn measured(command: &str, vp: Viewport) -> Result<(), HostError> {
        let (n, max) = (pixels(vp), flip_pixels());
        if n > max {
            let side = (max as f64).sqrt().floor() as u64;
            return Err(HostError::Limit(format!(
                "{command} at {}x{}: {} pixels is more than the {} that FLIP can measure (2^34 filter operations at {:.0} pixels per degree), e.g. {side}x{side}: choose a smaller --size",
                vp.width,
                vp.height,
                thousands(n),
                thousands(max),
                flip_rs::DEFAULT_PPD,
            )));
        }
        Ok(())
    }

    /// Checks the memory of `simulate`: `frames` frames of `vp`, all kept when
    /// `keep` (for the window).
    pub fn simulated(vp: Viewport, frames: u32, keep: bool) -> Result<(), HostError> {
        if frames == 0 || frames > MAX_ORBIT_FRAMES {
            return Err(HostError::Limit(format!(
                "--orbit {frames}: an orbit has 1 to {MAX_ORBIT_FRAMES} frames"
            )));
        }
        let kept = if keep { u64::from(frames) * 3 } else { 0 };
        let need = pixels(vp) * (SIMULATE_BYTES_PER_PIXEL + kept);
        if need > MEMORY_LIMIT {
            return Err(HostError::Limit(format!(
                "simulate at {}x{}{}: the simulated panel would need {} ({} bytes), more than the limit of {}: choose a smaller --size{}",
                vp.width,
                vp.height,
                if keep {
                    format!(", {frames} frame(s) kept for the window")
                } else {
                    String::new()
                },
                bytes(need),
                thousands(need),
                bytes(MEMORY_LIMIT),
                if keep { " or fewer frames" } else { "" }
            )));
        }
        Ok(())
    }

    /// Checks the runs of `trade`.
    pub fn runs(n: usize) -> Result<usize, HostError> {
        if n > MAX_RUNS {
            return Err(HostError::Limit(format!(
                "--runs {n}: at most {MAX_RUNS} timed runs per setting"
            )));
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use tessera::builtin::Builtin;

    /// What `write_png` wrote before it streamed: `image`'s encoder, whole image.
    fn image_png(img: &RgbImage) -> Vec<u8> {
        use image::ImageEncoder;
        use image::codecs::png::{CompressionType, FilterType, PngEncoder};
        let mut bytes = Vec::new();
        PngEncoder::new_with_quality(&mut bytes, CompressionType::Fast, FilterType::Paeth)
            .write_image(
                img,
                img.width(),
                img.height(),
                image::ExtendedColorType::Rgb8,
            )
            .unwrap();
        bytes
    }

    fn streamed(img: &RgbImage) -> Vec<u8> {
        encode_png(img, Cursor::new(Vec::new()))
            .unwrap()
            .into_inner()
    }

    fn frame(b: Builtin, w: u16, h: u16, f: impl FnOnce(&SceneView<'_>, &Frame)) {
        b.with_scene(|view, cam| {
            let frame = Frame::try_new(cam, Viewport::new(w, h), b.settings()).unwrap();
            f(view, &frame);
        })
        .unwrap();
    }

    #[test]
    fn the_streamed_png_has_the_bytes_of_the_whole_image_encoder() {
        let mut pattern = RgbImage::new(97, 61);
        for (x, y, p) in pattern.enumerate_pixels_mut() {
            *p = image::Rgb([(x * 3) as u8, (y * 5) as u8, ((x ^ y) * 7) as u8]);
        }
        let flat = RgbImage::from_pixel(33, 7, image::Rgb([10, 200, 30]));
        let dot = RgbImage::from_pixel(1, 1, image::Rgb([1, 2, 3]));
        let mut scenes = Vec::new();
        for b in Builtin::ALL {
            frame(b, 160, 120, |v, f| {
                scenes.push(render_tiles::<16>(v, f, None).unwrap());
            });
        }
        for img in [pattern, flat, dot].iter().chain(&scenes) {
            assert_eq!(streamed(img), image_png(img), "{:?}", img.dimensions());
        }
    }

    #[test]
    fn noise_and_small_chunks_decode_to_the_same_pixels() {
        // Noise: fast compression makes it larger than stored blocks, which the
        // whole-image encoder then writes: a small image gets the same bytes, a
        // large one (beyond KEEP_RAW) the same pixels. Chunks of 100 bytes: many
        // IDATs.
        let (w, h) = (700u32, 600u32);
        let mut noise = RgbImage::new(w, h);
        let mut s = 0x1234_5678u32;
        for p in noise.pixels_mut() {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            *p = image::Rgb([s as u8, (s >> 8) as u8, (s >> 16) as u8]);
        }
        let small = image::imageops::crop_imm(&noise, 0, 0, 40, 30).to_image();
        assert_eq!(streamed(&small), image_png(&small));
        assert!((w * h * 3) as usize > png::KEEP_RAW);
        for chunk in [100, png::MAX_CHUNK] {
            let mut png =
                png::PngStream::with_max_chunk(Cursor::new(Vec::new()), w, h, chunk).unwrap();
            for row in noise.as_raw().chunks_exact(w as usize * 3) {
                png.write_row(row).unwrap();
            }
            let bytes = png.finish().unwrap().into_inner();
            let back = image::load_from_memory(&bytes).unwrap().to_rgb8();
            assert_eq!(back.as_raw(), noise.as_raw());
            let idats = bytes.windows(4).filter(|w| w == b"IDAT").count();
            assert_eq!(idats > 1, chunk == 100, "{idats} IDAT chunks");
        }
        // Rows of the wrong length, too many or too few rows: errors, no panic.
        let mut png = png::PngStream::new(Cursor::new(Vec::new()), 2, 1).unwrap();
        assert!(png.write_row(&[0; 5]).is_err());
        png.write_row(&[0; 6]).unwrap();
        assert!(png.write_row(&[0; 6]).is_err());
        let short = png::PngStream::new(Cursor::new(Vec::new()), 2, 2).unwrap();
        assert!(short.finish().is_err());
        assert!(png::PngStream::new(Cursor::new(Vec::new()), 0, 2).is_err());
    }

    #[test]
    fn render_png_writes_the_bytes_of_the_assembled_image() {
        // 8 px wide: a row of tiles is a single tile, so bands of several rows.
        for (b, w, h) in [
            (Builtin::Showcase, 97, 61),
            (Builtin::ChapterReflect, 8, 100),
        ] {
            frame(b, w, h, |v, f| {
                let want = streamed(&render_tiles::<16>(v, f, None).unwrap());
                for tile in TILE_SIZES {
                    for threads in [1, 3] {
                        let (rays, out) =
                            render_png(v, f, tile, threads, &|| {}, Cursor::new(Vec::new()))
                                .unwrap();
                        assert_eq!(out.into_inner(), want, "tile {tile}, {threads} threads");
                        assert!(rays.total() > 0);
                    }
                }
            });
        }
    }

    /// Counts the bytes written through it.
    struct Counting(Cursor<Vec<u8>>, Arc<AtomicUsize>);
    impl Write for Counting {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            let n = self.0.write(buf)?;
            self.1.fetch_add(n, Ordering::SeqCst);
            Ok(n)
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    impl Seek for Counting {
        fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
            self.0.seek(pos)
        }
    }

    #[test]
    fn render_png_writes_rows_before_the_last_tile_is_rendered() {
        // The first rows of tiles are compressed and written while later ones are
        // still to render: the image is never whole in memory (beyond KEEP_RAW).
        frame(Builtin::ChapterReflect, 800, 600, |v, f| {
            let written = Arc::new(AtomicUsize::new(0));
            let tiles = AtomicUsize::new(0);
            let at_last = AtomicUsize::new(0);
            let (across, down) = f.tile_grid(16);
            let total = usize::from(across) * usize::from(down);
            let out = Counting(Cursor::new(Vec::new()), written.clone());
            render_png(
                v,
                f,
                16,
                1,
                &|| {
                    if tiles.fetch_add(1, Ordering::SeqCst) + 1 == total {
                        at_last.store(written.load(Ordering::SeqCst), Ordering::SeqCst);
                    }
                },
                out,
            )
            .unwrap();
            let end = written.load(Ordering::SeqCst);
            let before = at_last.load(Ordering::SeqCst);
            assert!(
                before > end / 2,
                "{before} of {end} bytes written before the last tile"
            );
        });
    }

    #[test]
    fn too_many_threads_are_refused_before_any_work() {
        frame(Builtin::ChapterDirect, 16, 16, |v, f| {
            let e = render_png(
                v,
                f,
                16,
                usize::MAX,
                &|| panic!("rendered"),
                Cursor::new(Vec::new()),
            )
            .unwrap_err()
            .to_string();
            assert!(
                e.contains("18446744073709551615") && e.contains("256"),
                "{e}"
            );
            let e = render_with(v, f, 16, 257, &|| panic!("rendered")).unwrap_err();
            assert!(e.to_string().contains("257"), "{e}");
        });
    }

    #[test]
    fn flip_refuses_one_pixel_more_than_the_limit() {
        let n = limits::flip_pixels() as usize;
        assert!((28_000_000..29_000_000).contains(&n), "{n}");
        let img = || flip_rs::RgbImage::new(n + 1, 1, vec![0u8; 3 * (n + 1)]).unwrap();
        let e = flip_rs::ldr_flip(&img(), &img(), flip_rs::DEFAULT_PPD).unwrap_err();
        assert!(e.to_string().contains("work limit"), "{e}");
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn devices_folders_and_empty_names_are_refused_without_touching_them() {
        use output::Target;
        let e = Target::check(Path::new("/dev/null"), &[]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "refusing to write /dev/null: it is a character device, not a regular file"
        );
        let dir = tempfile::tempdir().unwrap();
        let e = Target::check(dir.path(), &[]).unwrap_err().to_string();
        assert!(e.ends_with("it is a folder, not a regular file"), "{e}");
        let e = Target::check(Path::new(""), &[]).unwrap_err().to_string();
        assert!(e.contains("the file name is empty"), "{e}");
        // The same file twice in one write.
        let a = dir.path().join("a.png");
        std::os::unix::fs::symlink("a.png", dir.path().join("b.png")).unwrap();
        let e = Target::check_all(&[a.clone(), dir.path().join("b.png")], &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("b.png") && e.contains("names the same file"),
            "{e}"
        );
        assert_eq!(names(dir.path()), vec!["b.png"]);
    }

    #[test]
    fn a_failed_rename_puts_back_every_output_and_leaves_no_temporary_file() {
        use output::{Pending, Target, commit};
        let dir = tempfile::tempdir().unwrap();
        let path = |n: &str| dir.path().join(n);
        std::fs::write(path("a.png"), b"old a").unwrap();
        let targets =
            Target::check_all(&[path("a.png"), path("b.png"), path("c.png")], &[]).unwrap();
        let mut files = Vec::new();
        for t in targets {
            let mut f = Pending::create(t).unwrap();
            f.write_all(b"new").unwrap();
            files.push(f);
        }
        assert_eq!(names(dir.path()).len(), 4);
        // c.png becomes a folder (with a file in it) after the check.
        std::fs::create_dir(path("c.png")).unwrap();
        std::fs::write(path("c.png/x"), b"x").unwrap();
        let e = commit(files).unwrap_err().to_string();
        assert!(
            e.contains("cannot write") && e.contains("c.png: renaming onto it the temporary file"),
            "{e}"
        );
        assert_eq!(std::fs::read(path("a.png")).unwrap(), b"old a");
        assert_eq!(names(dir.path()), vec!["a.png", "c.png"]);
        // Without the obstacle: all replaced, nothing else left.
        std::fs::remove_dir_all(path("c.png")).unwrap();
        let targets =
            Target::check_all(&[path("a.png"), path("b.png"), path("c.png")], &[]).unwrap();
        let mut files = Vec::new();
        for t in targets {
            let mut f = Pending::create(t).unwrap();
            f.write_all(b"new").unwrap();
            files.push(f);
        }
        commit(files).unwrap();
        assert_eq!(names(dir.path()), vec!["a.png", "b.png", "c.png"]);
        assert_eq!(std::fs::read(path("a.png")).unwrap(), b"new");
    }

    #[test]
    fn an_unfinished_output_removes_its_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let t = output::Target::check(&dir.path().join("x.png"), &[]).unwrap();
        let mut f = output::Pending::create(t).unwrap();
        f.write_all(b"half").unwrap();
        let name = f.temp().file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(".tessera-") && name.len() < 48, "{name}");
        assert_eq!(names(dir.path()), vec![name]);
        drop(f);
        assert!(names(dir.path()).is_empty());
        // A write that fails: the error names the temporary file.
        let e = output::write_with(&dir.path().join("y.png"), &[], |_| {
            Err(HostError::Write(std::io::Error::other("disk on fire")))
        })
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("y.png: writing the temporary file") && e.contains("disk on fire"),
            "{e}"
        );
        assert!(names(dir.path()).is_empty());
    }

    #[test]
    fn figures_for_people() {
        assert_eq!(limits::thousands(0), "0");
        assert_eq!(limits::thousands(999), "999");
        assert_eq!(limits::thousands(1000), "1,000");
        assert_eq!(limits::thousands(4_294_836_225), "4,294,836,225");
        assert_eq!(limits::bytes(12), "12 bytes");
        assert_eq!(limits::bytes(3 << 29), "1.5 GiB");
        let e = limits::simulated(Viewport::new(65535, 65535), 1, false).unwrap_err();
        assert!(e.to_string().contains("68,717,379,600 bytes"), "{e}");
        assert!(limits::simulated(Viewport::new(240, 240), 3600, true).is_ok());
        assert!(limits::simulated(Viewport::new(240, 240), 3601, false).is_err());
        assert!(limits::measured("compare", Viewport::new(5000, 5000)).is_ok());
        assert!(limits::measured("compare", Viewport::new(8192, 8192)).is_err());
    }
}
