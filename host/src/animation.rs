//! A scene file's animation (`[[keyframes]]`, `[render] fps`): its tracks as
//! the core's ([`tessera_core::animation::Track`], checked there, each
//! refusal named by its `[[keyframes]]` item), and the scene at a time or a
//! frame ([`SceneDesc::at_time`]): each moved instance's placement is what
//! the core's evaluation gives for that time, the same `f32` numbers a chip
//! evaluating the same tracks gets, written back into the description, which
//! then renders as a still scene.

use crate::desc::{ChannelDesc, DescError, InterpolationDesc, ScaleDesc, SceneDesc};
use tessera_core::animation::{Animation, Channel, Interpolation, Track};

/// A track's numbers in `f32`, which a core [`Track`] borrows.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackData {
    /// The `[[instance]]` it moves (its place in the file's list).
    pub instance: usize,
    /// What it moves.
    pub channel: Channel,
    /// How.
    pub interpolation: Interpolation,
    /// The keyframes' times.
    pub times: Vec<f32>,
    /// Their values (a translation or scale in the first three numbers, a
    /// quaternion in all four).
    pub values: Vec<[f32; 4]>,
}

impl TrackData {
    /// The core's track of these numbers, moving instance `index`.
    #[must_use]
    pub fn track(&self, index: u16) -> Track<'_> {
        Track::new(
            index,
            self.channel,
            self.interpolation,
            &self.times,
            &self.values,
        )
    }
}

/// `x` in `f32`, or why not (`what` of `item`).
fn f32_of(x: f64, item: &str, what: &str) -> Result<f32, DescError> {
    let y = x as f32;
    if x.is_finite() && !y.is_finite() {
        return Err(DescError {
            item: item.into(),
            message: format!("a keyframe {what} is too large for f32, got {x:e}"),
        });
    }
    Ok(y)
}

impl SceneDesc {
    /// The tracks of `[[keyframes]]`, each checked by the core (`item`
    /// `keyframes 2`): its target an `[[instance]]` by name, each value of the
    /// channel's length, times strictly increasing, a rotation of non-zero
    /// length, no channel of an instance moved twice.
    ///
    /// # Errors
    /// The first track at fault, named.
    pub fn tracks(&self) -> Result<Vec<TrackData>, DescError> {
        let mut out: Vec<TrackData> = Vec::with_capacity(self.keyframes.len());
        for (i, k) in self.keyframes.iter().enumerate() {
            let item = format!("keyframes {}", i + 1);
            let fail = |message: String| DescError {
                item: item.clone(),
                message,
            };
            let instance = self
                .instances
                .iter()
                .position(|d| d.name.as_deref() == Some(k.target.as_str()))
                .ok_or_else(|| {
                    fail(format!(
                        "no instance is named {:?}: keyframes move an [[instance]] by its `name`",
                        k.target
                    ))
                })?;
            let (channel, len) = match k.channel {
                ChannelDesc::Translation => (Channel::Translation, 3),
                ChannelDesc::Rotation => (Channel::Rotation, 4),
                ChannelDesc::Rotate => (Channel::Rotation, 3),
                ChannelDesc::Scale => (Channel::Scale, 3),
            };
            if k.times.len() != k.values.len() {
                return Err(fail(format!(
                    "{} times and {} values: one value a time",
                    k.times.len(),
                    k.values.len()
                )));
            }
            let times = k
                .times
                .iter()
                .map(|&t| f32_of(t, &item, "time"))
                .collect::<Result<Vec<f32>, _>>()?;
            let mut values = Vec::with_capacity(k.values.len());
            for (j, v) in k.values.iter().enumerate() {
                // A scale may be one number for every axis.
                let v: Vec<f64> = match (k.channel, v.as_slice()) {
                    (ChannelDesc::Scale, &[s]) => vec![s; 3],
                    _ => v.clone(),
                };
                if v.len() != len {
                    return Err(fail(
                        format!(
                            "value {} has {} numbers: a {:?} keyframe has {len}",
                            j + 1,
                            v.len(),
                            k.channel
                        )
                        .to_lowercase(),
                    ));
                }
                let q: [f64; 4] = match k.channel {
                    ChannelDesc::Rotate if v.iter().all(|x| x.is_finite()) => {
                        crate::mesh::euler_quaternion([v[0], v[1], v[2]])
                    }
                    ChannelDesc::Rotate => [v[0], v[1], v[2], 0.0].map(|x| x * f64::NAN),
                    // Normalised in f64; a zero or non-finite one goes on as
                    // written, for the core's check to name.
                    ChannelDesc::Rotation => {
                        let q = [v[0], v[1], v[2], v[3]];
                        crate::mesh::unit_quaternion(q).unwrap_or(q)
                    }
                    _ => [v[0], v[1], v[2], 0.0],
                };
                let mut out4 = [0.0f32; 4];
                for (o, x) in out4.iter_mut().zip(q) {
                    *o = f32_of(x, &item, "value")?;
                }
                values.push(out4);
            }
            out.push(TrackData {
                instance,
                channel,
                interpolation: match k.interpolation {
                    InterpolationDesc::Step => Interpolation::Step,
                    InterpolationDesc::Linear => Interpolation::Linear,
                },
                times,
                values,
            });
            // The core's checks of this track, and of it among the others.
            let data = out.iter().map(|d| (d, track_index(d))).collect::<Vec<_>>();
            let tracks: Vec<Track<'_>> = data.iter().map(|(d, i)| d.track(*i)).collect();
            Animation::new(&tracks)
                .check(self.instances.len())
                .map_err(|e| match e {
                    tessera_core::Error::BadBaked { .. } => fail(
                        format!(
                            "another [[keyframes]] moves the {:?} of {:?} already",
                            k.channel, k.target
                        )
                        .to_lowercase(),
                    ),
                    e => fail(e.to_string()),
                })?;
        }
        Ok(out)
    }

