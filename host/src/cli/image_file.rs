//! The image files `tessera diff` reads: PNG through the `image` crate, PPM
//! (binary `P6` and plain `P3`, maxval 255, comments in the header) through a
//! small strict parser of its own. What a file is comes from its first bytes,
//! not its name. A file is opened and its header read ([`ImageFile::open`])
//! before any pixel is read ([`ImageFile::read`]), so that two images of
//! different sizes, or one above the limit, are refused before the work.
//!
//! Every fault is an [`Error::Image`] naming the file and what is wrong (wrong
//! magic number, truncated pixels, bytes after them, a maxval other than 255, a
//! PNG that is not 8-bit or not opaque, ...); nothing in a file can make it panic
//! or allocate more than the pixels of an image within the limit.

use super::Error;
use image::codecs::png::PngDecoder;
use image::{ColorType, DynamicImage, ImageDecoder, RgbImage};
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use tessera_host::limits;

/// The first bytes of every PNG file.
const PNG_SIGNATURE: &[u8; 8] = b"\x89PNG\r\n\x1a\n";

/// The only maxval read: 8 bits a channel, as `tessera render` and the firmware
/// write.
const MAXVAL: u64 = 255;

/// An image file opened, its header read: its size known, its pixels not read yet.
pub struct ImageFile {
    path: PathBuf,
    width: u32,
    height: u32,
    kind: Kind,
}

enum Kind {
    Png(Box<PngDecoder<BufReader<File>>>),
    /// A PPM: `plain` for P3 (decimal values), else P6 (bytes); the reader is just
    /// past the header, `header` bytes in.
    Ppm {
        plain: bool,
        scan: Scan,
        header: u64,
        file_len: Option<u64>,
    },
}

impl ImageFile {
    /// Opens the image at `path` and reads its header. The file must be a regular
    /// file (a FIFO or a device is refused unread) holding a PNG or a PPM of at
    /// most [`limits::flip_pixels`] pixels.
    pub fn open(path: &Path) -> Result<Self, Error> {
        let error = |message: String| Error::Image {
            path: path.to_path_buf(),
            message,
        };
        let file = open_input(path).map_err(error)?;
        let file_len = file.metadata().ok().map(|m| m.len());
        let mut reader = BufReader::new(file);
        let head = reader.fill_buf().map_err(|e| error(cannot_read(&e)))?;
        let head = head.get(..8).unwrap_or(head).to_vec();
        let (kind, width, height) = if head.starts_with(PNG_SIGNATURE) {
            let decoder =
                PngDecoder::new(reader).map_err(|e| error(format!("cannot read the PNG: {e}")))?;
            let (width, height) = decoder.dimensions();
            match decoder.color_type() {
                ColorType::L8 | ColorType::La8 | ColorType::Rgb8 | ColorType::Rgba8 => {}
                other => {
                    return Err(error(format!(
                        "a PNG of {other:?} pixels: diff reads 8-bit PNG files (grey or RGB, \
                         with or without an opaque alpha channel)"
                    )));
                }
            }
            (Kind::Png(Box::new(decoder)), width, height)
        } else if let [b'P', m @ (b'6' | b'3'), ..] = head[..] {
            let mut scan = Scan { reader, at: 2 };
            scan.reader.consume(2);
            let (width, height) = scan.header(m == b'6').map_err(error)?;
            let header = scan.at;
            let kind = Kind::Ppm {
                plain: m == b'3',
                scan,
                header,
                file_len,
            };
            (kind, width, height)
        } else {
            return Err(error(magic_error(&head)));
        };
        within_limit(width, height).map_err(error)?;
        Ok(Self {
            path: path.to_path_buf(),
            width,
            height,
            kind,
        })
    }

