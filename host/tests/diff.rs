//! `tessera diff A B`: two image files, a PNG (`tessera render`'s) or a PPM (the
//! firmware's, examples/qemu-m4f), compared pixel for pixel with compare's
//! figures: identical images report no difference and exit 0; a changed pixel is
//! found, where it is and by how much, with exit status 1; a bad file (wrong magic
//! number, truncated, other sizes, ...) is an error naming the file and what is
//! wrong, never a panic, and writes nothing.

use crate::common::{self, bin, scratch, text};
use image::{Rgb, RgbImage};
use std::path::Path;
use std::process::Output;

fn diff(dir: &Path, args: &[&str]) -> Output {
    let out = bin()
        .current_dir(dir)
        .arg("diff")
        .args(args)
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    out
}

/// `img` as a binary PPM, with a comment in its header as the netpbm tools
/// allow.
fn p6(img: &RgbImage) -> Vec<u8> {
    let mut bytes = format!(
        "P6\n# written by the test\n{} {}\n# 8 bits\n255\n",
        img.width(),
        img.height()
    )
    .into_bytes();
    bytes.extend_from_slice(img.as_raw());
    bytes
}

/// `img` as a plain PPM (P3): decimal values, a row of pixels a line.
fn p3(img: &RgbImage) -> Vec<u8> {
    let mut s = format!("P3 {} {} 255\n", img.width(), img.height());
    for row in img.rows() {
        let values: Vec<String> = row.flat_map(|p| p.0).map(|v| v.to_string()).collect();
        s.push_str(&values.join(" "));
        s.push('\n');
    }
    s.into_bytes()
}

/// `tessera render` of the default scene at 24x16 into `dir/a.png`, and its
/// pixels.
fn rendered(dir: &Path) -> RgbImage {
    let out = bin()
        .current_dir(dir)
        .args(["render", "--size", "24x16", "-o", "a.png"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    image::open(dir.join("a.png")).unwrap().to_rgb8()
}

/// The value of the figure `key` (the first word after the key's column).
fn figure<'a>(stdout: &'a str, key: &str) -> &'a str {
    let line = stdout
        .lines()
        .find(|l| l.starts_with(key))
        .unwrap_or_else(|| panic!("no {key:?} in {stdout}"));
    line[key.len()..].trim()
}

#[test]
fn the_png_and_the_ppm_of_the_same_pixels_are_identical() {
    let dir = scratch("diff-same");
    let img = rendered(&dir);
    std::fs::write(dir.join("b.ppm"), p6(&img)).unwrap();
    std::fs::write(dir.join("c.ppm"), p3(&img)).unwrap();
    for (a, b) in [("a.png", "b.ppm"), ("b.ppm", "a.png"), ("c.ppm", "b.ppm")] {
        let out = diff(&dir, &[a, b]);
        let stdout = text(&out.stdout);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{a} {b}: {stdout}{}",
            text(&out.stderr)
        );
        assert!(
            stdout.lines().next().unwrap().ends_with(": 24x16"),
            "{stdout}"
        );
        assert_eq!(figure(&stdout, "pixels"), "384");
        assert_eq!(figure(&stdout, "PSNR"), "inf dB");
        assert_eq!(figure(&stdout, "mean FLIP"), "0.000000");
        assert_eq!(figure(&stdout, "max abs difference"), "0 LSB");
        assert_eq!(figure(&stdout, "differing pixels"), "0 (0.000%)");
        assert_eq!(figure(&stdout, "identical"), "yes");
        assert!(!stdout.contains("largest differences"), "{stdout}");
        assert!(text(&out.stderr).is_empty(), "{}", text(&out.stderr));
    }
    let stdout = text(&diff(&dir, &["a.png", "c.ppm"]).stdout);
    assert!(
        stdout.starts_with("a.png (PNG) vs c.ppm (PPM P3): 24x16"),
        "{stdout}"
    );
}

