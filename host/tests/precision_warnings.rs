//! The loader's warnings about numbers that `f32` does not hold finely enough: a
//! surface moved by the rounding of its numbers by more than half a pixel at its
//! distance from the camera, a camera whose coordinates `f32` spaces more than a
//! quarter of a pixel apart at the nearest surface. An off-centre slope of
//! half-size 1e10, a ground sphere whose centre is not exact in `f32` and a camera
//! far from the origin warn, with the figure; the repository's scenes and a ground
//! 1.1e12 wide of vertices exact in `f32` (what docs/limits.md promises) do not;
//! and `tessera compare` shows a warned scene missing the accuracy bar where its
//! exact twin meets it.

use crate::common::{bin, scenes, scratch, text};
use tessera_host::{file, precision};

/// The warnings of the scene file `text`.
fn warnings(text: &str) -> Vec<String> {
    file::warnings(&file::parse(text, "t.toml").unwrap())
}

/// The number right after `before` in `w`, up to the next space.
fn figure(w: &str, before: &str) -> f64 {
    let at = w
        .find(before)
        .unwrap_or_else(|| panic!("{before:?} not in {w}"))
        + before.len();
    let end = w[at..].find([' ', ';', ')']).map_or(w.len(), |e| at + e);
    w[at..end]
        .parse()
        .unwrap_or_else(|_| panic!("{before:?} in {w}"))
}

/// What a pixel spans at `distance` at fovy 60 and `height` pixels.
fn footprint(distance: f64, height: f64) -> f64 {
    distance * 2.0 * 30f64.to_radians().tan() / height
}

const MATERIALS: &str = "[[material]]\nname = \"white\"\n[[material]]\nname = \"floor\"\n\
                         color = [0.5, 0.7, 0.5]\n";

/// The minimal scene with a floor 1 below its sphere, all moved by `[o, 0, o / 2]`.
fn moved_minimal(o: f64) -> String {
    let (x, z) = (o, o / 2.0);
    format!(
        "[camera]\nposition = [{x:?}, 1, {:?}]\nlook_at = [{x:?}, 0, {z:?}]\nnear = 0.1\n\
         far = 100\n{MATERIALS}[[sphere]]\ncenter = [{x:?}, 0, {z:?}]\nradius = 1\n\
         material = \"white\"\n[[plane]]\npoint = [{x:?}, -1, {z:?}]\nnormal = [0, 1, 0]\n\
         material = \"floor\"\n[[light]]\nposition = [{:?}, 4, {:?}]\nintensity = 20\n",
        z + 4.0,
        x + 2.0,
        z + 3.0
    )
}

/// A ground sphere of radius `r` whose centre is `top` below `-r` (its top at
/// `top`, 2 below the camera), with a unit sphere standing on it, at `size`.
fn ground_sphere(r: f64, top: f64, size: &str) -> String {
    format!(
        "[camera]\nposition = [0, 2, 0]\nlook_at = [0, 0, -10]\nnear = 0.1\nfar = 1000\n\
         [render]\n{size}\n{MATERIALS}[[sphere]]\ncenter = [0, 1, -8]\nradius = 1\n\
         material = \"white\"\n[[sphere]]\ncenter = [0, {:?}, 0]\nradius = {r:?}\n\
         material = \"floor\"\n[[light]]\nposition = [2, 6, 3]\nintensity = 40\n",
        -r + top
    )
}

/// A ground sloping by `k` (`y = k (x - cx)`) of two triangles of half-size `s`
/// centred on `(cx, cz)`, the camera 2 above its centre.
fn slope(cx: f64, cz: f64, s: f64, k: f64) -> (String, [[f64; 3]; 4]) {
    let v = [(-s, -s), (s, -s), (s, s), (-s, s)].map(|(dx, dz)| [cx + dx, k * dx, cz + dz]);
    let tri = |a: usize, b: usize, c: usize| {
        format!(
            "[[triangle]]\nvertices = [{:?}, {:?}, {:?}]\nmaterial = \"floor\"\n",
            v[a], v[b], v[c]
        )
    };
    let text = format!(
        "[camera]\nposition = [{cx:?}, 2, {cz:?}]\nlook_at = [{:?}, {:?}, {:?}]\nnear = 0.1\n\
         far = 1000\n[render]\nwidth = 64\nheight = 48\n{MATERIALS}[[sphere]]\n\
         center = [{:?}, {:?}, {:?}]\nradius = 1\nmaterial = \"white\"\n[[light]]\n\
         position = [{:?}, 40, {:?}]\nintensity = 400\n{}{}",
        cx - 3.0,
        -0.9 - 3.0 * k,
        cz - 8.0,
        cx - 3.0,
        1.0 - 3.0 * k,
        cz - 8.0,
        cx + 2.0,
        cz + 3.0,
        tri(0, 1, 2),
        tri(0, 2, 3)
    );
    (text, v)
}

