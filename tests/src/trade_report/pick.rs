//! "What to pick": the paragraph a user can act on, every figure taken from the
//! tables. One step per claim: the front, what is noise, the depth, fast-math on
//! the chip, where centre sampling fails at edges and on textures.

use super::document::ns;
use super::entries::{ChipKey, Entry, find, of_scene};
use super::{EXACT, FAST, FOOTPRINTS};
use crate::thousands_rounded as thousands;
use std::collections::HashMap;
use std::fmt::Write as _;
use tessera::builtin::Builtin;
use tessera_host::trade::{self, FringeResult};

/// The paragraph, claim after claim.
pub(super) fn paragraph(
    entries: &[Entry],
    chip: &HashMap<ChipKey, f64>,
    fringes: &[FringeResult],
) -> Result<String, String> {
    let mut p = String::new();
    the_front(&mut p, entries)?;
    let (no_texture, textured) = prefilter_effect(entries)?;
    noise(&mut p, entries, &no_texture)?;
    depth(&mut p, entries)?;
    fast_math(&mut p, entries, chip)?;
    edges(&mut p, entries)?;
    textures(&mut p, entries, fringes, &textured)?;
    Ok(p)
}

/// A mean FLIP as the paragraph prints it.
fn flip(x: f64) -> String {
    format!("{x:.4}")
}

/// An entry's chip count, or `-`.
fn chip_of(e: &Entry) -> String {
    e.chip.map_or_else(|| "-".into(), thousands)
}

/// Two rows with the same image (the same FLIP).
fn same_image(a: &Entry, b: &Entry) -> bool {
    (a.row.flip - b.row.flip).abs() < 1e-6
}

/// The fronts of all scenes, as the paragraph summarises them.
struct Fronts {
    /// Per scene, `scene: link > link ...`.
    chains: Vec<String>,
    /// The samplers of every front row.
    on_front: Vec<String>,
    /// Front rows of the fast-math backend.
    fast_on: usize,
    /// Of those, the ones within the timing noise of the exact row.
    fast_noise: usize,
    /// Front rows.
    all_on: usize,
}

/// The fronts, as chains of samplers: rows with the same image (other tile sizes,
/// deeper than the scene) and both backends merged, a depth below the scene's
/// noted; each link with its best FLIP, worst (cheapest) first.
fn fronts(entries: &[Entry]) -> Result<Fronts, String> {
    let mut chains = Vec::new();
    let mut on_front: Vec<String> = Vec::new();
    let (mut fast_on, mut fast_noise, mut all_on) = (0, 0, 0);
    for b in Builtin::ALL {
        let mut links: Vec<(String, f64)> = Vec::new();
        for e in of_scene(entries, b.name()).into_iter().filter(|e| e.front) {
            all_on += 1;
            let mut label = e.row.setting.sampler.to_string();
            on_front.push(label.clone());
            if e.row.setting.depth < b.settings().max_depth {
                let _ = write!(label, " at depth {}", e.row.setting.depth);
            }
            match links.iter_mut().find(|(l, _)| *l == label) {
                Some((_, best)) => *best = best.min(e.row.flip),
                None => links.push((label, e.row.flip)),
            }
            if e.row.backend == FAST {
                fast_on += 1;
                let s = &e.row.setting;
                let exact = find(
                    entries,
                    b.name(),
                    EXACT,
                    &s.sampler.to_string(),
                    s.depth,
                    s.tile,
                )?;
                if exact.row.ns_min <= e.row.ns_max
                    && e.row.ns_min <= exact.row.ns_max
                    && exact.row.flip <= e.row.flip
                {
                    fast_noise += 1;
                }
            }
        }
        links.sort_by(|x, y| y.1.total_cmp(&x.1));
        let chain: Vec<String> = links
            .iter()
            .map(|(l, f)| format!("{l} ({})", flip(*f)))
            .collect();
        chains.push(format!("{}: {}", b.name(), chain.join(" > ")));
    }
    Ok(Fronts {
        chains,
        on_front,
        fast_on,
        fast_noise,
        all_on,
    })
}