    /// The time of the animation's last keyframe (0 without keyframes).
    ///
    /// # Errors
    /// As [`SceneDesc::tracks`].
    pub fn duration(&self) -> Result<f64, DescError> {
        let data = self.tracks()?;
        let tracks: Vec<Track<'_>> = data.iter().map(|d| d.track(track_index(d))).collect();
        Ok(f64::from(Animation::new(&tracks).duration()))
    }

    /// How many frames at `[render] fps` play the animation whole: frame 0 to
    /// the last at or before its end, as the core counts them
    /// ([`Animation::frames`]; 1 without keyframes).
    ///
    /// # Errors
    /// As [`SceneDesc::tracks`] and [`SceneDesc::fps`].
    pub fn frames(&self) -> Result<u32, DescError> {
        let fps = self.fps()?;
        let data = self.tracks()?;
        let tracks: Vec<Track<'_>> = data.iter().map(|d| d.track(track_index(d))).collect();
        Ok(Animation::new(&tracks).frames(fps))
    }

    /// The scene at time `t` (seconds): each instance a track moves placed
    /// where the core's evaluation of its tracks has it (its rotation then a
    /// quaternion, its scale per axis); the rest as the file says.
    ///
    /// # Errors
    /// As [`SceneDesc::tracks`]; a time that is not finite.
    pub fn at_time(&self, t: f64) -> Result<SceneDesc, DescError> {
        if !t.is_finite() {
            return Err(DescError {
                item: "frame".into(),
                message: format!("the time must be finite, got {t}"),
            });
        }
        let tracks = self.tracks()?;
        let mut out = self.clone();
        for d in &tracks {
            let [x, y, z, w] = d.track(0).sample(t as f32).map(f64::from);
            let inst = &mut out.instances[d.instance];
            match d.channel {
                Channel::Translation => inst.translate = [x, y, z],
                Channel::Rotation => {
                    inst.rotate = None;
                    inst.quaternion = Some([x, y, z, w]);
                }
                _ => inst.scale = ScaleDesc::Axes([x, y, z]),
            }
        }
        Ok(out)
    }

    /// The scene at frame `n` of its animation (`[render] fps`): at the time
    /// [`tessera_core::animation::frame_time`] gives.
    ///
    /// # Errors
    /// As [`SceneDesc::at_time`]; an `fps` that is not a finite number above 0.
    pub fn at_frame(&self, n: u32) -> Result<SceneDesc, DescError> {
        // The core's rule for a frame's time, which a firmware playing the
        // baked `FPS` follows too.
        self.at_time(f64::from(tessera_core::animation::frame_time(
            n,
            self.fps()?,
        )))
    }

    /// `[render] fps` as the core and a baked scene take it (`f32`).
    ///
    /// # Errors
    /// An `fps` that is not a finite number above 0 once in `f32`.
    pub fn fps(&self) -> Result<f32, DescError> {
        let fps = self.render.fps;
        let fps32 = fps as f32;
        if fps32.is_finite() && fps32 > 0.0 {
            Ok(fps32)
        } else {
            Err(DescError {
                item: "render".into(),
                message: format!(
                    "fps must be a finite number above 0 (and below 3.4e38, in f32), got {fps}"
                ),
            })
        }
    }
}

/// A track's instance as the core's index (its place among the file's
/// instances; a host scene holds at most [`crate::desc::MAX_INSTANCES`]).
fn track_index(d: &TrackData) -> u16 {
    u16::try_from(d.instance).unwrap_or(u16::MAX)
}

