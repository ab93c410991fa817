// Baked by `tessera bake` from "scenes/showcase.toml": generated, do not edit.
//
// 8 materials, 2 lights, 3 spheres, 2 planes, 2 boxes, 4 triangles: 956 bytes of flash.

use crate::{BakedCamera, BakedScene, Color, Encoding, Primitive, Primitives, RenderSettings, Sampler, Viewport, capacities, geometry::Aabb, geometry::Plane, geometry::Sphere, geometry::Triangle, light::Light, material::Material, material::MaterialId, texture::Texture, tile::Loops, tile::TileLoop};

/// A triangle of material `m`.
const fn t(p0: [f32; 3], p1: [f32; 3], p2: [f32; 3], m: MaterialId) -> Primitive<Triangle> {
    Primitive {
        geometry: Triangle::baked(p0, p1, p2),
        material: m,
    }
}

// The materials: each constant is a material's reference (its place in MATERIALS).
/// The material "floor".
#[allow(dead_code)]
pub const MAT_FLOOR: MaterialId = MaterialId(0);
/// The material "wall".
#[allow(dead_code)]
pub const MAT_WALL: MaterialId = MaterialId(1);
/// The material "glass".
#[allow(dead_code)]
pub const MAT_GLASS: MaterialId = MaterialId(2);
/// The material "mirror".
#[allow(dead_code)]
pub const MAT_MIRROR: MaterialId = MaterialId(3);
/// The material "plastic".
#[allow(dead_code)]
pub const MAT_PLASTIC: MaterialId = MaterialId(4);
/// The material "fringed".
#[allow(dead_code)]
pub const MAT_FRINGED: MaterialId = MaterialId(5);
/// The material "teal".
#[allow(dead_code)]
pub const MAT_TEAL: MaterialId = MaterialId(6);
/// The material "boxes".
#[allow(dead_code)]
pub const MAT_BOXES: MaterialId = MaterialId(7);

/// The materials: texture, ambient, diffuse, specular, shininess, reflectivity, transparency, index of refraction.
#[rustfmt::skip]
pub static MATERIALS: [Material; 8] = [
    Material::baked( // MAT_FLOOR
        Texture::Checker { a: Color::new(0.85, 0.85, 0.85), b: Color::new(0.15, 0.15, 0.15), scale: 1.0 },
        1.0, 1.0, 0.0, 1.0, 0.1, 0.0, 1.0,
    ),
    Material::baked( // MAT_WALL
        Texture::Solid(Color::new(0.8, 0.75, 0.7)),
        1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0,
    ),
    Material::baked( // MAT_GLASS
        Texture::Solid(Color::new(1.0, 1.0, 1.0)),
        0.0, 0.0, 0.6, 200.0, 0.0, 0.95, 1.5,
    ),
    Material::baked( // MAT_MIRROR
        Texture::Solid(Color::new(0.9, 0.9, 0.9)),
        1.0, 0.05, 0.5, 300.0, 0.9, 0.0, 1.0,
    ),
    Material::baked( // MAT_PLASTIC
        Texture::Solid(Color::new(0.9, 0.35, 0.1)),
        1.0, 1.0, 0.5, 32.0, 0.0, 0.0, 1.0,
    ),
    Material::baked( // MAT_FRINGED
        Texture::Fringes { color: Color::new(1.0, 0.3, 0.8), spacing: 0.125 },
        1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0,
    ),
    Material::baked( // MAT_TEAL
        Texture::Solid(Color::new(0.1, 0.6, 0.6)),
        1.0, 1.0, 0.3, 16.0, 0.0, 0.0, 1.0,
    ),
    Material::baked( // MAT_BOXES
        Texture::Solid(Color::new(0.3, 0.3, 0.9)),
        1.0, 1.0, 0.2, 8.0, 0.2, 0.0, 1.0,
    ),
];

/// The lights: a point light's position (a sun's unit direction towards it), colour, intensity.
#[rustfmt::skip]
pub static LIGHTS: [Light; 2] = [
    Light::baked_point([-3.0, 6.0, 4.0], Color::new(1.0, 0.95, 0.9), 30.0),
    Light::baked_point([4.0, 4.0, 3.0], Color::new(0.5, 0.6, 0.8), 12.0),
];

