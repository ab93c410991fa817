//! The sparse sampler traces the pixels whose coordinates are both even, and
//! of the others exactly those its rule cannot interpolate; the rest are the
//! means of their traced neighbours.
//!
//! The expectations are computed here from another render: the prefiltered
//! image (the sparse sampler's ray in every pixel) gives each pixel's 8-bit
//! pixel and its class (what its ray met, read off the pixel
//! as in the adaptive sampler's tests, same scene); the rule is applied to
//! that image.

use super::adaptive::{H, W, class, scene, scene_in};
use tessera_core::testing::ViewHooks as _;
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
    spaced_neighbours(x, y, 1, (u32::from(W), u32::from(H)))
}

/// The neighbours of `(x, y)` on the grid of step `2 s` (`s` 1: the even
/// pixels; 2: the multiples of 4) that it is the mean of, for a point of the
/// grid of step `s`: `None` where one lies beyond the frame `(w, h)`, empty for
/// a point of the coarser grid.
fn spaced_neighbours(x: u32, y: u32, s: u32, (w, h): (u32, u32)) -> Option<Vec<(u32, u32)>> {
    let on = |v: u32| v.is_multiple_of(2 * s);
    let xs: Vec<u32> = if on(x) { vec![x] } else { vec![x - s, x + s] };
    let ys: Vec<u32> = if on(y) { vec![y] } else { vec![y - s, y + s] };
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

/// The mean of `px` (each channel rounded half up) when they are of one class
/// and each channel spans at most `t`.
fn mean_of(px: &[([u8; 3], u8)], t: u8) -> Option<([u8; 3], u8)> {
    let same = px.iter().all(|p| p.1 == px[0].1);
    let spread = (0..3).all(|c| {
        let lo = px.iter().map(|p| p.0[c]).min().unwrap();
        let hi = px.iter().map(|p| p.0[c]).max().unwrap();
        hi - lo <= t
    });
    let k = px.len() as u32;
    let mean = |c: usize| {
        let sum: u32 = px.iter().map(|p| u32::from(p.0[c])).sum();
        ((sum + k / 2) / k) as u8
    };
    (same && spread).then(|| ([mean(0), mean(1), mean(2)], px[0].1))
}

/// Each pixel's expected value under threshold `t` and spacing `spacing`
/// (`None`: its own ray, the prefiltered pixel) and how many pixels take
/// their own ray (with spacing 4, the even pixels that do too).
fn expected_spaced(t: u8, spacing: u32) -> (Vec<Option<[u8; 3]>>, usize) {
    let s = scene();
    let view = s.view();
    let pre = s
        .renderer(Viewport::new(W, H), settings(Sampler::Prefiltered))
        .unwrap();
    let frame = (u32::from(W), u32::from(H));
    let own_px = |x: u32, y: u32| {
        let q = pre.pixel_color(&view, x, y, &mut ()).to_rgb8();
        ([q.r, q.g, q.b], class([q.r, q.g, q.b]))
    };
    let mut own = 0;
    // The even pixels: their own ray, or with spacing 4 the mean of their
    // coarse neighbours.
    let mut even = std::collections::HashMap::new();
    for y in (0..frame.1).step_by(2) {
        for x in (0..frame.0).step_by(2) {
            let coarse = match spacing {
                4 => spaced_neighbours(x, y, 2, frame).filter(|n| !n.is_empty()),
                _ => None,
            };
            let blended = coarse.and_then(|n| {
                let px: Vec<_> = n.iter().map(|&(a, b)| own_px(a, b)).collect();
                mean_of(&px, t)
            });
            let v = blended.unwrap_or_else(|| {
                own += 1;
                own_px(x, y)
            });
            even.insert((x, y), v);
        }
    }
    let mut want = Vec::new();
    for y in 0..frame.1 {
        for x in 0..frame.0 {
            if x % 2 == 0 && y % 2 == 0 {
                want.push(Some(even[&(x, y)].0));
                continue;
            }
            let blended = neighbours(x, y).and_then(|n| {
                let px: Vec<_> = n.iter().map(|a| even[a]).collect();
                mean_of(&px, t)
            });
            if blended.is_none() {
                own += 1;
            }
            want.push(blended.map(|b| b.0));
        }
    }
    (want, own)
}

/// [`expected_spaced`] for spacing 2, where every even pixel takes its ray
/// (counted in `own`).
fn expected(t: u8) -> (Vec<Option<[u8; 3]>>, usize) {
    let (mut want, own) = expected_spaced(t, 2);
    for (i, w) in want.iter_mut().enumerate() {
        let (x, y) = (i % usize::from(W), i / usize::from(W));
        if x % 2 == 0 && y % 2 == 0 {
            *w = None;
        }
    }
    (want, own)
}

/// Renders the test scene with threshold `t` and `spacing`, and checks each
/// pixel against `want` (`None`: the prefiltered pixel); returns the renderer.
fn renders_as_the_rule_says(
    t: u8,
    spacing: u8,
    want: &[Option<[u8; 3]>],
) -> tessera_core::Renderer {
    let s = scene();
    let pre = {
        let r = s
            .renderer(Viewport::new(W, H), settings(Sampler::Prefiltered))
            .unwrap();
        render_tiles::<16>(&s.view(), &r, None).unwrap()
    };
    let r = s
        .renderer(
            Viewport::new(W, H),
            settings(Sampler::Sparse {
                threshold: t,
                spacing,
            }),
        )
        .unwrap();
    let img = render_tiles::<16>(&s.view(), &r, None).unwrap();
    for (i, w) in want.iter().enumerate() {
        let (x, y) = ((i % usize::from(W)) as u32, (i / usize::from(W)) as u32);
        let w = w.unwrap_or(pre.get_pixel(x, y).0);
        assert_eq!(
            img.get_pixel(x, y).0,
            w,
            "threshold {t}, spacing {spacing}: pixel ({x}, {y})"
        );
    }
    r
}

#[test]
fn interpolates_exactly_where_the_rule_says() {
    let mut interpolated = Vec::new();
    for t in [0, 8, 255] {
        let (want, _) = expected(t);
        renders_as_the_rule_says(t, 2, &want);
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
            settings(Sampler::Sparse {
                threshold: t,
                spacing: 2,
            }),
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

/// With spacing 4, every pixel is what the rule gives from the prefiltered
/// image: the coarse pixels and the even pixels it cannot interpolate their
/// own rays, the other even pixels the means of their coarse neighbours, and
/// the odd pixels as with spacing 2 from those; over one tile that covers the
/// frame, the camera rays are exactly the pixels that take their own ray.
#[test]
fn from_the_coarse_grid_interpolates_and_traces_exactly_where_the_rule_says() {
    let s = scene();
    let mut owns = Vec::new();
    for t in [0, 8, 255] {
        let (want, own) = expected_spaced(t, 4);
        let r = renders_as_the_rule_says(t, 4, &want);
        let mut count = RayCount::default();
        let mut one = Tile::<64>::new();
        r.render_tile(&s.view(), TileCoord::new(0, 0), &mut one, &mut count)
            .unwrap();
        assert_eq!(count.primary as usize, own, "threshold {t}");
        owns.push(own);
    }
    // Fewer rays than spacing 2 at the same threshold, fewer at a larger one.
    let (_, own2) = expected(8);
    assert!(owns[1] < own2, "{owns:?} against {own2}");
    assert!(owns[0] > owns[1] && owns[1] > owns[2], "{owns:?}");
}

/// A primitive whose outline may be narrower than twice the coarse spacing
/// turns the coarse grid off: a sphere 2 pixels in radius between the coarse
/// rays is drawn as spacing 2 draws it (the same image), where the coarse grid
/// alone would have missed it; at 5 pixels the coarse grid is taken.
#[test]
fn a_primitive_narrower_than_the_coarse_grid_keeps_spacing_2() {
    // The test scene's sphere is 5.2 pixels in radius at 45x34 (the focal
    // length 36.5 pixels, 0.8 units at 5.66).
    let small_at = |radius_px: f32| {
        let mut s =
            scene_in::<tessera_core::capacities!(spheres: 2, planes: 1, materials: 2, lights: 1)>();
        let red = s.view().spheres()[0].material;
        // Seen from the camera at a distance of 5 units, through the point
        // between four coarse rays (pixel (34, 10) and its diagonal
        // neighbours, 2 away).
        let r = s
            .renderer(Viewport::new(W, H), settings(Sampler::Prefiltered))
            .unwrap();
        let (ray, _) = r.basis().ray(34.5, 10.5);
        let dir = ray.dir();
        let center = s.camera().position() + dir * 5.0;
        let f = f32::from(H) / 2.0 / (25.0f32.to_radians()).tan();
        let radius = radius_px * 5.0 / f;
        s.add_sphere(Sphere::try_new(center, radius).unwrap(), red)
            .unwrap();
        s
    };
    let render = |s: &Scene<_>, spacing| {
        let r = s
            .renderer(
                Viewport::new(W, H),
                settings(Sampler::Sparse {
                    threshold: 8,
                    spacing,
                }),
            )
            .unwrap();
        render_tiles::<16>(&s.view(), &r, None).unwrap()
    };
    let small = small_at(2.0);
    let (two, four) = (render(&small, 2), render(&small, 4));
    let red = |img: &image::RgbImage| {
        (33..36).any(|x| (9..12).any(|y| class(img.get_pixel(x, y).0) == 1))
    };
    assert!(red(&two), "spacing 2 draws the small sphere");
    assert_eq!(two, four, "a sphere 2 pixels in radius: spacing 2");
    let large = small_at(5.0);
    assert_ne!(
        render(&large, 2),
        render(&large, 4),
        "5 pixels: the coarse grid"
    );
    assert!(red(&render(&large, 4)));
}

/// Where no primitive reaches a tile, the coarse grid's rays are counted as
/// tracing them would cast them: the same count as with culling off (every
/// ray traced, all missing), for every tile size and an odd frame.
#[test]
fn an_empty_view_counts_the_coarse_grids_rays_as_tracing_them_would() {
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
    let m = s.add_material(Material::matte(Color::WHITE)).unwrap();
    // Behind the camera: no tile's lists hold it, and it takes the coarse grid.
    s.add_sphere(Sphere::try_new(Vec3::new(0.0, 0.0, 5.0), 1.0).unwrap(), m)
        .unwrap();
    for (w, h) in [(W, H), (45, 35), (46, 34), (47, 33), (44, 36)] {
        let r = s
            .renderer(Viewport::new(w, h), settings(Sampler::sparse_spaced(4)))
            .unwrap();
        let count = |view: &tessera_core::SceneView<'_>, n: usize| match n {
            5 => camera_rays::<5>(view, &r),
            8 => camera_rays::<8>(view, &r),
            _ => camera_rays::<16>(view, &r),
        };
        for n in [5, 8, 16] {
            let view = s.view();
            assert_eq!(
                count(&view, n),
                count(&view.without_culling(), n),
                "{w}x{h}, tiles of {n}"
            );
        }
    }
}

/// The camera rays of a frame rendered in tiles of `N`.
fn camera_rays<const N: usize>(
    view: &tessera_core::SceneView<'_>,
    r: &tessera_core::Renderer,
) -> u64 {
    let (across, down) = r.tile_grid(N);
    let (mut count, mut buf) = (RayCount::default(), Tile::<N>::new());
    for ty in 0..down {
        for tx in 0..across {
            r.render_tile(view, TileCoord::new(tx, ty), &mut buf, &mut count)
                .unwrap();
        }
    }
    count.primary
}

/// A solid the camera cannot see keeps no frame from the coarse grid (a box
/// wholly behind it), and one that reaches into the view does, wherever the
/// ball inside it lies: a thin box from behind the camera into the frame,
/// whose inner ball is behind the camera, keeps spacing 2. A flat primitive
/// keeps spacing 2 wherever it lies.
#[test]
fn the_coarse_grid_follows_what_the_camera_can_see() {
    type Caps = tessera_core::capacities!(spheres: 1, planes: 1, triangles: 1, boxes: 2, materials: 2, lights: 1);
    let with = |triangle: bool, hidden_box: bool, thin_box: bool| {
        let mut s = scene_in::<Caps>();
        let red = s.view().spheres()[0].material;
        // The camera stands at (0, 5, 4) and looks down towards -z: z > 4
        // and above it lies behind.
        if triangle {
            let t = tessera_core::geometry::Triangle::try_new(
                Vec3::new(0.0, 5.0, 8.0),
                Vec3::new(1.0, 5.0, 8.0),
                Vec3::new(0.0, 6.0, 8.0),
            )
            .unwrap();
            s.add_triangle(t, red).unwrap();
        }
        let mut add_box = |min: Vec3, max: Vec3| {
            let b = tessera_core::geometry::Aabb::try_new(min, max).unwrap();
            s.add_box(b, red).unwrap();
        };
        if hidden_box {
            add_box(Vec3::new(0.0, 5.0, 8.0), Vec3::new(0.5, 5.5, 8.5));
        }
        if thin_box {
            // 0.04 across, from z = 12 (behind) to z = 1.5 (in the middle of
            // the frame): its inner ball, at z = 6.75, is behind the camera.
            add_box(Vec3::new(0.0, 2.8, 1.5), Vec3::new(0.04, 2.84, 12.0));
        }
        let r = s
            .renderer(Viewport::new(W, H), settings(Sampler::sparse_spaced(4)))
            .unwrap();
        r.sparse_spacing(&s.view())
    };
    assert_eq!(with(false, false, false), Some(4));
    assert_eq!(with(false, true, false), Some(4), "a box behind the camera");
    assert_eq!(
        with(false, true, true),
        Some(2),
        "a thin box reaching into the view"
    );
    assert_eq!(with(true, false, false), Some(2), "a triangle, even behind");
}

/// The rule's bound, at its edge: a sphere whose outline the rule takes as
/// just wide enough (`f r / d` a hair above 4 pixels) holds the ray of a
/// coarse pixel, wherever it lies in the frame (its outline inside it), near
/// or far, off the axis or on it. 400 spheres; each coarse ray checked against
/// the sphere in `f64`.
#[test]
fn a_sphere_the_coarse_grid_takes_holds_a_coarse_ray() {
    let (w, h) = (u32::from(W), u32::from(H));
    let base = scene();
    let cam = *base.camera();
    let probe = base
        .renderer(Viewport::new(W, H), settings(Sampler::sparse_spaced(4)))
        .unwrap();
    let basis = *probe.basis();
    // The focal length in pixels, as the rule computes it.
    let f = f64::from(cam.near()) / f64::from(basis.u1().length());
    let mut seed = 0x2545_f491_u64;
    let mut next = || {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for k in 0..400 {
        // A centre seen through a point of the frame at least 8 pixels from
        // its edges, 1 to 60 units away.
        let (px, py) = (
            8.0 + next() * f64::from(w - 16),
            8.0 + next() * f64::from(h - 16),
        );
        let (ray, _) = basis.ray(px as f32, py as f32);
        let d = 1.0 + next() * 59.0;
        let center = cam.position() + ray.dir() * d as f32;
        let to = center - cam.position();
        let dist = f64::from(to.length());
        // Just above the rule's bound.
        let r = 4.0 * dist / f * (1.0 + 2.0 / 1024.0);
        let sphere = Sphere::try_new(center, r as f32).unwrap();
        let mut s: Scene<tessera_core::capacities!(spheres: 1, materials: 1)> = Scene::new(cam);
        let m = s.add_material(Material::matte(Color::WHITE)).unwrap();
        s.add_sphere(sphere, m).unwrap();
        let renderer = s
            .renderer(Viewport::new(W, H), settings(Sampler::sparse_spaced(4)))
            .unwrap();
        assert_eq!(renderer.sparse_spacing(&s.view()), Some(4), "sphere {k}");
        let c = [
            f64::from(center.x),
            f64::from(center.y),
            f64::from(center.z),
        ];
        let hit = (0..h).step_by(4).any(|y| {
            (0..w).step_by(4).any(|x| {
                let (ray, _) = basis.ray(x as f32 + 0.5, y as f32 + 0.5);
                let (o, dir) = (ray.origin(), ray.dir());
                let o = [f64::from(o.x), f64::from(o.y), f64::from(o.z)];
                let dir = [f64::from(dir.x), f64::from(dir.y), f64::from(dir.z)];
                let oc: Vec<f64> = (0..3).map(|i| c[i] - o[i]).collect();
                let t: f64 = (0..3).map(|i| oc[i] * dir[i]).sum();
                let closest: f64 = (0..3).map(|i| (oc[i] - t * dir[i]).powi(2)).sum();
                t > 0.0 && closest < (r * r)
            })
        });
        assert!(
            hit,
            "sphere {k}: radius {r} at {dist} units, seen at ({px:.1}, {py:.1})"
        );
    }
}
