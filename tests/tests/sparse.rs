//! The sparse sampler traces the pixels whose coordinates are both even, and
//! of the others exactly those its rule cannot interpolate; the rest are the
//! means of their traced neighbours.
//!
//! The expectations are computed here from another render: the prefiltered
//! image (the sparse sampler's ray in every pixel) gives each pixel's 8-bit
//! pixel and its class (what its ray met, read off the pixel
//! as in the adaptive sampler's tests, same scene); the rule is applied to
//! that image.

use super::adaptive::{H, W, class, scene};
use tessera_core::{
    Camera, Color, Encoding, RenderSettings, Sampler, Scene, Tile, TileCoord, Vec3, Viewport,
    builtin::Builtin, geometry::Sphere, material::Material, trace::RayCount,
};
use tessera_host::render_tiles;

fn settings(sampler: Sampler) -> RenderSettings {
    RenderSettings {
        sampler,
        max_depth: 0,
        seed: 3,
        encoding: Encoding::Linear,
    }
}

/// The traced neighbours of `(x, y)` by the rule, `None` where one lies beyond
/// the frame, empty for a traced pixel.
fn neighbours(x: u32, y: u32) -> Option<Vec<(u32, u32)>> {
    let (w, h) = (u32::from(W), u32::from(H));
    let xs: Vec<u32> = if x.is_multiple_of(2) {
        vec![x]
    } else {
        vec![x - 1, x + 1]
    };
    let ys: Vec<u32> = if y.is_multiple_of(2) {
        vec![y]
    } else {
        vec![y - 1, y + 1]
    };
    if xs.iter().any(|&a| a >= w) || ys.iter().any(|&b| b >= h) {
        return None;
    }
    if xs.len() == 1 && ys.len() == 1 {
        return Some(Vec::new());
    }
    Some(
        ys.iter()
            .flat_map(|&b| xs.iter().map(move |&a| (a, b)))
            .collect(),
    )
}

/// Each pixel's expected value under threshold `t` (`None`: its own ray, the
/// prefiltered pixel) and how many pixels take their own ray.
fn expected(t: u8) -> (Vec<Option<[u8; 3]>>, usize) {
    let s = scene();
    let view = s.view();
    let pre = s
        .renderer(Viewport::new(W, H), settings(Sampler::Prefiltered))
        .unwrap();
    let colour = |x: u32, y: u32| pre.pixel_color(&view, x, y, &mut ());
    let byte = |c: Color| {
        let q = c.to_rgb8();
        [q.r, q.g, q.b]
    };
    let (mut want, mut own) = (Vec::new(), 0);
    for y in 0..u32::from(H) {
        for x in 0..u32::from(W) {
            let Some(n) = neighbours(x, y).filter(|n| !n.is_empty()) else {
                want.push(None);
                own += 1;
                continue;
            };
            let cs: Vec<Color> = n.iter().map(|&(a, b)| colour(a, b)).collect();
            let px: Vec<[u8; 3]> = cs.iter().map(|&c| byte(c)).collect();
            let same = px.iter().all(|p| class(*p) == class(px[0]));
            let spread = (0..3).all(|c| {
                let lo = px.iter().map(|p| p[c]).min().unwrap();
                let hi = px.iter().map(|p| p[c]).max().unwrap();
                hi - lo <= t
            });
            if same && spread {
                // Each channel's mean, rounded half up.
                let k = px.len() as u32;
                let mean = |c: usize| {
                    let sum: u32 = px.iter().map(|p| u32::from(p[c])).sum();
                    ((sum + k / 2) / k) as u8
                };
                want.push(Some([mean(0), mean(1), mean(2)]));
            } else {
                want.push(None);
                own += 1;
            }
        }
    }
    (want, own)
}

#[test]
fn interpolates_exactly_where_the_rule_says() {
    let s = scene();
    let pre = {
        let r = s
            .renderer(Viewport::new(W, H), settings(Sampler::Prefiltered))
            .unwrap();
        render_tiles::<16>(&s.view(), &r, None).unwrap()
    };
    let mut interpolated = Vec::new();
    for t in [0, 8, 255] {
        let r = s
            .renderer(
                Viewport::new(W, H),
                settings(Sampler::Sparse { threshold: t }),
            )
            .unwrap();
        let img = render_tiles::<16>(&s.view(), &r, None).unwrap();
        let (want, _) = expected(t);
        for (i, w) in want.iter().enumerate() {
            let (x, y) = ((i % usize::from(W)) as u32, (i / usize::from(W)) as u32);
            let w = w.unwrap_or(pre.get_pixel(x, y).0);
            assert_eq!(img.get_pixel(x, y).0, w, "threshold {t}: pixel ({x}, {y})");
        }
        interpolated.push(want.iter().filter(|w| w.is_some()).count());
    }
    // A larger threshold interpolates more; at 255 only the classes' edges and
    // the frame's last column and row are traced beyond the quarter.
    let total = usize::from(W) * usize::from(H);
    assert!(
        interpolated[0] < interpolated[1] && interpolated[1] < interpolated[2],
        "{interpolated:?}"
    );
    assert!(interpolated[2] > total / 2, "{interpolated:?} of {total}");
}

