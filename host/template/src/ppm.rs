//! The picture as a binary PPM file on the host, written over semihosting (ARM
//! semihosting's SYS_OPEN, SYS_SEEK, SYS_WRITE and SYS_CLOSE; qemu opens the file
//! in its working folder). Each tile row is written at its place in the file, so
//! the firmware never holds more than one tile.
//!
//! On a real board there is no host file: this module is what a display driver
//! replaces.

use core::ffi::CStr;
use core::fmt::{self, Write as _};
use cortex_m_semihosting::{nr, syscall};

/// A failed semihosting call: which one.
#[derive(Clone, Copy, Debug)]
pub struct IoError(pub &'static str);

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "semihosting {} failed", self.0)
    }
}

/// An open PPM file (`P6`: a text header, then 3 bytes, R G B, a pixel, row after
/// row); closed when dropped.
pub struct Ppm {
    fd: usize,
    width: usize,
    header: usize,
}

impl Ppm {
    /// Creates (or empties) the file `name` and writes the header of a
    /// `width x height` picture.
    pub fn create(name: &CStr, width: u16, height: u16) -> Result<Self, IoError> {
        let mode = nr::open::W_TRUNC_BINARY;
        // SAFETY: SYS_OPEN reads the name, NUL-terminated, and its length.
        let fd = unsafe { syscall!(OPEN, name.as_ptr(), mode, name.count_bytes()) };
        if fd as isize == -1 {
            return Err(IoError("open"));
        }
        let mut ppm = Self {
            fd,
            width: usize::from(width),
            header: 0,
        };
        write!(ppm, "P6\n{width} {height}\n255\n").map_err(|_| IoError("write"))?;
        Ok(ppm)
    }

    /// Writes `rgb`, pixels of row `y` from column `x` on, at their place.
    pub fn write_at(&mut self, x: usize, y: usize, rgb: &[u8]) -> Result<(), IoError> {
        let at = self.header + 3 * (y * self.width + x);
        // SAFETY: SYS_SEEK takes the handle and a position from the file's start.
        if unsafe { syscall!(SEEK, self.fd, at) } != 0 {
            return Err(IoError("seek"));
        }
        self.write(rgb)
    }

    /// Writes all of `bytes` at the current position.
    fn write(&mut self, mut bytes: &[u8]) -> Result<(), IoError> {
        while !bytes.is_empty() {
            // SAFETY: SYS_WRITE reads at most `bytes.len()` bytes of `bytes`; it
            // returns how many it did not write.
            let left = unsafe { syscall!(WRITE, self.fd, bytes.as_ptr(), bytes.len()) };
            let done = bytes.len().saturating_sub(left);
            if done == 0 {
                return Err(IoError("write"));
            }
            bytes = bytes.get(done..).unwrap_or_default();
        }
        Ok(())
    }
}

/// The header, written as it is formatted; its length is where the pixels start.
impl fmt::Write for Ppm {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.write(s.as_bytes()).map_err(|_| fmt::Error)?;
        self.header += s.len();
        Ok(())
    }
}

impl Drop for Ppm {
    fn drop(&mut self) {
        // SAFETY: SYS_CLOSE takes the handle, not used after this.
        unsafe { syscall!(CLOSE, self.fd) };
    }
}