    /// The image's width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The file as given.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What the file is: `PNG`, `PPM P6` or `PPM P3`.
    pub fn format(&self) -> &'static str {
        match &self.kind {
            Kind::Png(_) => "PNG",
            Kind::Ppm { plain: false, .. } => "PPM P6",
            Kind::Ppm { plain: true, .. } => "PPM P3",
        }
    }

    /// Reads the pixels, as 8-bit RGB.
    pub fn read(self) -> Result<RgbImage, Error> {
        let path = self.path;
        let error = |message: String| Error::Image {
            path: path.clone(),
            message,
        };
        let (w, h) = (self.width, self.height);
        match self.kind {
            Kind::Png(decoder) => {
                let img = DynamicImage::from_decoder(*decoder)
                    .map_err(|e| error(format!("cannot read the PNG: {e}")))?;
                opaque(&img).map_err(error)?;
                Ok(img.to_rgb8())
            }
            Kind::Ppm {
                plain,
                mut scan,
                header,
                file_len,
            } => {
                let bytes = if plain {
                    scan.plain_raster(w, h)
                } else {
                    scan.raster(w, h, header, file_len)
                }
                .map_err(error)?;
                RgbImage::from_raw(w, h, bytes)
                    .ok_or_else(|| error(format!("{w}x{h} pixels do not fit in memory")))
            }
        }
    }
}

/// Nothing if a `width x height` image is within what diff measures (FLIP's
/// work limit, as compare's), else the message.
fn within_limit(width: u32, height: u32) -> Result<(), String> {
    let (n, max) = (u64::from(width) * u64::from(height), limits::flip_pixels());
    if n > max {
        return Err(format!(
            "a {width}x{height} image: {} pixels is more than the {} that FLIP can measure",
            limits::thousands(n),
            limits::thousands(max)
        ));
    }
    Ok(())
}

/// Nothing if every pixel of `img` is opaque (or it has no alpha), else the
/// message naming the first that is not.
fn opaque(img: &DynamicImage) -> Result<(), String> {
    let first = match img {
        DynamicImage::ImageLumaA8(i) => i
            .enumerate_pixels()
            .find_map(|(x, y, p)| (p[1] != 255).then_some((x, y, p[1]))),
        DynamicImage::ImageRgba8(i) => i
            .enumerate_pixels()
            .find_map(|(x, y, p)| (p[3] != 255).then_some((x, y, p[3]))),
        _ => None,
    };
    match first {
        Some((x, y, alpha)) => Err(format!(
            "pixel ({x}, {y}) is not opaque (alpha {alpha}): diff compares opaque pixels"
        )),
        None => Ok(()),
    }
}

/// The message for a file that is neither a PPM diff reads nor a PNG, from its
/// first bytes.
fn magic_error(head: &[u8]) -> String {
    if head.is_empty() {
        return "the file is empty: expected a PPM (P6 or P3) or a PNG".into();
    }
    let magic: String = head.iter().take(2).map(|&b| shown_byte(b)).collect();
    let what = match head {
        [b'P', b'1' | b'4', ..] => " (a black-and-white PBM)",
        [b'P', b'2' | b'5', ..] => " (a grey PGM)",
        [b'P', b'7', ..] => " (a PAM)",
        _ => "",
    };
    format!(
        "wrong magic number \"{magic}\"{what}: expected \"P6\" or \"P3\" (a colour PPM) or \
         the PNG signature"
    )
}

/// A byte as a message shows it: itself when printable ASCII, else `\xNN`.
fn shown_byte(b: u8) -> String {
    if b.is_ascii_graphic() || b == b' ' {
        char::from(b).to_string()
    } else {
        format!("\\x{b:02x}")
    }
}

/// A byte found where something else was expected: `'x'`, `byte 0x00`, or the
/// end of the file.
fn found(b: Option<u8>) -> String {
    match b {
        Some(b) if b.is_ascii_graphic() => format!("{:?}", char::from(b)),
        Some(b) => format!("byte 0x{b:02x}"),
        None => "the end of the file".into(),
    }
}

fn cannot_read(e: &std::io::Error) -> String {
    format!("cannot read the image: {e}")
}

