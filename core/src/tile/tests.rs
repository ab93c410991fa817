use super::*;
use crate::color::{Encoding, Rgb8};
use crate::error::{Error, MAX_DEPTH};
use crate::sample::Sampler;
use crate::view::SceneView;
use core::mem::size_of;

#[test]
fn a_queue_hands_out_every_tile_once_however_the_cores_interleave() {
    let q = TileQueue::new(5, 3);
    let mut seen = std::vec::Vec::new();
    // Two "cores" asking in turn, then one alone: each tile once, in order.
    while let Some(c) = q.next() {
        seen.push(c);
        if let Some(c) = q.next() {
            seen.push(c);
        }
    }
    let want: std::vec::Vec<_> = (0..3)
        .flat_map(|ty| (0..5).map(move |tx| TileCoord::new(tx, ty)))
        .collect();
    assert_eq!(seen, want);
    assert_eq!(q.next(), None);
    q.reset();
    assert_eq!(q.next(), Some(TileCoord::new(0, 0)));
    assert_eq!(TileQueue::new(0, 7).next(), None);
}

#[test]
fn a_queue_shared_by_threads_gives_each_tile_to_one_of_them() {
    let q = TileQueue::new(37, 29);
    let taken: std::vec::Vec<std::vec::Vec<TileCoord>> = std::thread::scope(|s| {
        let hs: std::vec::Vec<_> = (0..4)
            .map(|_| s.spawn(|| core::iter::from_fn(|| q.next()).collect()))
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut all: std::vec::Vec<_> = taken.concat();
    all.sort_by_key(|c| (c.ty, c.tx));
    all.dedup();
    assert_eq!(all.len(), 37 * 29);
    assert_eq!(taken.iter().map(std::vec::Vec::len).sum::<usize>(), 37 * 29);
}

#[test]
fn interleaved_cores_cover_the_frame_once() {
    for cores in 1..5 {
        let mut all: std::vec::Vec<_> = (0..cores)
            .flat_map(|c| Interleave::new(c, cores, 4, 3))
            .collect();
        assert_eq!(all.len(), 12, "{cores} cores");
        all.sort_by_key(|c| (c.ty, c.tx));
        all.dedup();
        assert_eq!(all.len(), 12, "{cores} cores");
    }
    assert_eq!(Interleave::new(2, 2, 4, 3).count(), 0);
    let second: std::vec::Vec<_> = Interleave::new(1, 2, 3, 2).collect();
    assert_eq!(
        second,
        [
            TileCoord::new(1, 0),
            TileCoord::new(0, 1),
            TileCoord::new(2, 1)
        ]
    );
}

#[test]
fn an_edge_tile_packs_its_rows_and_leaves_the_rest_black() {
    // 20 x 13 with tiles of 8: tile (2, 1) holds 4 x 5 pixels.
    let b = crate::builtin::Builtin::ChapterReflect;
    b.with_scene(|view, cam| {
        let r = Renderer::try_new(cam, crate::Viewport::new(20, 13), b.settings()).unwrap();
        let mut tile = Tile::<8>::new();
        r.render_tile(view, TileCoord::new(2, 1), &mut tile, &mut ())
            .unwrap();
        assert_eq!((tile.width(), tile.height()), (4, 5));
        assert_eq!(tile.as_slice().len(), 20);
        for y in 0..5 {
            for x in 0..4 {
                let want = r.pixel_color(view, 16 + x, 8 + y, &mut ()).to_srgb8();
                assert_eq!(tile.as_slice()[(y * 4 + x) as usize], want, "({x}, {y})");
                assert_eq!(tile.pixel(x as usize, y as usize), Some(want));
            }
        }
        assert!(
            tile.pixels.as_flattened()[20..]
                .iter()
                .all(|p| *p == Rgb8::BLACK)
        );
        assert_eq!(
            tile.rows().map(<[Rgb8]>::len).collect::<std::vec::Vec<_>>(),
            [4; 5]
        );
    })
    .unwrap();
}
extern crate std;

/// The module docs' table's and the crate docs' bytes: `3 N^2 + 8`.
#[test]
fn tile_buffer_sizes_match_the_docs() {
    assert_eq!(size_of::<Tile<8>>(), 8 * 8 * 3 + 8);
    assert_eq!(size_of::<Tile<16>>(), 16 * 16 * 3 + 8);
    assert_eq!(size_of::<Tile<32>>(), 32 * 32 * 3 + 8);
    assert_eq!(
        [
            size_of::<Tile<8>>(),
            size_of::<Tile<16>>(),
            size_of::<Tile<32>>()
        ],
        [200, 776, 3_080]
    );
}

#[test]
fn settings_are_checked() {
    let mut s = RenderSettings {
        max_depth: MAX_DEPTH + 1,
        ..RenderSettings::default()
    };
    assert_eq!(
        s.validate(),
        Err(Error::DepthTooLarge {
            depth: MAX_DEPTH + 1
        })
    );
    s.max_depth = MAX_DEPTH;
    assert!(s.validate().is_ok());
    s.sampler = Sampler::Random(0);
    assert_eq!(s.validate(), Err(Error::BadSampleCount));
}

/// A set of loops by a mask over [`TileLoop::ALL`].
struct Set<const MASK: u8>;

impl<const MASK: u8> Loops for Set<MASK> {
    fn links(l: TileLoop) -> bool {
        TileLoop::ALL
            .iter()
            .position(|&x| x == l)
            .is_some_and(|i| MASK >> i & 1 == 1)
    }
}

/// Every tile of the frame with the loops of `L`, each tile's pixels in turn;
/// or the first error. The tile buffer holds another tile's pixels before
/// each render, so a tile left unfilled would show.
fn tiles_in<L: Loops>(
    renderer: &Renderer,
    view: &SceneView<'_>,
) -> Result<std::vec::Vec<Rgb8>, Error> {
    let mut out = std::vec::Vec::new();
    let mut tile = Tile::<8>::new();
    let (across, down) = renderer.tile_grid(8);
    for ty in 0..down {
        for tx in 0..across {
            for (i, p) in tile.pixels.iter_mut().flatten().enumerate() {
                *p = Rgb8::new(i as u8, 7, 200);
            }
            renderer.render_tile_in::<L, 8, _, _>(
                view,
                TileCoord::new(tx, ty),
                &mut tile,
                &mut (),
            )?;
            out.extend(tile.pixels());
        }
    }
    Ok(out)
}

/// One frame, its pixels with every loop, and the loop it needs.
struct Case<'a, 'v> {
    renderer: &'a Renderer,
    view: &'a SceneView<'v>,
    all: &'a [Rgb8],
    need: TileLoop,
}

/// The set `L` on `case`: the same bytes when it links the loop needed,
/// else refused (by `check_loops` too); returns whether it was refused.
fn one<L: Loops>(case: &Case<'_, '_>) -> bool {
    let enough = L::links(case.need);
    match tiles_in::<L>(case.renderer, case.view) {
        Ok(px) => assert!(enough && px == case.all, "{:?}", case.need),
        Err(e) => assert!(!enough && e == Error::NotLinked, "{:?}: {e}", case.need),
    }
    assert_eq!(case.renderer.check_loops::<L>(case.view).is_ok(), enough);
    !enough
}

/// The sets on `case`: each loop alone, every loop but one, all and none;
/// the number refused.
fn every_set(case: &Case<'_, '_>) -> usize {
    let alone = [
        one::<Set<0b000001>>(case),
        one::<Set<0b000010>>(case),
        one::<Set<0b000100>>(case),
        one::<Set<0b001000>>(case),
        one::<Set<0b010000>>(case),
        one::<Set<0b100000>>(case),
    ];
    let but = [
        one::<Set<0b111110>>(case),
        one::<Set<0b111101>>(case),
        one::<Set<0b111011>>(case),
        one::<Set<0b110111>>(case),
        one::<Set<0b101111>>(case),
        one::<Set<0b011111>>(case),
    ];
    let ends = [one::<Set<0b111111>>(case), one::<Set<0>>(case)];
    alone
        .iter()
        .chain(&but)
        .chain(&ends)
        .filter(|r| **r)
        .count()
}

/// With a set of loops that has what the settings and the scene need, a
/// render is the same bytes as with every loop; with a set that lacks one of
/// them, it is refused. All 32 sets on every built-in scene, with and without
/// bounces, in both encodings, with and without the adaptive sampler (whose
/// frames have background tiles too).
#[test]
fn a_render_with_fewer_loops_is_the_same_or_refused() {
    use crate::builtin::Builtin;
    for &b in Builtin::ALL {
        for (sampler, depth, encoding) in [
            (Sampler::Centre, 0, Encoding::Srgb),
            (Sampler::Stratified(2), 3, Encoding::Linear),
            (Sampler::adaptive(2), 3, Encoding::Srgb),
            (Sampler::adaptive(2), 0, Encoding::Linear),
            (
                Sampler::Adaptive { k: 2, threshold: 0 },
                5,
                Encoding::Linear,
            ),
        ] {
            b.with_scene(|view, cam| {
                let settings = RenderSettings {
                    sampler,
                    max_depth: depth,
                    seed: 3,
                    encoding,
                };
                let renderer =
                    Renderer::try_new(cam, crate::Viewport::new(20, 13), settings).unwrap();
                let all = tiles_in::<AllLoops>(&renderer, view).unwrap();
                let bounces = view.depth(depth) > 0;
                // The loop the settings and the scene need, derived here on its own.
                let need = match (sampler, bounces) {
                    (Sampler::Adaptive { .. }, bounces) => TileLoop::Adaptive { bounces },
                    (_, false) => TileLoop::Direct(encoding),
                    (_, true) => TileLoop::Bounces(encoding),
                };
                assert_eq!(renderer.tile_loop(view), need);
                let case = Case {
                    renderer: &renderer,
                    view,
                    all: &all,
                    need,
                };
                // Refused: the other five alone, the one "every loop but" it,
                // and none.
                assert_eq!(every_set(&case), 7);
            })
            .unwrap();
        }
    }
}
