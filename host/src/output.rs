//! Output files, written so that a failure or an interruption never leaves a
//! half-written file or a stray temporary file, and never replaces what the
//! user did not name.
//!
//! - Each output is written to a temporary file in the folder of the file it
//!   replaces, named `.tessera-PID-N.tmp` (short whatever the output's name),
//!   then renamed onto it: an existing file is replaced whole or left untouched.
//! - An output is checked before any work ([`Target::check`]): an existing
//!   output that is not a regular file (a folder, a device, a FIFO, a socket) is
//!   refused, and so is every file the command reads ([`Input`]: the scene file,
//!   the OBJ files of its meshes), compared by identity (device and inode, so
//!   another path, a symbolic link or a hard link to it is caught).
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

use crate::{HostError, TempStep};
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

/// A file a command reads, which no output may replace.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// The file, as the command reads it.
    pub path: PathBuf,
    /// What it is, for the message: `the input scene file m.toml`, `the OBJ file
    /// ok.obj of mesh 1 (scene m.toml)`.
    pub what: String,
}

impl Input {
    /// The scene file at `path`.
    #[must_use]
    pub fn scene(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
            what: format!("the input scene file {}", path.display()),
        }
    }
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
    /// FIFO or socket (also through a link), or one of `inputs` (the same file,
    /// by identity).
    pub fn check(path: &Path, inputs: &[Input]) -> Result<Self, HostError> {
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
                        crate::text::file_kind(&m.file_type())
                    ),
                ));
            }
            if let Some(input) = inputs.iter().find(|i| same_file(m, &file, &i.path)) {
                return Err(refused(
                    path,
                    format!("it is {}{through}; choose another output", input.what),
                ));
            }
        }
        Ok(Self {
            shown: path.to_path_buf(),
            file,
        })
    }

    /// [`Target::check`] for several outputs, which must be different files.
    pub fn check_all(paths: &[PathBuf], inputs: &[Input]) -> Result<Vec<Self>, HostError> {
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

    fn io<T>(&mut self, op: impl FnOnce(&mut BufWriter<File>) -> io::Result<T>) -> io::Result<T> {
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
    inputs: &[Input],
    write: impl FnOnce(&mut Pending) -> Result<(), HostError>,
) -> Result<(), HostError> {
    let mut pending = Pending::create(Target::check(path, inputs)?)?;
    if let Err(e) = write(&mut pending) {
        return Err(pending.error(e));
    }
    commit(vec![pending])
}
