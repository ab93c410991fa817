//! Host files over semihosting: open, length, read, seek, write, close.
//!
//! `cortex-m-semihosting`'s `hio` only writes to the console, so files go through
//! its `syscall!` macro (ARM semihosting SYS_OPEN, SYS_FLEN, SYS_READ, SYS_SEEK,
//! SYS_WRITE, SYS_CLOSE). On RISC-V `riscv-semihosting` has the same macro and
//! operation numbers (the RISC-V semihosting specification reuses Arm's). File
//! names are relative to qemu's working directory.

#[cfg(target_arch = "arm")]
use cortex_m_semihosting::{nr, syscall};
#[cfg(target_arch = "riscv32")]
use riscv_semihosting::{nr, syscall};

/// An open host file; closed when dropped.
pub struct HostFile {
    fd: usize,
}

/// Which semihosting operation failed, on which file.
#[derive(Clone, Copy, Debug)]
pub struct IoError {
    /// The operation (`open`, `read`, ...).
    pub op: &'static str,
}

impl HostFile {
    /// Opens `name` (without a NUL; at most 63 bytes) with an `fopen` mode from
    /// [`nr::open`].
    pub fn open(name: &str, mode: usize) -> Result<Self, IoError> {
        let err = IoError { op: "open" };
        let mut z = [0u8; 64];
        let bytes = name.as_bytes();
        if bytes.len() >= z.len() {
            return Err(err);
        }
        z.get_mut(..bytes.len()).ok_or(err)?.copy_from_slice(bytes);
        // SAFETY: SYS_OPEN reads `len` bytes of the NUL-terminated name at the
        // pointer, which `z` holds for the duration of the call.
        let fd = unsafe { syscall!(OPEN, z.as_ptr(), mode, bytes.len()) } as isize;
        if fd < 0 {
            return Err(err);
        }
        Ok(Self { fd: fd as usize })
    }

    /// Opens `name` for reading, binary.
    pub fn open_read(name: &str) -> Result<Self, IoError> {
        Self::open(name, nr::open::R_BINARY)
    }

    /// Creates (or truncates) `name` for writing, binary.
    pub fn create(name: &str) -> Result<Self, IoError> {
        Self::open(name, nr::open::W_TRUNC_BINARY)
    }

    /// The file's length in bytes.
    pub fn len(&self) -> Result<usize, IoError> {
        // SAFETY: SYS_FLEN takes the handle only.
        let n = unsafe { syscall!(FLEN, self.fd) } as isize;
        usize::try_from(n).map_err(|_| IoError { op: "flen" })
    }

    /// Fills `buf` from the current position.
    pub fn read_exact(&self, mut buf: &mut [u8]) -> Result<(), IoError> {
        while !buf.is_empty() {
            // SAFETY: SYS_READ writes at most `buf.len()` bytes into `buf`.
            let left = unsafe { syscall!(READ, self.fd, buf.as_mut_ptr(), buf.len()) };
            // The call returns how many bytes were *not* read.
            if left == 0 {
                return Ok(());
            }
            let done = buf.len().checked_sub(left).filter(|&d| d > 0);
            let done = done.ok_or(IoError { op: "read" })?;
            buf = buf.get_mut(done..).ok_or(IoError { op: "read" })?;
        }
        Ok(())
    }

    /// Moves to byte `pos` from the start (past the end is allowed when writing).
    pub fn seek(&self, pos: usize) -> Result<(), IoError> {
        // SAFETY: SYS_SEEK takes the handle and an absolute position.
        let r = unsafe { syscall!(SEEK, self.fd, pos) };
        if r == 0 {
            Ok(())
        } else {
            Err(IoError { op: "seek" })
        }
    }

    /// Writes all of `buf` at the current position.
    pub fn write_all(&self, mut buf: &[u8]) -> Result<(), IoError> {
        while !buf.is_empty() {
            // SAFETY: SYS_WRITE reads at most `buf.len()` bytes from `buf`.
            let left = unsafe { syscall!(WRITE, self.fd, buf.as_ptr(), buf.len()) };
            // The call returns how many bytes were *not* written.
            if left == 0 {
                return Ok(());
            }
            let done = buf.len().checked_sub(left).filter(|&d| d > 0);
            let done = done.ok_or(IoError { op: "write" })?;
            buf = buf.get(done..).ok_or(IoError { op: "write" })?;
        }
        Ok(())
    }
}

impl Drop for HostFile {
    fn drop(&mut self) {
        // SAFETY: SYS_CLOSE takes the handle only; it is not used afterwards.
        unsafe {
            syscall!(CLOSE, self.fd);
        }
    }
}
