//! `math-report`: the worst error of each approximation of the core's math
//! (`core/src/math.rs`, the cargo features `fast-rsqrt`, `fast-recip` and
//! `fast-pow`, and the variants the core does not offer, `(dropped)`) over its
//! input range, against `f64`; prints a markdown table.
//!
//! Exhaustive over the f32s of the range where that is feasible, on a sample
//! elsewhere (the table says which): the reciprocal square root and the
//! reciprocal over every f32 of one period of their error (`[1, 4)` and `[1, 2)`:
//! their guesses and Newton steps scale exactly with the exponent, so this is
//! every mantissa and exponent parity), then every 61st positive normal f32;
//! `log2` over every positive normal f32; `exp2` over every f32 of `[-125, 0]`;
//! the powers over every f32 of `[1/2, 1]` and every 61st below, at a dozen
//! exponents. It includes the core's `math.rs` itself (`#[path]`), so that it
//! measures the very functions the features compile, with or without them.
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin math-report > docs/math-report.md
//! ```

// The core's math module, as the core compiles it: most of it is unused here, and
// its `cfg(feature = ..)` name the core's features, which this crate does not have
// (the approximations measured here are compiled whatever the features).
#[allow(dead_code)]
#[path = "../../../core/src/math.rs"]
mod math;

use std::fmt::Write as _;
use std::time::Instant;

const COMMAND: &str =
    "cargo run -p tessera-tests --release --bin math-report > docs/math-report.md";

/// The worst error of one function over its range.
#[derive(Clone, Copy, Debug, Default)]
struct Worst {
    /// The largest relative error.
    rel: f64,
    /// The input where it is reached.
    rel_at: f64,
    /// The largest error in ulps of the exact result (rounded to f32).
    ulp: f64,
    /// The largest absolute error.
    abs: f64,
    /// The input where it is reached.
    abs_at: f64,
    /// Inputs checked.
    count: u64,
}

impl Worst {
    fn add(&mut self, x: f64, got: f64, exact: f64) {
        self.count += 1;
        let abs = (got - exact).abs();
        if abs > self.abs || abs.is_nan() {
            self.abs = abs;
            self.abs_at = x;
        }
        if exact != 0.0 {
            let rel = abs / exact.abs();
            if rel > self.rel || rel.is_nan() {
                self.rel = rel;
                self.rel_at = x;
            }
            self.ulp = self.ulp.max(abs / ulp(exact));
        }
    }

    fn merge(mut self, o: Self) -> Self {
        if o.rel > self.rel || o.rel.is_nan() {
            self.rel = o.rel;
            self.rel_at = o.rel_at;
        }
        if o.abs > self.abs || o.abs.is_nan() {
            self.abs = o.abs;
            self.abs_at = o.abs_at;
        }
        self.ulp = self.ulp.max(o.ulp);
        self.count += o.count;
        self
    }
}

/// The spacing of the f32s at `x` (an f32 ulp, for the exponent of `|x|` rounded
/// to f32; the normals' spacing below them).
fn ulp(x: f64) -> f64 {
    let e = (x.abs() as f32).to_bits() >> 23 & 0xff;
    let e = i32::try_from(e.max(1)).unwrap_or(1);
    2f64.powi(e - 127 - 23)
}

/// `f` over the f32s with bits `lo..hi` (`step` apart), split over the machine's
/// threads; `f` adds each input to its `Worst`.
fn over_bits(lo: u32, hi: u32, step: u32, f: impl Fn(f32, &mut Worst) + Sync) -> Worst {
    let threads = std::thread::available_parallelism().map_or(1, usize::from) as u32;
    let chunk = (hi - lo).div_ceil(threads).div_ceil(step) * step;
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let f = &f;
                s.spawn(move || {
                    let start = lo.saturating_add(t.saturating_mul(chunk));
                    let end = start.saturating_add(chunk).min(hi);
                    let mut w = Worst::default();
                    let mut b = start;
                    while b < end {
                        f(f32::from_bits(b), &mut w);
                        b = b.saturating_add(step);
                    }
                    w
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_default())
            .fold(Worst::default(), Worst::merge)
    })
}

/// The bits of the positive normal f32s.
const NORMALS: (u32, u32) = (0x0080_0000, 0x7f80_0000);