/// The spheres: centre, radius.
#[rustfmt::skip]
pub static SPHERES: [Primitive<Sphere>; 3] = [
    Primitive { geometry: Sphere::baked([0.8, 1.0, 0.9], 1.0), material: MAT_GLASS },
    Primitive { geometry: Sphere::baked([-2.6, 1.1, -1.0], 1.1), material: MAT_MIRROR },
    Primitive { geometry: Sphere::baked([2.3, 0.35, 2.1], 0.35), material: MAT_TEAL },
];

/// The planes: a point, the unit normal, the offset from the origin along it, the tangents of the texture's uv.
#[rustfmt::skip]
pub static PLANES: [Primitive<Plane>; 2] = [
    Primitive { geometry: Plane::baked([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 0.0, [[1.0, -0.0, -0.0], [-0.0, 0.0, -1.0]]), material: MAT_FLOOR },
    Primitive { geometry: Plane::baked([0.0, 0.0, -4.0], [0.0, 0.0, 1.0], -4.0, [[1.0, -0.0, -0.0], [-0.0, 1.0, -0.0]]), material: MAT_WALL },
];

/// The triangles, in the scene's order.
#[rustfmt::skip]
pub static TRIANGLES: [Primitive<Triangle>; 4] = [
    t([-1.5, 0.0, -1.5], [0.3, 0.0, -1.5], [-0.6, 1.9, -2.4], MAT_FRINGED),
    t([0.3, 0.0, -1.5], [0.3, 0.0, -3.3], [-0.6, 1.9, -2.4], MAT_FRINGED),
    t([0.3, 0.0, -3.3], [-1.5, 0.0, -3.3], [-0.6, 1.9, -2.4], MAT_FRINGED),
    t([-1.5, 0.0, -3.3], [-1.5, 0.0, -1.5], [-0.6, 1.9, -2.4], MAT_FRINGED),
];

/// The axis-aligned boxes: min and max corners.
#[rustfmt::skip]
pub static BOXES: [Primitive<Aabb>; 2] = [
    Primitive { geometry: Aabb::baked([1.6, 0.0, -1.6], [2.8, 1.2, -0.4]), material: MAT_PLASTIC },
    Primitive { geometry: Aabb::baked([-1.1, 0.0, 1.6], [-0.5, 0.6, 2.2]), material: MAT_BOXES },
];

/// The width the scene is meant to be rendered at, in pixels.
#[allow(dead_code)]
pub const WIDTH: u16 = 320;
/// Its height.
#[allow(dead_code)]
pub const HEIGHT: u16 = 240;
/// Its tile size (the file's `tile`: a `Tile<TILE, _>` buffer).
#[allow(dead_code)]
pub const TILE: usize = 16;

/// The tile loops this scene needs at its settings, for
/// `Renderer::render_tile_in::<SceneLoops, ..>`: a firmware links these alone.
#[allow(dead_code)]
pub enum SceneLoops {}

impl Loops for SceneLoops {
    fn links(tile_loop: TileLoop) -> bool {
        tile_loop == TileLoop::Bounces(Encoding::Srgb)
    }
}

/// The whole scene: `SCENE.view()?` and `SCENE.renderer()?` check it once and render it
/// from where it lies.
#[allow(dead_code)]
// `..Primitives::NONE` stands for the kinds it has none of (none, with the
// core's optional kinds off).
#[allow(clippy::needless_update)]
pub static SCENE: BakedScene<'static, capacities!(spheres: 3, planes: 2, triangles: 4, boxes: 2)> = BakedScene::new(
    BakedCamera {
        position: [0.5, 2.6, 7.5],
        forward: [-0.5, -1.8, -7.5],
        up: [0.0, 1.0, 0.0],
        fovy_degrees: 60.0,
        near: 0.1,
        far: 100.0,
    },
    Viewport::new(WIDTH, HEIGHT),
    RenderSettings {
        sampler: Sampler::Centre,
        max_depth: 5,
        seed: 0,
        encoding: Encoding::Srgb,
    },
    Color::new(0.1, 0.1, 0.1),
    Color::new(0.55, 0.7, 0.9),
    &MATERIALS,
    &LIGHTS,
    Primitives {
        spheres: &SPHERES,
        planes: &PLANES,
        triangles: &TRIANGLES,
        boxes: &BOXES,
        ..Primitives::NONE
    },
);

