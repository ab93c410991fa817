//! The chapter's interference example, quantified against the exact box-filtered
//! truth: Young's fringes (spacing 0.75 mm) seen through pixels smaller (0.3x) and
//! larger (1.6x) than the spacing. Prefiltering evaluates the texture once per pixel
//! with no error; centre sampling aliases once pixels outgrow the fringes; 5 random
//! rays (the chapter's example) drown the pattern in noise. Deterministic, no timing.

use tessera_core::Viewport;
use tessera_host::trade::{FringeResult, interference_study};

fn get<'a>(r: &'a [FringeResult], fp: f64, method: &str) -> &'a FringeResult {
    r.iter()
        .find(|x| x.footprint == fp && x.method == method)
        .unwrap_or_else(|| panic!("{method} at {fp}"))
}

#[test]
fn prefiltering_is_exact_and_point_sampling_fails_as_the_chapter_shows() {
    let (small, large) = (0.3, 1.6);
    let r = interference_study(&[small, large], Viewport::new(160, 120)).unwrap();
    for x in &r {
        println!(
            "footprint {:.1}x {:<13} rmse {:6.2} LSB  amplitude {:6.1}  row std {:6.1}",
            x.footprint, x.method, x.rmse, x.amplitude, x.row_std
        );
    }
    for fp in [small, large] {
        // One evaluation, (almost) no error: within rounding of the 8-bit output.
        assert!(get(&r, fp, "prefiltered").rmse < 0.6, "{fp}");
    }
    // The box filter scales a fringe of frequency f (cycles per pixel) by
    // sinc(f) = sin(pi f) / (pi f); point sampling keeps the full amplitude.
    let sinc = |f: f64| (std::f64::consts::PI * f).sin().abs() / (std::f64::consts::PI * f);
    for fp in [small, large] {
        let (truth, centre) = (get(&r, fp, "truth"), get(&r, fp, "centre"));
        let ratio = truth.amplitude / centre.amplitude;
        assert!(
            (ratio - sinc(fp)).abs() < 0.02,
            "{fp}: {ratio} vs sinc {}",
            sinc(fp)
        );
    }
    // Pixels smaller than the fringes: the truth has strong fringes; centre sampling
    // keeps them with too much contrast, 5 random rays add noise on top.
    let truth = get(&r, small, "truth");
    assert!(truth.amplitude > 100.0, "{}", truth.amplitude);
    let centre = get(&r, small, "centre");
    assert!(get(&r, small, "random:5").rmse > centre.rmse);
    assert!(get(&r, small, "stratified:3").rmse < centre.rmse);
    // Pixels larger than the fringes: the box-filtered truth is nearly flat; centre
    // sampling shows strong false (aliased) fringes; 5 random rays lose the pattern
    // in noise (large error, no fringe at the true frequency).
    let truth = get(&r, large, "truth");
    let centre = get(&r, large, "centre");
    let random = get(&r, large, "random:5");
    assert!(truth.row_std < 20.0, "{}", truth.row_std);
    assert!(
        centre.row_std > 3.0 * truth.row_std,
        "{} vs {}",
        centre.row_std,
        truth.row_std
    );
    assert!(centre.rmse > 20.0 && random.rmse > 20.0);
    assert!(get(&r, large, "stratified:3").rmse < random.rmse);
}
