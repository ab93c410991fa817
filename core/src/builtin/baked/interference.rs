// Baked by `tessera bake` from "scenes/interference.toml": generated, do not edit.
//
// 1 material, 1 plane: 120 bytes of flash.

use crate::{BakedCamera, BakedScene, Color, Encoding, Primitive, Primitives, RenderSettings, Sampler, Viewport, capacities, geometry::Plane, light::Light, material::Material, material::MaterialId, texture::Texture, tile::Loops, tile::TileLoop};

// The materials: each constant is a material's reference (its place in MATERIALS).
/// The material "screen".
#[allow(dead_code)]
pub const MAT_SCREEN: MaterialId = MaterialId(0);

/// The materials: texture, ambient, diffuse, specular, shininess, reflectivity, transparency, index of refraction.
#[rustfmt::skip]
pub static MATERIALS: [Material; 1] = [
    Material::baked( // MAT_SCREEN
        Texture::Fringes { color: Color::new(0.0, 1.0, 0.6), spacing: 0.00075 },
        1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0,
    ),
];

/// The lights: a point light's position (a sun's unit direction towards it), colour, intensity.
#[rustfmt::skip]
pub static LIGHTS: [Light; 0] = [
];

/// The planes: a point, the unit normal, the offset from the origin along it, the tangents of the texture's uv.
#[rustfmt::skip]
pub static PLANES: [Primitive<Plane>; 1] = [
    Primitive { geometry: Plane::baked([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 0.0, [[1.0, -0.0, -0.0], [-0.0, 1.0, -0.0]]), material: MAT_SCREEN },
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
pub static SCENE: BakedScene<'static, capacities!(planes: 1)> = BakedScene::new(
    BakedCamera {
        position: [0.0, 0.0, 0.1],
        forward: [0.0, 0.0, -1.0],
        up: [0.0, 1.0, 0.0],
        fovy_degrees: 4.0,
        near: 0.01,
        far: 1.0,
    },
    Viewport::new(WIDTH, HEIGHT),
    RenderSettings {
        sampler: Sampler::Centre,
        max_depth: 0,
        seed: 0,
        encoding: Encoding::Srgb,
    },
    Color::new(1.0, 1.0, 1.0),
    Color::new(0.0, 0.0, 0.0),
    &MATERIALS,
    &LIGHTS,
    Primitives {
        planes: &PLANES,
        ..Primitives::NONE
    },
);

/// The scene file this module is baked from, `scenes/interference.toml`.
pub const SOURCE: &str = r#"# interference: Young's interference fringes on a screen, seen head on.
#
# Slits 2 mm apart (d = 2e-3 m), light of 500 nm (wavelength = 500e-9 m), screen
# 3 m away (distance = 3.0 m): bright fringes every 0.75 mm. The screen is the
# plane z = 0; the camera, 0.1 m in front of it with a 4 degree opening angle,
# sees 7 mm of it from top to bottom. The texture is shown as is (ambient light 1,
# ambient weight 1, no diffuse, no light), so a pixel's value is the texture's.
# The numbers are exactly those of the built-in scene `interference`
# (core/src/builtin.rs); a test checks that this file renders byte-identical to it.

ambient = [1.0, 1.0, 1.0]
background = [0.0, 0.0, 0.0]

[render]
width = 320
height = 240
sampler = "centre"
depth = 0
seed = 0
tile = 16

[camera]
position = [0.0, 0.0, 0.1]
forward = [0.0, 0.0, -1.0]
up = [0.0, 1.0, 0.0]
fovy = 4.0
near = 0.01
far = 1.0

[[material]]
name = "screen"
texture = { kind = "young", color = [0.0, 1.0, 0.6], d = 2e-3, wavelength = 500e-9, distance = 3.0 }
diffuse = 0.0

[[plane]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
material = "screen"
"#;