/// One pixel changed by 40 in one channel: found at its place, counted once,
/// listed with both images' channels; the exit status is 1 with a message
/// saying so; the heat map shows that pixel alone, red.
#[test]
fn a_changed_pixel_is_found_where_it_is() {
    let dir = scratch("diff-one");
    let img = rendered(&dir);
    let mut changed = img.clone();
    let (x, y) = (5, 3);
    let Rgb([r, g, b]) = *img.get_pixel(x, y);
    let g2 = if g >= 128 { g - 40 } else { g + 40 };
    changed.put_pixel(x, y, Rgb([r, g2, b]));
    std::fs::write(dir.join("b.ppm"), p6(&changed)).unwrap();
    let out = diff(&dir, &["a.png", "b.ppm", "--heatmap", "h.png"]);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert_eq!(figure(&stdout, "max abs difference"), "40 LSB");
    assert_eq!(figure(&stdout, "differing pixels"), "1 (0.260%)");
    assert_eq!(
        figure(&stdout, "largest differences"),
        format!("(5, 3) 40 LSB: {r},{g},{b} vs {r},{g2},{b}")
    );
    assert!(
        stdout.contains(
            "all pixels:   within 0 / 1 / 2 LSB, more: 99.740% / 99.740% / 99.740%, 1 px"
        ),
        "{stdout}"
    );
    assert_eq!(figure(&stdout, "identical"), "no");
    assert!(figure(&stdout, "PSNR") != "inf dB", "{stdout}");
    assert!(stdout.contains("wrote h.png"), "{stdout}");
    assert!(
        stderr
            .contains("tessera: error: a.png and b.ppm differ: 1 pixel(s) of 384, by up to 40 LSB")
            && stderr.contains("(5, 3)"),
        "{stderr}"
    );
    let map = image::open(dir.join("h.png")).unwrap().to_rgb8();
    for (px, py, p) in map.enumerate_pixels() {
        let want = if (px, py) == (x, y) {
            [255, 30, 30]
        } else {
            [0, 0, 0]
        };
        assert_eq!(p.0, want, "heat map at ({px}, {py})");
    }
    // The largest first, equal ones in row order; a 1-LSB difference counts.
    changed.put_pixel(0, 0, {
        let Rgb([r, g, b]) = *img.get_pixel(0, 0);
        Rgb([r ^ 1, g, b])
    });
    changed.put_pixel(23, 15, {
        let Rgb([r, g, b]) = *img.get_pixel(23, 15);
        Rgb([r, g, if b >= 128 { b - 40 } else { b + 40 }])
    });
    std::fs::write(dir.join("c.ppm"), p3(&changed)).unwrap();
    let stdout = text(&diff(&dir, &["a.png", "c.ppm"]).stdout);
    assert_eq!(figure(&stdout, "differing pixels"), "3 (0.781%)");
    let listed = figure(&stdout, "largest differences");
    let places: Vec<&str> = listed
        .split("; ")
        .map(|d| d.split(" LSB").next().unwrap())
        .collect();
    assert_eq!(places, ["(5, 3) 40", "(23, 15) 40", "(0, 0) 1"], "{stdout}");
}

/// Runs `diff` on bad input: exit status 1, a message on stderr containing
/// every one of `want`, nothing written; returns stderr.
fn refused(dir: &Path, args: &[&str], want: &[&str]) -> String {
    let before = common::entries(dir);
    let out = diff(dir, args);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(stderr.starts_with("tessera: error: "), "{args:?}: {stderr}");
    for w in want {
        assert!(stderr.contains(w), "{args:?}: {w:?} not in {stderr}");
    }
    assert!(text(&out.stdout).is_empty(), "{args:?}");
    assert_eq!(common::entries(dir), before, "{args:?} wrote files");
    stderr
}