/// How a row gives its error.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Error {
    /// Relative to the exact value (and in ulps of it).
    Relative,
    /// Absolute, also in 8-bit steps: the powers (highlights, at most 1).
    Highlight,
    /// Absolute, in radians: the angles.
    Radians,
}

/// One row of the table.
struct Row {
    function: &'static str,
    feature: &'static str,
    range: String,
    worst: Worst,
    /// How the error is given.
    error: Error,
    note: String,
}

fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:.2e}")
    }
}

fn rsqrt_rows(rows: &mut Vec<Row>) {
    let exact = |x: f32| 1.0 / f64::from(x).sqrt();
    let check = |f: fn(f32) -> f32| {
        let g = |x: f32, w: &mut Worst| w.add(f64::from(x), f64::from(f(x)), exact(x));
        over_bits(0x3f80_0000, 0x4080_0000, 1, g).merge(over_bits(NORMALS.0, NORMALS.1, 61, g))
    };
    let all = "every f32 of [1, 4), every 61st positive normal".to_string();
    let guess: fn(f32) -> f32 = math::rsqrt_guess;
    let one: fn(f32) -> f32 = |x| math::rsqrt_step(0.5 * x, math::rsqrt_guess(x));
    let two: fn(f32) -> f32 = |x| {
        let h = 0.5 * x;
        math::rsqrt_step(h, math::rsqrt_step(h, math::rsqrt_guess(x)))
    };
    let reference: fn(f32) -> f32 = |x| 1.0 / math::sqrt(x);
    for (function, feature, f, note) in [
        (
            "`1 / sqrt(x)`",
            "exact",
            reference,
            "vsqrt + vdiv, 28 cycles",
        ),
        ("`rsqrt_guess` (bits)", "-", guess, "the first guess alone"),
        (
            "guess + 1 Newton step",
            "(dropped)",
            one,
            "FLIP 0.0170 for 0.0118 on chapter-reflect (centre), 0.0095 for 0.0036 (stratified:4)",
        ),
        ("guess + 2 Newton steps", "-", two, "always below the root"),
        (
            "`rsqrt_fast`: 2 steps, the last centred",
            "`fast-rsqrt`",
            math::rsqrt_fast,
            "the same instructions as 2 plain steps",
        ),
    ] {
        rows.push(Row {
            function,
            feature,
            range: all.clone(),
            worst: check(f),
            error: Error::Relative,
            note: note.into(),
        });
    }
}

fn recip_rows(rows: &mut Vec<Row>) {
    // Below 2^126 the reciprocal is a normal number.
    let hi = 0x7e80_0000;
    let range = "every f32 of [1, 2), every 61st positive normal below 2^126".to_string();
    let exact = |x: f32| 1.0 / f64::from(x);
    let check = |f: fn(f32) -> f32| {
        let g = |x: f32, w: &mut Worst| w.add(f64::from(x), f64::from(f(x)), exact(x));
        over_bits(0x3f80_0000, 0x4000_0000, 1, g).merge(over_bits(NORMALS.0, hi, 61, g))
    };
    let reference: fn(f32) -> f32 = |x| 1.0 / x;
    let two: fn(f32) -> f32 = |x| math::recip_newton(x, 2);
    let three: fn(f32) -> f32 = |x| math::recip_newton(x, 3);
    for (function, feature, f, note) in [
        (
            "`1 / x` (vdiv)",
            "exact, `fast-recip`",
            reference,
            "14 cycles; `fast-recip` does one per vector instead of three",
        ),
        ("bits + 2 Newton steps", "(dropped)", two, ""),
        (
            "bits + 3 Newton steps",
            "(dropped)",
            three,
            "costs more than vdiv on the chip (+1 to +9% cycles/px)",
        ),
    ] {
        rows.push(Row {
            function,
            feature,
            range: range.clone(),
            worst: check(f),
            error: Error::Relative,
            note: note.into(),
        });
    }
    // `fast-recip`'s quotient: a component times the rounded reciprocal, against
    // the exact quotient; a sample of pairs (the error depends on both mantissas).
    let mut w = Worst::default();
    let mut seed = 0x9e37_79b9_u32;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed
    };
    for _ in 0..50_000_000 {
        // Mantissas of both, exponents near 1 (the error is relative).
        let a = f32::from_bits(0x3f80_0000 | next() >> 9);
        let s = f32::from_bits(0x3f80_0000 | next() >> 9);
        let got = a * (1.0 / s);
        w.add(f64::from(s), f64::from(got), f64::from(a) / f64::from(s));
    }
    rows.push(Row {
        function: "`Vec3 / s` as `v * (1 / s)`, per component",
        feature: "`fast-recip`",
        range: "5e7 random pairs of mantissas".into(),
        worst: w,
        error: Error::Relative,
        note: "the exact build's `v / s`: 0.5 ulp".into(),
    });
}

