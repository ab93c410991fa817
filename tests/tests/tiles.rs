//! A pixel depends only on the scene, the camera, the settings and its coordinates:
//! never on the tile size or the order in which tiles are rendered.

use tessera_core::builtin::Builtin;
use tessera_core::{RenderSettings, Sampler, Viewport};
use tessera_host::render_tiles;

/// A deterministic shuffle (xorshift) of `0..n`.
fn shuffled(n: usize, mut seed: u64) -> Vec<usize> {
    let mut v: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        v.swap(i, (seed % (i as u64 + 1)) as usize);
    }
    v
}

#[test]
fn tile_size_and_order_do_not_change_a_pixel() {
    // An odd size, so that edge tiles are partial for every tile size.
    let vp = Viewport::new(77, 53);
    for &b in Builtin::ALL {
        for sampler in [
            Sampler::Centre,
            Sampler::Stratified(2),
            Sampler::Random(3),
            // The apron's centre rays decide; threshold 0 refines at every
            // colour step too.
            Sampler::adaptive(3),
            Sampler::Adaptive { k: 2, threshold: 0 },
            // The apron's traced pixels decide; threshold 255 interpolates
            // wherever the signatures agree.
            Sampler::sparse(),
            Sampler::Sparse {
                threshold: 255,
                spacing: 2,
            },
            // From the coarse grid where the scene allows it (the chapter's),
            // its three-pixel apron.
            Sampler::sparse_spaced(4),
            Sampler::Sparse {
                threshold: 255,
                spacing: 4,
            },
        ] {
            let settings = RenderSettings {
                sampler,
                seed: 7,
                ..b.settings()
            };
            b.with_scene(|view, cam| {
                let renderer = tessera_core::Renderer::try_new(cam, vp, settings).unwrap();
                let reference = render_tiles::<16>(view, &renderer, None).unwrap();
                let t8 = render_tiles::<8>(view, &renderer, None).unwrap();
                let t32 = render_tiles::<32>(view, &renderer, None).unwrap();
                let (ax, ay) = renderer.tile_grid(8);
                let order = shuffled(usize::from(ax) * usize::from(ay), 0x9e37_79b9);
                let t8_shuffled = render_tiles::<8>(view, &renderer, Some(&order)).unwrap();
                let name = b.name();
                assert_eq!(
                    reference.as_raw(),
                    t8.as_raw(),
                    "{name} {sampler:?}: 8 vs 16"
                );
                assert_eq!(
                    reference.as_raw(),
                    t32.as_raw(),
                    "{name} {sampler:?}: 32 vs 16"
                );
                assert_eq!(
                    reference.as_raw(),
                    t8_shuffled.as_raw(),
                    "{name} {sampler:?}: shuffled order"
                );
                // And equal to rendering each pixel on its own.
                for (x, y, p) in reference.enumerate_pixels() {
                    let q = settings
                        .encoding
                        .encode(renderer.pixel_color(view, x, y, &mut ()));
                    assert_eq!(p.0, [q.r, q.g, q.b], "{name} pixel ({x}, {y})");
                }
            })
            .unwrap();
        }
    }
}

#[test]
fn partial_edge_tiles_report_their_size_and_out_of_frame_is_an_error() {
    let b = Builtin::ChapterDirect;
    b.with_scene(|view, cam| {
        let renderer =
            tessera_core::Renderer::try_new(cam, Viewport::new(20, 10), b.settings()).unwrap();
        let mut tile = tessera_core::Tile::<16>::new();
        renderer
            .render_tile(view, tessera_core::TileCoord::new(1, 0), &mut tile, &mut ())
            .unwrap();
        assert_eq!((tile.width(), tile.height()), (4, 10));
        assert_eq!(tile.pixels().count(), 40);
        assert_eq!(
            renderer.render_tile(view, tessera_core::TileCoord::new(2, 0), &mut tile, &mut ()),
            Err(tessera_core::Error::TileOutOfFrame)
        );
        assert_eq!(
            renderer.render_tile(view, tessera_core::TileCoord::new(0, 1), &mut tile, &mut ()),
            Err(tessera_core::Error::TileOutOfFrame)
        );
    })
    .unwrap();
}
