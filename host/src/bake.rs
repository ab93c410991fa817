//! Baked scenes: a scene's triangles and meshes, with their BVHs, written out as
//! Rust `static` data (`tessera bake`), so that a firmware keeps them in flash and
//! spends no RAM on them. The firmware gives them to a view of the rest of its
//! scene (built in RAM as usual, with the same materials in the same order) with
//! [`tessera::SceneView::with_baked`] (the triangle list) and
//! [`tessera::SceneView::with_meshes`] (the meshes), which check them once.
//!
//! The generated file is plain Rust: `TRIANGLES` (the scene's triangles in its
//! order, each a `Primitive` of `Triangle::baked`) and `BVH` (a `BakedBvh` of the
//! `NODES` and `ORDER` the host builds for them, as [`tessera::Bvh::build`]
//! does); `MESHES` (each a `Mesh` of its `MESH{i}_VERTICES`, `_FACES`,
//! `_NORMALS` and BVH). Numbers are written in Rust's shortest form that reads
//! back to the same `f32`, so the baked scene is the host's bit for bit.

use crate::desc::{DescError, HostBvh, HostScene, SceneDesc};
use std::fmt::Write as _;
use tessera::BvhNode;

/// `x` as a Rust `f32` literal that reads back to the same value.
fn lit(x: f32) -> String {
    let s = format!("{x:?}");
    if s.contains(['.', 'e', 'i', 'N']) {
        s
    } else {
        format!("{s}.0")
    }
}

fn vec3(v: [f32; 3]) -> String {
    format!("[{}, {}, {}]", lit(v[0]), lit(v[1]), lit(v[2]))
}

/// A baked hierarchy: `{name}NODES`, `{name}ORDER` and the reach, and its bytes.
fn hierarchy(s: &mut String, name: &str, nodes: &[BvhNode], order: &[u16]) -> usize {
    let _ = writeln!(
        s,
        "/// The hierarchy's nodes, the root first.\n#[rustfmt::skip]\n\
         pub static {name}NODES: [BvhNode; {}] = [",
        nodes.len()
    );
    for node in nodes {
        let (min, max, first, count, axis) = node.parts();
        let _ = writeln!(
            s,
            "    n({}, {}, {first}, {count}, {axis}),",
            vec3(min),
            vec3(max)
        );
    }
    let _ = writeln!(
        s,
        "];\n\n/// Its leaves' entries, each leaf's a contiguous range.\n#[rustfmt::skip]\n\
         pub static {name}ORDER: [u16; {}] = [",
        order.len()
    );
    for chunk in order.chunks(16) {
        let row: Vec<String> = chunk.iter().map(u16::to_string).collect();
        let _ = writeln!(s, "    {},", row.join(", "));
    }
    let _ = writeln!(s, "];\n");
    size_of_val(nodes) + size_of_val(order)
}

/// A static array of `[f32; 3]`.
fn points(s: &mut String, doc: &str, name: &str, p: &[[f32; 3]]) -> usize {
    let _ = writeln!(
        s,
        "/// {doc}\n#[rustfmt::skip]\npub static {name}: [[f32; 3]; {}] = [",
        p.len()
    );
    for v in p {
        let _ = writeln!(s, "    {},", vec3(*v));
    }
    let _ = writeln!(s, "];\n");
    size_of_val(p)
}