#[cfg(test)]
mod tests {
    use crate::desc::SceneDesc;

    /// A scene of one instance `spin` of a one-triangle mesh, and `keyframes`.
    fn scene(keyframes: &str) -> Result<SceneDesc, String> {
        static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let k = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("tessera-anim-{}-{k}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let text = format!(
            "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\
             [render]\nfps = 10\n\
             [[material]]\nname = \"m\"\n\
             [[mesh]]\nobj = \"tri.obj\"\nmaterial = \"m\"\nname = \"tri\"\n\
             [[instance]]\nmesh = \"tri\"\nname = \"spin\"\ntranslate = [1, 2, 3]\n\
             {keyframes}"
        );
        let path = dir.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        crate::file::load(&path).map_err(|e| e.to_string())
    }

    /// Translations go straight between keyframes; a `rotate` in degrees is
    /// turned at constant speed (45 degrees halfway through a quarter turn);
    /// the untouched channels stay the file's; frames are times at `fps`.
    #[test]
    fn a_frame_places_each_moved_instance_from_its_keyframes() {
        let d = scene(
            "[[keyframes]]\ntarget = \"spin\"\nchannel = \"translation\"\n\
             times = [0.0, 2.0]\nvalues = [[0, 0, 0], [4, 2, -2]]\n\
             [[keyframes]]\ntarget = \"spin\"\nchannel = \"rotate\"\n\
             times = [0.0, 1.0]\nvalues = [[0, 0, 0], [0, 90, 0]]\n",
        )
        .unwrap();
        assert_eq!(d.duration().unwrap(), 2.0);
        let f = d.at_frame(5).unwrap(); // 0.5 s
        let i = &f.instances[0];
        assert_eq!(i.translate, [1.0, 0.5, -0.5]);
        let q = i.quaternion.unwrap();
        let h = (22.5f64).to_radians();
        let want = [0.0, h.sin(), 0.0, h.cos()];
        assert!(
            q.iter().zip(want).all(|(a, b)| (a - b).abs() < 3e-7),
            "{q:?}"
        );
        assert_eq!(i.scale, crate::desc::ScaleDesc::Uniform(1.0));
        // After the end: the last keyframes.
        let end = d.at_time(9.0).unwrap();
        assert_eq!(end.instances[0].translate, [4.0, 2.0, -2.0]);
        assert!(d.at_time(f64::NAN).is_err());
        // The frame renders (its placements pass the core's checks).
        assert!(d.at_frame(5).unwrap().to_core().is_ok());
    }

    /// `fps` is checked with the render settings: a frame rate that is not a
    /// finite number above 0 in `f32` (what a baked scene's `FPS` is) is
    /// refused, naming `render`; frame `n` is at `n / fps` in `f32`.
    #[test]
    fn a_bad_fps_is_refused_and_frames_are_f32_times() {
        let mut d = scene("").unwrap();
        for bad in [0.0, -12.0, f64::NAN, f64::INFINITY, 1e39, 1e-50] {
            d.render.fps = bad;
            let e = d.settings().unwrap_err();
            assert_eq!(e.item, "render", "{bad}");
            assert!(e.message.contains("fps must be"), "{bad}: {e}");
            assert_eq!(d.at_frame(1).unwrap_err(), e);
        }
        d.render.fps = 29.97;
        assert!(d.settings().is_ok());
        assert_eq!(d.fps().unwrap(), 29.97f32);
        let d = scene(
            "[[keyframes]]\ntarget = \"spin\"\nchannel = \"translation\"\n\
             times = [0.0, 3.0]\nvalues = [[0, 0, 0], [3, 0, 0]]\n",
        )
        .unwrap();
        // Frame 7 is at 7 / 10 in f32, a firmware's `7 as f32 / FPS`.
        let t = 7.0f32 / 10.0;
        let at = |f: SceneDesc| f.instances[0].translate;
        assert_eq!(
            at(d.at_frame(7).unwrap()),
            at(d.at_time(f64::from(t)).unwrap())
        );
        assert!((at(d.at_frame(7).unwrap())[0] - 0.7).abs() < 1e-6);
    }

