//! The glTF reader against real exporter files (tests/data/gltf, see its
//! README) and hand-written ones, with expectations computed independently: from
//! the files' own JSON (accessor bounds) or by hand in the comments.

use super::*;
use base64::Engine as _;
use std::path::{Path, PathBuf};

/// The sample models' folder.
fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/gltf")
        .join(rel)
}

/// Reads `path` with the default limits.
fn read_default(path: &Path) -> Result<Imported, String> {
    read(path, &Limits::default())
}

/// Little-endian bytes of `v`.
fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// Little-endian bytes of `v`.
fn u16s(v: &[u16]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A glTF being written by hand: one buffer (a `data:` URI), its views and
/// accessors, then the rest of the JSON.
#[derive(Default)]
struct Doc {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Doc {
    /// Adds `bytes` as a buffer view (4-byte aligned); its index.
    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            self.bin.len(),
            bytes.len()
        ));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// Adds an accessor over a new view of `bytes`: `count` elements of `ty`
    /// (`VEC3`, ...) of `component` (5126: float, ...), with `extra` members.
    fn accessor(
        &mut self,
        bytes: &[u8],
        component: u32,
        ty: &str,
        count: usize,
        extra: &str,
    ) -> usize {
        let view = self.view(bytes);
        self.accessors.push(format!(
            r#"{{"bufferView":{view},"componentType":{component},"type":"{ty}","count":{count}{extra}}}"#
        ));
        self.accessors.len() - 1
    }

    /// Adds a `POSITION` accessor (with the `min` and `max` glTF requires).
    fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        let bound = |f: fn(f32, f32) -> f32, start: f32| {
            let b: Vec<String> = (0..3)
                .map(|k| p.iter().map(|v| v[k]).fold(start, f).to_string())
                .collect();
            b.join(",")
        };
        let extra = format!(
            r#","min":[{}],"max":[{}]"#,
            bound(f32::min, f32::INFINITY),
            bound(f32::max, f32::NEG_INFINITY)
        );
        self.accessor(&f32s(&p.concat()), 5126, "VEC3", p.len(), &extra)
    }

    /// The whole JSON: asset, buffer, views, accessors and `body` (more
    /// members, without braces).
    fn text(&self, body: &str) -> String {
        let uri = base64::engine::general_purpose::STANDARD.encode(&self.bin);
        format!(
            r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{uri}"}}],"bufferViews":[{}],"accessors":[{}],{body}}}"#,
            self.bin.len(),
            self.views.join(","),
            self.accessors.join(",")
        )
    }
}

/// Writes `text` as `model.gltf` in a new folder; the folder (kept alive) and
/// the file's path.
fn write(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.gltf");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

/// Reads the glTF `text` from a file; the result and the file as messages
/// name it.
fn read_text(text: &str) -> (Result<Imported, String>, String) {
    let (_dir, path) = write(text);
    (read_default(&path), path.display().to_string())
}

/// The error of reading `text`, checked to start with the file's name.
fn error_of(text: &str) -> String {
    let (result, file) = read_text(text);
    let e = result.expect_err("the file should be refused");
    assert!(e.starts_with(&format!("{file}: ")), "{e}");
    e
}

/// A mesh of one primitive with `attributes` (JSON) and `more` (JSON members),
/// on node 0 (`node`: its other members), the one node of scene 0.
fn one_mesh(attributes: &str, more: &str, node: &str) -> String {
    format!(
        r#""meshes":[{{"name":"M","primitives":[{{"attributes":{{{attributes}}}{more}}}]}}],"nodes":[{{"mesh":0{node}}}],"scenes":[{{"nodes":[0]}}],"scene":0"#
    )
}

/// A unit triangle in the xy plane, facing +z, as a document's first accessor.
fn triangle_doc() -> Doc {
    let mut doc = Doc::default();
    doc.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    doc
}

/// `(b - a) × (c - a)`.
fn face_normal(p: &[[f64; 3]], t: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = t.map(|i| p[i as usize]);
    crate::arr3::cross(crate::arr3::sub(b, a), crate::arr3::sub(c, a))
}

/// Asserts `a` and `b` agree to 1e-12.
fn close(a: [f64; 3], b: [f64; 3]) {
    assert!(
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12),
        "{a:?} != {b:?}"
    );
}

/// The smallest and largest coordinates of `p`.
fn bounds(p: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let lo = std::array::from_fn(|k| p.iter().map(|v| v[k]).fold(f64::INFINITY, f64::min));
    let hi = std::array::from_fn(|k| p.iter().map(|v| v[k]).fold(f64::NEG_INFINITY, f64::max));
    (lo, hi)
}

/// Box.gltf's JSON, as `serde_json` reads it (not through the reader).
fn box_json() -> json::Value {
    let text = std::fs::read(data("Box/Box.gltf")).unwrap();
    json::deserialize::from_slice(&text).unwrap()
}

use gltf::json;

/// Packs `json` (the text) and `bin` into a `.glb` by hand, as the GLB spec
/// lays it out: the 12-byte header, the JSON chunk padded with spaces, the
/// binary chunk padded with zeros.
fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| n.div_ceil(4) * 4;
    let (j, b) = (pad(json.len()), pad(bin.len()));
    let total = 12 + 8 + j + 8 + b;
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.resize(20 + j, b' ');
    out.extend_from_slice(&(b as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.resize(total, 0);
    out
}

/// Box.gltf packed as a `.glb` (its buffer's `uri` taken out), and as a
/// `.gltf` with its buffer as a `data:` URI: the same model in the three ways
/// glTF stores it.
fn box_variants(dir: &Path) -> (PathBuf, PathBuf) {
    let mut value = box_json();
    let bin = std::fs::read(data("Box/Box0.bin")).unwrap();
    let buffer = value["buffers"][0].as_object_mut().unwrap();
    buffer.remove("uri");
    let glb_path = dir.join("Box.glb");
    std::fs::write(&glb_path, glb(value.to_string().as_bytes(), &bin)).unwrap();
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bin)
    );
    value["buffers"][0]["uri"] = json::Value::String(uri);
    let embedded = dir.join("Box-embedded.gltf");
    std::fs::write(&embedded, value.to_string()).unwrap();
    (glb_path, embedded)
}

#[test]
fn box_has_12_triangles_24_vertices_its_bounds_and_red() {
    let model = read_default(&data("Box/Box.gltf")).unwrap();
    assert_eq!(model.warnings, Vec::<String>::new());
    assert_eq!(model.meshes.len(), 1);
    let mesh = &model.meshes[0];
    // Node 1 has no name; its mesh is "Mesh".
    assert_eq!(
        (mesh.name.as_str(), mesh.node, mesh.mesh, mesh.primitive),
        ("Mesh", 1, 0, 0)
    );
    assert_eq!(mesh.triangles.len(), 12);
    assert_eq!(mesh.positions.len(), 24);
    assert_eq!(mesh.normals.as_ref().map(Vec::len), Some(24));
    assert_eq!(mesh.uvs, None);
    // The bounds: the POSITION accessor's min and max, from the JSON, through
    // the parent's matrix (also from the JSON): the 8 corners moved.
    let json = box_json();
    let position = json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
        .as_u64()
        .unwrap() as usize;
    let get3 = |key: &str| -> [f64; 3] {
        let v = &json["accessors"][position][key];
        std::array::from_fn(|k| v[k].as_f64().unwrap())
    };
    let (min, max) = (get3("min"), get3("max"));
    let m: Vec<f64> = json["nodes"][0]["matrix"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            let c = [0, 1, 2].map(|k| if i >> k & 1 == 1 { max[k] } else { min[k] });
            // Column-major: x' = m0 x + m4 y + m8 z + m12, ...
            std::array::from_fn(|r| m[r] * c[0] + m[4 + r] * c[1] + m[8 + r] * c[2] + m[12 + r])
        })
        .collect();
    let (lo, hi) = bounds(&corners);
    let (got_lo, got_hi) = bounds(&mesh.positions);
    close(got_lo, lo);
    close(got_hi, hi);
    // Every triangle faces the way its vertices' normals say (winding and
    // normals both through the parent's rotation), and the normals are the 6
    // axis directions, 4 vertices each.
    let normals = mesh.normals.as_ref().unwrap();
    for &t in &mesh.triangles {
        let f = face_normal(&mesh.positions, t);
        for i in t {
            let n = normals[i as usize];
            assert!(f[0] * n[0] + f[1] * n[1] + f[2] * n[2] > 0.0, "{t:?}");
        }
    }
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let count = normals
                .iter()
                .filter(|n| (0..3).all(|k| n[k] == if k == axis { sign } else { 0.0 }))
                .count();
            assert_eq!(count, 4, "axis {axis} sign {sign}");
        }
    }
    // The material: "Red", base colour (0.800000011920929, 0, 0, 1) as the
    // JSON says, metallic 0, roughness 1 (glTF's default).
    assert_eq!(mesh.material, Some(0));
    let red = &model.materials[0];
    let factor: Vec<f64> = json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(red.base_color.to_vec(), factor);
    assert_eq!(red.base_color, [0.800000011920929, 0.0, 0.0, 1.0]);
    assert_eq!((red.name.as_str(), red.index), ("Red", 0));
    assert_eq!(
        (red.metallic, red.roughness, red.transmission, red.ior),
        (0.0, 1.0, 0.0, 1.5)
    );
    assert_eq!(
        (red.emissive, red.double_sided, red.base_color_texture),
        ([0.0; 3], false, None)
    );
    assert!(model.images.is_empty() && model.cameras.is_empty() && model.lights.is_empty());
}

#[test]
fn box_as_glb_and_as_data_uri_reads_as_the_gltf_with_its_bin() {
    let dir = tempfile::tempdir().unwrap();
    let (glb_path, embedded) = box_variants(dir.path());
    let gltf = read_default(&data("Box/Box.gltf")).unwrap();
    assert_eq!(read_default(&glb_path).unwrap(), gltf);
    assert_eq!(read_default(&embedded).unwrap(), gltf);
}