/// The Rust source of a scene's baked triangles and meshes, using the core crate
/// as `krate` (`tessera`, or `crate` inside the core); `header`: comment lines
/// put first (without `//`). Writes `TRIANGLES` (the triangle list, if any) and
/// its hierarchy `BVH` (`NODES`, `ORDER`), and for each mesh `i` its
/// `MESH{i}_VERTICES`, `_FACES`, `_NORMALS`, `_NODES`, `_ORDER`, all in `MESHES`.
#[must_use]
pub fn source(scene: &HostScene, krate: &str, header: &[String]) -> String {
    let mut body = String::new();
    let mut bytes = 0;
    let triangles = scene.lists().view().triangles();
    let mut parts = Vec::new();
    if !triangles.is_empty() {
        let mut bvh = Box::new(HostBvh::new());
        // The host scene's capacities: 2 T nodes always suffice.
        if bvh.build(triangles).is_ok() {
            let _ = writeln!(
                body,
                "/// How many triangles.\npub const TRIANGLE_COUNT: usize = {};\n\n\
                 /// The triangles, in the scene's order.\n#[rustfmt::skip]\n\
                 pub static TRIANGLES: [Primitive<Triangle>; TRIANGLE_COUNT] = [",
                triangles.len()
            );
            for t in triangles {
                let v = |p: tessera::Vec3| vec3([p.x, p.y, p.z]);
                let [a, b, c] = t.geometry.vertices();
                let m = t.material.0;
                let _ = writeln!(body, "    t({}, {}, {}, {m}),", v(a), v(b), v(c));
            }
            let _ = writeln!(body, "];\n");
            bytes += size_of_val(triangles);
            bytes += hierarchy(&mut body, "", bvh.nodes(), bvh.order());
            let _ = writeln!(
                body,
                "/// The triangles' hierarchy (`SceneView::with_baked(&TRIANGLES, &BVH)`).\n\
                 pub static BVH: BakedBvh<'static> = BakedBvh::new(&NODES, &ORDER, {});\n",
                lit(bvh.reach())
            );
            parts.push(format!("{} triangles", triangles.len()));
        }
    }
    let mut meshes = Vec::new();
    for (i, m) in scene.mesh_parts().enumerate() {
        let (vertices, faces, normals, material, bvh) =
            (m.vertices, m.faces, m.normals, m.material, m.bvh);
        let name = format!("MESH{i}_");
        bytes += points(
            &mut body,
            "The vertices.",
            &format!("{name}VERTICES"),
            vertices,
        );
        let _ = writeln!(
            body,
            "/// The faces.\n#[rustfmt::skip]\npub static {name}FACES: [[u16; 3]; {}] = [",
            faces.len()
        );
        for chunk in faces.chunks(6) {
            let row: Vec<String> = chunk
                .iter()
                .map(|[a, b, c]| format!("[{a}, {b}, {c}]"))
                .collect();
            let _ = writeln!(body, "    {},", row.join(", "));
        }
        let _ = writeln!(body, "];\n");
        bytes += size_of_val(faces);
        bytes += points(
            &mut body,
            "The vertex normals (none: flat shading).",
            &format!("{name}NORMALS"),
            normals,
        );
        bytes += hierarchy(&mut body, &name, bvh.nodes(), bvh.order());
        meshes.push(format!(
            "    Mesh::new(\n        &{name}VERTICES,\n        &{name}FACES,\n        \
             &{name}NORMALS,\n        MaterialId({}),\n        \
             BakedBvh::new(&{name}NODES, &{name}ORDER, {}),\n    ),",
            material.0,
            lit(bvh.reach())
        ));
        parts.push(format!(
            "mesh {i}: {} vertices, {} faces, {} BVH nodes",
            vertices.len(),
            faces.len(),
            bvh.nodes().len()
        ));
    }
    if !meshes.is_empty() {
        let _ = writeln!(
            body,
            "/// The meshes (`SceneView::with_meshes(&MESHES)`).\n\
             pub static MESHES: [Mesh<'static>; {}] = [\n{}\n];",
            meshes.len(),
            meshes.join("\n")
        );
    }
    let mut s = String::new();
    for line in header {
        let _ = writeln!(s, "{}", format!("// {line}").trim_end());
    }
    let _ = writeln!(s, "//\n// {}: {bytes} bytes of flash.\n", parts.join("; "));
    let mut names = vec!["BakedBvh", "BvhNode"];
    if !triangles.is_empty() {
        names.extend(["MaterialId", "Primitive", "Triangle"]);
    }
    if !meshes.is_empty() {
        names.extend(["MaterialId", "Mesh"]);
    }
    names.sort_unstable();
    names.dedup();
    let _ = writeln!(s, "use {krate}::{{{}}};\n", names.join(", "));
    if !triangles.is_empty() {
        let _ = writeln!(
            s,
            "/// A triangle of material `m`.\n\
             const fn t(p0: [f32; 3], p1: [f32; 3], p2: [f32; 3], m: u16) -> Primitive<Triangle> {{\n    \
                 Primitive {{\n        geometry: Triangle::baked(p0, p1, p2),\n        \
                 material: MaterialId(m),\n    }}\n}}\n"
        );
    }
    let _ = writeln!(
        s,
        "/// A node of a hierarchy.\n\
         const fn n(min: [f32; 3], max: [f32; 3], first: u16, count: u16, axis: u16) -> BvhNode {{\n    \
             BvhNode::new(min, max, first, count, axis)\n}}\n"
    );
    s + body.trim_end() + "\n"
}