fn log_exp_rows(rows: &mut Vec<Row>) {
    rows.push(Row {
        function: "`log2_unit`",
        feature: "`fast-pow`",
        range: "every positive normal f32".into(),
        worst: over_bits(NORMALS.0, NORMALS.1, 1, |x, w| {
            let exact = f64::from(x).log2();
            w.add(f64::from(x), f64::from(math::log2_unit(x)), exact);
        }),
        error: Error::Relative,
        note: "relative to log2 x: exact at the powers of 2".into(),
    });
    // Every f32 of [-125, 0]: the bits of +0, and of -0 up to -125.
    let neg = over_bits(0x8000_0000, 0xc2fa_0001, 1, |z, w| {
        w.add(
            f64::from(z),
            f64::from(math::exp2_unit(z)),
            f64::from(z).exp2(),
        );
    });
    rows.push(Row {
        function: "`exp2_unit`",
        feature: "`fast-pow`",
        range: "every f32 of [-125, 0]".into(),
        worst: neg,
        error: Error::Relative,
        note: String::new(),
    });
}

/// The highlight exponents the powers are measured at: integer ones (the
/// built-in scenes', raised by `powi` in every build) and non-integer ones (the
/// only ones `fast-pow` changes).
const EXPONENTS: [f32; 12] = [
    1.5, 4.0, 8.0, 16.0, 32.0, 32.5, 48.0, 100.5, 200.0, 300.0, 1000.5, 10_000.0,
];

/// `f(x, y)` against `x^y` in `f64` over every f32 of `[1/2, 1]` and every 61st
/// of `[2^-40, 1/2)`, for every exponent of `ys`. Absolute error: the
/// highlight is at most 1 and 1/255 is one 8-bit step.
fn power(ys: &[f32], f: impl Fn(f32, f32) -> f32 + Sync) -> Worst {
    ys.iter()
        .map(|&y| {
            let g = |x: f32, w: &mut Worst| {
                let exact = f64::from(x).powf(f64::from(y));
                w.add(f64::from(x), f64::from(f(x, y)), exact);
            };
            over_bits(0x3f00_0000, 0x3f80_0001, 1, g).merge(over_bits(
                0x2b80_0000,
                0x3f00_0000,
                61,
                g,
            ))
        })
        .fold(Worst::default(), Worst::merge)
}

fn power_rows(rows: &mut Vec<Row>) {
    let integers: Vec<f32> = EXPONENTS
        .iter()
        .copied()
        .filter(|y| y.fract() == 0.0)
        .collect();
    let range = |ys: &[f32]| {
        let ys: Vec<String> = ys.iter().map(f32::to_string).collect();
        format!(
            "x: every f32 of [1/2, 1], every 61st of [2^-40, 1/2); y in {{{}}}",
            ys.join(", ")
        )
    };
    let power_row = |function, feature, ys: &[f32], worst, note: &str| Row {
        function,
        feature,
        range: range(ys),
        worst,
        error: Error::Highlight,
        note: note.into(),
    };
    rows.push(power_row(
        "libm `powf`",
        "exact",
        &EXPONENTS,
        power(&EXPONENTS, libm::powf),
        "within an ulp",
    ));
    rows.push(power_row(
        "`powi` (repeated squaring)",
        "every build, integer y",
        &integers,
        power(&integers, |x, y| math::powi(x, y as u32)),
        "relative error about 2 y 2^-24 (the largest at y = 10000)",
    ));
    rows.push(power_row(
        "`pow_unit` = exp2(y log2 x)",
        "`fast-pow`",
        &EXPONENTS,
        power(&EXPONENTS, math::pow_unit),
        "integer y too (measured, not used there: no cheaper than `powi`)",
    ));
    rows.push(power_row(
        "Schlick `x / (y - y x + x)`",
        "(dropped)",
        &EXPONENTS,
        power(&EXPONENTS, math::pow_schlick),
        "another curve (a wider lobe), not an approximation of x^y",
    ));
}