/// The scene file this module is baked from, `scenes/showcase.toml`.
pub const SOURCE: &str = r#"# showcase: every geometry kind and every material kind in one scene.
#
# Geometry: two planes (a checkered floor and a back wall), three spheres, two
# boxes and a pyramid of four triangles. Materials: matte, specular plastic, a
# mirror, glass, a checker texture and a fringe texture. Two coloured lights.
# `depth = 5` lets rays pass through the glass and bounce between mirrors.
# The numbers are exactly those of the built-in scene `showcase`
# (core/src/builtin.rs); a test checks that this file renders byte-identical to it.

ambient = [0.1, 0.1, 0.1]
background = [0.55, 0.7, 0.9]

[render]
width = 320
height = 240
sampler = "centre"
depth = 5
seed = 0
tile = 16

[camera]
position = [0.5, 2.6, 7.5]
look_at = [0.0, 0.8, 0.0]
up = [0.0, 1.0, 0.0]
fovy = 60.0
near = 0.1
far = 100.0

# Materials, in the order the core adds them.

# A slightly reflective checkerboard, one square per unit.
[[material]]
name = "floor"
texture = { kind = "checker", a = [0.85, 0.85, 0.85], b = [0.15, 0.15, 0.15], scale = 1.0 }
reflectivity = 0.1

[[material]]
name = "wall"
color = [0.8, 0.75, 0.7]

# Glass: no ambient or diffuse light, a sharp highlight, mostly transparent.
[[material]]
name = "glass"
color = [1.0, 1.0, 1.0]
diffuse = 0.0
ambient = 0.0
specular = 0.6
shininess = 200.0
transparency = 0.95
ior = 1.5

[[material]]
name = "mirror"
color = [0.9, 0.9, 0.9]
diffuse = 0.05
specular = 0.5
shininess = 300.0
reflectivity = 0.9

[[material]]
name = "plastic"
color = [0.9, 0.35, 0.1]
specular = 0.5
shininess = 32.0

[[material]]
name = "fringed"
texture = { kind = "fringes", color = [1.0, 0.3, 0.8], spacing = 0.125 }

[[material]]
name = "teal"
color = [0.1, 0.6, 0.6]
specular = 0.3
shininess = 16.0

[[material]]
name = "boxes"
color = [0.3, 0.3, 0.9]
specular = 0.2
shininess = 8.0
reflectivity = 0.2

[[plane]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "floor"

[[plane]]
point = [0.0, 0.0, -4.0]
normal = [0.0, 0.0, 1.0]
material = "wall"

[[sphere]]
center = [0.8, 1.0, 0.9]
radius = 1.0
material = "glass"

[[sphere]]
center = [-2.6, 1.1, -1.0]
radius = 1.1
material = "mirror"

[[sphere]]
center = [2.3, 0.35, 2.1]
radius = 0.35
material = "teal"

[[box]]
min = [1.6, 0.0, -1.6]
max = [2.8, 1.2, -0.4]
material = "plastic"

[[box]]
min = [-1.1, 0.0, 1.6]
max = [-0.5, 0.6, 2.2]
material = "boxes"

# A pyramid of four triangles: apex [-0.6, 1.9, -2.4] over a square base on the
# floor; each triangle is (base corner i, base corner i + 1, apex).
[[triangle]]
vertices = [[-1.5, 0.0, -1.5], [0.3, 0.0, -1.5], [-0.6, 1.9, -2.4]]
material = "fringed"

[[triangle]]
vertices = [[0.3, 0.0, -1.5], [0.3, 0.0, -3.3], [-0.6, 1.9, -2.4]]
material = "fringed"

[[triangle]]
vertices = [[0.3, 0.0, -3.3], [-1.5, 0.0, -3.3], [-0.6, 1.9, -2.4]]
material = "fringed"

[[triangle]]
vertices = [[-1.5, 0.0, -3.3], [-1.5, 0.0, -1.5], [-0.6, 1.9, -2.4]]
material = "fringed"

[[light]]
position = [-3.0, 6.0, 4.0]
color = [1.0, 0.95, 0.9]
intensity = 30.0

[[light]]
position = [4.0, 4.0, 3.0]
color = [0.5, 0.6, 0.8]
intensity = 12.0
"#;