/// The baked source of a scene description's triangles and meshes, with a header
/// naming the scene and its materials in order (the firmware's scene must have
/// the same). Errors: the scene's own (as for rendering it), and a scene without
/// triangles or meshes (nothing to bake).
pub fn scene_source(desc: &SceneDesc, name: &str, krate: &str) -> Result<String, DescError> {
    let scene = desc.to_core()?;
    if scene.lists().view().triangles().is_empty() && scene.mesh_count() == 0 {
        return Err(DescError {
            item: "scene".to_string(),
            message: "it has no triangles or meshes: nothing to bake".to_string(),
        });
    }
    let mut header = vec![
        format!("Baked by `tessera bake` from {name}: generated, do not edit."),
        "They use the scene's materials by index:".to_string(),
    ];
    for (i, m) in desc.materials.iter().enumerate() {
        header.push(format!("  {i}: {}", m.name));
    }
    let others = [
        ("spheres", desc.spheres.len()),
        ("planes", desc.planes.len()),
        ("boxes", desc.boxes.len()),
        ("lights", desc.lights.len()),
    ];
    let rest: Vec<String> = others
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(what, n)| format!("{n} {what}"))
        .collect();
    header.push(format!(
        "Not baked (build them in the firmware's scene): {}the camera.",
        rest.iter().map(|r| format!("{r}, ")).collect::<String>()
    ));
    Ok(source(&scene, krate, &header))
}

/// The source of the core's baked teapot (`core/src/builtin/teapot_data.rs`):
/// the built-in scene file `scenes/teapot.toml` baked for use inside the core.
#[must_use]
pub fn teapot_source() -> String {
    let desc = crate::file::builtin_desc(tessera::builtin::Builtin::Teapot);
    scene_source(&desc, "scenes/teapot.toml", "crate")
        .unwrap_or_else(|e| panic!("the built-in teapot scene does not bake: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The core's baked teapot is what the host bakes from `scenes/teapot.toml`
    /// today (run with `TESSERA_BLESS=1` to write it after a deliberate change).
    #[test]
    fn the_cores_baked_teapot_is_current() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../core/src/builtin/teapot_data.rs");
        let want = teapot_source();
        if std::env::var_os("TESSERA_BLESS").is_some() {
            std::fs::write(&path, &want).unwrap();
        }
        let have = std::fs::read_to_string(&path).unwrap();
        assert!(
            have == want,
            "{} is not what the host bakes: run `TESSERA_BLESS=1 cargo test -p \
             tessera-host --lib bake` and rebuild",
            path.display()
        );
    }

    #[test]
    fn literals_read_back_to_the_same_f32() {
        for x in [
            0.0f32,
            -0.0,
            1.0,
            -3.0,
            0.1,
            1e-7,
            -1.234_567_9e-30,
            3.402_823_5e38,
            f32::MIN_POSITIVE,
            1.0e-45,
            16_777_216.0,
        ] {
            let s = lit(x);
            assert!(s.contains(['.', 'e']), "{s}");
            let back: f32 = s.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{s}");
        }
    }
}