#[test]
fn an_off_centre_slope_of_half_size_1e10_is_warned_about_with_its_move() {
    let (k, cx, cz) = (0.3, 1234.5678, -4321.123);
    let (text, v) = slope(cx, cz, 1e10, k);
    let w = warnings(&text);
    let moved: Vec<&String> = w.iter().filter(|w| w.contains("rounding")).collect();
    assert_eq!(moved.len(), 2, "{w:?}");
    // Independently: the height at the camera's foot of the plane through the
    // first triangle's rounded vertices, by barycentric weights in x and z (the
    // written slope is at height 0 there), then across the slope.
    let g = [v[0], v[1], v[2]].map(|p| p.map(|x| f64::from(x as f32)));
    let (d1, d2) = (
        [g[1][0] - g[0][0], g[1][2] - g[0][2]],
        [g[2][0] - g[0][0], g[2][2] - g[0][2]],
    );
    let q = [cx - g[0][0], cz - g[0][2]];
    let det = d1[0] * d2[1] - d1[1] * d2[0];
    let (b1, b2) = (
        (q[0] * d2[1] - q[1] * d2[0]) / det,
        (d1[0] * q[1] - d1[1] * q[0]) / det,
    );
    let height = g[0][1] + b1 * (g[1][1] - g[0][1]) + b2 * (g[2][1] - g[0][1]);
    let expected = height.abs() / (1.0 + k * k).sqrt();
    assert!(expected > 10.0, "{expected}");
    let by = figure(moved[0], "moves it by ");
    assert!(moved[0].starts_with("triangle 1: "), "{}", moved[0]);
    assert!((by / expected - 1.0).abs() < 0.01, "{by} vs {expected}");
    let pixels = figure(moved[0], "units where it is nearest the camera, ");
    let distance = figure(moved[0], "at its distance from the camera (");
    assert!(
        (pixels / (by / footprint(distance, 48.0)) - 1.0).abs() < 0.01,
        "{}",
        moved[0]
    );
    assert!(
        moved[0].contains("split the triangle into smaller ones"),
        "{}",
        moved[0]
    );
}

#[test]
fn a_ground_sphere_whose_centre_is_not_exact_in_f32_is_warned_about() {
    // Its centre -1e10 - 0.5 rounds to -1e10: the top rises from -0.5 to 0.
    let w = warnings(&ground_sphere(1e10, -0.5, ""));
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].starts_with("sphere 2: rounding its numbers to f32 moves it by 0.5 units"));
    let pixels = figure(&w[0], "units where it is nearest the camera, ");
    assert!(
        (pixels / (0.5 / footprint(2.5, 240.0)) - 1.0).abs() < 0.01,
        "{}",
        w[0]
    );
    // With its top exactly at 0 (numbers exact in f32): nothing to say.
    assert_eq!(
        warnings(&ground_sphere(1e10, 0.0, "")),
        Vec::<String>::new()
    );
}

#[test]
fn a_camera_far_from_the_origin_is_warned_about_with_its_spacing() {
    // f32 numbers are 2^-5 apart from 2^18 to 2^19, 1 apart from 2^23 to 2^24;
    // the nearest surface (the floor) is 2 below the camera.
    for (o, spacing, shown) in [(3e5, 0.03125, "0.0312"), (1e7, 1.0, "1")] {
        let w = warnings(&moved_minimal(o));
        let camera: Vec<&String> = w.iter().filter(|w| w.starts_with("camera: at ")).collect();
        assert_eq!(camera.len(), 1, "{o}: {w:?}");
        let c = camera[0];
        assert!(c.contains(&format!("only to {shown} units")), "{c}");
        let pixels = figure(c, "(the spacing of f32 numbers there), ");
        assert!(
            (pixels / (spacing / footprint(2.0, 240.0)) - 1.0).abs() < 0.01,
            "{c}"
        );
        assert!(c.contains("move the origin near the camera"), "{c}");
    }
    // 3e4 out: a fifth of a pixel, no warning.
    assert_eq!(
        precision::rounding_warnings(&file::parse(&moved_minimal(3e4), "t.toml").unwrap()),
        Vec::<String>::new()
    );
}

#[test]
fn a_ground_1e12_wide_of_vertices_exact_in_f32_is_not_warned_about() {
    // Half-size 2^40, sloping by 3/8: every vertex exact in f32. Two units
    // above its centre, as docs/limits.md promises.
    let s = 2f64.powi(40);
    let (text, v) = slope(0.0, 0.0, s, 0.375);
    assert!(v.iter().flatten().all(|&x| f64::from(x as f32) == x));
    let d = file::parse(&text, "t.toml").unwrap();
    assert_eq!(precision::rounding_warnings(&d), Vec::<String>::new());
}

#[test]
fn no_scene_of_the_repository_is_moved_by_its_rounding() {
    let mut n = 0;
    for dir in [scenes(), scenes().join("examples")] {
        for e in std::fs::read_dir(&dir).unwrap() {
            let path = e.unwrap().path();
            if path.extension().is_some_and(|x| x == "toml") {
                let d = file::load(&path).unwrap();
                let w = precision::rounding_warnings(&d);
                assert_eq!(w, Vec::<String>::new(), "{}", path.display());
                n += 1;
            }
        }
    }
    assert!(n > 25, "{n}");
}

/// `tessera compare` at 64x48: the ground sphere moved by its rounding warns
/// and misses the accuracy bar; its twin of numbers exact in f32 (the same
/// sphere, its top at 0) neither warns nor misses it.
#[test]
fn the_warned_sphere_misses_the_bar_and_its_exact_twin_meets_it() {
    let dir = scratch("precision");
    let size = "width = 64\nheight = 48";
    for (name, top, warned) in [("moved.toml", -0.5, true), ("exact.toml", 0.0, false)] {
        std::fs::write(dir.join(name), ground_sphere(1e10, top, size)).unwrap();
        let out = bin()
            .current_dir(&dir)
            .args(["compare", "--threads", "1", name])
            .output()
            .unwrap();
        let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
        assert_eq!(
            stderr.contains("warning: moved.toml: sphere 2: rounding its numbers to f32"),
            warned,
            "{stderr}"
        );
        assert_eq!(out.status.success(), !warned, "{stdout}{stderr}");
        let bar = if warned { "NOT met" } else { "met" };
        assert!(
            stdout.contains(&format!("0 NaN): {bar}")),
            "{name}: {stdout}{stderr}"
        );
    }
}
