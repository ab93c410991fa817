//! "What to pick": the paragraph a user can act on, every figure taken from the
//! tables. One step per claim: the fronts, what is noise, the depth, each
//! approximate backend on the chip, where centre sampling fails at edges and on
//! textures. Chip costs are the estimated Cortex-M4 cycles per pixel.

use super::chart::Cost;
use super::document::ns;
use super::entries::{Entry, find, of_scene, same_setting};
use super::{EXACT, FOOTPRINTS, approximations};
use crate::thousands_rounded as thousands;
use std::fmt::Write as _;
use tessera_core::builtin::Builtin;
use tessera_host::trade::{self, FringeResult};

/// The paragraph, claim after claim.
pub(super) fn paragraph(entries: &[Entry], fringes: &[FringeResult]) -> Result<String, String> {
    let mut p = String::new();
    the_front(&mut p, entries)?;
    chip_front(&mut p, entries)?;
    let (no_texture, textured) = prefilter_effect(entries)?;
    noise(&mut p, entries, &no_texture)?;
    depth(&mut p, entries)?;
    adaptive(&mut p, entries)?;
    sparse(&mut p, entries)?;
    for b in approximations() {
        approximation(&mut p, entries, b.name)?;
    }
    edges(&mut p, entries)?;
    textures(&mut p, entries, fringes, &textured)?;
    Ok(p)
}

/// A mean FLIP as the paragraph prints it.
fn flip(x: f64) -> String {
    format!("{x:.4}")
}

/// An entry's estimated chip cycles per pixel, or `-`.
fn chip_of(e: &Entry) -> String {
    e.cycles().map_or_else(|| "-".into(), thousands)
}

/// Two rows with the same image (the same FLIP).
fn same_image(a: &Entry, b: &Entry) -> bool {
    (a.row.flip - b.row.flip).abs() < 1e-6
}

