//! A few frames of the scene's animation (compiled for a scene with
//! `[[keyframes]]`: build.rs then sets `tessera_animation`), as a firmware plays
//! it: the baked instances copied into RAM once, then for each frame `n` the
//! animation evaluated at its time (`frame_time(n, FPS)`, the host's rule for
//! `tessera render --frame N`), the moved instances placed (`ANIMATION.place`)
//! and handed to the view (`with_instances`), and the frame rendered through
//! that view. Each frame is written to `frame-NNN.ppm` and printed with its
//! checksum, the instructions of its render and of its set-up.

use crate::{Error, N, Picture, clock, render_picture, scene};
use cortex_m_semihosting::hprintln;
use tessera_core::animation::frame_time;
use tessera_core::instance::Instances;
use tessera_core::{Renderer, SceneView, Tile};

/// How many frames are written: those at 0, 1/4, 1/2 and 3/4 of the
/// animation's frames (fewer for an animation of fewer frames).
const WRITTEN: u32 = 4;

/// Plays frames of the scene's animation through `view` (the baked scene's)
/// with `renderer` (its camera, size and settings), into `tile`.
pub fn play(view: &SceneView<'_>, renderer: &Renderer, tile: &mut Tile<N>) -> Result<(), Error> {
    // The tracks checked once against the view's instances.
    scene::ANIMATION.check(view.instance_count())?;
    // Where the tracks start from: each instance's placement in the scene file.
    let rest = scene::INSTANCES.map(|p| p.instance().placement);
    // The frame's instances, in RAM: as many as the scene has.
    let mut moving: Instances<'_, { scene::INSTANCES.len() }> = Instances::of(view)?;
    let frames = scene::ANIMATION.frames(scene::FPS);
    hprintln!(
        "animation: frames={} fps={} duration={} s",
        frames,
        scene::FPS,
        scene::ANIMATION.duration()
    );
    let written = WRITTEN.min(frames);
    for k in 0..written {
        let n = k * frames / written;
        let t0 = clock::ticks();
        scene::ANIMATION.place(frame_time(n, scene::FPS), &rest, &mut moving)?;
        let frame = view.with_instances(&moving)?;
        let setup = (clock::ticks() - t0) * clock::INSTRUCTIONS_PER_TICK;
        let (checksum, instructions) = render_picture(&frame, renderer, tile, Picture::Frame(n))?;
        hprintln!(
            "frame={} checksum={:016x} instructions={} setup={} (wrote {})",
            n,
            checksum,
            instructions,
            setup,
            Picture::Frame(n)
        );
    }
    Ok(())
}