#[test]
fn traces_the_even_pixels_of_tile_and_apron_then_only_what_it_cannot_interpolate() {
    let t = 8;
    let (_, own) = expected(t);
    let s = scene();
    let r = s
        .renderer(
            Viewport::new(W, H),
            settings(Sampler::Sparse { threshold: t }),
        )
        .unwrap();
    let (across, down) = r.tile_grid(16);
    let mut count = RayCount::default();
    let mut buf = Tile::<16>::new();
    let mut grid = 0;
    for ty in 0..down {
        for tx in 0..across {
            r.render_tile(&s.view(), TileCoord::new(tx, ty), &mut buf, &mut count)
                .unwrap();
            // The even coordinates of the tile widened by one on each side,
            // within the frame.
            let evens = |t: u16, n: u16| {
                let lo = (usize::from(t) * 16).saturating_sub(1);
                let hi = ((usize::from(t) + 1) * 16 + 1).min(usize::from(n));
                (lo..hi).filter(|v| v % 2 == 0).count()
            };
            grid += evens(tx, W) * evens(ty, H);
        }
    }
    // `own` counts the traced pixels too (both coordinates even).
    let even = usize::from(W).div_ceil(2) * usize::from(H).div_ceil(2);
    assert_eq!(count.primary as usize, grid + own - even);
}

/// On every built-in scene at its own depth, with the default threshold, a
/// sparse render is within 2 levels of the prefiltered render (its ray in every
/// pixel) but in a few pixels (highlights, reflections and texture detail
/// narrower than two pixels), with far fewer camera rays. The bounds, per
/// scene, are a little above what was measured at 160x120 (in the comments):
/// the untextured chapter scenes interpolate almost everywhere off their edges;
/// the interference fringes vary fastest and keep the most rays.
#[test]
fn stays_close_to_the_prefiltered_image_with_fewer_rays() {
    let vp = Viewport::new(160, 120);
    // (scene, pixels more than 2 levels off per 10,000, camera rays per 100
    // of the prefiltered render's)
    let bounds = [
        (Builtin::ChapterDirect, 5, 50),  // 1.0, 43.7
        (Builtin::ChapterReflect, 5, 50), // 1.6, 44.1
        (Builtin::Interference, 250, 85), // 185.9, 79.6
        (Builtin::Showcase, 80, 60),      // 52.1, 54.3
        (Builtin::Teapot, 80, 60),        // 60.9, 55.9
    ];
    assert_eq!(bounds.len(), Builtin::ALL.len());
    for (b, far_max, rays_max) in bounds {
        let run = |sampler| {
            let st = RenderSettings {
                sampler,
                ..b.settings()
            };
            b.with_scene(|view, cam| {
                let r = tessera_core::Renderer::try_new(cam, vp, st).unwrap();
                let (img, c) = tessera_host::render_parallel::<16>(view, &r, &|| {}).unwrap();
                (img, c.primary)
            })
            .unwrap()
        };
        let (pre, pre_rays) = run(Sampler::Prefiltered);
        let (sparse, rays) = run(Sampler::sparse());
        let far = pre
            .pixels()
            .zip(sparse.pixels())
            .filter(|(a, b)| a.0.iter().zip(&b.0).any(|(p, q)| p.abs_diff(*q) > 2))
            .count() as u64;
        let total = pre.pixels().count() as u64;
        println!(
            "{}: {:.1} per 10,000 pixels off, {:.1} rays per 100",
            b.name(),
            far as f64 * 1e4 / total as f64,
            rays as f64 * 100.0 / pre_rays as f64
        );
        assert!(
            far * 10_000 <= far_max * total,
            "{}: {far} of {total} pixels",
            b.name()
        );
        assert!(
            rays * 100 <= rays_max * pre_rays,
            "{}: {rays} camera rays against {pre_rays}",
            b.name()
        );
    }
}

/// Where no primitive reaches a tile, its rays are counted, not traced: as
/// many as tracing it would cast (the even pixels of the tile and its apron,
/// and the pixels with a neighbour beyond the frame: here the last row, odd),
/// counted here from the rule; and every pixel is the background.
#[test]
fn an_empty_view_counts_the_rays_it_does_not_trace() {
    let cam = Camera::try_new(
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::Y,
        50.0,
        0.1,
        100.0,
    )
    .unwrap();
    let mut s: Scene<tessera_core::capacities!(spheres: 1, materials: 1)> = Scene::new(cam);
    let bg = Color::new(0.0, 0.0, 0.7);
    s.set_background(bg).unwrap();
    let m = s.add_material(Material::matte(Color::WHITE)).unwrap();
    // Behind the camera: no tile's lists hold it.
    s.add_sphere(Sphere::try_new(Vec3::new(0.0, 0.0, 5.0), 1.0).unwrap(), m)
        .unwrap();
    let r = s
        .renderer(Viewport::new(W, H), settings(Sampler::sparse()))
        .unwrap();
    let (across, down) = r.tile_grid(16);
    let (mut count, mut buf, mut grid) = (RayCount::default(), Tile::<16>::new(), 0);
    let evens = |t: u16, n: u16| {
        let lo = (usize::from(t) * 16).saturating_sub(1);
        let hi = ((usize::from(t) + 1) * 16 + 1).min(usize::from(n));
        (lo..hi).filter(|v| v % 2 == 0).count()
    };
    let want = bg.to_rgb8();
    for ty in 0..down {
        for tx in 0..across {
            r.render_tile(&s.view(), TileCoord::new(tx, ty), &mut buf, &mut count)
                .unwrap();
            grid += evens(tx, W) * evens(ty, H);
            for y in 0..usize::from(buf.height()) {
                for x in 0..usize::from(buf.width()) {
                    assert_eq!(buf.pixel(x, y), Some(want));
                }
            }
        }
    }
    let edge = (0..u32::from(H))
        .flat_map(|y| (0..u32::from(W)).map(move |x| (x, y)))
        .filter(|&(x, y)| neighbours(x, y).is_none())
        .count();
    assert_eq!(edge, usize::from(W), "the last row, odd");
    assert_eq!(count.primary as usize, grid + edge);
}
