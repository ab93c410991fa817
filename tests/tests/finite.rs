//! An accepted scene never gives a NaN or infinite colour, and its bytes do not
//! depend on the tile size: random scenes built through the public API with values
//! drawn from the whole accepted range (and beyond it: whatever a constructor
//! refuses is simply left out), lights on surfaces, colours at `MAX_COLOR`,
//! textures at their extreme scales (the generator's `Values::Wild`, in
//! `tessera_tests::random_scene`).

use proptest::prelude::*;
use tessera_core::Viewport;
use tessera_host::render_tiles;
use tessera_tests::random_scene::{Values, recipe};

/// Scenes built and rendered by the property below (the test checks that the
/// generator is not refused too often to mean anything).
static RENDERED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
/// Scenes generated.
static GENERATED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

proptest! {
    // 160 random scenes at 20x14, every pixel's colour checked,
    // rendered with three tile sizes.
    #![proptest_config(ProptestConfig { cases: 160, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn accepted_scenes_give_finite_colours_whatever_the_tile_size(
        r in recipe::<tessera_core::capacities!(spheres: 4, planes: 3, triangles: 3, boxes: 3, cylinders: 3, disks: 3, materials: 4, lights: 4)>(Values::Wild)
    ) {
        let generated = GENERATED.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        // By the end, at least an eighth of the scenes (shrinking included) must
        // have been rendered: most recipes hold a value some constructor refuses.
        prop_assert!(generated < 150 || 8 * RENDERED.load(std::sync::atomic::Ordering::Relaxed) >= generated,
            "only {} of {} random scenes were accepted", RENDERED.load(std::sync::atomic::Ordering::Relaxed), generated);
        let Some(scene) = r.build() else {
            return Ok(());
        };
        let Ok(renderer) = scene.renderer(Viewport::new(20, 14), r.settings(1)) else {
            return Ok(());
        };
        RENDERED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let view = scene.view();
        for y in 0..14 {
            for x in 0..20 {
                let colour = renderer.pixel_color(&view, x, y, &mut ());
                prop_assert!(
                    colour.is_finite() && colour.min_component() >= 0.0,
                    "pixel ({}, {}) is {:?}", x, y, colour
                );
            }
        }
        let eight = render_tiles::<8>(&view, &renderer, None).unwrap();
        prop_assert!(eight == render_tiles::<16>(&view, &renderer, None).unwrap(), "tiles of 8 and 16 differ");
        prop_assert!(eight == render_tiles::<32>(&view, &renderer, None).unwrap(), "tiles of 8 and 32 differ");
    }
}