/// The front, how much of it is fast-math, and the samplers never on it.
fn the_front(p: &mut String, entries: &[Entry]) -> Result<(), String> {
    let Fronts {
        chains,
        on_front,
        fast_on,
        fast_noise,
        all_on,
    } = fronts(entries)?;
    let mut never: Vec<String> = Vec::new();
    for b in Builtin::ALL {
        for s in trade::grid(b.settings()) {
            let n = s.sampler.to_string();
            if !on_front.contains(&n) && !never.contains(&n) {
                never.push(n);
            }
        }
    }
    let _ = write!(
        p,
        "**The Pareto front**, by sampler (cheapest first, best mean FLIP in \
         brackets): {}. ",
        chains.join("; ")
    );
    if fast_on > 0 {
        let _ = write!(
            p,
            "{fast_on} of its {all_on} rows are fast-math{}. ",
            if fast_noise == fast_on {
                ", each only by timing noise: within the min-max host time of the exact \
                 row with the same setting, which has the same or a lower FLIP"
                    .to_string()
            } else {
                format!(
                    "; {fast_noise} of them lie within the min-max host time of the \
                     exact row with the same setting, which has the same or a lower FLIP"
                )
            }
        );
    }
    let r = Builtin::ChapterReflect.name();
    let d = Builtin::ChapterReflect.settings().max_depth;
    if !never.is_empty() {
        let _ = write!(p, "Never on it: {}", never.join(", "));
        let r16 = find(entries, r, EXACT, "random:16", d, 16);
        let s4 = find(entries, r, EXACT, "stratified:4", d, 16);
        if let (true, Ok(r16), Ok(s4)) = (never.iter().any(|n| n == "random:16"), r16, s4) {
            let _ = write!(
                p,
                " (on {r}, random:16 costs {} instr/px on the chip for FLIP {}, \
                 stratified:4 {} for {})",
                chip_of(r16),
                flip(r16.row.flip),
                chip_of(s4),
                flip(s4.row.flip)
            );
        }
        let _ = write!(p, ". ");
    }
    Ok(())
}

/// A scene and its centre and prefiltered rows.
type Textured<'a> = Vec<(Builtin, &'a Entry, &'a Entry)>;

/// The scenes where prefiltering changes nothing (no texture), and those where it
/// lowers the error, with their centre and prefiltered rows.
fn prefilter_effect(entries: &[Entry]) -> Result<(Vec<&'static str>, Textured<'_>), String> {
    let mut no_texture = Vec::new();
    let mut textured = Vec::new();
    for b in Builtin::ALL {
        let bd = b.settings().max_depth;
        let (c, pf) = (
            find(entries, b.name(), EXACT, "centre", bd, 16)?,
            find(entries, b.name(), EXACT, "prefiltered", bd, 16)?,
        );
        if same_image(c, pf) {
            no_texture.push(b.name());
        } else if pf.row.flip < c.row.flip {
            textured.push((b, c, pf));
        }
    }
    Ok((no_texture, textured))
}

/// What is noise: identical images, and fast-math's host time.
fn noise(p: &mut String, entries: &[Entry], no_texture: &[&str]) -> Result<(), String> {
    let r = Builtin::ChapterReflect.name();
    let d = Builtin::ChapterReflect.settings().max_depth;
    let mut ratios: Vec<f64> = Vec::new();
    for e in entries.iter().filter(|e| e.row.backend == FAST) {
        let s = &e.row.setting;
        if let Ok(x) = find(
            entries,
            &e.row.scene,
            EXACT,
            &s.sampler.to_string(),
            s.depth,
            s.tile,
        ) {
            ratios.push(e.row.ns_median / x.row.ns_median);
        }
    }
    ratios.sort_by(f64::total_cmp);
    let median = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
    let _ = write!(
        p,
        "Several rows render the same image (same FLIP) and differ only by timing \
         noise, so which of them makes the front is chance: the tile size changes no \
         pixel (pick it for RAM: 3N\u{b2} + 8 bytes), nor does a depth beyond the \
         scene's reflections ({r} at depth 3: FLIP {}, as at depth {d}){}; and on the \
         host fast-math is no faster (fast/exact median time {:.2}, {:.2}-{:.2} over \
         {} settings). ",
        flip(find(entries, r, EXACT, "centre", 3, 16)?.row.flip),
        if no_texture.is_empty() {
            String::new()
        } else {
            format!(", nor prefiltered on {}", no_texture.join(" and "))
        },
        median,
        ratios.first().copied().unwrap_or(f64::NAN),
        ratios.last().copied().unwrap_or(f64::NAN),
        ratios.len()
    );
    Ok(())
}

