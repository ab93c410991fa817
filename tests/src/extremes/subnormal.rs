//! Case 14: subnormal numbers in a scene. One rule for the core and the f64
//! reference alike: a number whose `f32` is subnormal (below `2^-126` in
//! magnitude) is read as a zero of its sign. Each kind of number a scene takes
//! is set to subnormal values in a description built in code (so that the loader,
//! which applies the rule too, does not hide what the renderers do) and rendered
//! by both: each must give the image of the same scene with a zero there, and
//! they must agree.

use super::support::compared;
use tessera_core::Viewport;
use tessera_host::desc::{SceneDesc, TextureDesc};

/// The subnormal values tried: the smallest and the largest of each sign.
pub const SUBNORMALS: [f64; 4] = [1e-45, -1e-45, 1.1e-38, -1.1e-38];

/// The viewport of case 14.
pub const SUBNORMAL_VIEWPORT: Viewport = Viewport::new(64, 48);

/// A kind of number: its name and how it is set in a description.
pub struct Kind {
    /// What the report calls it.
    pub name: &'static str,
    /// True when a zero there is refused (a length or a scale), so that the
    /// subnormal must be refused too.
    pub refused: bool,
    set: fn(&mut SceneDesc, f64),
}

/// The scene every kind is set in: a checkered floor, a mirror sphere, a
/// triangle, a box, two lights, the camera above.
const BASE: &str = "\
ambient = [0.1, 0.1, 0.1]
background = [0.1, 0.2, 0.4]
[camera]
position = [0.3, 2.5, 5]
look_at = [0, 0.5, 0]
near = 0.1
far = 100
[[material]]
name = \"floor\"
texture = { kind = \"checker\", a = [0.9, 0.9, 0.9], b = [0.2, 0.2, 0.2], scale = 2 }
[[material]]
name = \"mirror\"
color = [0.8, 0.3, 0.2]
reflectivity = 0.4
specular = 0.5
shininess = 20
[[material]]
name = \"fringes\"
texture = { kind = \"fringes\", color = [0.2, 0.9, 0.3], spacing = 0.2 }
[[plane]]
point = [0, 0, 0]
normal = [0, 1, 0]
material = \"floor\"
[[sphere]]
center = [0, 0.6, 0]
radius = 0.6
material = \"mirror\"
[[triangle]]
vertices = [[1, 0, -1], [2.5, 0, -1], [1.8, 1.5, -1]]
material = \"fringes\"
[[box]]
min = [-2.5, 0, -1.5]
max = [-1.5, 1, -0.5]
material = \"mirror\"
[[light]]
position = [2, 5, 3]
intensity = 30
[[light]]
position = [-3, 4, 2]
color = [0.5, 0.6, 1]
intensity = 10
";

/// The kinds of numbers, each set to `x` somewhere it matters.
#[must_use]
pub fn kinds() -> Vec<Kind> {
    fn mat(d: &mut SceneDesc, name: &str) -> usize {
        d.materials.iter().position(|m| m.name == name).unwrap_or(0)
    }
    vec![
        Kind {
            name: "camera position (straight above its target)",
            refused: false,
            set: |d, x| {
                d.camera.position = [0.0, 2.5, x];
                d.camera.look_at = Some([0.0, 0.0, 0.0]);
            },
        },
        Kind {
            name: "camera look_at - position (normal numbers, a subnormal difference)",
            refused: false,
            set: |d, x| {
                // Both normal in f32; their difference is `x` (when `x` is one
                // of the subnormals tried), which decides the roll.
                d.camera.position = [0.0, 2.5, 2e-37];
                d.camera.look_at = Some([0.0, 0.0, 2e-37 + x]);
            },
        },
        Kind {
            name: "camera up (along the view)",
            refused: false,
            set: |d, x| {
                d.camera.look_at = None;
                d.camera.forward = Some([0.0, -1.0, 0.0]);
                d.camera.up = [x, 1.0, 0.0];
            },
        },
        Kind {
            name: "sphere centre",
            refused: false,
            set: |d, x| d.spheres[0].center = [x, 0.6, x],
        },
        Kind {
            name: "plane point and normal",
            refused: false,
            set: |d, x| {
                d.planes[0].point = [x, 0.0, x];
                d.planes[0].normal = [x, 1.0, x];
            },
        },
        Kind {
            name: "triangle vertex",
            refused: false,
            set: |d, x| d.triangles[0].vertices[0] = [1.0, x, -1.0],
        },
        Kind {
            name: "box corner",
            refused: false,
            set: |d, x| d.boxes[0].min = [-2.5, x, -1.5],
        },
        Kind {
            name: "light position and colour",
            refused: false,
            set: |d, x| {
                d.lights[0].position = [2.0, 5.0, x];
                d.lights[1].color = [0.5, x.abs(), 1.0];
            },
        },
        Kind {
            name: "light intensity",
            refused: false,
            set: |d, x| d.lights[1].intensity = x.abs(),
        },
        Kind {
            name: "material and texture colours",
            refused: false,
            set: |d, x| {
                let m = mat(d, "mirror");
                d.materials[m].color = [0.8, x.abs(), 0.2];
                let f = mat(d, "floor");
                d.materials[f].texture = Some(TextureDesc::Checker {
                    a: [0.9, x.abs(), 0.9],
                    b: [x.abs(), 0.2, 0.2],
                    scale: 2.0,
                });
            },
        },
        Kind {
            name: "material weights (reflectivity, specular)",
            refused: false,
            set: |d, x| {
                let m = mat(d, "mirror");
                d.materials[m].reflectivity = x.abs();
                d.materials[m].specular = x.abs();
            },
        },
        Kind {
            name: "ambient and background",
            refused: false,
            set: |d, x| {
                d.ambient = [0.1, x.abs(), 0.1];
                d.background = [x.abs(), 0.2, 0.4];
            },
        },
        Kind {
            name: "checker scale",
            refused: true,
            set: |d, x| {
                let f = mat(d, "floor");
                d.materials[f].texture = Some(TextureDesc::Checker {
                    a: [0.9, 0.9, 0.9],
                    b: [0.2, 0.2, 0.2],
                    scale: x.abs(),
                });
            },
        },
        Kind {
            name: "fringe spacing",
            refused: true,
            set: |d, x| {
                let m = mat(d, "fringes");
                d.materials[m].texture = Some(TextureDesc::Fringes {
                    color: [0.2, 0.9, 0.3],
                    spacing: x.abs(),
                });
            },
        },
        Kind {
            name: "sphere radius",
            refused: true,
            set: |d, x| d.spheres[0].radius = x.abs(),
        },
    ]
}

/// Figures of case 14 for one kind and value.
#[derive(Clone, Debug)]
pub struct Subnormal {
    /// The value set.
    pub value: f64,
    /// Both the subnormal and the zero scene refused (for a length or scale).
    pub refused: bool,
    /// Pixels of the core's image that differ from the zero scene's.
    pub core_differ: usize,
    /// Pixels of the reference's image that differ from the zero scene's.
    pub reference_differ: usize,
    /// The largest difference of the core against the reference outside the
    /// silhouette band, and whether `tessera compare`'s bar is met.
    pub max_outside: u8,
    /// `tessera compare`'s bar met.
    pub meets_bar: bool,
}

/// The base scene with `kind` set to `x`, not read by the loader's rule.
#[must_use]
pub fn subnormal_desc(kind: &Kind, x: f64) -> SceneDesc {
    let mut d = tessera_host::file::parse(BASE, "case 14").unwrap_or_else(|e| panic!("{e}"));
    (kind.set)(&mut d, x);
    d
}

fn differ(a: &image::RgbImage, b: &image::RgbImage) -> usize {
    a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count()
}

/// Case 14 for one kind and value: the core and the reference, each against
/// itself on the zero scene, and against each other.
#[must_use]
pub fn subnormal(kind: &Kind, x: f64) -> Subnormal {
    let (dx, d0) = (
        subnormal_desc(kind, x),
        subnormal_desc(kind, 0f64.copysign(x)),
    );
    let (cx, c0) = (
        compared(&dx, SUBNORMAL_VIEWPORT),
        compared(&d0, SUBNORMAL_VIEWPORT),
    );
    match (cx, c0) {
        (Ok(cx), Ok(c0)) => Subnormal {
            value: x,
            refused: false,
            core_differ: differ(&cx.core, &c0.core),
            reference_differ: differ(&cx.reference, &c0.reference),
            max_outside: cx.accuracy.max_outside(),
            meets_bar: cx.accuracy.meets_bar(),
        },
        // Refused: `compared` asks the core first, and the reference refuses
        // what the core refuses (`reference::render`).
        (Err(_), Err(_)) => Subnormal {
            value: x,
            refused: true,
            core_differ: 0,
            reference_differ: 0,
            max_outside: 0,
            meets_bar: true,
        },
        (cx, c0) => panic!(
            "{} = {x}: refused with one value only: {:?}, at 0 {:?}",
            kind.name,
            cx.err(),
            c0.err()
        ),
    }
}
