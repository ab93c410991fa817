//! Keyframe animations of mesh instances (feature `animation`): a [`Track`]
//! moves one instance's translation, rotation or scale through keyframes
//! (glTF's channels: step or linear interpolation, spherical for rotations),
//! and an [`Animation`] of tracks places every instance it moves at a time
//! `t` ([`Animation::place`]), which a frame hands to its view
//! (`SceneView::with_instances`). The tracks are numbers (a baked scene's
//! `static` tables), checked once ([`Animation::check`]); evaluating them is
//! the same `f32` arithmetic on the host and on the chip, so a frame is the
//! same bytes on both.
//!
//! Before a track's first keyframe its value is the first keyframe's, after
//! its last the last one's (glTF's clamping).

use crate::error::{Error, Field, List};
use crate::instance::{Instances, Placement};

/// How a track goes from one keyframe to the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Interpolation {
    /// The earlier keyframe's value until the next keyframe's time.
    Step,
    /// Linearly (translation, scale); spherically at constant angular speed
    /// along the shorter arc (rotation).
    Linear,
}

/// What a track moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Channel {
    /// The translation (`x, y, z`; the fourth number unused).
    Translation,
    /// The rotation, a quaternion `x, y, z, w` (each keyframe of non-zero
    /// length; normalised when checked).
    Rotation,
    /// The scale on each axis (`x, y, z`; the fourth number unused).
    Scale,
}

/// One instance's translation, rotation or scale through time: keyframe `k`
/// is `values[k]` at `times[k]` (seconds, strictly increasing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Track<'a> {
    /// The instance it moves (its index in the view's instances).
    pub instance: u16,
    /// What it moves.
    pub channel: Channel,
    /// How it goes between keyframes.
    pub interpolation: Interpolation,
    /// The keyframes' times.
    pub times: &'a [f32],
    /// The keyframes' values.
    pub values: &'a [[f32; 4]],
}

impl<'a> Track<'a> {
    /// A track of these numbers (checked by [`Animation::check`]).
    #[must_use]
    pub const fn new(
        instance: u16,
        channel: Channel,
        interpolation: Interpolation,
        times: &'a [f32],
        values: &'a [[f32; 4]],
    ) -> Self {
        Self {
            instance,
            channel,
            interpolation,
            times,
            values,
        }
    }

    /// Checks the keyframes: at least one, as many values as times, times
    /// finite, at least 0 and strictly increasing, values finite, a
    /// rotation's of non-zero length.
    fn check(&self) -> Result<(), Error> {
        if self.times.is_empty() || self.times.len() != self.values.len() {
            return Err(Error::OutOfRange {
                field: Field::KeyframeTime,
                range: "one time per value, at least one keyframe",
            });
        }
        let mut last = f32::NEG_INFINITY;
        for &t in self.times {
            if !t.is_finite() {
                return Err(Error::NotFinite(Field::KeyframeTime));
            }
            if t < 0.0 || t <= last {
                return Err(Error::OutOfRange {
                    field: Field::KeyframeTime,
                    range: "times >= 0 and strictly increasing",
                });
            }
            last = t;
        }
        for v in self.values {
            if v.iter().any(|x| !x.is_finite()) {
                return Err(Error::NotFinite(Field::KeyframeValue));
            }
            if self.channel == Channel::Rotation {
                let len2 = v.iter().map(|x| x * x).sum::<f32>();
                if len2.is_nan() || len2 <= 0.0 {
                    return Err(Error::ZeroLength(Field::KeyframeValue));
                }
            }
        }
        Ok(())
    }