/// A depth below the scene's costs accuracy.
fn depth(p: &mut String, entries: &[Entry]) -> Result<(), String> {
    let r = Builtin::ChapterReflect.name();
    let d = Builtin::ChapterReflect.settings().max_depth;
    let d0 = find(entries, r, EXACT, "centre", 0, 16)?;
    let centre = find(entries, r, EXACT, "centre", d, 16)?;
    let _ = write!(
        p,
        "A depth below the scene's costs accuracy ({r} at depth 0: FLIP {} against {}). ",
        flip(d0.row.flip),
        flip(centre.row.flip)
    );
    Ok(())
}

/// The smallest and largest fast-math/exact ratio of the chip's counts, and how
/// many settings have both.
fn chip_ratios(chip: &HashMap<ChipKey, f64>) -> (f64, f64, usize) {
    let mut chip_ratios: Vec<f64> = Vec::new();
    for ((backend, scene, sampler, depth, tile), e) in chip {
        if backend != EXACT {
            continue;
        }
        let fast = (
            FAST.to_string(),
            scene.clone(),
            sampler.clone(),
            *depth,
            *tile,
        );
        if let Some(f) = chip.get(&fast) {
            chip_ratios.push(f / e);
        }
    }
    chip_ratios.sort_by(f64::total_cmp);
    let (rmin, rmax) = (
        chip_ratios.first().copied().unwrap_or(f64::NAN),
        chip_ratios.last().copied().unwrap_or(f64::NAN),
    );
    (rmin, rmax, chip_ratios.len())
}

/// Fast-math on the chip: what it saves and what it costs in error.
fn fast_math(
    p: &mut String,
    entries: &[Entry],
    chip: &HashMap<ChipKey, f64>,
) -> Result<(), String> {
    let r = Builtin::ChapterReflect.name();
    let d = Builtin::ChapterReflect.settings().max_depth;
    let centre = find(entries, r, EXACT, "centre", d, 16)?;
    let (rmin, rmax, settings) = chip_ratios(chip);
    let fast_centre = find(entries, r, FAST, "centre", d, 16)?;
    let ex_s4 = find(entries, r, EXACT, "stratified:4", d, 16)?;
    let fa_s4 = find(entries, r, FAST, "stratified:4", d, 16)?;
    let i = Builtin::Interference.name();
    let same = |a: f64, b: f64| (a - b).abs() < 1e-5;
    let fringe_same = of_scene(entries, i)
        .iter()
        .filter(|e| e.row.backend == FAST)
        .all(|e| {
            let s = &e.row.setting;
            find(entries, i, EXACT, &s.sampler.to_string(), s.depth, s.tile)
                .is_ok_and(|x| same(x.row.flip, e.row.flip))
        });
    if same(fast_centre.row.flip, centre.row.flip) && same(fa_s4.row.flip, ex_s4.row.flip) {
        let _ = write!(
            p,
            "**Fast-math changes nothing here**: the built-in scenes' highlights have \
             integer shininess, raised by repeated squaring with either backend, and none \
             has a textured sphere (the other approximated calls), so both backends render \
             the same images (on {r}, mean FLIP {} with centre sampling, {} with \
             stratified 4x4) for {:.3} to {:.3} times the instructions on the chip ({} \
             settings of {r} and {i}). ",
            flip(centre.row.flip),
            flip(ex_s4.row.flip),
            rmin,
            rmax,
            settings,
        );
    } else {
        let _ = write!(
            p,
            "**{}** On the chip fast-math takes {:.3} to {:.3} times the exact build's \
             instructions per pixel ({} settings of {r} and {i}), but it raises the error: \
             on {r}, mean FLIP {} instead of {} with centre sampling and {} instead of {} \
             with stratified 4x4, so it caps what more samples can buy{}. ",
            if rmax > 0.9 && fast_centre.row.flip > centre.row.flip {
                "Keep the exact math."
            } else {
                "Fast-math:"
            },
            rmin,
            rmax,
            settings,
            flip(fast_centre.row.flip),
            flip(centre.row.flip),
            flip(fa_s4.row.flip),
            flip(ex_s4.row.flip),
            if fringe_same {
                format!(" ({i} is unaffected: the same FLIP with either backend)")
            } else {
                String::new()
            }
        );
    }
    Ok(())
}