/// The fronts of all scenes on one cost, as the paragraph summarises them.
struct Fronts {
    /// Per scene, `scene: link > link ...`.
    chains: Vec<String>,
    /// The samplers of every front row.
    on_front: Vec<String>,
    /// Front rows per backend other than the exact one, in the order of
    /// [`super::BACKENDS`].
    approx_on: Vec<(&'static str, usize)>,
    /// Of the approximations' rows on the host front, the ones within the timing
    /// noise of the exact row with the same setting, which is at most as wrong.
    approx_noise: usize,
    /// Front rows.
    all_on: usize,
}

/// The fronts on `cost`, as chains of samplers: rows with the same image (other
/// tile sizes, deeper than the scene) and every backend merged, a depth below the
/// scene's noted; each link with its best FLIP, worst (cheapest) first.
fn fronts(entries: &[Entry], cost: Cost) -> Result<Fronts, String> {
    let mut chains = Vec::new();
    let mut on_front: Vec<String> = Vec::new();
    let mut approx_on: Vec<(&'static str, usize)> = approximations().map(|b| (b.name, 0)).collect();
    let (mut approx_noise, mut all_on) = (0, 0);
    for b in super::SCENES {
        let mut links: Vec<(String, f64)> = Vec::new();
        let front = of_scene(entries, b.name())
            .into_iter()
            .filter(|e| match cost {
                Cost::Host => e.front,
                Cost::Chip => e.chip_front,
            });
        for e in front {
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
            if let Some((_, n)) = approx_on.iter_mut().find(|(n, _)| *n == e.row.backend) {
                *n += 1;
                let exact = same_setting(entries, e, EXACT)?;
                if cost == Cost::Host
                    && exact.row.ns_min <= e.row.ns_max
                    && e.row.ns_min <= exact.row.ns_max
                    && exact.row.flip <= e.row.flip
                {
                    approx_noise += 1;
                }
            }
        }
        links.sort_by(|x, y| y.1.total_cmp(&x.1));
        let chain: Vec<String> = links
            .iter()
            .map(|(l, f)| format!("{l} ({})", flip(*f)))
            .collect();
        if !chain.is_empty() {
            chains.push(format!("{}: {}", b.name(), chain.join(" > ")));
        }
    }
    Ok(Fronts {
        chains,
        on_front,
        approx_on,
        approx_noise,
        all_on,
    })
}

/// `n1 are a, n2 b` for the backends with front rows, or `None`.
fn shares(approx_on: &[(&str, usize)]) -> Option<String> {
    let parts: Vec<String> = approx_on
        .iter()
        .filter(|(_, n)| *n > 0)
        .enumerate()
        .map(|(i, (name, n))| {
            if i == 0 {
                format!("{n} are {name}")
            } else {
                format!("{n} {name}")
            }
        })
        .collect();
    (!parts.is_empty()).then(|| parts.join(", "))
}

/// The host front, how much of it is an approximation, and the samplers never on
/// it.
fn the_front(p: &mut String, entries: &[Entry]) -> Result<(), String> {
    let Fronts {
        chains,
        on_front,
        approx_on,
        approx_noise,
        all_on,
    } = fronts(entries, Cost::Host)?;
    let mut never: Vec<String> = Vec::new();
    for b in super::SCENES {
        for s in trade::grid(b.settings()) {
            let n = s.sampler.to_string();
            if !on_front.contains(&n) && !never.contains(&n) {
                never.push(n);
            }
        }
    }
    let _ = write!(
        p,
        "**The Pareto front on the host**, by sampler (cheapest first, best mean FLIP in \
         brackets): {}. ",
        chains.join("; ")
    );
    let approx: usize = approx_on.iter().map(|(_, n)| n).sum();
    if let Some(shares) = shares(&approx_on) {
        let _ = write!(
            p,
            "Of its {all_on} rows, {shares}{}. ",
            if approx_noise == approx {
                ", each only by timing noise: within the min-max host time of the exact \
                 row with the same setting, which has the same or a lower FLIP"
                    .to_string()
            } else {
                format!(
                    "; {approx_noise} of those lie within the min-max host time of the \
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
                " (on {r}, random:16 costs an estimated {} cycles/px on the chip for FLIP \
                 {}, stratified:4 {} for {})",
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

/// The chip's front (estimated cycles against error), and how much of it is an
/// approximation.
fn chip_front(p: &mut String, entries: &[Entry]) -> Result<(), String> {
    let f = fronts(entries, Cost::Chip)?;
    if f.chains.is_empty() {
        return Ok(());
    }
    let _ = write!(
        p,
        "**On the chip** (estimated cycles per pixel) the front is: {}",
        f.chains.join("; ")
    );
    match shares(&f.approx_on) {
        Some(shares) => {
            let _ = write!(p, "; of its {} rows, {shares}. ", f.all_on);
        }
        None => {
            let _ = write!(p, ". ");
        }
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
    for b in super::SCENES {
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

/// The median, smallest and largest of `ratios` (sorted here), or NaN.
fn spread(ratios: &mut [f64]) -> (f64, f64, f64) {
    ratios.sort_by(f64::total_cmp);
    (
        ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN),
        ratios.first().copied().unwrap_or(f64::NAN),
        ratios.last().copied().unwrap_or(f64::NAN),
    )
}

/// `backend`'s figure over the exact one's, over every setting where both have it.
fn ratios(entries: &[Entry], backend: &str, figure: fn(&Entry) -> Option<f64>) -> Vec<f64> {
    entries
        .iter()
        .filter(|e| e.row.backend == backend)
        .filter_map(|e| {
            let x = same_setting(entries, e, EXACT).ok()?;
            Some(figure(e)? / figure(x)?)
        })
        .collect()
}

/// What is noise: identical images, and each approximation's host time.
fn noise(p: &mut String, entries: &[Entry], no_texture: &[&str]) -> Result<(), String> {
    let r = Builtin::ChapterReflect.name();
    let d = Builtin::ChapterReflect.settings().max_depth;
    let mut host = Vec::new();
    for b in approximations() {
        let mut t = ratios(entries, b.name, |e| Some(e.row.ns_median));
        let (median, lo, hi) = spread(&mut t);
        host.push(format!(
            "{}/{EXACT} median host time {median:.2} ({lo:.2}-{hi:.2} over {} settings)",
            b.name,
            t.len()
        ));
    }
    let _ = write!(
        p,
        "Several rows render the same image (same FLIP) and differ only by timing \
         noise, so which of them makes the host front is chance: the tile size changes \
         no pixel (pick it for RAM: 3N\u{b2} + 8 bytes), nor does a depth beyond the \
         scene's reflections ({r} at depth 3: FLIP {}, as at depth {d}){}{}. ",
        flip(find(entries, r, EXACT, "centre", 3, 16)?.row.flip),
        if no_texture.is_empty() {
            String::new()
        } else {
            format!(", nor prefiltered on {}", no_texture.join(" and "))
        },
        if host.is_empty() {
            String::new()
        } else {
            format!("; {}", host.join("; "))
        }
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

/// What one approximate backend buys on the chip and what it costs in error: the
/// same images everywhere, a change of mean FLIP below the table's precision
/// (0.0001: far below what the samplers move), or a visible one.
fn approximation(p: &mut String, entries: &[Entry], backend: &str) -> Result<(), String> {
    let r = Builtin::ChapterReflect.name();
    let d = Builtin::ChapterReflect.settings().max_depth;
    let centre = find(entries, r, EXACT, "centre", d, 16)?;
    let mut cycles = ratios(entries, backend, Entry::cycles);
    let (median, rmin, rmax) = spread(&mut cycles);
    let settings = cycles.len();
    let scenes: Vec<&str> = super::SCENES
        .iter()
        .map(|b| b.name())
        .filter(|s| {
            of_scene(entries, s)
                .iter()
                .any(|e| e.row.backend == backend && e.chip.is_some())
        })
        .collect();
    let scenes = scenes.join(", ");
    let approx_centre = find(entries, r, backend, "centre", d, 16)?;
    let ex_s4 = find(entries, r, EXACT, "stratified:4", d, 16)?;
    let ap_s4 = find(entries, r, backend, "stratified:4", d, 16)?;
    // The largest change of mean FLIP, and of the worst pixel, over every setting of
    // every scene.
    let (mut dflip, mut ddiff, mut rows) = (0.0f64, 0u8, 0);
    for e in entries.iter().filter(|e| e.row.backend == backend) {
        if let Ok(x) = same_setting(entries, e, EXACT) {
            dflip = dflip.max((e.row.flip - x.row.flip).abs());
            ddiff = ddiff.max(e.row.max_diff.abs_diff(x.row.max_diff));
            rows += 1;
        }
    }
    let cost = format!(
        "{rmin:.3} to {rmax:.3} times the {EXACT} build's estimated cycles per pixel on the \
         chip (median {median:.3}, {settings} settings of {scenes})"
    );
    if dflip < 1e-6 {
        let _ = write!(
            p,
            "**{backend} renders the same images as {EXACT}** (the same mean FLIP on all \
             {rows} settings: none of the built-in scenes computes what it approximates) for \
             {cost}. "
        );
    } else if dflip < 1e-4 {
        let _ = write!(
            p,
            "**{backend} saves {:.1}% of the chip's cycles for no visible error**: {cost}; \
             it moves pixels, but no mean FLIP by more than {dflip:.1e} over {rows} settings \
             (the table's fourth digit; on {r}, stratified 4x4 instead of centre sampling \
             moves it by {:.1e}) {}. ",
            100.0 * (1.0 - median),
            centre.row.flip - ex_s4.row.flip,
            if ddiff == 0 {
                "and leaves every setting's largest difference from the truth as it was".to_string()
            } else {
                format!(
                    "and moves a setting's largest difference from the truth by at most {ddiff} LSB"
                )
            },
        );
    } else {
        let _ = write!(
            p,
            "**{}** On the chip {backend} takes {cost}, but it changes the error: on {r}, \
             mean FLIP {} instead of {} with centre sampling and {} instead of {} with \
             stratified 4x4{}. ",
            if rmax > 0.9 && approx_centre.row.flip > centre.row.flip {
                format!("Keep the {EXACT} math rather than {backend}.")
            } else {
                format!("{backend}:")
            },
            flip(approx_centre.row.flip),
            flip(centre.row.flip),
            flip(ap_s4.row.flip),
            flip(ex_s4.row.flip),
            if ap_s4.row.flip > ex_s4.row.flip {
                ", so it caps what more samples can buy"
            } else {
                ""
            },
        );
    }
    Ok(())
}

/// Adaptive 4x4 against stratified 4x4, scene by scene: mean FLIP, and the share
/// of the chip's estimated cycles and of the host time; then adaptive sampling's
/// target (FLIP within 10% at no more than 35% of the cost, on both), where it
/// holds.
fn adaptive(p: &mut String, entries: &[Entry]) -> Result<(), String> {
    let _ = write!(
        p,
        "**Adaptive 4x4 spends the 16 rays only where a pixel needs them** (a centre \
         ray per pixel, then stratified 4x4 where the centre rays of a pixel and a \
         neighbour hit different things or, on untextured surfaces, differ in colour); \
         against stratified 4x4, exact math, at each scene's depth:"
    );
    let (mut held, mut missed) = (Vec::new(), Vec::new());
    for b in super::SCENES {
        let (s, d) = (b.name(), b.settings().max_depth);
        let a = find(entries, s, EXACT, "adaptive:4", d, 16)?;
        let st = find(entries, s, EXACT, "stratified:4", d, 16)?;
        let chip = match (a.cycles(), st.cycles()) {
            (Some(x), Some(y)) => x / y,
            _ => f64::NAN,
        };
        let host = a.row.ns_median / st.row.ns_median;
        let _ = write!(
            p,
            " {s}, FLIP {:.5} against {:.5} at {:.0}% of the chip's cycles ({} against {}) and \
             {:.0}% of the host time;",
            a.row.flip,
            st.row.flip,
            100.0 * chip,
            chip_of(a),
            chip_of(st),
            100.0 * host,
        );
        if a.row.flip <= 1.1 * st.row.flip && chip <= 0.35 && host <= 0.35 {
            held.push(s);
        } else {
            missed.push(s);
        }
    }
    p.pop();
    let _ = write!(
        p,
        ". Within 10% of stratified 4x4's FLIP at no more than 35% of its cost on both \
         machines: {}; not: {}. ",
        if held.is_empty() {
            "none".to_string()
        } else {
            held.join(", ")
        },
        if missed.is_empty() {
            "none".to_string()
        } else {
            missed.join(", ")
        },
    );
    Ok(())
}

/// The sparse sampler against the prefiltered one (its ray, in every pixel),
/// scene by scene: mean FLIP, and the share of the chip's estimated cycles and
/// of the host time.
fn sparse(p: &mut String, entries: &[Entry]) -> Result<(), String> {
    let _ = write!(
        p,
        "**Sparse sampling traces fewer rays than pixels** (the prefiltered ray through a \
         quarter of the pixels, the others interpolated from their traced neighbours \
         where these met the same things and agree within {} levels, else traced); \
         against prefiltered, exact math, at each scene's depth, at {}:",
        tessera_core::Sampler::SPARSE_THRESHOLD,
        super::SIZE
    );
    for b in super::SCENES {
        let (s, d) = (b.name(), b.settings().max_depth);
        let sp = find(entries, s, EXACT, "sparse", d, 16)?;
        let pre = find(entries, s, EXACT, "prefiltered", d, 16)?;
        let chip = match (sp.cycles(), pre.cycles()) {
            (Some(x), Some(y)) => x / y,
            _ => f64::NAN,
        };
        let host = sp.row.ns_median / pre.row.ns_median;
        let _ = write!(
            p,
            " {s}, FLIP {} against {} at {:.0}% of the chip's cycles ({} against {}) and \
             {:.0}% of the host time;",
            flip(sp.row.flip),
            flip(pre.row.flip),
            100.0 * chip,
            chip_of(sp),
            chip_of(pre),
            100.0 * host,
        );
    }
    p.pop();
    let coarse = tessera_core::Sampler::sparse_spaced(4).to_string();
    let _ = write!(
        p,
        ". From its coarse grid (`{coarse}`, a ray through every pixel whose coordinates \
         are multiples of 4 first; taken where every primitive is sure to show 8 pixels \
         across, else the same as `sparse`), at {}:",
        super::SIZE
    );
    for b in super::SCENES {
        let (s, d) = (b.name(), b.settings().max_depth);
        let co = find(entries, s, EXACT, &coarse, d, 16)?;
        let sp = find(entries, s, EXACT, "sparse", d, 16)?;
        let _ = write!(
            p,
            " {s}, FLIP {} against sparse's {} at {:.0}% of sparse's host time;",
            flip(co.row.flip),
            flip(sp.row.flip),
            100.0 * co.row.ns_median / sp.row.ns_median,
        );
    }
    p.pop();
    let _ = write!(
        p,
        ". The larger the frame, the more both save (at 240x240 on the chip: \
         [chip-cost.md](chip-cost.md#with-the-sparse-sampler)). "
    );
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
         reaches FLIP {} with pixels up to {} LSB off where an edge crosses them (an \
         estimated {} cycles/px on the chip); stratified 2x2 brings FLIP to {} and the \
         worst pixel to {} LSB for {} cycles/px, stratified 3x3 to {} and {} LSB for {} \
         cycles/px. \
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
         has FLIP {} for an estimated {} cycles/px on the chip, centre {} for {}, and \
         stratified 4x4 still {} for {}",
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
