//! The built-in scenes, rendered to PNG through the host (written under
//! `target/test-images/` to be looked at), with checks of what each must show.

use image::RgbImage;
use tessera_core::builtin::Builtin;
use tessera_core::{Encoding, RenderSettings, Viewport};
use tessera_tests::output_dir;

/// `b` with its own settings (sRGB, what a viewer sees), for the PNG files.
fn render(b: Builtin, w: u16, h: u16) -> RgbImage {
    render_in(b, w, h, b.settings().encoding)
}

/// `b` encoded linear: the checks below are on the light's values (ratios,
/// brightness differences, fringe maxima), which the sRGB curve would bend.
fn render_linear(b: Builtin, w: u16, h: u16) -> RgbImage {
    render_in(b, w, h, Encoding::Linear)
}

fn render_in(b: Builtin, w: u16, h: u16, encoding: Encoding) -> RgbImage {
    let settings = RenderSettings {
        encoding,
        ..b.settings()
    };
    b.with_scene(|view, cam| tessera_host::render(view, cam, Viewport::new(w, h), settings, 16))
        .unwrap()
        .unwrap()
}

fn mean(img: &RgbImage, x0: u32, y0: u32, x1: u32, y1: u32) -> [f64; 3] {
    let mut s = [0.0; 3];
    let mut n = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            for (acc, &v) in s.iter_mut().zip(&img.get_pixel(x, y).0) {
                *acc += f64::from(v);
            }
            n += 1.0;
        }
    }
    s.map(|v| v / n)
}

#[test]
fn builtin_scenes_render_to_png() {
    let dir = output_dir();
    for &b in Builtin::ALL {
        let img = render(b, 320, 240);
        let path = dir.join(format!("{}.png", b.name()));
        tessera_host::write_png(&img, &path).unwrap();
        let back = image::open(&path).unwrap().to_rgb8();
        assert_eq!(back.as_raw(), img.as_raw(), "{}: PNG round trip", b.name());
        let distinct: std::collections::HashSet<_> = img.pixels().map(|p| p.0).collect();
        assert!(
            distinct.len() > 20,
            "{}: only {} colours",
            b.name(),
            distinct.len()
        );
    }
}

#[test]
fn chapter_pictures_show_a_lit_blue_sphere_and_reflections() {
    let direct = render_linear(Builtin::ChapterDirect, 160, 120);
    let reflect = render_linear(Builtin::ChapterReflect, 160, 120);
    // The blue sphere is in the middle: blue dominates there.
    let c = mean(&direct, 72, 50, 88, 60);
    assert!(c[2] > 2.0 * c[0] && c[2] > 2.0 * c[1], "centre {c:?}");
    // Lit from above: its top is brighter than its bottom.
    let top = mean(&direct, 76, 45, 84, 49);
    let bottom = mean(&direct, 76, 66, 84, 70);
    assert!(top[2] > bottom[2] + 30.0, "top {top:?} bottom {bottom:?}");
    // Reflection changes the mirror spheres but not the matte blue one.
    let diff = |x0, y0, x1, y1| {
        let (a, b) = (
            mean(&direct, x0, y0, x1, y1),
            mean(&reflect, x0, y0, x1, y1),
        );
        (0..3).map(|i| (a[i] - b[i]).abs()).sum::<f64>()
    };
    assert!(diff(72, 50, 88, 60) < 1.0, "blue sphere changed");
    assert!(
        diff(104, 52, 120, 64) > 10.0,
        "green mirror sphere unchanged"
    );
}

#[test]
fn interference_screen_shows_fringes_at_the_chapter_spacing() {
    // 7 mm screen height at 240 px: 0.75 mm spacing = 240 * 0.75 / h px.
    let img = render_linear(Builtin::Interference, 320, 240);
    let row: Vec<f64> = (0..320)
        .map(|x| f64::from(img.get_pixel(x, 120).0[1]))
        .collect();
    // Count bright maxima along the row.
    let maxima = (1..319)
        .filter(|&i| row[i] > 200.0 && row[i] >= row[i - 1] && row[i] > row[i + 1])
        .count();
    let h = 2.0 * 0.1 * (2.0f64).to_radians().tan(); // screen height seen, metres
    let width = h * 320.0 / 240.0;
    let fringes = width / 0.75e-3;
    assert!(
        (maxima as f64 - fringes).abs() <= 1.0,
        "{maxima} maxima, expected about {fringes:.1}"
    );
    // Dark fringes reach black, bright ones full green.
    assert!(row.iter().cloned().fold(f64::MAX, f64::min) < 5.0);
    assert!(row.iter().cloned().fold(0.0, f64::max) > 250.0);
}
