//! Host side of tessera: renders frames tile by tile with the core, assembles the
//! tiles into an [`image::RgbImage`], and writes PNG files without ever leaving a
//! half-written file behind.

pub mod compare;
pub mod desc;
pub mod file;
pub mod reference;
pub mod simulate;
pub mod trade;

use image::RgbImage;
use std::fmt;
use std::io::Write;
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
    /// Encoding the PNG failed.
    Encode(String),
    /// The thread pool could not be built.
    Threads(String),
}

impl fmt::Display for HostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Core(e) => write!(f, "{e}"),
            Self::TileSize(n) => write!(f, "tile size {n} is not one of 8, 16, 32"),
            Self::Io { path, source } => write!(f, "cannot write {path}: {source}"),
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
    let (x0, y0) = tile.origin();
    let (x0, y0) = (x0 as usize, y0 as usize);
    let width = img.width() as usize;
    let buf: &mut [u8] = img;
    for (j, row) in tile.rows().enumerate() {
        let start = ((y0 + j) * width + x0) * 3;
        // Inside the image whenever the tile comes from a frame of its size.
        let Some(dst) = buf.get_mut(start..start + row.len() * 3) else {
            continue;
        };
        for (d, p) in dst.chunks_exact_mut(3).zip(row) {
            d.copy_from_slice(&[p.r, p.g, p.b]);
        }
    }
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
    use rayon::prelude::*;
    let vp = frame.viewport();
    let (across, down) = frame.tile_grid(N);
    let count = usize::from(across) * usize::from(down);
    let tiles: Vec<(Tile<N>, RayCount)> = (0..count)
        .into_par_iter()
        .map(|i| {
            let coord = TileCoord::new(
                (i % usize::from(across)) as u16,
                (i / usize::from(across)) as u16,
            );
            let mut tile = Tile::<N>::new();
            let mut rays = RayCount::default();
            frame.render_tile_counted(scene, coord, &mut tile, &mut rays)?;
            on_tile();
            Ok((tile, rays))
        })
        .collect::<Result<_, tessera::Error>>()?;
    let mut img = RgbImage::new(u32::from(vp.width), u32::from(vp.height));
    let mut rays = RayCount::default();
    for (tile, r) in &tiles {
        place(&mut img, tile);
        rays.add(r);
    }
    Ok((img, rays))
}

/// [`render_parallel`] for a tile size chosen at run time (8, 16 or 32), on a pool
/// of `threads` threads (0 = one per core).
pub fn render_with(
    scene: &SceneView<'_>,
    frame: &Frame,
    tile: usize,
    threads: usize,
    on_tile: &(dyn Fn() + Sync),
) -> Result<(RgbImage, RayCount), HostError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| HostError::Threads(e.to_string()))?;
    pool.install(|| match tile {
        8 => render_parallel::<8>(scene, frame, on_tile),
        16 => render_parallel::<16>(scene, frame, on_tile),
        32 => render_parallel::<32>(scene, frame, on_tile),
        n => Err(HostError::TileSize(n)),
    })
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

/// Writes `img` as a PNG at `path` atomically (see [`write_atomic`]).
pub fn write_png(img: &RgbImage, path: &Path) -> Result<(), HostError> {
    use image::ImageEncoder;
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let mut bytes = Vec::new();
    // Fast compression, Paeth filter on every row. Measured on the four built-in
    // scenes at 320x240 against the adaptive filter (which tries all five filters
    // per row): files within 1 % (27,059 vs 27,175 bytes on chapter-direct, 2,553
    // vs 2,523 on interference, 62,050 vs 61,472 on showcase) for 0.65 M fewer of
    // the 42.7 M instructions of a whole chapter-reflect run (callgrind). Up and
    // Average cost less still but give files 1.3-1.6 times larger (Average 58 times
    // on interference), Sub triples smooth images such as docs/interference.png.
    PngEncoder::new_with_quality(&mut bytes, CompressionType::Fast, FilterType::Paeth)
        .write_image(
            img,
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| HostError::Encode(e.to_string()))?;
    write_atomic(&bytes, path)
}

/// Writes `bytes` at `path` atomically: they go to a temporary file in the same
/// folder, which is then renamed over `path`. An existing file at `path` is either
/// replaced whole or left untouched, and no temporary file is left behind.
pub fn write_atomic(bytes: &[u8], path: &Path) -> Result<(), HostError> {
    let shown = path.display().to_string();
    let io = |source| HostError::Io {
        path: shown.clone(),
        source,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out.png".into());
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = std::fs::File::create(&tmp)
        .and_then(|mut f| {
            f.write_all(bytes)?;
            f.sync_all()
        })
        .and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(io(e));
    }
    Ok(())
}