    /// Every frame of the repository's animation places its instances as a
    /// firmware does, to the bit: the rest placements copied (`Instances::of`
    /// of the still scene), `Animation::place` at `frame_time(n, fps)`,
    /// against the instances of `at_frame(n)` made into the core's scene.
    #[test]
    fn each_frame_places_the_instances_a_firmware_places() {
        use tessera_core::animation::{Animation, frame_time};
        use tessera_core::instance::Instances;
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../scenes/examples/animated.toml");
        let d = crate::file::load(&path).unwrap();
        let data = d.tracks().unwrap();
        let tracks: Vec<_> = data
            .iter()
            .map(|t| t.track(super::track_index(t)))
            .collect();
        let anim = Animation::new(&tracks);
        let fps = d.fps().unwrap();
        type Bits = Option<([u32; 24], [u32; 7])>;
        let bits = |x: Option<([f32; 24], [f32; 7])>| -> Bits {
            x.map(|(a, b)| (a.map(f32::to_bits), b.map(f32::to_bits)))
        };
        let frames = anim.frames(fps);
        // The firmware's way, frame after frame, on the still scene's view.
        let chip: Vec<Vec<Bits>> = d.to_core().unwrap().with_view(|view| {
            let mut placed: Instances<'_, 8> = Instances::of(view).unwrap();
            let rest: Vec<_> = (0..placed.len())
                .map(|k| placed.get(k).unwrap().placement)
                .collect();
            (0..frames)
                .map(|n| {
                    anim.place(frame_time(n, fps), &rest, &mut placed).unwrap();
                    (0..rest.len()).map(|k| bits(placed.numbers(k))).collect()
                })
                .collect()
        });
        for (n, want) in (0..frames).zip(&chip) {
            let host = d.at_frame(n).unwrap().to_core().unwrap();
            let have: Vec<Bits> = host.with_view(|frame| {
                let placed: Instances<'_, 8> = Instances::of(frame).unwrap();
                (0..want.len()).map(|k| bits(placed.numbers(k))).collect()
            });
            assert_eq!(&have, want, "frame {n}");
        }
    }

    /// Bad keyframes are refused, naming the `[[keyframes]]` and what is wrong.
    #[test]
    fn bad_keyframes_are_refused_by_item() {
        let cases = [
            (
                "target = \"nobody\"\nchannel = \"scale\"\ntimes = [0]\nvalues = [[1, 1, 1]]",
                "no instance is named \"nobody\"",
            ),
            (
                "target = \"spin\"\nchannel = \"scale\"\ntimes = [1, 0.5]\nvalues = [[1, 1, 1], [2, 2, 2]]",
                "strictly increasing",
            ),
            (
                "target = \"spin\"\nchannel = \"scale\"\ntimes = [0, 0]\nvalues = [[1, 1, 1], [2, 2, 2]]",
                "strictly increasing",
            ),
            (
                "target = \"spin\"\nchannel = \"rotation\"\ntimes = [0]\nvalues = [[0, 0, 0, 0]]",
                "keyframe value has zero length",
            ),
            (
                "target = \"spin\"\nchannel = \"translation\"\ntimes = [0]\nvalues = [[1, 2]]",
                "value 1 has 2 numbers",
            ),
            (
                "target = \"spin\"\nchannel = \"translation\"\ntimes = [0, 1]\nvalues = [[1, 2, 3]]",
                "2 times and 1 values",
            ),
            (
                "target = \"spin\"\nchannel = \"translation\"\ntimes = [nan]\nvalues = [[1, 2, 3]]",
                "keyframe time is NaN or infinite",
            ),
            (
                "target = \"spin\"\nchannel = \"translation\"\ntimes = [0]\nvalues = [[1, inf, 3]]",
                "keyframe value is NaN or infinite",
            ),
            (
                "target = \"spin\"\nchannel = \"spin\"\ntimes = [0]\nvalues = [[1, 2, 3]]",
                "unknown variant",
            ),
        ];
        for (body, words) in cases {
            let text = format!("[[keyframes]]\n{body}\n");
            let err = match scene(&text) {
                Err(e) => e,
                Ok(d) => match d.tracks() {
                    Err(e) => e.to_string(),
                    Ok(_) => panic!("accepted: {body}"),
                },
            };
            assert!(err.contains(words), "{body}: {err}");
            // Named by its item, or (a file that does not parse) its line.
            assert!(
                err.contains("keyframes 1") || err.contains("scene.toml:2"),
                "{body}: {err}"
            );
        }
        // One channel of one instance moved twice.
        let twice =
            "[[keyframes]]\ntarget = \"spin\"\nchannel = \"scale\"\ntimes = [0]\nvalues = [[1]]\n";
        let d = scene(&format!("{twice}{twice}")).unwrap();
        let e = d.tracks().unwrap_err();
        assert_eq!(e.item, "keyframes 2");
        assert!(
            e.message.contains("moves the scale of \"spin\" already"),
            "{e}"
        );
        // A scale keyframe of 0 is refused when the frame is placed.
        let zero =
            "[[keyframes]]\ntarget = \"spin\"\nchannel = \"scale\"\ntimes = [0]\nvalues = [[0]]\n";
        let d = scene(zero).unwrap();
        let e = d.at_frame(0).unwrap().to_core().unwrap_err();
        assert!(e.message.contains("instance scale"), "{e}");
    }
}