#[test]
fn box_textured_has_uvs_and_a_png_texture() {
    let model = read_default(&data("BoxTextured/BoxTextured.gltf")).unwrap();
    assert_eq!(model.warnings, Vec::<String>::new());
    let mesh = &model.meshes[0];
    assert_eq!((mesh.triangles.len(), mesh.positions.len()), (12, 24));
    // TEXCOORD_0's accessor says min [0, 0], max [6, 1].
    let uvs = mesh.uvs.as_ref().unwrap();
    assert_eq!(uvs.len(), 24);
    let max = uvs
        .iter()
        .fold([f64::MIN; 2], |m, v| [m[0].max(v[0]), m[1].max(v[1])]);
    let min = uvs
        .iter()
        .fold([f64::MAX; 2], |m, v| [m[0].min(v[0]), m[1].min(v[1])]);
    assert_eq!((min, max), ([0.0, 0.0], [6.0, 1.0]));
    // The sampler: magFilter 9729 (LINEAR), wrapS and wrapT 10497 (REPEAT).
    let texture = model.materials[0].base_color_texture.unwrap();
    assert_eq!(
        texture,
        TextureRef {
            image: 0,
            mag_nearest: false,
            wrap_s: Wrap::Repeat,
            wrap_t: Wrap::Repeat
        }
    );
    // The image: a PNG (its signature), the bytes of the data: URI, which are
    // CesiumLogoFlat.png's.
    let image = &model.images[0];
    assert_eq!(
        (image.mime.as_str(), image.index, image.name.as_str()),
        ("image/png", 0, "image 0")
    );
    assert!(image.bytes.starts_with(b"\x89PNG\r\n\x1a\n"));
    assert_eq!(
        image.bytes,
        std::fs::read(data("BoxTextured/CesiumLogoFlat.png")).unwrap()
    );
}

#[test]
fn an_external_image_is_read_beside_the_model() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("tex")).unwrap();
    let png = std::fs::read(data("BoxTextured/CesiumLogoFlat.png")).unwrap();
    std::fs::write(dir.path().join("tex/logo flat.png"), &png).unwrap();
    let doc = triangle_doc();
    let body = one_mesh(r#""POSITION":0"#, r#","material":0"#, "")
        + r#","materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],"textures":[{"source":0,"sampler":0}],"samplers":[{"magFilter":9728,"wrapS":33071,"wrapT":33648}],"images":[{"uri":"tex/logo%20flat.png"}]"#;
    let path = dir.path().join("model.gltf");
    std::fs::write(&path, doc.text(&body)).unwrap();
    let model = read_default(&path).unwrap();
    assert_eq!(model.images[0].bytes, png);
    assert_eq!(model.images[0].name, "logo flat.png");
    // magFilter 9728: NEAREST; 33071: CLAMP_TO_EDGE; 33648: MIRRORED_REPEAT.
    assert_eq!(
        model.materials[0].base_color_texture,
        Some(TextureRef {
            image: 0,
            mag_nearest: true,
            wrap_s: Wrap::ClampToEdge,
            wrap_t: Wrap::MirroredRepeat
        })
    );
    // The images together are bounded.
    let small = Limits {
        max_image_bytes: 100,
        ..Limits::default()
    };
    let e = read(&path, &small).unwrap_err();
    assert!(
        e.contains("image 0: 'tex/logo flat.png': ") && e.contains("limit of 100 bytes"),
        "{e}"
    );
}

#[test]
fn box_animated_keeps_its_hierarchy_and_warns_of_its_animations() {
    let model = read_default(&data("BoxAnimated/BoxAnimated.gltf")).unwrap();
    assert_eq!(
        model.warnings,
        [
            "animations are not read for a [[mesh]] file: 2 animations ignored, the triangles are as the file poses them (`tessera render` of the glTF file itself plays its first animation)"
        ]
    );
    // Scene nodes [3, 0]: node 3 (outer_box) first, then node 0 > 1 > 2
    // (inner_box, 3 levels down).
    let names: Vec<(&str, usize)> = model
        .meshes
        .iter()
        .map(|m| (m.name.as_str(), m.node))
        .collect();
    assert_eq!(names, [("outer_box", 3), ("inner_box", 2)]);
    // Every transform on the way is the identity (rotation [-0, -0, -0, -1]
    // is the identity): the bounds are the accessors' min and max, from the
    // JSON: inner ±0.33504000306129458, ±0.5, ±0.33504000306129458; outer ±0.5.
    let (lo, hi) = bounds(&model.meshes[1].positions);
    // (The JSON's f64, read as the f32 it stands for.)
    let inner = f64::from(0.335_040_003_061_294_58_f64 as f32);
    close(lo, [-inner, -0.5, -inner]);
    close(hi, [inner, 0.5, inner]);
    let (lo, hi) = bounds(&model.meshes[0].positions);
    close(lo, [-0.5; 3]);
    close(hi, [0.5; 3]);
    // 186 and 576 indices: 62 and 192 triangles; 96 and 224 vertices, all used.
    assert_eq!(model.meshes[1].triangles.len(), 62);
    assert_eq!(model.meshes[0].triangles.len(), 192);
    assert_eq!(
        (
            model.meshes[1].positions.len(),
            model.meshes[0].positions.len()
        ),
        (96, 224)
    );
    let names: Vec<&str> = model.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["outer", "inner"]);
    assert_eq!(
        (model.meshes[0].material, model.meshes[1].material),
        (Some(0), Some(1))
    );
}

#[test]
fn simple_skin_is_drawn_in_its_bind_pose_with_warnings() {
    let model = read_default(&data("SimpleSkin/SimpleSkin.gltf")).unwrap();
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.starts_with("node 0: skin ignored: ")),
        "{:?}",
        model.warnings
    );
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.starts_with("animations are not read for a [[mesh]] file"))
    );
    // 24 indices over 10 vertices: 8 triangles; the accessor's bounds.
    let mesh = &model.meshes[0];
    assert_eq!((mesh.triangles.len(), mesh.positions.len()), (8, 10));
    let (lo, hi) = bounds(&mesh.positions);
    close(lo, [-0.5, 0.0, 0.0]);
    close(hi, [0.5, 2.0, 0.0]);
}

#[test]
fn cameras_model_reads_its_perspective_camera_and_skips_the_orthographic_one() {
    let model = read_default(&data("Cameras/Cameras.gltf")).unwrap();
    assert_eq!(
        model.warnings,
        ["camera 1 (on node 2): orthographic, skipped: only perspective cameras are read"]
    );
    assert_eq!(model.cameras.len(), 1);
    let c = &model.cameras[0];
    assert_eq!((c.name.as_str(), c.node), ("camera 0", 1));
    // Node 1: translation [0.5, 0.5, 3], no rotation: looking down -Z, +Y up.
    close(c.position, [0.5, 0.5, 3.0]);
    close(c.forward, [0.0, 0.0, -1.0]);
    close(c.up, [0.0, 1.0, 0.0]);
    // yfov 0.7 rad = 0.7 × 180 / π = 40.1070456...°, as f32 then f64.
    assert!(
        (c.yfov_degrees - 40.107_045_659_157_63).abs() < 1e-5,
        "{}",
        c.yfov_degrees
    );
    assert_eq!((c.aspect, c.zfar), (Some(1.0), Some(100.0)));
    assert_eq!(c.znear, f64::from(0.01f32));
    // Node 0 turns the square (0, 0, 0)..(1, 1, 0) about X by the quaternion
    // (-0.383, 0, 0, 0.924), normalized (its length is 1.00023...): with
    // s = x / |q|, c = w / |q|, (0, 1, 0) goes to (0, c² - s², 2 s c)
    // = (0, 0.70717.., -0.70703..): 45° down from +Y towards -Z.
    let mesh = &model.meshes[0];
    let len = (0.383f64.powi(2) + 0.924f64.powi(2)).sqrt();
    let (s, co) = (-f64::from(0.383f32) / len, f64::from(0.924f32) / len);
    let want = [0.0, co * co - s * s, 2.0 * s * co];
    let got = mesh
        .positions
        .iter()
        .find(|p| p[0] == 0.0 && p[1] > 0.5)
        .copied()
        .unwrap();
    assert!(
        (0..3).all(|k| (got[k] - want[k]).abs() < 1e-6),
        "{got:?} != {want:?}"
    );
}

