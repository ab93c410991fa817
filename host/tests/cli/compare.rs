//! `tessera compare`'s silhouette band: the same rule on every frame's shape (a
//! pixel on the frame's border has the ring of pixels outside the frame as
//! neighbours), and the edges where one primitive's shading jumps (a box's
//! faces) in it.

use crate::common::{bin, scenes, scratch, text};
use std::path::Path;

/// Runs `compare` in `dir` with `args`: its exit code and stdout (stderr
/// appended).
fn compare(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let out = bin()
        .current_dir(dir)
        .arg("compare")
        .args(args)
        .output()
        .unwrap();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(!stderr.contains("panicked"), "{stderr}");
    (out.status.code(), format!("{stdout}{stderr}"))
}

/// The pixels in the band, as `compare` prints them.
fn band(stdout: &str) -> usize {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("silhouette band"))
        .unwrap_or_else(|| panic!("no band in {stdout}"));
    line.split_whitespace().nth(2).unwrap().parse().unwrap()
}

/// A sphere of radius `r` whose silhouette the camera's centre ray grazes: the
/// camera at `z = 6` looks down `-z` along `x = 0`, the sphere's centre is
/// `(r, 0, -1)`. Where the f32 core and the f64 reference put that ray, on or
/// off the sphere, is rounding.
fn grazed_sphere(r: f64) -> String {
    format!(
        "background = [0.5, 0.6, 0.8]\n\
         [camera]\nposition = [0, 0, 6]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\
         [[material]]\nname = \"m\"\ncolor = [0.9, 0.2, 0.1]\n\
         [[sphere]]\ncenter = [{r}, 0, -1]\nradius = {r}\nmaterial = \"m\"\n\
         [[light]]\nposition = [0, 5, 3]\nintensity = 30\n"
    )
}

/// A frame of one pixel and a frame of one row, each crossed through its
/// pixels' centres by an edge (a sphere's silhouette, a checker's cell edge):
/// the core and the reference disagree there by rounding (148 to 231 LSB), and
/// the pixels are in the band because the ring outside the frame lies on the
/// edge's other side, as they would be with neighbours inside a larger frame.
#[test]
fn one_pixel_and_one_row_frames_band_the_edges_through_them() {
    let dir = scratch("compare-shapes");
    std::fs::write(dir.join("graze.toml"), grazed_sphere(10.0)).unwrap();
    let checker = std::fs::read_to_string(scenes().join("examples/texture-checker.toml")).unwrap();
    std::fs::write(dir.join("checker.toml"), &checker).unwrap();
    // The camera's centre ray meets the board at its origin, where four cells
    // meet.
    let corner = checker.replace("position = [0, 2, 6]", "position = [0, 2, 6.1]");
    assert_ne!(corner, checker);
    std::fs::write(dir.join("corner.toml"), corner).unwrap();
    // The middle row's centres meet the board on the line z = 0, a cell edge.
    for (scene, size, pixels) in [
        ("graze.toml", "1x1", 1),
        ("corner.toml", "1x1", 1),
        ("checker.toml", "64x1", 64),
    ] {
        let (code, out) = compare(&dir, &[scene, "--size", size]);
        assert_eq!(code, Some(0), "{scene} at {size}: {out}");
        assert_eq!(band(&out), pixels, "{scene} at {size}: {out}");
        assert!(out.contains("pixels                 "), "{out}");
    }
}

/// A box 1e4 from the origin seen across two of its faces: the pixel on their
/// edge (found here with the reference's own intersection, the faces its
/// neighbours' centre rays hit) is 26 LSB off, and in the band.
#[test]
fn a_boxs_face_edge_far_from_the_origin_is_in_the_band() {
    use tessera_host::reference::geometry::Shape;
    let dir = scratch("compare-box");
    let off = 9.7e3;
    let scene = format!(
        "ambient = [0.1, 0.1, 0.1]\nbackground = [0.6, 0.7, 0.9]\n\
         [camera]\nposition = [{}, 3.0, 5.0]\nlook_at = [{off}, 0, 0]\nnear = 0.1\nfar = 100\n\
         [[material]]\nname = \"blue\"\ncolor = [0.2, 0.3, 0.9]\n\
         [[box]]\nmin = [{}, -1, -1]\nmax = [{}, 1, 1]\nmaterial = \"blue\"\n\
         [[light]]\nposition = [{}, 7, 6]\nintensity = 60\n",
        off + 2.0,
        off - 1.0,
        off + 1.0,
        off + 5.0
    );
    std::fs::write(dir.join("box.toml"), &scene).unwrap();
    let (code, out) = compare(&dir, &["box.toml", "--size", "96x64"]);
    assert_eq!(code, Some(0), "{out}");
    // The pixel the core and the reference disagree on lies on an edge between
    // two faces: the centre rays of its 3x3 neighbourhood all hit the box, on
    // more than one face.
    let desc = tessera_host::file::parse(&scene, "box.toml").unwrap();
    let vp = tessera_core::Viewport::new(96, 64);
    let camera = tessera_host::reference::RefCamera::new(&desc.camera, vp).unwrap();
    let b = &desc.boxes[0];
    let shape = Shape::Box {
        min: tessera_host::reference::vec::V3::from_array(b.min),
        max: tessera_host::reference::vec::V3::from_array(b.max),
    };
    let (px, py) = (56u32, 26u32);
    let mut faces = Vec::new();
    for y in py - 1..=py + 1 {
        for x in px - 1..=px + 1 {
            let (ray, t_far) = camera.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
            let hit = shape
                .intersect(&ray, t_far)
                .expect("every ray hits the box");
            faces.push(hit.face);
        }
    }
    faces.sort_unstable();
    faces.dedup();
    assert!(faces.len() >= 2, "{faces:?}");
    let settings = desc.settings().unwrap();
    let reference = tessera_host::reference::render(&desc, vp, &settings).unwrap();
    let band = tessera_host::compare::silhouette_band(96, 64, &reference.signature).unwrap();
    assert!(
        band[(py * 96 + px) as usize],
        "({px}, {py}) not in the band"
    );
    // It is the pixel that differs: the core's render against the reference.
    let core = desc.to_core().unwrap();
    let img = core
        .with_view(|v| tessera_host::render(v, core.camera(), vp, settings, 16))
        .unwrap();
    let (a, r) = (
        img.get_pixel(px, py).0,
        reference.to_rgb8().get_pixel(px, py).0,
    );
    let off_by = a.iter().zip(r).map(|(a, r)| a.abs_diff(r)).max().unwrap();
    assert!(off_by > 2, "{a:?} vs {r:?}");
}
