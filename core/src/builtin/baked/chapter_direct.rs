// Baked by `tessera bake` from "scenes/chapter-direct.toml": generated, do not edit.
//
// 5 materials, 1 light, 4 spheres, 1 plane: 484 bytes of flash.

use crate::{BakedCamera, BakedScene, Color, Encoding, Primitive, Primitives, RenderSettings, Sampler, Viewport, capacities, geometry::Plane, geometry::Sphere, light::Light, material::Material, material::MaterialId, texture::Texture, tile::Loops, tile::TileLoop};

// The materials: each constant is a material's reference (its place in MATERIALS).
/// The material "floor".
#[allow(dead_code)]
pub const MAT_FLOOR: MaterialId = MaterialId(0);
/// The material "blue".
#[allow(dead_code)]
pub const MAT_BLUE: MaterialId = MaterialId(1);
/// The material "red".
#[allow(dead_code)]
pub const MAT_RED: MaterialId = MaterialId(2);
/// The material "green".
#[allow(dead_code)]
pub const MAT_GREEN: MaterialId = MaterialId(3);
/// The material "yellow".
#[allow(dead_code)]
pub const MAT_YELLOW: MaterialId = MaterialId(4);

/// The materials: texture, ambient, diffuse, specular, shininess, reflectivity, transparency, index of refraction.
#[rustfmt::skip]
pub static MATERIALS: [Material; 5] = [
    Material::baked( // MAT_FLOOR
        Texture::Solid(Color::new(0.75, 0.75, 0.75)),
        1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0,
    ),
    Material::baked( // MAT_BLUE
        Texture::Solid(Color::new(0.1, 0.25, 0.95)),
        1.0, 1.0, 0.4, 48.0, 0.0, 0.0, 1.0,
    ),
    Material::baked( // MAT_RED
        Texture::Solid(Color::new(0.9, 0.15, 0.1)),
        1.0, 1.0, 0.4, 48.0, 0.0, 0.0, 1.0,
    ),
    Material::baked( // MAT_GREEN
        Texture::Solid(Color::new(0.15, 0.8, 0.2)),
        1.0, 1.0, 0.4, 48.0, 0.0, 0.0, 1.0,
    ),
    Material::baked( // MAT_YELLOW
        Texture::Solid(Color::new(0.95, 0.8, 0.1)),
        1.0, 1.0, 0.4, 48.0, 0.0, 0.0, 1.0,
    ),
];

/// The lights: a point light's position (a sun's unit direction towards it), colour, intensity.
#[rustfmt::skip]
pub static LIGHTS: [Light; 1] = [
    Light::baked_point([0.0, 7.0, 1.0], Color::new(1.0, 1.0, 1.0), 40.0),
];

/// The spheres: centre, radius.
#[rustfmt::skip]
pub static SPHERES: [Primitive<Sphere>; 4] = [
    Primitive { geometry: Sphere::baked([0.0, 1.0, 0.0], 1.0), material: MAT_BLUE },
    Primitive { geometry: Sphere::baked([-2.3, 0.8, 0.4], 0.8), material: MAT_RED },
    Primitive { geometry: Sphere::baked([2.2, 0.9, -0.3], 0.9), material: MAT_GREEN },
    Primitive { geometry: Sphere::baked([0.9, 0.35, 1.9], 0.35), material: MAT_YELLOW },
];

/// The planes: a point, the unit normal, the offset from the origin along it, the tangents of the texture's uv.
#[rustfmt::skip]
pub static PLANES: [Primitive<Plane>; 1] = [
    Primitive { geometry: Plane::baked([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 0.0, [[1.0, -0.0, -0.0], [-0.0, 0.0, -1.0]]), material: MAT_FLOOR },
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
        tile_loop == TileLoop::Direct(Encoding::Srgb)
    }
}

/// The whole scene: `SCENE.view()?` and `SCENE.renderer()?` check it once and render it
/// from where it lies.
#[allow(dead_code)]
// `..Primitives::NONE` stands for the kinds it has none of (none, with the
// core's optional kinds off).
#[allow(clippy::needless_update)]
pub static SCENE: BakedScene<'static, capacities!(spheres: 4, planes: 1)> = BakedScene::new(
    BakedCamera {
        position: [0.0, 1.8, 7.0],
        forward: [0.0, -0.9, -7.0],
        up: [0.0, 1.0, 0.0],
        fovy_degrees: 60.0,
        near: 0.1,
        far: 100.0,
    },
    Viewport::new(WIDTH, HEIGHT),
    RenderSettings {
        sampler: Sampler::Centre,
        max_depth: 0,
        seed: 0,
        encoding: Encoding::Srgb,
    },
    Color::new(0.12, 0.12, 0.12),
    Color::new(0.08, 0.09, 0.14),
    &MATERIALS,
    &LIGHTS,
    Primitives {
        spheres: &SPHERES,
        planes: &PLANES,
        ..Primitives::NONE
    },
);

/// The scene file this module is baked from, `scenes/chapter-direct.toml`.
pub const SOURCE: &str = r#"# chapter-direct: the chapter's first picture, direct illumination only.
#
# Four spheres on a grey floor under one white light above the blue sphere. No
# mirror: `depth = 0` casts no secondary rays. The numbers are exactly those of the
# built-in scene `chapter-direct` (core/src/builtin.rs); a test checks that this
# file renders byte-identical to it.

ambient = [0.12, 0.12, 0.12]
background = [0.08, 0.09, 0.14]

[render]
width = 320
height = 240
sampler = "centre"
depth = 0
seed = 0
tile = 16

[camera]
position = [0.0, 1.8, 7.0]
look_at = [0.0, 0.9, 0.0]
up = [0.0, 1.0, 0.0]
fovy = 60.0
near = 0.1
far = 100.0

# Materials, in the order the core adds them.
[[material]]
name = "floor"
color = [0.75, 0.75, 0.75]

[[material]]
name = "blue"
color = [0.1, 0.25, 0.95]
specular = 0.4
shininess = 48.0

[[material]]
name = "red"
color = [0.9, 0.15, 0.1]
specular = 0.4
shininess = 48.0
diffuse = 1.0
reflectivity = 0.0

[[material]]
name = "green"
color = [0.15, 0.8, 0.2]
specular = 0.4
shininess = 48.0
diffuse = 1.0
reflectivity = 0.0

[[material]]
name = "yellow"
color = [0.95, 0.8, 0.1]
specular = 0.4
shininess = 48.0

[[plane]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "floor"

[[sphere]]
center = [0.0, 1.0, 0.0]
radius = 1.0
material = "blue"

[[sphere]]
center = [-2.3, 0.8, 0.4]
radius = 0.8
material = "red"

[[sphere]]
center = [2.2, 0.9, -0.3]
radius = 0.9
material = "green"

[[sphere]]
center = [0.9, 0.35, 1.9]
radius = 0.35
material = "yellow"

# The white light above the blue sphere.
[[light]]
position = [0.0, 7.0, 1.0]
color = [1.0, 1.0, 1.0]
intensity = 40.0
"#;