    /// The track's value at time `t` (clamped to its first and last
    /// keyframes; a NaN `t` is the first).
    #[must_use]
    pub fn sample(&self, t: f32) -> [f32; 4] {
        let n = self.times.len().min(self.values.len());
        let (Some(&first), Some(&last)) = (self.values.first(), self.values.get(n.wrapping_sub(1)))
        else {
            return [0.0; 4];
        };
        // The keyframe at or before `t`: the times are increasing.
        let k = self
            .times
            .get(..n)
            .unwrap_or(&[])
            .partition_point(|&x| x <= t);
        if k == 0 {
            return first;
        }
        if k >= n {
            return last;
        }
        let (Some(&t0), Some(&t1), Some(&a), Some(&b)) = (
            self.times.get(k - 1),
            self.times.get(k),
            self.values.get(k - 1),
            self.values.get(k),
        ) else {
            return last;
        };
        match self.interpolation {
            Interpolation::Step => a,
            Interpolation::Linear => {
                let u = (t - t0) / (t1 - t0);
                match self.channel {
                    Channel::Rotation => slerp(a, b, u),
                    _ => lerp(a, b, u),
                }
            }
        }
    }

    /// The time of its last keyframe.
    fn end(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }
}

/// `a + (b - a) u`, component by component.
fn lerp(a: [f32; 4], b: [f32; 4], u: f32) -> [f32; 4] {
    let [a0, a1, a2, a3] = a;
    let [b0, b1, b2, b3] = b;
    [
        a0 + (b0 - a0) * u,
        a1 + (b1 - a1) * u,
        a2 + (b2 - a2) * u,
        a3 + (b3 - a3) * u,
    ]
}

/// `a` and `b` (unit quaternions) at `u` in `[0, 1]` along the shorter arc, at
/// constant angular speed; linearly and normalised where they are within
/// about 0.03 degrees (where the arc's sine loses its digits).
fn slerp(a: [f32; 4], b: [f32; 4], u: f32) -> [f32; 4] {
    let norm = |q: [f32; 4]| {
        let len = crate::math::sqrt(q.iter().map(|x| x * x).sum::<f32>());
        q.map(|x| x / len)
    };
    let (a, mut b) = (norm(a), norm(b));
    let mut d: f32 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
    if d < 0.0 {
        b = b.map(|x| -x);
        d = -d;
    }
    let (wa, wb) = if d > 0.999_999_9 {
        (1.0 - u, u)
    } else {
        let angle = crate::math::acos(d);
        let s = crate::math::sin(angle);
        (
            crate::math::sin((1.0 - u) * angle) / s,
            crate::math::sin(u * angle) / s,
        )
    };
    let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (a, b);
    norm([
        wa * a0 + wb * b0,
        wa * a1 + wb * b1,
        wa * a2 + wb * b2,
        wa * a3 + wb * b3,
    ])
}

/// The time of frame `n` at `fps` frames a second: `n / fps`, in `f32`.
/// The host (`tessera render --frame N`) and a firmware (with a baked
/// scene's `FPS`) both take a frame's time so, which makes frame `n` the
/// same bytes on both.
#[must_use]
pub fn frame_time(n: u32, fps: f32) -> f32 {
    n as f32 / fps
}

/// The tracks of a scene's animation (a baked scene's `static` table).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Animation<'a> {
    tracks: &'a [Track<'a>],
}