/// micromath's `atan2` and `acos` (candidates for the sphere texture coordinates,
/// not offered: `(dropped)`) against `f64`, as absolute errors in radians (the
/// texture coordinate is the angle over `2 pi` or `pi`; `atan2`'s modulo `2 pi`,
/// the texture's period).
fn trig_rows(rows: &mut Vec<Row>) {
    use micromath::F32Ext;
    let acos = over_bits(0, 0x3f80_0001, 1, |x, w| {
        for x in [x, -x] {
            let exact = f64::from(x).acos();
            w.add(f64::from(x), f64::from(F32Ext::acos(x)), exact);
        }
    });
    rows.push(Row {
        function: "micromath `acos`",
        feature: "(dropped)",
        range: "every f32 of [-1, 1]".into(),
        worst: acos,
        error: Error::Radians,
        note: "NaN for tiny negative x; libm's `acosf`: within an ulp".into(),
    });
    // atan2 on the unit circle's directions (the angle is all that matters): y
    // over every f32 of [-1, 1] with x = +-sqrt(1 - y^2).
    let atan2 = over_bits(0, 0x3f80_0001, 1, |y, w| {
        let x = (1.0 - f64::from(y) * f64::from(y)).sqrt() as f32;
        for (y, x) in [(y, x), (-y, x), (y, -x), (-y, -x)] {
            let exact = f64::from(y).atan2(f64::from(x));
            let turns = (f64::from(F32Ext::atan2(y, x)) - exact) / std::f64::consts::TAU;
            let off = (turns - turns.round()) * std::f64::consts::TAU;
            w.add(f64::from(y), exact + off, exact);
        }
    });
    rows.push(Row {
        function: "micromath `atan2`",
        feature: "(dropped)",
        range: "y: every f32 of [-1, 1], x = +-sqrt(1 - y^2)".into(),
        worst: atan2,
        error: Error::Radians,
        note: "modulo 2 pi; libm's `atan2f`: within an ulp".into(),
    });
}

/// An input, as the f32 it is (shortest form; in scientific notation far from 1).
fn at(x: f64) -> String {
    let x = x as f32;
    if x != 0.0 && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

fn table(rows: &[Row]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "| function | feature | input range (checked) | worst error | at x | ulps of the result | note |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|");
    for r in rows {
        let w = &r.worst;
        let (error, at, ulps) = match r.error {
            Error::Highlight => (
                format!("{} absolute ({:.4} LSB)", sci(w.abs), w.abs * 255.0),
                at(w.abs_at),
                "-".to_string(),
            ),
            Error::Radians => (
                format!("{} rad absolute", sci(w.abs)),
                at(w.abs_at),
                format!("{:.1}", w.ulp),
            ),
            Error::Relative => (
                format!("{} relative", sci(w.rel)),
                at(w.rel_at),
                format!("{:.1}", w.ulp),
            ),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} ({} inputs) | {} | {} | {} | {} |",
            r.function, r.feature, r.range, w.count, error, at, ulps, r.note
        );
    }
    md
}

fn main() {
    let start = Instant::now();
    let mut rows = Vec::new();
    rsqrt_rows(&mut rows);
    recip_rows(&mut rows);
    log_exp_rows(&mut rows);
    power_rows(&mut rows);
    trig_rows(&mut rows);
    println!("# The approximations of the core's math against f64\n");
    println!(
        "Generated by `{COMMAND}` in {:.0} s. Errors against the exact value in f64 of the \
         same f32 input; ulps are those of the exact result rounded to f32. The powers \
         (highlights, at most 1) by their absolute error, also in 8-bit steps (LSB = \
         1/255); the angles by their absolute error in radians.\n",
        start.elapsed().as_secs_f64()
    );
    print!("{}", table(&rows));
}