#[test]
fn bad_images_are_refused_with_the_file_and_the_fault() {
    let dir = scratch("diff-bad");
    let img = rendered(&dir);
    let good = p6(&img);
    let put = |name: &str, bytes: &[u8]| std::fs::write(dir.join(name), bytes).unwrap();
    // Truncated: the pixels' last bytes missing.
    put("short.ppm", &good[..good.len() - 10]);
    refused(
        &dir,
        &["a.png", "short.ppm"],
        &[
            "short.ppm: truncated: its 24x16 pixels take 1152 bytes after the",
            "the file has 1142",
        ],
    );
    // Bytes after the pixels.
    put("long.ppm", &[&good[..], b"\n"].concat());
    refused(
        &dir,
        &["a.png", "long.ppm"],
        &["long.ppm: 1 more bytes after"],
    );
    // Wrong magic numbers.
    put("grey.ppm", &[b"P5", &good[2..]].concat());
    refused(
        &dir,
        &["a.png", "grey.ppm"],
        &[
            "grey.ppm: wrong magic number \"P5\" (a grey PGM)",
            "\"P6\" or \"P3\"",
        ],
    );
    put("gif.ppm", b"GIF89a....");
    refused(
        &dir,
        &["gif.ppm", "a.png"],
        &["gif.ppm: wrong magic number \"GI\""],
    );
    put("empty.ppm", b"");
    refused(
        &dir,
        &["empty.ppm", "a.png"],
        &["empty.ppm: the file is empty"],
    );
    // Different sizes: both named.
    let smaller = RgbImage::from_fn(24, 15, |x, y| *img.get_pixel(x, y));
    put("small.ppm", &p6(&smaller));
    refused(
        &dir,
        &["a.png", "small.ppm"],
        &["the images are not the same size: a.png is 24x16, small.ppm is 24x15"],
    );
    // The header: maxval, sizes, truncated, not a number.
    put("deep.ppm", b"P6 24 16 65535\n");
    refused(
        &dir,
        &["deep.ppm", "a.png"],
        &["deep.ppm: maxval 65535", "(maxval 255)"],
    );
    put("zero.ppm", b"P6 0 16 255\n");
    refused(&dir, &["zero.ppm", "a.png"], &["zero.ppm: a 0x16 picture"]);
    put("cut.ppm", b"P6\n# only a comment\n24");
    refused(
        &dir,
        &["cut.ppm", "a.png"],
        &["cut.ppm: truncated header: the file ends before the height"],
    );
    put("word.ppm", b"P6 24x16 255\n");
    refused(
        &dir,
        &["word.ppm", "a.png"],
        &["word.ppm: expected whitespace after the width 24, found 'x'"],
    );
    put("huge.ppm", b"P6 99999 99999 255\n");
    refused(
        &dir,
        &["huge.ppm", "a.png"],
        &[
            "huge.ppm: a 99999x99999 image",
            "more than the",
            "FLIP can measure",
        ],
    );
    put("wide.ppm", b"P6 99999999999 1 255\n");
    refused(
        &dir,
        &["wide.ppm", "a.png"],
        &["wide.ppm: the width is more than 4294967295"],
    );
    // P3: a value above the maxval, too few values, too many.
    put("over.ppm", b"P3 1 1 255 0 256 0\n");
    refused(
        &dir,
        &["over.ppm", "over.ppm"],
        &["over.ppm: the value of pixel (0, 0) is 256, more than the maxval 255"],
    );
    put("few.ppm", b"P3 2 1 255 0 0 0 1\n");
    refused(
        &dir,
        &["few.ppm", "few.ppm"],
        &["few.ppm: truncated: its 2x1 pixels take 6 values, the file has 4"],
    );
    put("more.ppm", b"P3 1 1 255 0 0 0 7\n");
    refused(
        &dir,
        &["more.ppm", "more.ppm"],
        &["more.ppm: more than the 3 values"],
    );
    // PNGs: truncated, not opaque, 16 bits.
    let png = std::fs::read(dir.join("a.png")).unwrap();
    put("cut.png", &png[..png.len() / 2]);
    refused(
        &dir,
        &["cut.png", "a.png"],
        &["cut.png: cannot read the PNG"],
    );
    let mut clear = image::RgbaImage::from_pixel(24, 16, image::Rgba([1, 2, 3, 255]));
    clear.put_pixel(2, 1, image::Rgba([1, 2, 3, 128]));
    clear.save(dir.join("clear.png")).unwrap();
    refused(
        &dir,
        &["clear.png", "a.png"],
        &["clear.png: pixel (2, 1) is not opaque (alpha 128)"],
    );
    let deep = image::ImageBuffer::<Rgb<u16>, _>::from_pixel(24, 16, Rgb([1u16, 2, 3]));
    deep.save(dir.join("deep.png")).unwrap();
    refused(
        &dir,
        &["deep.png", "a.png"],
        &["deep.png: a PNG of Rgb16 pixels"],
    );
    // Not a file, or no file.
    std::fs::create_dir(dir.join("folder.ppm")).unwrap();
    refused(
        &dir,
        &["folder.ppm", "a.png"],
        &["folder.ppm: cannot read the image: it is a folder, not a regular file"],
    );
    refused(
        &dir,
        &["a.png", "missing.ppm"],
        &["missing.ppm: cannot read the image"],
    );
    // The heat map may not replace an input.
    put("b.ppm", &good);
    refused(
        &dir,
        &["a.png", "b.ppm", "--heatmap", "b.ppm"],
        &["b.ppm", "the input image b.ppm"],
    );
    // A missing B is a usage error.
    let out = diff(&dir, &["a.png"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
}

/// Every prefix of a valid P6 and of a valid P3, and each of their bytes
/// replaced, is refused with a message or read: never a panic.
#[test]
fn no_prefix_or_mutation_of_a_ppm_panics() {
    let dir = scratch("diff-fuzz");
    let img = RgbImage::from_fn(3, 2, |x, y| Rgb([x as u8 * 80, y as u8 * 200, 7]));
    for (kind, good) in [("p6", p6(&img)), ("p3", p3(&img))] {
        let mut cases: Vec<Vec<u8>> = (0..good.len()).map(|n| good[..n].to_vec()).collect();
        for i in 0..good.len().min(30) {
            for b in [b'#', b'9', 0xff] {
                let mut m = good.clone();
                m[i] = b;
                cases.push(m);
            }
        }
        // Each against itself: what is read is the same on both sides.
        for (i, case) in cases.iter().enumerate() {
            let name = format!("{kind}-{i}.ppm");
            std::fs::write(dir.join(&name), case).unwrap();
            let out = diff(&dir, &[&name, &name]);
            let code = out.status.code();
            assert!(
                code == Some(0) || code == Some(1),
                "{name} {case:?}: {code:?} {}",
                text(&out.stderr)
            );
            if code == Some(1) {
                assert!(
                    text(&out.stderr).contains(&format!("tessera: error: {name}: ")),
                    "{}",
                    text(&out.stderr)
                );
            }
        }
    }
}