/// A PPM file read a byte at a time (the header, P3's values) or in one piece
/// (P6's pixels), counting the bytes read.
struct Scan {
    reader: BufReader<File>,
    /// Bytes read (consumed) so far.
    at: u64,
}

impl Scan {
    fn peek(&mut self) -> Result<Option<u8>, String> {
        let buf = self.reader.fill_buf().map_err(|e| cannot_read(&e))?;
        Ok(buf.first().copied())
    }

    fn bump(&mut self) {
        self.reader.consume(1);
        self.at += 1;
    }

    /// Skips a comment: `#` to the end of its line, the line break included.
    fn comment(&mut self) -> Result<(), String> {
        while let Some(b) = self.peek()? {
            self.bump();
            if b == b'\n' || b == b'\r' {
                break;
            }
        }
        Ok(())
    }

    /// Skips whitespace and comments.
    fn blanks(&mut self) -> Result<(), String> {
        while let Some(b) = self.peek()? {
            if b == b'#' {
                self.comment()?;
            } else if b.is_ascii_whitespace() {
                self.bump();
            } else {
                break;
            }
        }
        Ok(())
    }

    /// The next decimal number, after whitespace and comments, at most `max`,
    /// and followed by whitespace, a comment or the end of the file. `what`
    /// names it for the messages (`the width`, `the value of pixel (3, 4)`);
    /// `None` at the end of the file.
    fn number(&mut self, what: &str, max: u64) -> Result<Option<u64>, String> {
        self.blanks()?;
        match self.peek()? {
            None => return Ok(None),
            Some(b) if b.is_ascii_digit() => {}
            b => {
                return Err(format!(
                    "expected {what} (a decimal number), found {}",
                    found(b)
                ));
            }
        }
        let mut n: u64 = 0;
        while let Some(b) = self.peek()?.filter(u8::is_ascii_digit) {
            n = n * 10 + u64::from(b - b'0');
            if n > max {
                return Err(format!("{what} is more than {max}"));
            }
            self.bump();
        }
        match self.peek()? {
            None => {}
            Some(b) if b.is_ascii_whitespace() || b == b'#' => {}
            b => {
                return Err(format!(
                    "expected whitespace after {what} {n}, found {}",
                    found(b)
                ));
            }
        }
        Ok(Some(n))
    }

    /// The header after the magic number: width, height and maxval (255), with
    /// whitespace and comments between them; for `binary` (P6), the one
    /// whitespace byte (or comment) after the maxval too. The width and height.
    fn header(&mut self, binary: bool) -> Result<(u32, u32), String> {
        let field = |scan: &mut Self, what: &str| {
            scan.number(what, u64::from(u32::MAX))?.ok_or_else(|| {
                format!("truncated header: the file ends before {what} (width, height, maxval)")
            })
        };
        let width = field(self, "the width")?;
        let height = field(self, "the height")?;
        let maxval = field(self, "the maxval")?;
        if width == 0 || height == 0 {
            return Err(format!(
                "a {width}x{height} picture: the width and the height must be at least 1"
            ));
        }
        if maxval != MAXVAL {
            return Err(format!(
                "maxval {maxval}: diff reads 8-bit PPM files only (maxval {MAXVAL})"
            ));
        }
        if binary {
            // `number` left a whitespace byte, a comment or the end here.
            match self.peek()? {
                Some(b'#') => self.comment()?,
                Some(_) => self.bump(),
                None => {}
            }
        }
        Ok((width as u32, height as u32))
    }

