//! The one error type of the `tessera` command.

use std::fmt;
use std::path::PathBuf;
use tessera_host::desc::DescError;
use tessera_host::file::FileError;
use tessera_host::{HostError, escape, escape_path};

/// Why a command failed (printed as `tessera: error: ...`, exit status 1). Names
/// and paths are shown through [`escape`].
#[derive(Debug)]
pub enum Error {
    /// The host library refused or failed: the core's errors, outputs, limits, ...
    Host(HostError),
    /// A scene file could not be read or is invalid (the message names the file).
    File(FileError),
    /// The scene called `name` was refused: its settings, its conversion to a core
    /// scene, or the reference's checks.
    Scene {
        /// The built-in scene's name or the file, as given.
        name: String,
        /// Why.
        source: DescError,
    },
    /// A scene argument that is neither a built-in name nor an existing file.
    NoSuchScene(String),
    /// `--camera` (a glTF file's camera) with a scene that is not a glTF file.
    CameraOfNoGltf(String),
    /// `trade --scenes` names a scene that is not built in.
    UnknownBuiltin(String),
    /// `compare`'s accuracy bar is not met.
    BelowBar {
        /// The scene.
        name: String,
        /// What falls short, with the figures.
        shortfall: String,
    },
    /// `simulate --orbit 0`.
    NoOrbitFrames,
    /// `simulate --window` in a build without the `sdl` feature.
    #[cfg(not(feature = "sdl"))]
    NoWindow,
    /// An image file `diff` reads: unreadable, or not a PNG or PPM it takes (the
    /// message says what is wrong).
    Image {
        /// The file, as given.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// `diff`'s two images are not the same size.
    SizesDiffer {
        /// The first image and its width and height.
        a: (PathBuf, u32, u32),
        /// The second.
        b: (PathBuf, u32, u32),
    },
    /// `diff`'s two images differ.
    ImagesDiffer {
        /// The first image.
        a: PathBuf,
        /// The second.
        b: PathBuf,
        /// How: the pixels and the largest difference.
        how: String,
    },
    /// What `completions` or `man` made could not be written to stdout.
    Stdout(std::io::Error),
    /// `new` could not create the crate at `path`.
    New {
        /// The folder asked for, or the checkout.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A folder could not be created.
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Host(e) => write!(f, "{e}"),
            Self::File(e) => write!(f, "{e}"),
            Self::Scene { name, source } => write!(f, "{}: {source}", escape(name)),
            Self::CameraOfNoGltf(camera) => write!(
                f,
                "--camera {:?} names a glTF file's camera, and the scene is not a glTF file \
                 (.gltf, .glb); a scene file's camera is its [camera] table",
                escape(camera)
            ),
            Self::NoSuchScene(name) => {
                let names: Vec<&str> = tessera_core::builtin::Builtin::ALL
                    .iter()
                    .map(|b| b.name())
                    .collect();
                write!(
                    f,
                    "{:?} is neither a built-in scene ({}) nor an existing file",
                    escape(name),
                    names.join(", ")
                )
            }
            Self::UnknownBuiltin(name) => write!(f, "unknown built-in scene {:?}", escape(name)),
            Self::BelowBar { name, shortfall } => write!(f, "{}: {shortfall}", escape(name)),
            Self::NoOrbitFrames => f.write_str("--orbit needs at least 1 frame"),
            #[cfg(not(feature = "sdl"))]
            Self::NoWindow => f.write_str(
                "this tessera was built without the SDL window: rebuild with `--features sdl` (needs libsdl2-dev)",
            ),
            Self::Image { path, message } => write!(f, "{}: {message}", escape_path(path)),
            Self::SizesDiffer { a, b } => write!(
                f,
                "the images are not the same size: {} is {}x{}, {} is {}x{}",
                escape_path(&a.0),
                a.1,
                a.2,
                escape_path(&b.0),
                b.1,
                b.2
            ),
            Self::ImagesDiffer { a, b, how } => write!(
                f,
                "{} and {} differ: {how}",
                escape_path(a),
                escape_path(b)
            ),
            Self::Stdout(e) => write!(f, "cannot write to stdout: {e}"),
            Self::Folder { path, source } => write!(f, "{}: {source}", escape_path(path)),
            Self::New { path, message } => write!(f, "{}: {message}", escape_path(path)),
        }
    }
}

impl std::error::Error for Error {}

impl From<HostError> for Error {
    fn from(e: HostError) -> Self {
        Self::Host(e)
    }
}

impl From<tessera_core::Error> for Error {
    fn from(e: tessera_core::Error) -> Self {
        Self::Host(HostError::Core(e))
    }
}

impl From<FileError> for Error {
    fn from(e: FileError) -> Self {
        Self::File(e)
    }
}