/// Where centre sampling fails: edges.
fn edges(p: &mut String, entries: &[Entry]) -> Result<(), String> {
    let r = Builtin::ChapterReflect.name();
    let d = Builtin::ChapterReflect.settings().max_depth;
    let centre = find(entries, r, EXACT, "centre", d, 16)?;
    let s2 = find(entries, r, EXACT, "stratified:2", d, 16)?;
    let s3 = find(entries, r, EXACT, "stratified:3", d, 16)?;
    let corner = find(entries, r, EXACT, "corner", d, 16)?;
    let _ = write!(
        p,
        "**Centre sampling is the cheapest setting but fails at edges**: on {r} it \
         reaches FLIP {} with pixels up to {} LSB off where an edge crosses them ({} \
         instr/px on the chip); stratified 2x2 brings FLIP to {} and the worst pixel to \
         {} LSB for {} instr/px, stratified 3x3 to {} and {} LSB for {} instr/px. \
         Corner sampling (the chapter's `r0`) shifts the image by half a pixel: FLIP \
         {}{}. ",
        flip(centre.row.flip),
        centre.row.max_diff,
        chip_of(centre),
        flip(s2.row.flip),
        s2.row.max_diff,
        chip_of(s2),
        flip(s3.row.flip),
        s3.row.max_diff,
        chip_of(s3),
        flip(corner.row.flip),
        if corner.row.flip > centre.row.flip {
            ", worse than centre at the same cost"
        } else {
            ""
        }
    );
    Ok(())
}

/// Where centre sampling fails: textures finer than a pixel.
fn textures(
    p: &mut String,
    entries: &[Entry],
    fringes: &[FringeResult],
    textured: &Textured<'_>,
) -> Result<(), String> {
    let i = Builtin::Interference.name();
    let ib = Builtin::Interference.settings();
    let ic = find(entries, i, EXACT, "centre", ib.max_depth, 16)?;
    let ip = find(entries, i, EXACT, "prefiltered", ib.max_depth, 16)?;
    let is4 = find(entries, i, EXACT, "stratified:4", ib.max_depth, 16)?;
    let fr = |fp: f64, m: &str| -> Result<&FringeResult, String> {
        fringes
            .iter()
            .find(|x| x.footprint == fp && x.method == m)
            .ok_or_else(|| format!("no interference result {m} at {fp}"))
    };
    let big = FOOTPRINTS[1];
    let _ = write!(
        p,
        "**On a textured scene, prefilter instead of adding rays**: on {i}, prefiltered \
         has FLIP {} for {} instr/px on the chip, centre {} for {}, and stratified 4x4 \
         still {} for {}",
        flip(ip.row.flip),
        chip_of(ip),
        flip(ic.row.flip),
        chip_of(ic),
        flip(is4.row.flip),
        chip_of(is4),
    );
    for (b, c, pf) in textured.iter().filter(|(b, _, _)| b.name() != i) {
        let bd = b.settings().max_depth;
        let _ = write!(
            p,
            "; on {}, prefiltered has FLIP {} against centre's {}, one ray per pixel \
             either way ({} and {} ns/px){}",
            b.name(),
            flip(pf.row.flip),
            flip(c.row.flip),
            ns(pf.row.ns_median),
            ns(c.row.ns_median),
            find(entries, b.name(), EXACT, "stratified:2", bd, 16).map_or(
                String::new(),
                |s2| format!(
                    ", stratified 2x2 {} for {} ns/px",
                    flip(s2.row.flip),
                    ns(s2.row.ns_median)
                )
            )
        );
    }
    let _ = write!(
        p,
        ". With pixels {big} times the fringe spacing (the study below), centre \
         sampling shows false fringes (row std {:.1} LSB where the truth has {:.1}; RMSE \
         {:.1} LSB), 5 random rays miss by {:.1} LSB, stratified 3x3 by {:.1} LSB, and \
         prefiltered by {:.2} LSB.",
        fr(big, "centre")?.row_std,
        fr(big, "truth")?.row_std,
        fr(big, "centre")?.rmse,
        fr(big, "random:5")?.rmse,
        fr(big, "stratified:3")?.rmse,
        fr(big, "prefiltered")?.rmse
    );
    Ok(())
}