    /// P6's pixels: exactly `width x height x 3` bytes after the `header` bytes
    /// of the header, the file's last. `file_len`, the file's size when known,
    /// refuses a truncated file, or one with bytes after its pixels, unread.
    fn raster(
        &mut self,
        width: u32,
        height: u32,
        header: u64,
        file_len: Option<u64>,
    ) -> Result<Vec<u8>, String> {
        let need = u64::from(width) * u64::from(height) * 3;
        let truncated = |have: u64| {
            format!(
                "truncated: its {width}x{height} pixels take {need} bytes after the \
                 {header}-byte header, the file has {have}"
            )
        };
        let trailing = |more: String| {
            format!(
                "{more} after its {width}x{height} pixels ({need} bytes after the \
                 {header}-byte header): one picture a file"
            )
        };
        if let Some(len) = file_len {
            let have = len.saturating_sub(header);
            if have < need {
                return Err(truncated(have));
            }
            if have > need {
                return Err(trailing(format!("{} more bytes", have - need)));
            }
        }
        let mut bytes = Vec::new();
        bytes
            .try_reserve_exact(usize::try_from(need).unwrap_or(usize::MAX))
            .map_err(|e| format!("cannot hold {need} bytes of pixels: {e}"))?;
        (&mut self.reader)
            .take(need)
            .read_to_end(&mut bytes)
            .map_err(|e| cannot_read(&e))?;
        let have = bytes.len() as u64;
        self.at += have;
        if have < need {
            return Err(truncated(have));
        }
        if self.peek()?.is_some() {
            return Err(trailing("more bytes".into()));
        }
        Ok(bytes)
    }

    /// P3's pixels: `width x height x 3` decimal values of at most 255, row by
    /// row, and nothing after them but whitespace and comments.
    fn plain_raster(&mut self, width: u32, height: u32) -> Result<Vec<u8>, String> {
        let need = u64::from(width) * u64::from(height) * 3;
        let mut bytes = Vec::new();
        bytes
            .try_reserve_exact(usize::try_from(need).unwrap_or(usize::MAX))
            .map_err(|e| format!("cannot hold {need} bytes of pixels: {e}"))?;
        for i in 0..need {
            let pixel = i / 3;
            let (x, y) = (pixel % u64::from(width), pixel / u64::from(width));
            let what = format!("the value of pixel ({x}, {y})");
            let Some(v) = self.number(&what, 65535)? else {
                return Err(format!(
                    "truncated: its {width}x{height} pixels take {need} values, the file \
                     has {i}"
                ));
            };
            let v = u8::try_from(v)
                .map_err(|_| format!("{what} is {v}, more than the maxval {MAXVAL}"))?;
            bytes.push(v);
        }
        self.blanks()?;
        if let Some(b) = self.peek()? {
            return Err(format!(
                "more than the {need} values of its {width}x{height} pixels: found {} after \
                 them (one picture a file)",
                found(Some(b))
            ));
        }
        Ok(bytes)
    }
}

/// The file at `path` opened for reading if it is a regular file (following
/// symbolic links), else the message naming what it is. Nothing waits: the type
/// is checked before opening, then the file is opened non-blocking and its type
/// checked again on the handle (as the scene reader does).
fn open_input(path: &Path) -> Result<File, String> {
    let meta = std::fs::metadata(path).map_err(|e| cannot_read(&e))?;
    regular(&meta)?;
    let file = open_nonblocking(path).map_err(|e| cannot_read(&e))?;
    regular(&file.metadata().map_err(|e| cannot_read(&e))?)?;
    Ok(file)
}

/// Nothing if `m` is a regular file's, else the message naming what it is.
fn regular(m: &std::fs::Metadata) -> Result<(), String> {
    if m.is_file() {
        return Ok(());
    }
    let t = m.file_type();
    let kind = if t.is_dir() {
        "a folder"
    } else {
        special_kind(&t)
    };
    Err(format!(
        "cannot read the image: it is {kind}, not a regular file"
    ))
}

#[cfg(unix)]
fn special_kind(t: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "something else"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "something else"
}

/// Opens `path` for reading without waiting (`O_NONBLOCK`: a FIFO put in the
/// file's place opens at once; `O_NOCTTY`: a terminal does not become the
/// controlling one).
#[cfg(unix)]
fn open_nonblocking(path: &Path) -> std::io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY)
        .open(path)
}

#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> std::io::Result<File> {
    File::open(path)
}