#[test]
fn a_node_chain_composes_parent_times_child() {
    // Parent: scale [2, 2, 2]. Child: rotation 90° about Z (quaternion
    // (0, 0, sin 45°, cos 45°)) and translation [1, 0, 0]. Grandchild: a matrix
    // translating by [0, 0, 3]; it carries the mesh.
    //
    // Vertex (1, 2, 0) with normal (1, 0, 0), by hand:
    //   grandchild: (1, 2, 0) + (0, 0, 3)             = (1, 2, 3)
    //   child: rotation about Z, (x, y, z) → (-y, x, z) = (-2, 1, 3),
    //          then + (1, 0, 0)                        = (-1, 1, 3)
    //   parent: × 2                                    = (-2, 2, 6)
    // The normal: the translations do not move it; the rotation turns
    // (1, 0, 0) to (0, 1, 0); the uniform scale's inverse transpose (× 1/2)
    // only shortens it, and it is made unit again: (0, 1, 0).
    let mut doc = Doc::default();
    let p = doc.positions(&[[1.0, 2.0, 0.0], [1.0, 3.0, 0.0], [1.0, 2.0, 1.0]]);
    let n = doc.accessor(&f32s(&[1.0, 0.0, 0.0].repeat(3)), 5126, "VEC3", 3, "");
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let body = format!(
        r#""meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"NORMAL":{n}}}}}]}}],
        "nodes":[
          {{"name":"parent","scale":[2,2,2],"children":[1]}},
          {{"name":"child","rotation":[0,0,{h},{h}],"translation":[1,0,0],"children":[2]}},
          {{"name":"grandchild","matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,3,1],"mesh":0}}],
        "scenes":[{{"nodes":[0]}}]"#
    );
    let (model, _) = read_text(&doc.text(&body));
    let model = model.unwrap();
    let mesh = &model.meshes[0];
    assert_eq!((mesh.name.as_str(), mesh.node), ("grandchild", 2));
    // Vertex 0 of the file is the first the triangle uses.
    assert!(
        mesh.positions[0]
            .iter()
            .zip([-2.0, 2.0, 6.0])
            .all(|(a, b)| (a - b).abs() < 1e-6)
    );
    close(
        mesh.normals.as_ref().unwrap()[0].map(|x| (x * 1e6).round() / 1e6),
        [0.0, 1.0, 0.0],
    );
    // Still front-facing: the face's normal along the vertex normals.
    let f = face_normal(&mesh.positions, mesh.triangles[0]);
    assert!(f[1] > 0.0, "{f:?}");
}

#[test]
fn normals_turn_by_the_inverse_transpose_and_a_mirror_reverses_the_winding() {
    // A triangle in the plane x + y = 1, its normal (1, 1, 0) / √2, under a
    // scale of [2, 1, 1]: the plane becomes x / 2 + y = 1, whose normal is
    // (1/2, 1, 0), normalized (1, 2, 0) / √5 — the inverse transpose's
    // diag(1/2, 1, 1) applied to (1, 1, 0).
    let mut doc = Doc::default();
    let p = doc.positions(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 1.0]]);
    let r = std::f32::consts::FRAC_1_SQRT_2;
    let n = doc.accessor(&f32s(&[r, r, 0.0].repeat(3)), 5126, "VEC3", 3, "");
    let body = one_mesh(
        &format!(r#""POSITION":{p},"NORMAL":{n}"#),
        "",
        r#","scale":[2,1,1]"#,
    );
    let (model, _) = read_text(&doc.text(&body));
    let mesh = &model.unwrap().meshes[0];
    let s5 = 5f64.sqrt();
    for v in mesh.normals.as_ref().unwrap() {
        assert!(
            (v[0] - 1.0 / s5).abs() < 1e-6 && (v[1] - 2.0 / s5).abs() < 1e-6 && v[2] == 0.0,
            "{v:?}"
        );
    }
    // The unit triangle (0,0,0), (1,0,0), (0,1,0) faces +z (counter-clockwise
    // seen from +z). Mirrored by scale [-1, 1, 1] its vertices are (0,0,0),
    // (-1,0,0), (0,1,0): in the file's order clockwise seen from +z, so the
    // winding is reversed to keep it facing +z: (0, 2, 1), whose
    // (b - a) × (c - a) = (0,1,0) × (-1,0,0) = (0, 0, 1).
    let doc = triangle_doc();
    let (model, _) = read_text(&doc.text(&one_mesh(r#""POSITION":0"#, "", r#","scale":[-1,1,1]"#)));
    let mesh = &model.unwrap().meshes[0];
    assert_eq!(mesh.triangles, [[0, 2, 1]]);
    close(
        face_normal(&mesh.positions, mesh.triangles[0]),
        [0.0, 0.0, 1.0],
    );
}

#[test]
fn strips_and_fans_become_triangles() {
    // Four vertices of a square, as a strip (0 1 2 3: triangles (0, 1, 2) and,
    // every other one reversed, (1, 3, 2)) and as a fan (0 1 2 3: (1, 2, 0)
    // and (2, 3, 0)); all face +z.
    let square = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let mut doc = Doc::default();
    doc.positions(&square);
    let (model, _) = read_text(&doc.text(&one_mesh(r#""POSITION":0"#, r#","mode":5"#, "")));
    let mesh = &model.unwrap().meshes[0];
    assert_eq!(mesh.triangles, [[0, 1, 2], [1, 3, 2]]);
    for &t in &mesh.triangles {
        assert!(face_normal(&mesh.positions, t)[2] > 0.0);
    }
    let fan = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let mut doc = Doc::default();
    doc.positions(&fan);
    let (model, _) = read_text(&doc.text(&one_mesh(r#""POSITION":0"#, r#","mode":6"#, "")));
    let mesh = &model.unwrap().meshes[0];
    // Renumbered in order of first use: file vertices 1, 2, 0, 3 → 0, 1, 2, 3.
    assert_eq!(mesh.triangles, [[0, 1, 2], [1, 3, 2]]);
    close(mesh.positions[3], [0.0, 1.0, 0.0]);
    for &t in &mesh.triangles {
        assert!(face_normal(&mesh.positions, t)[2] > 0.0);
    }
}

#[test]
fn points_and_lines_are_skipped_with_a_warning() {
    let doc = triangle_doc();
    let (model, _) = read_text(&doc.text(&one_mesh(r#""POSITION":0"#, r#","mode":1"#, "")));
    let model = model.unwrap();
    assert!(model.meshes.is_empty());
    assert_eq!(
        model.warnings,
        ["mesh 'M', primitive 0: lines (mode LINES) skipped: only triangles are drawn"]
    );
}

#[test]
fn u8_indices_normalized_u16_uvs_and_sparse_positions_are_read() {
    let mut doc = Doc::default();
    // Positions: 3 zeros in the buffer view, vertex 1 and 2 replaced by a
    // sparse accessor: (1, 0, 0) and (0, 1, 0).
    let base = doc.view(&f32s(&[0.0; 9]));
    let sparse_indices = doc.view(&[1u8, 2]);
    let sparse_values = doc.view(&f32s(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]));
    doc.accessors.push(format!(
        r#"{{"bufferView":{base},"componentType":5126,"type":"VEC3","count":3,"min":[0,0,0],"max":[1,1,0],
        "sparse":{{"count":2,"indices":{{"bufferView":{sparse_indices},"componentType":5121}},"values":{{"bufferView":{sparse_values}}}}}}}"#
    ));
    // UVs: normalized u16, 65535 = 1.0, 32768 = 32768 / 65535.
    let uv = doc.accessor(
        &u16s(&[0, 0, 65535, 0, 0, 32768]),
        5123,
        "VEC2",
        3,
        r#","normalized":true"#,
    );
    let idx = doc.accessor(&[0u8, 1, 2, 0], 5121, "SCALAR", 3, "");
    let body = one_mesh(
        &format!(r#""POSITION":0,"TEXCOORD_0":{uv}"#),
        &format!(r#","indices":{idx}"#),
        "",
    );
    let (model, _) = read_text(&doc.text(&body));
    let mesh = &model.unwrap().meshes[0];
    assert_eq!(mesh.positions, [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let uvs = mesh.uvs.as_ref().unwrap();
    assert_eq!(uvs[1], [1.0, 0.0]);
    assert!((uvs[2][1] - 32768.0 / 65535.0).abs() < 1e-6);
    assert_eq!(mesh.triangles, [[0, 1, 2]]);
}

#[test]
fn a_perspective_camera_looks_down_its_node_s_minus_z() {
    // Rotation 90° about +Y: quaternion (0, sin 45°, 0, cos 45°). Turning
    // (x, y, z) to (z, y, -x): -Z = (0, 0, -1) goes to (-1, 0, 0); +Y stays.
    let doc = triangle_doc();
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let body = format!(
        r#""cameras":[{{"name":"eye","type":"perspective","perspective":{{"yfov":0.5,"znear":0.1}}}}],
        "nodes":[{{"camera":0,"rotation":[0,{h},0,{h}],"translation":[1,2,3]}}],"scenes":[{{"nodes":[0]}}]"#
    );
    let (model, _) = read_text(&doc.text(&body));
    let model = model.unwrap();
    let c = &model.cameras[0];
    assert_eq!(c.name, "eye");
    close(c.position, [1.0, 2.0, 3.0]);
    assert!(
        (0..3).all(|k| (c.forward[k] - [-1.0, 0.0, 0.0][k]).abs() < 1e-7),
        "{:?}",
        c.forward
    );
    assert!(
        (0..3).all(|k| (c.up[k] - [0.0, 1.0, 0.0][k]).abs() < 1e-7),
        "{:?}",
        c.up
    );
    // 0.5 rad = 28.6478897...°.
    assert!((c.yfov_degrees - 0.5f64.to_degrees()).abs() < 1e-9);
    assert_eq!((c.aspect, c.zfar), (None, None));
}

#[test]
fn lights_point_their_node_s_way_and_sit_at_its_place() {
    // The directional light's node turns -90° about X (quaternion
    // (-sin 45°, 0, 0, cos 45°)): (x, y, z) → (x, z, -y), so its -Z,
    // (0, 0, -1), goes to (0, -1, 0): straight down. The point light sits at its
    // node's translation; the spot light becomes a point light.
    let doc = triangle_doc();
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let body = format!(
        r#""extensionsUsed":["KHR_lights_punctual"],
        "extensions":{{"KHR_lights_punctual":{{"lights":[
          {{"name":"sun","type":"directional","color":[1,0.9,0.8],"intensity":3}},
          {{"type":"point","intensity":20,"range":10}},
          {{"name":"cone","type":"spot","spot":{{"outerConeAngle":0.5}}}}]}}}},
        "nodes":[
          {{"rotation":[-{h},0,0,{h}],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}},
          {{"name":"bulb","translation":[1,4,2],"extensions":{{"KHR_lights_punctual":{{"light":1}}}}}},
          {{"translation":[0,5,0],"extensions":{{"KHR_lights_punctual":{{"light":2}}}}}}],
        "scenes":[{{"nodes":[0,1,2]}}]"#
    );
    let (model, _) = read_text(&doc.text(&body));
    let model = model.unwrap();
    let [sun, bulb, cone] = &model.lights[..] else {
        panic!("{:?}", model.lights);
    };
    let ImportedLightKind::Directional { direction } = sun.kind else {
        panic!("{sun:?}");
    };
    assert!(
        (0..3).all(|k| (direction[k] - [0.0, -1.0, 0.0][k]).abs() < 1e-7),
        "{direction:?}"
    );
    assert_eq!((sun.name.as_str(), sun.intensity), ("sun", 3.0));
    assert_eq!(sun.color, [1.0, f64::from(0.9f32), f64::from(0.8f32)]);
    assert_eq!(bulb.name, "bulb");
    assert_eq!(
        bulb.kind,
        ImportedLightKind::Point {
            position: [1.0, 4.0, 2.0],
            range: Some(10.0)
        }
    );
    assert_eq!(
        cone.kind,
        ImportedLightKind::Point {
            position: [0.0, 5.0, 0.0],
            range: None
        }
    );
    assert_eq!(
        model.warnings,
        ["light 'cone': a spot light, read as a point light: its cone is ignored"]
    );
}

#[test]
fn unread_material_features_are_warned_about_by_name() {
    let mut doc = triangle_doc();
    let png = std::fs::read(data("BoxTextured/CesiumLogoFlat.png")).unwrap();
    let image_view = doc.view(&png);
    let body = one_mesh(r#""POSITION":0,"COLOR_0":0"#, r#","material":0"#, "")
        + &format!(
            r#","extensionsUsed":["KHR_texture_transform","KHR_materials_clearcoat"],
            "materials":[{{"name":"Glass","alphaMode":"BLEND","normalTexture":{{"index":0}},"emissiveTexture":{{"index":0}},
              "extensions":{{"KHR_materials_clearcoat":{{"clearcoatFactor":1}}}},
              "pbrMetallicRoughness":{{"baseColorTexture":{{"index":0,"extensions":{{"KHR_texture_transform":{{"scale":[2,2]}}}}}}}}}}],
            "textures":[{{"source":0}}],"images":[{{"bufferView":{image_view},"mimeType":"image/png"}}]"#
        );
    let (model, _) = read_text(&doc.text(&body));
    let model = model.unwrap();
    assert_eq!(
        model.warnings,
        [
            "extension 'KHR_materials_clearcoat' (extensionsUsed) is not read: what it adds is ignored",
            "material 'Glass': KHR_texture_transform on its base colour texture ignored: the texture is drawn untransformed",
            "material 'Glass': its normal, emissive textures ignored: only the base colour texture is read",
            "material 'Glass': alphaMode BLEND ignored: drawn opaque",
            "mesh 'M', primitive 0: COLOR_0 vertex colours ignored",
        ]
    );
    // The texture is still read (untransformed), from the buffer view.
    assert_eq!(model.images[0].bytes, png);
    assert!(model.materials[0].base_color_texture.is_some());
}

#[test]
fn a_base_colour_texture_on_texcoord_1_is_dropped_with_a_warning() {
    let doc = triangle_doc();
    let body = one_mesh(r#""POSITION":0"#, r#","material":0"#, "")
        + r#","materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":1}}}],"textures":[{"source":0}],"images":[{"uri":"missing.png"}]"#;
    let (model, _) = read_text(&doc.text(&body));
    let model = model.unwrap();
    assert_eq!(
        model.warnings,
        [
            "material 0: its base colour texture reads TEXCOORD_1: only TEXCOORD_0 is read, so the texture is dropped"
        ]
    );
    // Nothing draws the image: it is not read (the file does not exist).
    assert!(model.images.is_empty() && model.materials[0].base_color_texture.is_none());
}

#[test]
fn material_extensions_are_read() {
    let doc = triangle_doc();
    let body = one_mesh(r#""POSITION":0"#, r#","material":0"#, "")
        + r#","extensionsUsed":["KHR_materials_transmission","KHR_materials_ior","KHR_materials_emissive_strength"],
        "materials":[{"doubleSided":true,"emissiveFactor":[1,0.5,0],
          "pbrMetallicRoughness":{"baseColorFactor":[0.5,0.25,1,1],"metallicFactor":0.25,"roughnessFactor":0.5},
          "extensions":{"KHR_materials_transmission":{"transmissionFactor":0.75},"KHR_materials_ior":{"ior":1.25},
            "KHR_materials_emissive_strength":{"emissiveStrength":4}}}]"#;
    let (model, _) = read_text(&doc.text(&body));
    let model = model.unwrap();
    assert_eq!(model.warnings, Vec::<String>::new());
    let m = &model.materials[0];
    assert_eq!(m.base_color, [0.5, 0.25, 1.0, 1.0]);
    assert_eq!(
        (m.metallic, m.roughness, m.transmission, m.ior),
        (0.25, 0.5, 0.75, 1.25)
    );
    // emissiveFactor × emissiveStrength.
    assert_eq!((m.emissive, m.double_sided), ([4.0, 2.0, 0.0], true));
}

#[test]
fn a_truncated_glb_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (glb_path, _) = box_variants(dir.path());
    let whole = std::fs::read(&glb_path).unwrap();
    let shown = glb_path.display().to_string();
    let cases = [
        (
            1000,
            format!(
                "truncated .glb: its header declares {} bytes, the file has 1000",
                whole.len()
            ),
        ),
        (
            8,
            "truncated .glb: 8 bytes, fewer than its 12-byte header".to_string(),
        ),
        (12, "truncated .glb: its header declares".to_string()),
    ];
    for (len, want) in cases {
        std::fs::write(&glb_path, &whole[..len]).unwrap();
        let e = read_default(&glb_path).unwrap_err();
        assert!(e.starts_with(&format!("{shown}: {want}")), "{e}");
    }
    // A header that declares fewer bytes than a header (`gltf` would panic).
    let mut short = whole.clone();
    short[8..12].copy_from_slice(&4u32.to_le_bytes());
    std::fs::write(&glb_path, &short).unwrap();
    let e = read_default(&glb_path).unwrap_err();
    assert!(
        e.contains("not a valid .glb: its header declares 4 bytes"),
        "{e}"
    );
    // The binary chunk cut short, the header's length fixed to match.
    let mut cut = whole[..whole.len() - 100].to_vec();
    let n = cut.len() as u32;
    cut[8..12].copy_from_slice(&n.to_le_bytes());
    std::fs::write(&glb_path, &cut).unwrap();
    let e = read_default(&glb_path).unwrap_err();
    assert!(
        e.contains("truncated .glb: its second chunk declares 648 bytes"),
        "{e}"
    );
}

#[test]
fn a_buffer_index_out_of_range_is_an_error() {
    let doc = triangle_doc();
    let text = doc
        .text(&one_mesh(r#""POSITION":0"#, "", ""))
        .replace(r#""buffer":0"#, r#""buffer":5"#);
    let e = error_of(&text);
    assert!(
        e.contains("not valid glTF: bufferViews[0].buffer: Index out of bounds"),
        "{e}"
    );
}

#[test]
fn an_accessor_past_its_buffer_view_is_an_error() {
    let mut doc = Doc::default();
    doc.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    // 4 vertices claimed over a view of 3 (36 bytes).
    doc.accessors[0] = doc.accessors[0].replace(r#""count":3"#, r#""count":4"#);
    let e = error_of(&doc.text(&one_mesh(r#""POSITION":0"#, "", "")));
    assert!(
        e.contains("mesh 'M', primitive 0: POSITION: accessor 0: 4 elements of 12 bytes every 12 from byte 0 lie past the end of buffer view 0 (36 bytes)"),
        "{e}"
    );
    // A byte offset that overflows, a stride shorter than the element, a
    // count of 0: refused before `gltf`'s reader (which would panic) sees them.
    for (from, to, want) in [
        (
            r#""count":3"#,
            r#""count":3,"byteOffset":18446744073709551615"#,
            "lie past the end of buffer view 0",
        ),
        (r#""count":3"#, r#""count":0"#, "a count of 0"),
    ] {
        let mut doc = triangle_doc();
        doc.accessors[0] = doc.accessors[0].replace(from, to);
        let e = error_of(&doc.text(&one_mesh(r#""POSITION":0"#, "", "")));
        assert!(e.contains(want), "{e}");
    }
    let doc = triangle_doc();
    let text = doc
        .text(&one_mesh(r#""POSITION":0"#, "", ""))
        .replace(r#""byteLength":36}"#, r#""byteLength":36,"byteStride":8}"#);
    let e = error_of(&text);
    assert!(
        e.contains("buffer view 0: a byteStride of 8, less than the element's 12 bytes"),
        "{e}"
    );
}

#[test]
fn a_nan_position_is_an_error_naming_the_attribute() {
    let mut doc = Doc::default();
    // f32 bytes of NaN at vertex 1 (min and max written by hand).
    let bytes = f32s(&[0.0, 0.0, 0.0, f32::NAN, 0.0, 0.0, 0.0, 1.0, 0.0]);
    doc.accessor(&bytes, 5126, "VEC3", 3, r#","min":[0,0,0],"max":[1,1,0]"#);
    let e = error_of(&doc.text(&one_mesh(r#""POSITION":0"#, "", "")));
    assert!(
        e.contains("mesh 'M', primitive 0: POSITION: vertex 1 is not finite ([NaN, 0, 0])"),
        "{e}"
    );
}

#[test]
fn a_missing_external_bin_is_an_error_naming_the_buffer() {
    let text = std::fs::read_to_string(data("Box/Box.gltf")).unwrap();
    let (_dir, path) = write(&text);
    let e = read_default(&path).unwrap_err();
    assert!(
        e.starts_with(&format!(
            "{}: buffer 0: 'Box0.bin': cannot read the buffer file: ",
            path.display()
        )),
        "{e}"
    );
}

#[test]
fn a_buffer_declared_larger_than_its_file_is_an_error() {
    let text = std::fs::read_to_string(data("Box/Box.gltf"))
        .unwrap()
        .replace(r#""byteLength": 648"#, r#""byteLength": 1000"#);
    let (dir, path) = write(&text);
    std::fs::copy(data("Box/Box0.bin"), dir.path().join("Box0.bin")).unwrap();
    let e = read_default(&path).unwrap_err();
    assert!(
        e.ends_with("buffer 0: declares 1000 bytes, its file 'Box0.bin' has 648"),
        "{e}"
    );
    // A data: URI shorter than declared too.
    let mut doc = triangle_doc();
    doc.bin.truncate(30);
    let text = doc
        .text(&one_mesh(r#""POSITION":0"#, "", ""))
        .replace(r#""byteLength":30,"uri""#, r#""byteLength":36,"uri""#);
    let e = error_of(&text);
    assert!(
        e.contains("buffer 0: declares 36 bytes, its data has 30"),
        "{e}"
    );
}

#[test]
fn uris_outside_the_model_s_folder_are_refused() {
    for (uri, want) in [
        ("../Box0.bin", "leaves the model's folder"),
        ("sub/../../Box0.bin", "leaves the model's folder"),
        ("%2e%2e/Box0.bin", "leaves the model's folder"),
        ("/etc/passwd", "is an absolute path"),
        ("file:///etc/passwd", "has a scheme"),
        ("https://example.com/Box0.bin", "has a scheme"),
        ("C:/Box0.bin", "has a scheme"),
        ("dir\\Box0.bin", "has a backslash"),
    ] {
        let text = std::fs::read_to_string(data("Box/Box.gltf"))
            .unwrap()
            .replace(
                "\"Box0.bin\"",
                &format!("\"{}\"", uri.replace('\\', "\\\\")),
            );
        let e = error_of(&text);
        assert!(e.contains("buffer 0: ") && e.contains(want), "{uri}: {e}");
    }
}

#[test]
fn an_index_past_the_vertex_count_is_an_error() {
    let mut doc = triangle_doc();
    let idx = doc.accessor(&u16s(&[0, 1, 5]), 5123, "SCALAR", 3, "");
    let e = error_of(&doc.text(&one_mesh(
        r#""POSITION":0"#,
        &format!(r#","indices":{idx}"#),
        "",
    )));
    assert!(
        e.contains("mesh 'M', primitive 0: indices: index 5 (at 2) is past the 3 vertices"),
        "{e}"
    );
    // Indices of floats: glTF allows unsigned integers only (`gltf`'s reader
    // would panic on them).
    let mut doc = triangle_doc();
    let idx = doc.accessor(&f32s(&[0.0, 1.0, 2.0]), 5126, "SCALAR", 3, "");
    let e = error_of(&doc.text(&one_mesh(
        r#""POSITION":0"#,
        &format!(r#","indices":{idx}"#),
        "",
    )));
    assert!(
        e.contains("indices: accessor 1: Scalar of F32, glTF allows SCALAR of UNSIGNED_BYTE"),
        "{e}"
    );
}

#[test]
fn a_node_cycle_is_an_error_not_a_hang() {
    let doc = triangle_doc();
    let body = r#""meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
        "nodes":[{"name":"a","children":[1],"mesh":0},{"name":"b","children":[0]}],"scenes":[{"nodes":[0]}]"#;
    let e = error_of(&doc.text(body));
    assert!(
        e.contains("node 'a': reached twice by the scene's hierarchy (a cycle"),
        "{e}"
    );
    // A node with two parents.
    let body = r#""meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
        "nodes":[{"children":[2]},{"children":[2]},{"mesh":0}],"scenes":[{"nodes":[0,1]}]"#;
    let e = error_of(&doc.text(body));
    assert!(e.contains("node 2: reached twice"), "{e}");
}

#[test]
fn required_extensions_not_read_are_errors_naming_them() {
    let e = read_default(&data("Box-Draco/Box.gltf")).unwrap_err();
    let shown = data("Box-Draco/Box.gltf").display().to_string();
    assert!(
        e.starts_with(&format!(
            "{shown}: extension 'KHR_draco_mesh_compression' is required (extensionsRequired): its meshes are Draco-compressed"
        )),
        "{e}"
    );
    let doc = triangle_doc();
    for (ext, want) in [
        ("EXT_meshopt_compression", "meshoptimizer-compressed"),
        ("KHR_mesh_quantization", "quantized"),
        ("KHR_texture_basisu", "KTX2"),
        ("EXT_unknown_thing", "tessera does not read it"),
    ] {
        let body = one_mesh(r#""POSITION":0"#, "", "")
            + &format!(r#","extensionsRequired":["{ext}"],"extensionsUsed":["{ext}"]"#);
        let e = error_of(&doc.text(&body));
        assert!(
            e.contains(&format!(
                "extension '{ext}' is required (extensionsRequired): "
            )) && e.contains(want),
            "{e}"
        );
    }
}

#[test]
fn draco_not_required_reads_the_uncompressed_data_or_refuses() {
    let doc = triangle_doc();
    let draco = r#","extensions":{"KHR_draco_mesh_compression":{"bufferView":0,"attributes":{"POSITION":0}}}"#;
    let body = one_mesh(r#""POSITION":0"#, draco, "")
        + r#","extensionsUsed":["KHR_draco_mesh_compression"]"#;
    let (model, _) = read_text(&doc.text(&body));
    let model = model.unwrap();
    assert_eq!(model.meshes[0].triangles.len(), 1);
    assert_eq!(
        model.warnings,
        [
            "mesh 'M', primitive 0: KHR_draco_mesh_compression ignored: its uncompressed data is read"
        ]
    );
    // Without the uncompressed data.
    let text = doc
        .text(&body)
        .replace(r#"{"bufferView":0,"componentType""#, r#"{"componentType""#);
    let e = error_of(&text);
    assert!(
        e.contains("mesh 'M', primitive 0: its data is compressed with KHR_draco_mesh_compression"),
        "{e}"
    );
}

#[test]
fn a_file_over_the_size_limit_is_refused_before_it_is_read() {
    let path = data("Box/Box.gltf");
    let small = Limits {
        max_file_bytes: 100,
        ..Limits::default()
    };
    let e = read(&path, &small).unwrap_err();
    let size = std::fs::metadata(&path).unwrap().len();
    let want = format!(
        "{}: the glTF file is {size} bytes, more than the limit of 100 bytes (",
        path.display()
    );
    assert!(e.starts_with(&want), "{e}");
}

#[test]
fn the_triangles_and_buffers_are_bounded_before_reading() {
    let path = data("Box/Box.gltf");
    let few = Limits {
        max_triangles: 11,
        ..Limits::default()
    };
    let e = read(&path, &few).unwrap_err();
    assert!(e.ends_with(
            "the scene's meshes have more than the limit of 11 triangles (every instance of every primitive counted)"
        ), "{e}");
    let small = Limits {
        max_buffer_bytes: 600,
        ..Limits::default()
    };
    let e = read(&path, &small).unwrap_err();
    assert!(
        e.ends_with("declare 648 bytes together, more than the limit of 600 bytes"),
        "{e}"
    );
    // A sparse accessor needs no buffer for its count: the count is bounded
    // (by the buffer limit, as if it were stored).
    let mut doc = Doc::default();
    let indices = doc.view(&[0u8]);
    let values = doc.view(&f32s(&[1.0, 1.0, 1.0]));
    doc.accessors.push(format!(
        r#"{{"componentType":5126,"type":"VEC3","count":1000000000,"min":[0,0,0],"max":[1,1,1],
        "sparse":{{"count":1,"indices":{{"bufferView":{indices},"componentType":5121}},"values":{{"bufferView":{values}}}}}}}"#
    ));
    let (_dir, path) = write(&doc.text(&one_mesh(r#""POSITION":0"#, "", "")));
    let many = Limits {
        max_triangles: usize::MAX,
        ..Limits::default()
    };
    let e = read(&path, &many).unwrap_err();
    assert!(
        e.contains("POSITION: accessor 0: 1000000000 elements of 12 bytes, more than the limit of 67108864 buffer bytes"),
        "{e}"
    );
}

#[test]
fn a_position_accessor_that_does_not_exist_is_an_error_not_a_panic() {
    let doc = triangle_doc();
    let e = error_of(&doc.text(&one_mesh(r#""POSITION":7"#, "", "")));
    assert!(
        e.contains("mesh 'M', primitive 0: POSITION: accessor 7 does not exist (the file has 1)"),
        "{e}"
    );
}

#[test]
fn broken_json_and_gltf_1_are_errors() {
    let e = error_of(r#"{"asset":{"version":"2.0"},"#);
    assert!(e.contains("not valid glTF JSON: "), "{e}");
    let e = error_of(r#"{"asset":{"version":"1.0"},"scenes":{"defaultScene":{"nodes":[]}}}"#);
    assert!(e.contains("a glTF 1.0 file: only glTF 2.0 is read"), "{e}");
    // A camera of type perspective with only an orthographic object, and an
    // image with neither uri nor buffer view (`gltf`'s wrappers would panic).
    let doc = triangle_doc();
    let body = r#""cameras":[{"type":"perspective","orthographic":{"xmag":1,"ymag":1,"zfar":10,"znear":1}}],
        "nodes":[{"camera":0}],"scenes":[{"nodes":[0]}]"#;
    let e = error_of(&doc.text(body));
    assert!(
        e.contains("camera 0: of type perspective, but has no perspective object"),
        "{e}"
    );
    let body = one_mesh(r#""POSITION":0"#, r#","material":0"#, "")
        + r#","materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],"textures":[{"source":0}],"images":[{"name":"nothing"}]"#;
    let e = error_of(&doc.text(&body));
    assert!(
        e.contains("image 'nothing': neither a uri nor a buffer view"),
        "{e}"
    );
}

#[test]
fn warnings_are_given_once_and_bounded() {
    // 300 meshes of points, each its own warning; 300 nodes on one of them,
    // one warning.
    let doc = triangle_doc();
    let meshes: Vec<String> = (0..300)
        .map(|i| {
            format!(
                r#"{{"name":"p{i}","primitives":[{{"attributes":{{"POSITION":0}},"mode":0}}]}}"#
            )
        })
        .collect();
    let nodes: Vec<String> = (0..600)
        .map(|i| format!(r#"{{"mesh":{}}}"#, i.min(299)))
        .collect();
    let all: Vec<String> = (0..600).map(|i| i.to_string()).collect();
    let body = format!(
        r#""meshes":[{}],"nodes":[{}],"scenes":[{{"nodes":[{}]}}]"#,
        meshes.join(","),
        nodes.join(","),
        all.join(",")
    );
    let (model, _) = read_text(&doc.text(&body));
    let warnings = model.unwrap().warnings;
    assert_eq!(warnings.len(), MAX_WARNINGS + 1);
    assert_eq!(
        warnings[0],
        "mesh 'p0', primitive 0: points (mode POINTS) skipped: only triangles are drawn"
    );
    assert_eq!(
        warnings[MAX_WARNINGS],
        format!("and {} more warnings", 300 - MAX_WARNINGS)
    );
}

/// Reads `bytes` as the file `model.gltf` of the folder `base` would be read,
/// from memory.
fn import_bytes(bytes: &[u8], base: &Path) -> Result<Imported, String> {
    let limits = Limits::default();
    let mut cx = Cx {
        file: "model".to_string(),
        base,
        limits: &limits,
        warnings: Vec::new(),
        seen: std::collections::HashSet::new(),
        unshown: 0,
    };
    import(bytes, true, &mut cx)
}

/// Reads `count` damaged copies of `good` (bytes overwritten, cut short, a
/// digit changed), none of which may panic.
fn survives_damage(good: &[u8], base: &Path, count: usize) {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for _ in 0..count {
        let mut bytes = good.to_vec();
        match next() % 3 {
            0 => {
                for _ in 0..1 + next() % 4 {
                    let at = (next() as usize) % bytes.len();
                    bytes[at] = next() as u8;
                }
            }
            1 => bytes.truncate((next() as usize) % bytes.len()),
            _ => {
                // A digit of the JSON replaced by another, or by a huge number.
                let digits: Vec<usize> = (0..bytes.len())
                    .filter(|&i| bytes[i].is_ascii_digit())
                    .collect();
                if let Some(&at) = digits.get((next() as usize) % digits.len().max(1)) {
                    if next() % 2 == 0 {
                        bytes[at] = b'0' + (next() % 10) as u8;
                    } else {
                        bytes.splice(at..=at, *b"4294967295000");
                    }
                }
            }
        }
        let _ = import_bytes(&bytes, base);
    }
}

#[test]
fn damaged_files_are_errors_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("Box/Box0.bin"), dir.path().join("Box0.bin")).unwrap();
    let (glb_path, embedded) = box_variants(dir.path());
    for good in [
        std::fs::read(&glb_path).unwrap(),
        std::fs::read(&embedded).unwrap(),
        std::fs::read(data("Box/Box.gltf")).unwrap(),
        std::fs::read(data("SimpleSkin/SimpleSkin.gltf")).unwrap(),
        std::fs::read(data("BoxTextured/BoxTextured.gltf")).unwrap(),
    ] {
        assert!(import_bytes(&good, dir.path()).is_ok());
        survives_damage(&good, dir.path(), 400);
    }
}

#[test]
fn a_mesh_moved_past_the_range_of_f64_is_an_error() {
    // Eight nodes scaling x by 1e38 and y by 1e-38 (finite f32s): x by 1e304
    // in all, the determinant still about 1. The leaf's translation of 1e38 in
    // x lands at 1e342, past f64's 1.8e308.
    let doc = triangle_doc();
    let chain: Vec<String> = (0..8)
        .map(|i| format!(r#"{{"scale":[1e38,1e-38,1],"children":[{}]}}"#, i + 1))
        .collect();
    let body = format!(
        r#""meshes":[{{"name":"M","primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "nodes":[{},{{"translation":[1e38,0,0],"mesh":0}}],"scenes":[{{"nodes":[0]}}]"#,
        chain.join(",")
    );
    let e = error_of(&doc.text(&body));
    assert!(
        e.ends_with("node 8: its world matrix moves mesh 'M' past the range of f64"),
        "{e}"
    );
    // Scaled by 1e38 nine times, the determinant overflows too: singular, the
    // mesh skipped with a warning.
    let chain: Vec<String> = (0..9)
        .map(|i| format!(r#"{{"scale":[1e38,1,1],"children":[{}]}}"#, i + 1))
        .collect();
    let body = format!(
        r#""meshes":[{{"name":"M","primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "nodes":[{},{{"mesh":0}}],"scenes":[{{"nodes":[0]}}]"#,
        chain.join(",")
    );
    let (model, _) = read_text(&doc.text(&body));
    let model = model.unwrap();
    assert!(model.meshes.is_empty());
    assert_eq!(
        model.warnings,
        [
            "node 9: its world matrix cannot be inverted (a zero scale, or one past the range of f64): its mesh, camera or light is skipped"
        ]
    );
}

#[test]
fn meshopt_not_required_reads_the_fallback_or_refuses() {
    let doc = triangle_doc();
    let ext = r#","extensions":{"EXT_meshopt_compression":{"buffer":0,"byteLength":36,"byteStride":12,"mode":"ATTRIBUTES","count":3}}}"#;
    let body =
        one_mesh(r#""POSITION":0"#, "", "") + r#","extensionsUsed":["EXT_meshopt_compression"]"#;
    let text = doc.text(&body).replacen(
        r#""byteLength":36}"#,
        &format!(r#""byteLength":36{ext}"#),
        1,
    );
    let (model, _) = read_text(&text);
    let model = model.unwrap();
    assert_eq!(model.meshes[0].triangles.len(), 1);
    assert_eq!(
        model.warnings,
        ["buffer view 0: EXT_meshopt_compression ignored: its uncompressed data is read"]
    );
    // A placeholder buffer put first (no uri: the fallback that decoding would
    // fill), so that the view reads it: no data to read.
    let text = text.replacen(
        r#""buffers":[{"#,
        r#""buffers":[{"byteLength":36,"extensions":{"EXT_meshopt_compression":{"fallback":true}}},{"#,
        1,
    );
    let e = error_of(&text);
    assert!(
        e.contains("buffer 0: a placeholder for EXT_meshopt_compression data"),
        "{e}"
    );
}

// ---- Animations ----------------------------------------------------------

/// A box 2 x 1 x 0.5 centred on the origin (its silhouette changes as it
/// turns about Y), 12 triangles facing out, as accessors of `doc`: its
/// positions and indices.
fn box_accessors(doc: &mut Doc) -> (usize, usize) {
    let corner = |i: u16| {
        let s = |bit: u16| if i >> bit & 1 == 1 { 1.0f32 } else { -1.0 };
        [s(0), 0.5 * s(1), 0.25 * s(2)]
    };
    let corners: Vec<[f32; 3]> = (0..8).map(corner).collect();
    // Each face: the corners with one coordinate's bit fixed, as a quad.
    let quads: [[u16; 4]; 6] = [
        [0, 2, 6, 4],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 5, 7, 6],
    ];
    let mut indices = Vec::new();
    for q in quads {
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            let [a, b, c] = t.map(|i| corners[usize::from(i)].map(f64::from));
            let n = crate::arr3::cross(crate::arr3::sub(b, a), crate::arr3::sub(c, a));
            let centre = [0, 1, 2].map(|k| a[k] + b[k] + c[k]);
            // Facing away from the centre (the origin).
            if crate::arr3::dot(n, centre) > 0.0 {
                indices.extend(t);
            } else {
                indices.extend([t[0], t[2], t[1]]);
            }
        }
    }
    let p = doc.positions(&corners);
    let i = doc.accessor(&u16s(&indices), 5123, "SCALAR", indices.len(), "");
    (p, i)
}

/// Adds a sampler's accessors to `doc`: `times` (SCALAR) and `values`
/// (`ty`, of as many floats as it holds); their indices.
fn keys(doc: &mut Doc, times: &[f32], ty: &str, values: &[f32]) -> (usize, usize) {
    let lo = times.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = times.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    let input = doc.accessor(
        &f32s(times),
        5126,
        "SCALAR",
        times.len(),
        &format!(r#","min":[{lo}],"max":[{hi}]"#),
    );
    let width = match ty {
        "VEC4" => 4,
        "VEC2" => 2,
        "SCALAR" => 1,
        _ => 3,
    };
    let output = doc.accessor(&f32s(values), 5126, ty, values.len() / width, "");
    (input, output)
}

/// A glTF of the box on node 1 `"cube"` (`cube`: more members of it) under
/// node 0 `"parent"` (`parent`: its members), seen by a camera at (0, 0, 5)
/// looking down -Z, lit by a sun from above the camera; with the members
/// `animations` (`"animations":[...]`, or nothing). Written in a new folder.
fn boxed(doc: &Doc, parent: &str, cube: &str, animations: &str) -> (tempfile::TempDir, PathBuf) {
    let s = (std::f64::consts::PI / 8.0).sin();
    let c = (std::f64::consts::PI / 8.0).cos();
    let body = format!(
        r#""meshes":[{{"name":"box","primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"material":0}}]}}],
        "materials":[{{"name":"m","pbrMetallicRoughness":{{"baseColorFactor":[0.9,0.5,0.2,1],"metallicFactor":0,"roughnessFactor":1}}}}],
        "cameras":[{{"type":"perspective","perspective":{{"yfov":0.8,"znear":0.1,"zfar":100,"aspectRatio":1.3333334}}}}],
        "extensionsUsed":["KHR_lights_punctual"],
        "extensions":{{"KHR_lights_punctual":{{"lights":[{{"type":"directional","intensity":2}}]}}}},
        "nodes":[
          {{"name":"parent","children":[1]{parent}}},
          {{"name":"cube","mesh":0{cube}}},
          {{"name":"eye","camera":0,"translation":[0,0,5]}},
          {{"name":"sun","rotation":[{},0,0,{c}],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}}],
        "scenes":[{{"nodes":[0,2,3]}}],"scene":0{animations}"#,
        -s
    );
    write(&doc.text(&body))
}

/// One animation named `name` of `channels` (`(sampler, node, path)`) over
/// `samplers` (`(input, output, interpolation)`), as JSON.
fn animation_json(
    name: &str,
    channels: &[(usize, usize, &str)],
    samplers: &[(usize, usize, &str)],
) -> String {
    let channels: Vec<String> = channels
        .iter()
        .map(|(s, n, p)| format!(r#"{{"sampler":{s},"target":{{"node":{n},"path":"{p}"}}}}"#))
        .collect();
    let samplers: Vec<String> = samplers
        .iter()
        .map(|(i, o, how)| format!(r#"{{"input":{i},"output":{o},"interpolation":"{how}"}}"#))
        .collect();
    format!(
        r#"{{"name":"{name}","channels":[{}],"samplers":[{}]}}"#,
        channels.join(","),
        samplers.join(",")
    )
}

/// The whole scene of the glTF file at `path`.
fn scene_of(path: &Path) -> Result<crate::desc::SceneDesc, String> {
    super::desc::scene(path, None)
}

/// `a` and `b` within `eps`, component by component.
fn within(a: &[f64], b: &[f64], eps: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= eps)
}

/// The core's render of `d` at 96 x 72.
#[cfg(feature = "cli")]
fn picture(d: &crate::desc::SceneDesc) -> image::RgbImage {
    let s = d.to_core().unwrap();
    let vp = tessera_core::Viewport::new(96, 72);
    s.with_view(|v| crate::render(v, s.camera(), vp, d.settings().unwrap(), 16))
        .unwrap()
}

/// How many pixels of `a` and `b` differ by more than 2 levels in a channel.
#[cfg(feature = "cli")]
fn differing(a: &image::RgbImage, b: &image::RgbImage) -> usize {
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 2))
        .count()
}

/// Frame `n` of `animated` looks as the `still` scene: its pixels within 2
/// levels but on the box's edges (at most 0.5% of them, where an instance's
/// f32 transform of the ray and the still mesh's f32 vertices may put a
/// pixel on either side), and frame 0 (the rest pose) does not (the test
/// can fail).
#[cfg(feature = "cli")]
fn looks_alike(animated: &crate::desc::SceneDesc, n: u32, still: &crate::desc::SceneDesc) {
    let want = picture(still);
    let got = picture(&animated.at_frame(n).unwrap());
    let total = (want.width() * want.height()) as usize;
    let off = differing(&got, &want);
    assert!(
        off * 200 <= total,
        "frame {n}: {off} of {total} pixels differ"
    );
    let rest = differing(&picture(&animated.at_frame(0).unwrap()), &want);
    assert!(
        rest * 20 > total,
        "frame 0 looks as frame {n}: {rest} pixels differ"
    );
}

/// A box turning a quarter about Y and moving 2 along X in its first second
/// (LINEAR): at frame 30 (1 s at glTF's default 30 fps) it stands as a still
/// file with the node turned 90 degrees (quaternion (0, sin 45°, 0, cos
/// 45°)) at (2, 0, 0) does; at frame 15 (0.5 s) halfway: 45 degrees
/// (quaternion (0, sin 22.5°, 0, cos 22.5°)) at (1, 0, 0). The box is an
/// instance of a mesh in the node's own space, named after the node, with a
/// track per channel.
#[test]
fn an_animated_box_turns_and_moves_as_an_instance() {
    let mut doc = Doc::default();
    box_accessors(&mut doc);
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let (ti, to) = keys(
        &mut doc,
        &[0.0, 1.0],
        "VEC3",
        &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0],
    );
    let (ri, ro) = keys(
        &mut doc,
        &[0.0, 1.0],
        "VEC4",
        &[0.0, 0.0, 0.0, 1.0, 0.0, h, 0.0, h],
    );
    let anim = animation_json(
        "go",
        &[(0, 1, "translation"), (1, 1, "rotation")],
        &[(ti, to, "LINEAR"), (ri, ro, "LINEAR")],
    );
    let (_d, path) = boxed(&doc, "", "", &format!(r#","animations":[{anim}]"#));
    let d = scene_of(&path).unwrap();
    assert_eq!(d.render.fps, 30.0);
    assert_eq!(d.meshes.len(), 1);
    assert_eq!(d.meshes[0].name.as_deref(), Some("cube/m"));
    assert_eq!(d.instances.len(), 1);
    let inst = &d.instances[0];
    assert_eq!(
        (inst.mesh.as_str(), inst.name.as_deref()),
        ("cube", Some("cube"))
    );
    // At rest: where the node stands (no TRS: the identity).
    assert_eq!(inst.translate, [0.0; 3]);
    assert_eq!(inst.quaternion, Some([0.0, 0.0, 0.0, 1.0]));
    assert_eq!(d.keyframes.len(), 2);
    assert_eq!(d.keyframes[0].times, [0.0, 1.0]);
    assert_eq!(d.keyframes[0].values[1], [2.0, 0.0, 0.0]);
    // The mesh is the file's box, in its own space: x within [-1, 1].
    let xs = d.meshes[0].faces.iter().flatten().map(|p| p[0].abs());
    assert_eq!(xs.fold(0.0, f64::max), 1.0);

    let at = |n: u32| d.at_frame(n).unwrap().instances[0].clone();
    let (s45, s22, c22) = (
        std::f64::consts::FRAC_1_SQRT_2,
        (std::f64::consts::PI / 8.0).sin(),
        (std::f64::consts::PI / 8.0).cos(),
    );
    let end = at(30);
    assert!(within(&end.translate, &[2.0, 0.0, 0.0], 1e-6), "{end:?}");
    assert!(
        within(&end.quaternion.unwrap(), &[0.0, s45, 0.0, s45], 1e-6),
        "{end:?}"
    );
    let mid = at(15);
    assert!(within(&mid.translate, &[1.0, 0.0, 0.0], 1e-6), "{mid:?}");
    assert!(
        within(&mid.quaternion.unwrap(), &[0.0, s22, 0.0, c22], 1e-6),
        "{mid:?}"
    );
    d.at_frame(15).unwrap().to_core().unwrap();

    #[cfg(feature = "cli")]
    {
        let still = |t: &str, q: [f64; 4]| {
            let node = format!(
                r#","translation":[{t}],"rotation":[{},{},{},{}]"#,
                q[0], q[1], q[2], q[3]
            );
            let (_d, p) = boxed(&doc, "", &node, "");
            scene_of(&p).unwrap()
        };
        looks_alike(&d, 30, &still("2,0,0", [0.0, s45, 0.0, s45]));
        looks_alike(&d, 15, &still("1,0,0", [0.0, s22, 0.0, c22]));
    }
}

/// A parent scaled by 2 and moved by (0, 0.5, -1) (a similarity) is composed
/// into the keyframes: by hand, the box's translation (0.5, 0, 0) at rest is
/// (1, 0.5, -1) in the world, its scale keyframes (1, 1, 1) and (0.5, 1, 1)
/// are (2, 2, 2) and (1, 2, 2), and a parent turned a quarter about Z turns
/// each rotation keyframe: (0, 0, sin 45°, cos 45°) times the identity. At
/// frame 30 it looks as the still file with the parent and the node at
/// that keyframe.
#[test]
fn a_similar_parent_is_composed_into_the_keyframes() {
    let mut doc = Doc::default();
    box_accessors(&mut doc);
    let (si, so) = keys(
        &mut doc,
        &[0.0, 1.0],
        "VEC3",
        &[1.0, 1.0, 1.0, 0.5, 1.0, 1.0],
    );
    let (ri, ro) = keys(
        &mut doc,
        &[0.0, 1.0],
        "VEC4",
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
    );
    let anim = animation_json(
        "grow",
        &[(0, 1, "scale"), (1, 1, "rotation")],
        &[(si, so, "LINEAR"), (ri, ro, "STEP")],
    );
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let parent = format!(r#","scale":[2,2,2],"translation":[0,0.5,-1],"rotation":[0,0,{h},{h}]"#);
    let cube = r#","translation":[0.5,0,0]"#;
    let (_d, path) = boxed(&doc, &parent, cube, &format!(r#","animations":[{anim}]"#));
    let d = scene_of(&path).unwrap();
    let inst = &d.instances[0];
    // (0.5, 0, 0) turned a quarter about Z is (0, 0.5, 0), times 2, moved.
    assert!(within(&inst.translate, &[0.0, 1.5, -1.0], 1e-6), "{inst:?}");
    assert!(within(&inst.scale.axes(), &[2.0; 3], 1e-6), "{inst:?}");
    assert!(
        within(&inst.quaternion.unwrap(), &[0.0, 0.0, h, h], 1e-6),
        "{inst:?}"
    );
    let scales = &d.keyframes[0].values;
    assert!(within(&scales[0], &[2.0; 3], 1e-12) && within(&scales[1], &[1.0, 2.0, 2.0], 1e-12));
    assert!(within(&d.keyframes[1].values[0], &[0.0, 0.0, h, h], 1e-7));
    assert_eq!(
        d.keyframes[1].interpolation,
        crate::desc::InterpolationDesc::Step
    );
    let end = d.at_frame(30).unwrap();
    assert!(within(
        &end.instances[0].scale.axes(),
        &[1.0, 2.0, 2.0],
        1e-6
    ));

    #[cfg(feature = "cli")]
    {
        let still = format!(r#"{cube},"scale":[0.5,1,1]"#);
        let (_s, p) = boxed(&doc, &parent, &still, "");
        looks_alike(&d, 30, &scene_of(&p).unwrap());
    }
    // Without the parent's turn, but with a mirror (a scale of -2 on every
    // axis, a similarity too): the scale keyframes are negated.
    let (_m, path) = boxed(
        &doc,
        r#","scale":[-2,-2,-2]"#,
        cube,
        &format!(r#","animations":[{anim}]"#),
    );
    let d = scene_of(&path).unwrap();
    assert_eq!(d.keyframes[0].values[1], [-1.0, -2.0, -2.0]);
    assert!(within(&d.instances[0].translate, &[-1.0, 0.0, 0.0], 1e-12));
    d.at_frame(30).unwrap().to_core().unwrap();
}

/// A parent that scales unevenly: the node's animation is refused with a
/// warning naming the node, and it is drawn still at its rest pose, in
/// world space, as the file without the animation draws it.
#[test]
fn an_uneven_parent_is_refused_and_the_node_drawn_still() {
    let mut doc = Doc::default();
    box_accessors(&mut doc);
    let (ti, to) = keys(
        &mut doc,
        &[0.0, 1.0],
        "VEC3",
        &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0],
    );
    let anim = animation_json("slide", &[(0, 1, "translation")], &[(ti, to, "LINEAR")]);
    let parent = r#","scale":[1,2,1]"#;
    let (_d, path) = boxed(&doc, parent, "", &format!(r#","animations":[{anim}]"#));
    let d = scene_of(&path).unwrap();
    assert!(d.instances.is_empty() && d.keyframes.is_empty());
    let all = d.warnings.join("\n");
    assert!(
        all.contains(
            "node 'cube': its animation (animation 'slide') is not read: its parent's world \
             matrix shears or scales unevenly"
        ) && all.contains("drawn still, at its rest pose"),
        "{all}"
    );
    let (_s, still) = boxed(&doc, parent, "", "");
    let s = scene_of(&still).unwrap();
    assert_eq!(d.meshes, s.meshes);
}

/// CUBICSPLINE: read as linear through the keyframes' values (the middle of
/// each in-tangent, value, out-tangent triple; the tangents, 100s here,
/// dropped), with a warning naming the animation and the channel.
#[test]
fn cubicspline_is_read_as_linear_through_its_values_with_a_warning() {
    let mut doc = Doc::default();
    box_accessors(&mut doc);
    let t = [100.0f32; 3];
    let values = [t, [0.0, 0.0, 0.0], t, t, [2.0, 0.0, 0.0], t].concat();
    let (ti, to) = keys(&mut doc, &[0.0, 1.0], "VEC3", &values);
    let anim = animation_json("bend", &[(0, 1, "translation")], &[(ti, to, "CUBICSPLINE")]);
    let (_d, path) = boxed(&doc, "", "", &format!(r#","animations":[{anim}]"#));
    let d = scene_of(&path).unwrap();
    assert_eq!(d.keyframes[0].values, [vec![0.0; 3], vec![2.0, 0.0, 0.0]]);
    assert_eq!(
        d.keyframes[0].interpolation,
        crate::desc::InterpolationDesc::Linear
    );
    assert!(within(
        &d.at_frame(15).unwrap().instances[0].translate,
        &[1.0, 0.0, 0.0],
        1e-6
    ));
    let all = d.warnings.join("\n");
    assert!(
        all.contains(
            "animation 'bend', channel 0 (translation): CUBICSPLINE interpolation is read as \
             LINEAR"
        ),
        "{all}"
    );
}

/// Bad keyframes are errors naming the file, the animation, the channel and
/// the sampler, and what is wrong.
#[test]
fn bad_keyframes_are_errors_naming_animation_channel_and_sampler() {
    let nan = f32::NAN;
    // (times, output type, values, path, words)
    /// Times, the output's type, its values, the channel's path, the words.
    type Case<'a> = (&'a [f32], &'a str, &'a [f32], &'a str, &'a str);
    let cases: [Case<'_>; 7] = [
        (
            &[0.0, 1.0, 1.0],
            "VEC3",
            &[0.0; 9],
            "translation",
            "not strictly increasing: time 2 is 1 after 1",
        ),
        (
            &[0.0, 1.0],
            "VEC3",
            &[0.0; 9],
            "translation",
            "2 times (input accessor 2) and 3 values",
        ),
        (
            &[0.0, 1.0],
            "VEC4",
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
            "rotation",
            "value 1 is a quaternion of length 0",
        ),
        (
            &[0.0, 1.0],
            "VEC3",
            &[0.0, 0.0, 0.0, 1.0, nan, 0.0],
            "scale",
            "output: value 1 is not finite",
        ),
        (
            &[0.0, nan],
            "VEC3",
            &[0.0; 6],
            "scale",
            "input: time 1 is not finite",
        ),
        (
            &[-1.0, 1.0],
            "VEC3",
            &[0.0; 6],
            "translation",
            "time 0 is -1: tessera's animations start at 0 s",
        ),
        (
            &[0.0, 1.0],
            "VEC4",
            &[0.0; 8],
            "translation",
            "output: accessor 3: Vec4 of F32, glTF allows VEC3 of FLOAT",
        ),
    ];
    for (times, ty, values, path_name, words) in cases {
        let mut doc = Doc::default();
        box_accessors(&mut doc);
        let (i, o) = keys(&mut doc, times, ty, values);
        let anim = animation_json("bad", &[(0, 1, path_name)], &[(i, o, "LINEAR")]);
        let (_d, path) = boxed(&doc, "", "", &format!(r#","animations":[{anim}]"#));
        let e = scene_of(&path).unwrap_err();
        assert!(e.starts_with(&path.display().to_string()), "{e}");
        let at = format!("animation 'bad', channel 0 ({path_name}), sampler 0: ");
        assert!(e.contains(&at) && e.contains(words), "{words}: {e}");
    }
    // An input of the wrong type.
    let mut doc = Doc::default();
    box_accessors(&mut doc);
    let input = doc.accessor(&f32s(&[0.0, 1.0]), 5126, "VEC2", 1, "");
    let output = doc.accessor(&f32s(&[0.0; 3]), 5126, "VEC3", 1, "");
    let anim = animation_json(
        "bad",
        &[(0, 1, "translation")],
        &[(input, output, "LINEAR")],
    );
    let (_d, path) = boxed(&doc, "", "", &format!(r#","animations":[{anim}]"#));
    let e = scene_of(&path).unwrap_err();
    assert!(
        e.contains("sampler 0: input: accessor 2: Vec2 of F32, glTF allows SCALAR of FLOAT"),
        "{e}"
    );
    // More keyframes than the limit.
    let mut doc = Doc::default();
    box_accessors(&mut doc);
    let (i, o) = keys(&mut doc, &[0.0, 1.0], "VEC3", &[0.0; 6]);
    let anim = animation_json("long", &[(0, 1, "translation")], &[(i, o, "LINEAR")]);
    let (_d, path) = boxed(&doc, "", "", &format!(r#","animations":[{anim}]"#));
    let few = Limits {
        max_keyframes: 1,
        ..Limits::default()
    };
    let e = read_animated(&path, &few).unwrap_err();
    assert!(e.contains("animation 'long', channel 0 (translation), sampler 0: 2 keyframes, more than the limit of 1"), "{e}");
    assert!(read_animated(&path, &Limits::default()).is_ok());
    // Two channels moving one property.
    let anim = animation_json(
        "twice",
        &[(0, 1, "translation"), (0, 1, "translation")],
        &[(i, o, "LINEAR")],
    );
    let (_d, path) = boxed(&doc, "", "", &format!(r#","animations":[{anim}]"#));
    let e = scene_of(&path).unwrap_err();
    assert!(
        e.contains(
            "animation 'twice', channel 1: channel 0 moves the translation of node 'cube' already"
        ),
        "{e}"
    );
}

/// Only the first animation is read; the others are named in a warning. A
/// `weights` channel and a channel moving a node that draws no mesh (the
/// camera's) leave them still, with warnings naming them; so does the inner
/// of two nested animated nodes (only the outermost is read). A `[[mesh]]`
/// file's triangles ignore animations, with a warning that says so.
#[test]
fn what_is_not_played_is_warned_about() {
    let mut doc = Doc::default();
    box_accessors(&mut doc);
    let (i, o) = keys(
        &mut doc,
        &[0.0, 1.0],
        "VEC3",
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
    );
    let (wi, wo) = keys(&mut doc, &[0.0, 1.0], "SCALAR", &[0.0, 1.0]);
    let first = animation_json(
        "first",
        &[
            (0, 0, "translation"),
            (0, 1, "translation"),
            (0, 2, "translation"),
            (1, 1, "weights"),
        ],
        &[(i, o, "LINEAR"), (wi, wo, "LINEAR")],
    );
    let second = animation_json("second", &[(0, 1, "translation")], &[(i, o, "LINEAR")]);
    let third = animation_json("", &[(0, 1, "translation")], &[(i, o, "STEP")]);
    let all = format!(r#","animations":[{first},{second},{third}]"#);
    let (_d, path) = boxed(&doc, "", "", &all);
    let d = scene_of(&path).unwrap();
    let w = d.warnings.join("\n");
    for words in [
        "only the first animation, animation 'first', is read: animation 'second', animation 2 ignored",
        "animation 'first', channel 3: the morph target weights of node 'cube' are not animated",
        "animation 'first': moves node 'eye', which draws no mesh",
        "node 'cube': its animation (animation 'first') is not read: node 'parent' above it is animated too",
    ] {
        assert!(w.contains(words), "{words}\n{w}");
    }
    // The outermost, the parent, moves the box: one instance, named after it.
    assert_eq!(d.instances.len(), 1);
    assert_eq!(d.instances[0].name.as_deref(), Some("parent"));
    assert_eq!(d.meshes[0].name.as_deref(), Some("parent/m"));
    assert_eq!(d.keyframes.len(), 1);
    assert_eq!(d.keyframes[0].target, "parent");
    // A [[mesh]] file: the box as posed, and a warning.
    let m = super::desc::mesh_file(
        &path,
        "model.gltf",
        &crate::mesh::Placement::of(&crate::desc::MeshDesc::unplaced("x", Some("m".into())))
            .unwrap(),
        crate::desc::MAX_TRIANGLES,
    )
    .unwrap();
    assert_eq!(m.faces.len(), 12);
    let w = m.warnings.join("\n");
    assert!(
        w.contains("model.gltf: animations are not read for a [[mesh]] file: 3 animations ignored"),
        "{w}"
    );
}