impl<'a> Animation<'a> {
    /// An animation of `tracks` (checked by [`Animation::check`]).
    #[must_use]
    pub const fn new(tracks: &'a [Track<'a>]) -> Self {
        Self { tracks }
    }

    /// The tracks.
    #[must_use]
    pub fn tracks(&self) -> &'a [Track<'a>] {
        self.tracks
    }

    /// The time of its last keyframe (0 without tracks): where it ends.
    #[must_use]
    pub fn duration(&self) -> f32 {
        self.tracks
            .iter()
            .map(Track::end)
            .fold(0.0, crate::math::max)
    }

    /// How many frames at `fps` frames a second play it whole: frame 0 to
    /// the last whose [`frame_time`] is at most [`Animation::duration`] (1
    /// for an animation without tracks, or an `fps` that is not a finite
    /// number above 0; at most `u32::MAX`).
    #[must_use]
    pub fn frames(&self, fps: f32) -> u32 {
        let end = self.duration();
        if !(fps.is_finite() && fps > 0.0) {
            return 1;
        }
        // The product's rounding may put the count one off either way: the
        // last frame is the one `frame_time` itself puts at or before the end.
        let mut last = (end * fps) as u32;
        while last < u32::MAX && frame_time(last + 1, fps) <= end {
            last += 1;
        }
        while last > 0 && frame_time(last, fps) > end {
            last -= 1;
        }
        last.saturating_add(1)
    }

    /// How many frames one pass takes when it plays in a loop, its time
    /// wrapping at its end: frame 0 to the last before the end (a frame at
    /// the end is the next pass's frame 0), at least 1.
    #[must_use]
    pub fn looped_frames(&self, fps: f32) -> u32 {
        let n = self.frames(fps);
        if n > 1 && frame_time(n - 1, fps) >= self.duration() {
            n - 1
        } else {
            n
        }
    }

    /// Checks every track (see [`Track`]) and that each moves an instance of
    /// the `count` a view has, no two the same channel of one instance.
    ///
    /// # Errors
    /// [`Error::NotFinite`], [`Error::ZeroLength`] or [`Error::OutOfRange`]
    /// naming the keyframes' times or values; [`Error::BadBaked`] (list
    /// `Instances`, the track's index) for a track of an instance the view
    /// does not have, or a channel moved twice.
    pub fn check(&self, count: usize) -> Result<(), Error> {
        for (i, tr) in self.tracks.iter().enumerate() {
            tr.check()?;
            let twice = self
                .tracks
                .iter()
                .take(i)
                .any(|o| o.instance == tr.instance && o.channel == tr.channel);
            if usize::from(tr.instance) >= count || twice {
                return Err(Error::BadBaked {
                    list: List::Instances,
                    index: u16::try_from(i).unwrap_or(u16::MAX),
                });
            }
        }
        Ok(())
    }

    /// Moves each instance of `instances` that a track moves to where the
    /// animation has it at time `t`: its `rest` placement (the scene's, which
    /// [`crate::instance::Instances::get`] gives before any move) with each
    /// channel a track moves replaced by the track's value at `t`.
    ///
    /// # Errors
    /// As [`Instances::set`] (a value that places the mesh out of range);
    /// [`Error::BadBaked`] for a track of an instance `rest` does not have.
    pub fn place<const N: usize>(
        &self,
        t: f32,
        rest: &[Placement],
        instances: &mut Instances<'_, N>,
    ) -> Result<(), Error> {
        for (k, base) in rest.iter().enumerate() {
            let mut p = *base;
            let mut moved = false;
            for tr in self
                .tracks
                .iter()
                .filter(|tr| usize::from(tr.instance) == k)
            {
                let [x, y, z, w] = tr.sample(t);
                match tr.channel {
                    Channel::Translation => p.translation = [x, y, z],
                    Channel::Rotation => p.rotation = [x, y, z, w],
                    Channel::Scale => p.scale = [x, y, z],
                }
                moved = true;
            }
            if moved {
                instances.set(k, p)?;
            }
        }
        if let Some((i, _)) = self
            .tracks
            .iter()
            .enumerate()
            .find(|(_, tr)| usize::from(tr.instance) >= rest.len())
        {
            return Err(Error::BadBaked {
                list: List::Instances,
                index: u16::try_from(i).unwrap_or(u16::MAX),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: f32 = core::f32::consts::FRAC_1_SQRT_2;

    fn close(a: [f32; 4], b: [f32; 4], tol: f32) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
    }

    /// Step holds the earlier keyframe, linear goes straight between them;
    /// both clamp before the first and after the last.
    #[test]
    fn translations_step_and_go_straight_between_keyframes() {
        let times = [1.0, 2.0, 4.0];
        let values = [
            [0.0, 0.0, 0.0, 0.0],
            [2.0, 4.0, -2.0, 0.0],
            [2.0, 0.0, 6.0, 0.0],
        ];
        let lin = Track::new(
            0,
            Channel::Translation,
            Interpolation::Linear,
            &times,
            &values,
        );
        let step = Track {
            interpolation: Interpolation::Step,
            ..lin
        };
        assert_eq!(lin.sample(1.5), [1.0, 2.0, -1.0, 0.0]);
        assert_eq!(lin.sample(3.0), [2.0, 2.0, 2.0, 0.0]);
        assert_eq!(step.sample(1.5), values[0]);
        assert_eq!(step.sample(3.999), values[1]);
        assert_eq!(step.sample(4.0), values[2]);
        for tr in [lin, step] {
            assert_eq!(tr.sample(0.0), values[0]);
            assert_eq!(tr.sample(-5.0), values[0]);
            assert_eq!(tr.sample(9.0), values[2]);
            assert_eq!(tr.sample(f32::NAN), values[0]);
            assert_eq!(tr.sample(2.0), values[1]);
        }
    }

    /// A rotation goes at constant angular speed along the shorter arc: a
    /// quarter turn about y is an eighth at half time and a sixteenth at a
    /// quarter; the same end written as its negative gives the same turn.
    #[test]
    fn rotations_turn_at_constant_speed_along_the_shorter_arc() {
        let times = [0.0, 1.0];
        let quarter = [0.0, S, 0.0, S];
        let values = [[0.0, 0.0, 0.0, 1.0], quarter];
        let tr = Track::new(0, Channel::Rotation, Interpolation::Linear, &times, &values);
        let about_y = |deg: f64| {
            let h = deg.to_radians() / 2.0;
            [0.0, h.sin() as f32, 0.0, h.cos() as f32]
        };
        assert!(
            close(tr.sample(0.5), about_y(45.0), 2e-7),
            "{:?}",
            tr.sample(0.5)
        );
        assert!(
            close(tr.sample(0.25), about_y(22.5), 2e-7),
            "{:?}",
            tr.sample(0.25)
        );
        assert!(close(tr.sample(1.0), quarter, 0.0));
        let negated = [values[0], quarter.map(|x| -x)];
        let tr2 = Track {
            values: &negated,
            ..tr
        };
        let (a, b) = (tr.sample(0.3), tr2.sample(0.3));
        assert!(close(a, b, 2e-7), "{a:?} {b:?}");
        // Two keyframes a hair apart: no division by a vanishing sine.
        let near = [[0.0, 0.0, 0.0, 1.0], [0.0, 1e-5, 0.0, 1.0]];
        let tr3 = Track {
            values: &near,
            ..tr
        };
        let q = tr3.sample(0.5);
        assert!(q.iter().all(|x| x.is_finite()));
        assert!((q.iter().map(|x| x * x).sum::<f32>() - 1.0).abs() < 1e-6);
    }

    /// A track's times, values and channel, and the error it gives.
    type Case<'a> = (&'a [f32], &'a [[f32; 4]], Channel, Error);

    /// Bad keyframes are refused, naming what is wrong.
    #[test]
    fn bad_keyframes_are_refused() {
        let v1 = [[0.0; 4]];
        let v2 = [[0.0; 4], [1.0, 0.0, 0.0, 0.0]];
        let cases: [Case<'_>; 7] = [
            (
                &[],
                &[],
                Channel::Translation,
                Error::OutOfRange {
                    field: Field::KeyframeTime,
                    range: "one time per value, at least one keyframe",
                },
            ),
            (
                &[0.0, 1.0],
                &v1,
                Channel::Translation,
                Error::OutOfRange {
                    field: Field::KeyframeTime,
                    range: "one time per value, at least one keyframe",
                },
            ),
            (
                &[1.0, 0.5],
                &v2,
                Channel::Translation,
                Error::OutOfRange {
                    field: Field::KeyframeTime,
                    range: "times >= 0 and strictly increasing",
                },
            ),
            (
                &[1.0, 1.0],
                &v2,
                Channel::Scale,
                Error::OutOfRange {
                    field: Field::KeyframeTime,
                    range: "times >= 0 and strictly increasing",
                },
            ),
            (
                &[-1.0],
                &v1,
                Channel::Scale,
                Error::OutOfRange {
                    field: Field::KeyframeTime,
                    range: "times >= 0 and strictly increasing",
                },
            ),
            (
                &[f32::NAN],
                &v1,
                Channel::Scale,
                Error::NotFinite(Field::KeyframeTime),
            ),
            (
                &[0.0, 1.0],
                &v2,
                Channel::Rotation,
                Error::ZeroLength(Field::KeyframeValue),
            ),
        ];
        for (times, values, channel, e) in cases {
            let tr = [Track::new(0, channel, Interpolation::Linear, times, values)];
            assert_eq!(Animation::new(&tr).check(1), Err(e), "{times:?} {values:?}");
        }
        let nan = [[0.0, f32::INFINITY, 0.0, 0.0]];
        let tr = [Track::new(
            0,
            Channel::Translation,
            Interpolation::Step,
            &[0.0],
            &nan,
        )];
        assert_eq!(
            Animation::new(&tr).check(1),
            Err(Error::NotFinite(Field::KeyframeValue))
        );
        // An instance the view lacks; one channel moved twice.
        let ok = [[1.0; 4]];
        let a = Track::new(2, Channel::Scale, Interpolation::Step, &[0.0], &ok);
        let b = Track { instance: 0, ..a };
        let bad = |i| Error::BadBaked {
            list: List::Instances,
            index: i,
        };
        assert_eq!(Animation::new(&[a]).check(2), Err(bad(0)));
        assert_eq!(Animation::new(&[b, b]).check(2), Err(bad(1)));
        assert_eq!(Animation::new(&[b, a]).check(3), Ok(()));
        assert_eq!(Animation::new(&[b, a]).duration(), 0.0);
    }

    /// `place` moves each instance a track moves, from its rest placement,
    /// channel by channel, and leaves the others; a value that places the mesh
    /// out of range is refused and names the field.
    #[test]
    fn place_moves_the_tracked_instances_from_their_rest() {
        use crate::bvh::{BakedBvh, Bvh};
        use crate::geometry::Triangle;
        use crate::instance::Instance;
        use crate::material::{Material, MaterialId};
        use crate::{Camera, Color, Primitive, Scene, Vec3};
        let v = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]];
        let faces = [[0u16, 1, 2]];
        let tri = [Primitive {
            geometry: Triangle::baked(v[0], v[1], v[2]),
            material: MaterialId(0),
        }];
        let mut bvh: Bvh<2, 1> = Bvh::new();
        bvh.build(&tri).unwrap();
        let mesh = [crate::mesh::Mesh::new(
            &v,
            &faces,
            &[],
            MaterialId(0),
            BakedBvh::new(bvh.nodes(), bvh.order(), bvh.reach()),
        )];
        let cam =
            Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.1, 100.0).unwrap();
        let mut scene: Scene<crate::capacities!(materials: 1)> = Scene::new(cam);
        scene.add_material(Material::matte(Color::WHITE)).unwrap();
        let view = scene.view().with_meshes(&mesh).unwrap();
        let rest = [
            Placement::new([0.0, 0.0, 0.0, 1.0], [1.0; 3], [-2.0, 0.0, 0.0]),
            Placement::new([0.0, 0.0, 0.0, 1.0], [0.5; 3], [2.0, 0.0, 0.0]),
        ];
        let mut placed: Instances<'_, 2> = Instances::new(&view);
        for p in rest {
            placed.push(Instance::new(0, p)).unwrap();
        }
        let times = [0.0, 2.0];
        let up = [[2.0, 0.0, 0.0, 0.0], [2.0, 3.0, 0.0, 0.0]];
        let turn = [[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, S, S]];
        let tracks = [
            Track::new(1, Channel::Translation, Interpolation::Linear, &times, &up),
            Track::new(1, Channel::Rotation, Interpolation::Step, &times, &turn),
        ];
        let anim = Animation::new(&tracks);
        anim.check(placed.len()).unwrap();
        assert_eq!(anim.duration(), 2.0);
        anim.place(1.0, &rest, &mut placed).unwrap();
        assert_eq!(placed.get(0).map(|i| i.placement), Some(rest[0]));
        let moved = placed.get(1).unwrap().placement;
        assert_eq!(moved.translation, [2.0, 1.5, 0.0]);
        assert_eq!(moved.rotation, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(moved.scale, [0.5; 3]);
        anim.place(2.0, &rest, &mut placed).unwrap();
        assert_eq!(placed.get(1).unwrap().placement.rotation, [0.0, 0.0, S, S]);
        // The frame's view finds the moved triangle where the track put it.
        let frame = view.with_instances(&placed).unwrap();
        let ray = crate::ray::Ray::new(Vec3::new(2.0, 3.0, 5.0), -Vec3::Z).unwrap();
        assert_eq!(crate::search::first_hit(&frame, &ray, 100.0), Some(5.0));
        // A track of an instance `rest` lacks.
        assert_eq!(
            anim.place(1.0, &rest[..1], &mut placed),
            Err(Error::BadBaked {
                list: List::Instances,
                index: 0
            })
        );
        // A scale that a keyframe makes 0 on an axis.
        let zero = [[1.0, 0.0, 1.0, 0.0]];
        let bad = [Track::new(
            0,
            Channel::Scale,
            Interpolation::Step,
            &[0.0],
            &zero,
        )];
        assert_eq!(
            Animation::new(&bad).place(0.0, &rest, &mut placed),
            Err(Error::OutOfRange {
                field: Field::InstanceScale,
                range: "[2^-20, 2^20] in magnitude on each axis (not 0)",
            })
        );
    }

    /// The frames that play an animation whole end at the last frame whose
    /// time is at most its end, also where `end * fps` rounds past a whole
    /// number; frame times are `n / fps` in `f32`.
    #[test]
    fn frames_cover_the_animation_to_its_last_keyframe() {
        let values = [[0.0; 4]; 2];
        let ends = [0.0f32, 2.0, 1.0 / 3.0, 0.7, 10.0];
        let times: [[f32; 2]; 5] = ends.map(|e| [0.0, if e > 0.0 { e } else { 1e-3 }]);
        for (k, t) in times.iter().enumerate() {
            let track = [Track::new(
                0,
                Channel::Translation,
                Interpolation::Linear,
                t,
                &values,
            )];
            let anim = Animation::new(&track);
            for fps in [1.0f32, 12.0, 24.0, 29.97, 30.0, 60.0, 1000.0] {
                let n = anim.frames(fps);
                let end = anim.duration();
                assert!(n >= 1);
                assert!(frame_time(n - 1, fps) <= end, "{k} {fps}");
                assert!(frame_time(n, fps) > end, "{k} {fps}");
            }
        }
        // Two seconds at 12 frames a second: frames 0 to 24.
        let two = [Track::new(
            0,
            Channel::Translation,
            Interpolation::Linear,
            &[0.0, 2.0],
            &values,
        )];
        assert_eq!(Animation::new(&two).frames(12.0), 25);
        // In a loop the frame at the end is the next pass's first.
        assert_eq!(Animation::new(&two).looped_frames(12.0), 24);
        assert_eq!(Animation::new(&two).looped_frames(7.0), 14);
        assert_eq!(Animation::new(&two).frames(7.0), 15);
        assert_eq!(Animation::new(&[]).looped_frames(12.0), 1);
        assert_eq!(frame_time(6, 12.0), 0.5);
        // No tracks, or no frame rate: one frame.
        assert_eq!(Animation::new(&[]).frames(12.0), 1);
        for fps in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(Animation::new(&two).frames(fps), 1);
        }
    }
}
