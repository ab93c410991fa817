//! Golden images: the built-in scenes must still render to the PNGs in
//! `tests/golden/`, byte for byte. They were looked at when committed (see the
//! README). To accept a deliberate change, run with `TESSERA_BLESS=1` and look at
//! the new images before committing them.

use std::path::PathBuf;
use tessera_core::Viewport;
use tessera_core::builtin::Builtin;

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("golden")
}

#[test]
fn builtin_scenes_match_their_golden_images() {
    let bless = std::env::var_os("TESSERA_BLESS").is_some();
    let mut failures = Vec::new();
    for &b in Builtin::ALL {
        let img = b
            .with_scene(|v, c| {
                tessera_host::render(v, c, Viewport::new(320, 240), b.settings(), 16)
            })
            .unwrap()
            .unwrap();
        let path = golden_dir().join(format!("{}.png", b.name()));
        if bless {
            tessera_host::write_png(&img, &path).unwrap();
            continue;
        }
        let golden = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (run with TESSERA_BLESS=1)", path.display()))
            .to_rgb8();
        if golden.as_raw() != img.as_raw() {
            let differing = golden
                .pixels()
                .zip(img.pixels())
                .filter(|(a, b)| a != b)
                .count();
            let actual = tessera_tests::output_dir().join(format!("{}-actual.png", b.name()));
            tessera_host::write_png(&img, &actual).unwrap();
            failures.push(format!(
                "{}: {differing} pixels differ (actual image: {})",
                b.name(),
                actual.display()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
