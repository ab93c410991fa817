//! Which tiles a frame must render again when only its instances moved
//! ([`Renderer::tile_may_change`]): an animation of mesh instances under a
//! still camera changes the tiles that a moved instance can reach, in its old
//! place or its new one, and no other.
//!
//! The rule is the culling's (module `cull`), which never changes a pixel: a
//! tile's camera rays search only its camera lists, and the shadow rays of
//! their hits only its shadow lists. When no moved instance is in either list
//! of the tile in either frame, each frame's tile is the render of the scene
//! without the moved instances, with the same lists of everything else (the
//! camera lists of a primitive depend on it alone; the shadow lists on the
//! visible boxes of the camera lists, the same in both frames): the same
//! pixels and the same rays. Reflected and refracted rays search every
//! primitive, and the shadow rays of lights beyond the lists' masks too: a
//! frame with either renders every tile again.

use super::buffer::TileCoord;
use super::renderer::Renderer;
use crate::cull::{LISTS, MASKED_LIGHTS, TileLists};
use crate::error::Error;
use crate::kind::{Geometry, each_kind};
use crate::mesh::MAX_MESHES;
use crate::view::SceneView;

/// The instances that moved between two views of one scene
/// ([`moved_instances`]): bit `i` for instance `i`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Moved(u64);

impl Moved {
    /// Whether no instance moved.
    #[must_use]
    pub fn is_none(self) -> bool {
        self.0 == 0
    }

    /// How many instances moved.
    #[must_use]
    pub fn count(self) -> u32 {
        self.0.count_ones()
    }
}

/// The instances of `after` placed otherwise than in `before`, when the two
/// views are of one scene and differ in nothing else: the same primitives,
/// materials, lights and meshes (the same tables: a frame's view made from
/// the scene's by `SceneView::with_instances`), the same number of instances,
/// each of the same mesh. `None` otherwise (or for more than 64 instances):
/// every tile may change.
#[must_use]
pub fn moved_instances(before: &SceneView<'_>, after: &SceneView<'_>) -> Option<Moved> {
    let mut kinds = true;
    let (pa, pb) = (before.primitives, after.primitives);
    each_kind!(|G| {
        kinds &= same(G::of(&pa), G::of(&pb));
    });
    let scene = kinds
        && same(before.materials, after.materials)
        && same(before.lights, after.lights)
        && same(before.meshes, after.meshes)
        && before.ambient == after.ambient
        && before.background == after.background
        && before.secondary == after.secondary
        && before.culling == after.culling
        && before.instances.len() == after.instances.len()
        && before.instances.len() <= 64;
    if !scene {
        return None;
    }
    let mut moved = 0u64;
    for (i, (a, b)) in before.instances.iter().zip(after.instances).enumerate() {
        if !core::ptr::eq(a.mesh, b.mesh) {
            return None;
        }
        if !a.same(b) {
            moved |= 1 << i;
        }
    }
    Some(Moved(moved))
}

impl Renderer {
    /// Whether tile `coord` (of tiles of `N` pixels) may differ between frames
    /// `before` and `after` rendered by this renderer, two views of one scene
    /// of which only the instances in `moved` ([`moved_instances`]) are placed
    /// otherwise. `false` is a guarantee: the tile's pixels and the rays it
    /// counts are the same in both frames, so that a firmware which keeps the
    /// last frame on its panel need neither render the tile nor send it
    /// (module documentation). `true` where a moved instance may reach the
    /// tile, in either frame: seen through it, or between a light and what it
    /// sees; and for every tile of a frame whose rays bounce (reflected and
    /// refracted rays may meet anything), with more lights than the tile
    /// lists follow (8), or whose tiles build no lists (a hierarchy over its
    /// triangles or spheres, more than 64 meshes and instances, or culling
    /// off).
    ///
    /// # Errors
    /// [`Error::TileOutOfFrame`] for a tile outside the frame.
    pub fn tile_may_change<const N: usize>(
        &self,
        before: &SceneView<'_>,
        after: &SceneView<'_>,
        moved: Moved,
        coord: TileCoord,
    ) -> Result<bool, Error> {
        let Some((rect, _)) = self.tile_rect::<N>(coord, self.coarse(before)) else {
            return Err(Error::TileOutOfFrame);
        };
        if moved.is_none() {
            return Ok(false);
        }
        let bounces = |v: &SceneView<'_>| v.depth(self.settings.max_depth) > 0;
        let many_lights = |v: &SceneView<'_>| v.lights.len() > MASKED_LIGHTS;
        if bounces(before) || bounces(after) || many_lights(before) || many_lights(after) {
            return Ok(true);
        }
        let reached = |v: &SceneView<'_>| {
            self.listed_instances(v, rect)
                .is_none_or(|listed| listed & moved.0 != 0)
        };
        Ok(reached(before) || reached(after))
    }

    /// The instances that tile lists of `scene` over `rect` hold, camera or
    /// shadow (bit `i` for instance `i`); `None` where the tile builds no
    /// lists or its rays search every primitive.
    fn listed_instances(&self, scene: &SceneView<'_>, rect: (f32, f32, f32, f32)) -> Option<u64> {
        let mut listed = None;
        let mut body = |lists: Option<&mut TileLists<'_>>| {
            let Some(lists) = lists else {
                return;
            };
            let picks = lists.build(&self.basis, scene, rect);
            let Some(camera) = picks.camera.or(picks.with_tops) else {
                return;
            };
            // No shadow lists where there are lights: every shadow ray
            // searches every primitive.
            let shadow = match picks.shadow {
                Some(s) => s.lists[LISTS - 1],
                None if scene.lights.is_empty() => &[],
                None => return,
            };
            let tops = camera[LISTS - 1].iter().map(|&t| u32::from(t));
            let mut bits = 0u64;
            for top in tops.chain(shadow.iter().map(|&e| e & 0xffff)) {
                if let Some(i) = (top as usize).checked_sub(MAX_MESHES) {
                    // Beyond 64 (never: `moved_instances` refuses more): all.
                    bits |= 1u64.checked_shl(i as u32).unwrap_or(u64::MAX);
                }
            }
            listed = Some(bits);
        };
        (scene.tile_storage)(scene.culled_lists(), &mut body);
        listed
    }
}

/// Whether `a` and `b` are the same table (the same memory and length).
fn same<T>(a: &[T], b: &[T]) -> bool {
    core::ptr::eq(a, b)
}
