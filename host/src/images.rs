//! Rendering to images: frames tile by tile into an [`image::RgbImage`], on a
//! thread pool, or streamed into a PNG a row of tiles at a time; PNG files and
//! other outputs written atomically. Only with the `cli` feature; the items are
//! re-exported at the crate root.

use crate::{HostError, limits, output, png};
use image::RgbImage;
use std::io::{Seek, Write};
use std::path::Path;
use tessera_core::{
    Camera, RenderSettings, Renderer, SceneView, Tile, TileCoord, Viewport, trace::RayCount,
};

/// Renders the whole frame tile by tile with tiles of `N x N`, in the order given
/// by `order` (a permutation of the tile indices, row-major; `None` = row-major).
pub fn render_tiles<const N: usize>(
    scene: &SceneView<'_>,
    renderer: &Renderer,
    order: Option<&[usize]>,
) -> Result<RgbImage, HostError> {
    let vp = renderer.viewport();
    let mut img = RgbImage::new(u32::from(vp.width), u32::from(vp.height));
    let (across, down) = renderer.tile_grid(N);
    let count = usize::from(across) * usize::from(down);
    let row_major: Vec<usize> = (0..count).collect();
    let order = order.unwrap_or(&row_major);
    let mut tile = Tile::<N>::new();
    for &i in order {
        let coord = TileCoord::new(
            (i % usize::from(across)) as u16,
            (i / usize::from(across)) as u16,
        );
        renderer.render_tile(scene, coord, &mut tile, &mut ())?;
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
    renderer: &Renderer,
    across: usize,
    i: usize,
) -> Result<(Tile<N>, RayCount), tessera_core::Error> {
    let coord = TileCoord::new((i % across) as u16, (i / across) as u16);
    let mut tile = Tile::<N>::new();
    let mut rays = RayCount::default();
    renderer.render_tile(scene, coord, &mut tile, &mut rays)?;
    Ok((tile, rays))
}

/// Renders tiles `tiles` (row-major indices, `across` tiles a row) of `frame` on
/// the current rayon pool, in order, calling `on_tile` after each (for progress).
fn tiles_parallel<const N: usize>(
    scene: &SceneView<'_>,
    renderer: &Renderer,
    across: usize,
    tiles: std::ops::Range<usize>,
    on_tile: &(dyn Fn() + Sync),
) -> Result<Vec<(Tile<N>, RayCount)>, tessera_core::Error> {
    use rayon::prelude::*;
    tiles
        .into_par_iter()
        .map(|i| {
            let t = one_tile::<N>(scene, renderer, across, i)?;
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
    renderer: &Renderer,
    on_tile: &(dyn Fn() + Sync),
) -> Result<(RgbImage, RayCount), HostError> {
    let vp = renderer.viewport();
    let (across, down) = renderer.tile_grid(N);
    let across = usize::from(across);
    let count = across * usize::from(down);
    let tiles = tiles_parallel::<N>(scene, renderer, across, 0..count, on_tile)?;
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
    renderer: &Renderer,
    tile: usize,
    threads: usize,
    on_tile: &(dyn Fn() + Sync),
) -> Result<(RgbImage, RayCount), HostError> {
    pool(threads)?
        .install(|| with_tile_size!(tile, |N| render_parallel::<N>(scene, renderer, on_tile)))
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
    renderer: &Renderer,
    tile: usize,
    threads: usize,
    on_tile: &(dyn Fn() + Sync),
    out: W,
) -> Result<(RayCount, W), HostError> {
    let pool = pool(threads)?;
    let threads = pool.current_num_threads();
    pool.install(|| {
        with_tile_size!(tile, |N| stream::<N, W>(
            scene, renderer, threads, on_tile, out
        ))
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
    renderer: &Renderer,
    threads: usize,
    on_tile: &(dyn Fn() + Sync),
    out: W,
) -> Result<(RayCount, W), HostError> {
    let vp = renderer.viewport();
    let (width, height) = (usize::from(vp.width), usize::from(vp.height));
    let (across, down) = renderer.tile_grid(N);
    let (across, down) = (usize::from(across), usize::from(down));
    let group = band_rows(across, down, threads);
    let mut png = png::PngStream::new(out, u32::from(vp.width), u32::from(vp.height))
        .map_err(HostError::Write)?;
    let mut band = vec![0u8; width * 3 * N * group];
    let mut rays = RayCount::default();
    for first in (0..down).step_by(group) {
        let rows = group.min(down - first);
        let band_tiles = first * across..(first + rows) * across;
        let tiles = tiles_parallel::<N>(scene, renderer, across, band_tiles, on_tile)?;
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
    let renderer = Renderer::try_new(camera, viewport, settings)?;
    with_tile_size!(tile, |N| render_tiles::<N>(scene, &renderer, None))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TILE_SIZES;
    use std::io::Cursor;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use tessera_core::builtin::Builtin;

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

    fn with_renderer(b: Builtin, w: u16, h: u16, f: impl FnOnce(&SceneView<'_>, &Renderer)) {
        b.with_scene(|view, cam| {
            let renderer = Renderer::try_new(cam, Viewport::new(w, h), b.settings()).unwrap();
            f(view, &renderer);
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
        for &b in Builtin::ALL {
            with_renderer(b, 160, 120, |v, f| {
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
            with_renderer(b, w, h, |v, f| {
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
        with_renderer(Builtin::ChapterReflect, 800, 600, |v, f| {
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
        with_renderer(Builtin::ChapterDirect, 16, 16, |v, f| {
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
