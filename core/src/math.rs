//! The one math module: every square root, power and trigonometric call of the core,
//! and the approximations the cargo features trade accuracy for cycles with.
//!
//! Free functions, never method syntax: on the host `x.sqrt()` would silently resolve
//! to `std` and the host would no longer compute what the chip computes.
//!
//! The default math is **exact**: `libm`, except `sqrt` on a core whose FPU has a
//! square root: `vsqrt.f32` on every Arm hard-float core (Cortex-M4F, M7, M33, M55),
//! `fsqrt.s` on RISC-V with the F extension (`cfg(tessera_riscv_f)`, from
//! core/build.rs). All are correctly rounded (IEEE 754), so the host and the chip
//! give the same bits (the firmware test image checks each core: its hard cases
//! and its renders). Each approximation is a cargo feature of its own, measured on
//! its own (worst error over its input range: docs/math-report.md, from `cargo run -p
//! tessera-tests --release --bin math-report`; cycles and image error: the trade
//! report, docs/trade.md):
//! - `fast-rsqrt`: [`rsqrt`] by a bit-level first guess and two Newton steps (relative
//!   error below 2.6e-6) instead of `vsqrt.f32` and `vdiv.f32` (14 cycles each on the
//!   Cortex-M4F), for the shading vectors of the light loop only (the light's
//!   direction, distance and irradiance, the half vector): ray directions, which the
//!   intersection tests take as unit vectors, stay exact.
//! - `fast-recip`: a vector divided by a scalar (`Vec3 / s`) as one reciprocal and
//!   three products, instead of three divisions (within 1.5 ulp per component instead
//!   of 0.5).
//! - `fast-pow`: [`powf`] of the highlights (`x` in `(0, 1]`: a non-integer shininess;
//!   an integer one is raised by repeated squaring, [`powi`], in every build) by
//!   polynomial `log2` and `exp2` ([`pow_unit`]: absolute error below 3e-5) instead of
//!   libm's `powf`.
//!
//! `fast-math` is the three together (fewer cycles on the chip than the exact
//! build, for no visible error: docs/trade.md).
//! Approximations not offered (measured in docs/math-report.md, its `(dropped)`
//! rows): one Newton step for `rsqrt` (fewer cycles than exact, but a clearly larger
//! image error on the default scene); `rsqrt` for every normalisation (ray
//! directions and normals: the intersections' analytic tests fail); a reciprocal by
//! Newton steps (more cycles than `vdiv.f32`); Schlick's rational highlight (another
//! lobe, a larger image error); micromath's `powf`, `atan2` and `acos` (hardly fewer
//! instructions on the chip: no built-in scene calls them per pixel; its `powf` far
//! less accurate than [`pow_unit`] on the highlights, its `acos` NaN for tiny
//! negative arguments).
//!
//! `tan`, `atan2` and `acos` stay exact in every build: `tan` runs once a frame,
//! `atan2` and `acos` only for textured spheres (none of the built-in scenes has one).
//! Per-pixel paths use only `sqrt`, `powf`, `floor` and the polynomial
//! [`cos_turns`] (libm's `sinf`/`cosf` go through `f64`, which is software on an
//! M4F). The hardware root does not reach inside libm: libm's `powf` returns its
//! own software `sqrtf` for an exponent of exactly 0.5 (a shininess of 0.5), and
//! its `acosf` (textured spheres) calls that `sqrtf` too; every other root is
//! [`sqrt`]'s.
#![allow(clippy::disallowed_methods)] // the one home of libm calls (core/clippy.toml)

/// Square root of an `f64`, correctly rounded (libm; software on the Cortex-M4F,
/// which has no `f64` unit): for the rare hits computed in `f64`
/// (`geometry::wide`), never per pixel in an ordinary scene.
#[must_use]
pub fn sqrt64(x: f64) -> f64 {
    libm::sqrt(x)
}

/// Square root, correctly rounded with the exact backend.
#[inline]
#[must_use]
pub fn sqrt(x: f32) -> f32 {
    // Exact in every build: the intersection tests need exact roots, and the
    // approximation (`fast-rsqrt`) is [`rsqrt`], for the shading vectors only.
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        vsqrt(x)
    }
    #[cfg(tessera_riscv_f)]
    {
        fsqrt(x)
    }
    #[cfg(not(any(all(target_arch = "arm", target_abi = "eabihf"), tessera_riscv_f)))]
    {
        libm::sqrtf(x)
    }
}

/// `x` raised to the power `y`: libm's `powf` (within an ulp); with `fast-pow`,
/// [`pow_unit`] where `x` is in `(0, 1]` and `y` finite and not negative (the
/// highlights' domain), libm's `powf` elsewhere.
#[inline]
#[must_use]
pub fn powf(x: f32, y: f32) -> f32 {
    #[cfg(feature = "fast-pow")]
    if (f32::MIN_POSITIVE..=1.0).contains(&x) && (0.0..=f32::MAX).contains(&y) {
        return pow_unit(x, y);
    }
    libm::powf(x, y)
}

/// `x` raised to the integer power `n` by repeated squaring (right to left): at most
/// `2 log2(n) + 1` products, each correctly rounded, so the host and the chip give
/// the same bits. Each squaring doubles the relative error carried so far, so the
/// result is within about `2 n u` of `x^n` (`u = 2^-24`: 6e-6 for `n = 48`, 1.2e-3
/// for `n = 10000`), against about one ulp for `powf`. `powi(x, 0) = 1`.
#[inline]
#[must_use]
pub fn powi(x: f32, n: u32) -> f32 {
    let (mut result, mut base, mut n) = (1.0, x, n);
    while n != 0 {
        if n & 1 != 0 {
            result *= base;
        }
        n >>= 1;
        if n != 0 {
            base *= base;
        }
    }
    result
}

/// Tangent of `x` radians (used once a frame).
#[inline]
#[must_use]
pub fn tan(x: f32) -> f32 {
    // Exact in every backend: it runs once a frame (the camera's opening angle),
    // where an approximation saves nothing and would skew the whole field of view.
    libm::tanf(x)
}

/// Four-quadrant arc tangent of `y / x`, in radians.
#[inline]
#[must_use]
pub fn atan2(y: f32, x: f32) -> f32 {
    libm::atan2f(y, x)
}

/// Arc cosine in radians; the argument is clamped to `[-1, 1]` first, so rounding
/// just outside the domain never yields NaN.
#[inline]
#[must_use]
pub fn acos(x: f32) -> f32 {
    libm::acosf(x.clamp(-1.0, 1.0))
}

/// The larger of `a` and `b` by one comparison (if either is NaN, `b`). Not
/// `f32::max`: on the Cortex-M4F (no `vmaxnm`) that lowers to a call of the IEEE
/// `fmaxf` routine, far dearer than one comparison on the paths that run per
/// ray.
#[inline]
#[must_use]
pub fn max(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// The smaller of `a` and `b` by one comparison (if either is NaN, `b`); see [`max`].
#[inline]
#[must_use]
pub fn min(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// The sine of `x` radians (libm: the same bits on every target; an
/// animation's rotations, once a frame, not a pixel's work). Unused without
/// the feature `animation` (not gated by it: this file is also compiled alone,
/// by the tests' benchmarks, which know no such feature).
#[allow(dead_code)]
#[inline]
#[must_use]
pub fn sin(x: f32) -> f32 {
    libm::sinf(x)
}

/// Largest integer not greater than `x`.
#[inline]
#[must_use]
pub fn floor(x: f32) -> f32 {
    libm::floorf(x)
}

/// Absolute value (bit operation: exact, no branch, keeps NaN a NaN).
#[inline]
#[must_use]
pub fn abs(x: f32) -> f32 {
    // `f32::abs` is in `core` (a sign-bit clear, `vabs.f32` or `andps`): the same
    // bits as masking the integer, without the moves to and from integer registers.
    x.abs()
}

/// `x` with the sign of `s` (bit operation).
#[inline]
#[must_use]
pub fn copysign(x: f32, s: f32) -> f32 {
    f32::from_bits((x.to_bits() & 0x7fff_ffff) | (s.to_bits() & 0x8000_0000))
}

/// The next representable `f32` above `x` (pbrt's `NextFloatUp`); `+inf` and NaN
/// are returned unchanged, `-0.0` steps like `+0.0`.
#[must_use]
pub fn next_up(x: f32) -> f32 {
    if x.is_infinite() && x > 0.0 || x.is_nan() {
        return x;
    }
    let x = if x == 0.0 { 0.0 } else { x };
    let bits = x.to_bits();
    let bits = if x >= 0.0 { bits + 1 } else { bits - 1 };
    f32::from_bits(bits)
}

/// The next representable `f32` below `x` (pbrt's `NextFloatDown`).
#[must_use]
pub fn next_down(x: f32) -> f32 {
    -next_up(-x)
}

/// pbrt's `gamma(n) = n u / (1 - n u)` with `u = 2^-24`: the relative bound on the
/// rounding error of `n` successive f32 operations.
#[inline]
#[must_use]
pub const fn gamma(n: u32) -> f32 {
    let nu = n as f32 * (f32::EPSILON * 0.5);
    nu / (1.0 - nu)
}

/// `cos(2 pi x)` in plain f32 arithmetic (no libm, no f64): argument reduction to a
/// quarter turn, then the even Taylor polynomial to degree 12 (truncation error below
/// 1e-8 on `[0, pi/2]`). Absolute error about 2e-7 for any finite `x`; used per pixel
/// by the interference texture, so it must not go through `f64`.
#[must_use]
pub fn cos_turns(x: f32) -> f32 {
    // Exact: x - n has no rounding error for any f32 x and integer n nearest to x.
    // Below 2^22 in magnitude, adding and subtracting 1.5 * 2^23 rounds x to the
    // nearest integer (ties to even: the sum lies in [2^23, 2^24), whose spacing is
    // 1) in two instructions; beyond, x is a multiple of 1/2 and `roundf` does it
    // (the two may differ on a tie, where |x - n| = 1/2 either way). From 2^23 on
    // every f32 is an integer, whose cosine is 1: an infinity too (the limit along
    // the f32 integers), so that a fringe texture far away stays finite. A NaN
    // takes the second path and gives NaN.
    const ROUND: f32 = 12_582_912.0; // 1.5 * 2^23
    let n = if abs(x) < 4_194_304.0 {
        (x + ROUND) - ROUND
    } else if abs(x) >= 8_388_608.0 {
        return 1.0;
    } else {
        libm::roundf(x)
    };
    let r = abs(x - n); // in [0, 0.5]
    let (z, sign) = if r > 0.25 { (0.5 - r, -1.0) } else { (r, 1.0) };
    let t = z * core::f32::consts::TAU; // [0, pi/2]
    let t2 = t * t;
    // cos t = 1 - t^2/2! + t^4/4! - ... + t^12/12!, Horner form.
    let p = 1.0
        + t2 * (-1.0 / 2.0
            + t2 * (1.0 / 24.0
                + t2 * (-1.0 / 720.0
                    + t2 * (1.0 / 40_320.0
                        + t2 * (-1.0 / 3_628_800.0 + t2 * (1.0 / 479_001_600.0))))));
    sign * p
}

/// `sin(2 pi x)`, from [`cos_turns`] of the quarter-turn complement; 0 for an
/// infinity (the limit along the f32 integers, as for [`cos_turns`]), NaN for NaN.
#[must_use]
pub fn sin_turns(x: f32) -> f32 {
    if x.is_infinite() {
        return 0.0;
    }
    if x.is_nan() {
        return x;
    }
    let r = x - libm::roundf(x); // exact, in [-0.5, 0.5]
    cos_turns(0.25 - r)
}

/// The reciprocal square root `1 / sqrt(x)`. With `fast-rsqrt`, [`rsqrt_fast`] for a
/// positive normal `x` (relative error below 2.6e-6); otherwise, and for zero,
/// subnormals, infinities, negative numbers and NaN in every build, `1 / sqrt(x)`
/// (`inf` for 0, 0 for `inf`, NaN below 0).
#[inline]
#[must_use]
#[cfg_attr(not(feature = "fast-rsqrt"), allow(dead_code))]
pub fn rsqrt(x: f32) -> f32 {
    if cfg!(feature = "fast-rsqrt") && is_positive_normal(x) {
        rsqrt_fast(x)
    } else {
        1.0 / sqrt(x)
    }
}

/// True for a positive, normal, finite `x` (one integer comparison).
#[inline]
#[must_use]
#[cfg_attr(not(feature = "fast-rsqrt"), allow(dead_code))]
pub fn is_positive_normal(x: f32) -> bool {
    // Positive normals are the bit patterns 0x0080_0000..0x7f80_0000; the
    // subtraction wraps everything else (zero, subnormals, the negative numbers)
    // above, with the infinities and NaN.
    x.to_bits().wrapping_sub(0x0080_0000) < 0x7f00_0000
}

/// The first guess of [`rsqrt_fast`] (Lomont's constant: halving the bits halves
/// the exponent, the subtraction negates it; relative error within 3.5%).
const RSQRT_MAGIC: u32 = 0x5f37_5a86;

/// The bit-level first guess of `1 / sqrt(x)` for a positive normal `x`: relative
/// error within 3.44% (exhaustive, `math-report`).
#[inline]
#[must_use]
#[cfg_attr(not(feature = "fast-rsqrt"), allow(dead_code))]
pub fn rsqrt_guess(x: f32) -> f32 {
    f32::from_bits(RSQRT_MAGIC - (x.to_bits() >> 1))
}

/// One Newton step for `1 / sqrt(x)` from `y`, with `half = x / 2`:
/// `y (3/2 - half y^2)`. A relative error `e` becomes about `-3 e^2 / 2` (always
/// below: 3.4% gives 1.75e-3, which gives 4.7e-6).
#[inline]
#[must_use]
#[cfg_attr(not(feature = "fast-rsqrt"), allow(dead_code))]
pub fn rsqrt_step(half: f32, y: f32) -> f32 {
    y * (1.5 - half * y * y)
}

/// The last Newton step of [`rsqrt_fast`] scaled by `1 + 2.36e-6`, which centres its
/// one-sided error (-4.73e-6 to 0 becomes -2.4e-6 to +2.4e-6): the same
/// instructions as [`rsqrt_step`] with other constants.
const RSQRT_CENTRED: (f32, f32) = (1.500_003_5, 1.000_002_4);

/// `1 / sqrt(x)` for a positive normal `x` (else meaningless: see [`rsqrt`]) without
/// `vsqrt` or `vdiv`: the bit-level guess [`rsqrt_guess`], one Newton step, and a
/// second one scaled to centre the error. Relative error below 2.6e-6, about 44
/// ulp (exhaustive over `[1, 4)`, where the error pattern repeats: `math-report`).
/// On the Cortex-M4F about 13 single-cycle instructions against 28 cycles for
/// `vsqrt.f32` and `vdiv.f32`.
#[inline]
#[must_use]
#[cfg_attr(not(feature = "fast-rsqrt"), allow(dead_code))]
pub fn rsqrt_fast(x: f32) -> f32 {
    let half = 0.5 * x;
    let y = rsqrt_step(half, rsqrt_guess(x));
    let (a, b) = RSQRT_CENTRED;
    y * (a - b * (half * y * y))
}

/// The reciprocal `1 / x` by a bit-level first guess and `steps` Newton steps
/// `r (2 - x r)` (each squares the relative error: 5.05%, then 2.55e-3, 6.65e-6,
/// 1.5e-7), for a positive normal `x`. Not used by any build: on the Cortex-M4F
/// three steps (nine single-cycle instructions and the guess) cost as much as the
/// `vdiv.f32` they replace (14 cycles), so `fast-recip` divides once and
/// multiplies instead. Kept for `math-report`, which measures it.
#[must_use]
#[allow(dead_code)]
pub fn recip_newton(x: f32, steps: u32) -> f32 {
    let mut r = f32::from_bits(0x7ef3_11c3_u32.wrapping_sub(x.to_bits()));
    for _ in 0..steps {
        r *= 2.0 - x * r;
    }
    r
}

/// `log2(x)` for a positive normal `x`, in plain f32 arithmetic: `x = 2^e m` with
/// `m` in `[sqrt(1/2), sqrt(2))` from the bits, then `e + u q(u)`, `u = m - 1`
/// (exact), `q` a degree-4 polynomial (Chebyshev interpolation of `log2(1 + u) / u`,
/// relative error 5.6e-5). The error is relative to `log2(x)` (below 5.7e-5), so
/// that `log2` of numbers close to 1 keeps its digits.
#[inline]
#[must_use]
#[cfg_attr(not(feature = "fast-pow"), allow(dead_code))]
pub fn log2_unit(x: f32) -> f32 {
    const SQRT_HALF: u32 = 0x3f35_04f3; // the bits of sqrt(1/2), rounded
    let bits = x.to_bits();
    // The exponent of x / sqrt(1/2), rounded down: an arithmetic shift of the
    // offset bits (x / 2^e is then in [sqrt(1/2), sqrt(2))).
    let e = (bits.wrapping_sub(SQRT_HALF) as i32) >> 23;
    let m = f32::from_bits(bits.wrapping_sub((e as u32) << 23));
    let u = m - 1.0;
    let q = 1.442_640_5
        + u * (-0.720_629_2 + u * (0.485_737_84 + u * (-0.389_675_22 + u * 0.250_287_85)));
    e as f32 + u * q
}

/// `2^z` for `z` in `[-125, 0]` (0 below; meant for the highlights, where `z` is
/// never positive): `z = n + f` with `n` the nearest integer, `2^f` by a degree-4
/// polynomial on `[-1/2, 1/2]` (Chebyshev interpolation, relative error 3.5e-6),
/// `2^n` added to the exponent bits.
#[inline]
#[must_use]
#[cfg_attr(not(feature = "fast-pow"), allow(dead_code))]
pub fn exp2_unit(z: f32) -> f32 {
    // A NaN (never passed) gives 0 too.
    if z.is_nan() || z < -125.0 {
        return 0.0;
    }
    // Below 2^22 in magnitude, adding and subtracting 1.5 * 2^23 rounds to the
    // nearest integer (see `cos_turns`); z - n is exact, in [-1/2, 1/2].
    const ROUND: f32 = 12_582_912.0;
    let n = (z + ROUND) - ROUND;
    let f = z - n;
    let p = 1.0 + f * (0.693_121_1 + f * (0.240_223_5 + f * (0.055_921_975 + f * 0.009_666_368)));
    // p is in [0.70, 1.42] (exponent field 126 or 127) and n >= -125: the sum of the
    // fields is a normal number's, never a carry into the sign.
    f32::from_bits(p.to_bits().wrapping_add(((n as i32) << 23) as u32))
}

/// `x^y` for `x` in `(0, 1]` (positive normal) and a finite `y >= 0`, as
/// `exp2(y log2(x))` with [`log2_unit`] and [`exp2_unit`]: about 40 single-cycle
/// instructions on the Cortex-M4F, where libm's `powf` runs a few hundred.
/// Absolute error below 3e-5 (0.008 of an 8-bit step; the relative error of the
/// logarithm, times `|y log2 x|`, is largest where `x^y = 1/e`), measured over
/// the highlights' domain by `math-report` and the unit test.
#[inline]
#[must_use]
#[cfg_attr(not(feature = "fast-pow"), allow(dead_code))]
pub fn pow_unit(x: f32, y: f32) -> f32 {
    exp2_unit(y * log2_unit(x))
}

/// Schlick's rational stand-in for `x^n` (1994), `x / (n - n x + x)`: one
/// division, but another curve (a wider lobe, off by up to 0.19 at `n = 48`).
/// Not used by any build (the measurements in `math-report` say why).
#[must_use]
#[allow(dead_code)]
pub fn pow_schlick(x: f32, n: f32) -> f32 {
    x / (n - n * x + x)
}

/// One of the two audited `unsafe` spots of the core: the Arm FPU square root
/// (the other is [`fsqrt`], RISC-V's).
///
/// Why asm: `libm::sqrtf` is a software loop (hundreds of cycles); the FPU does it
/// in 14 cycles on a Cortex-M4F. `core` has no stable `f32::sqrt`, and on stable
/// Rust 1.95 the `sreg` register class (operands in FPU registers) is refused for
/// `thumbv7em-none-eabihf` and `thumbv8m.main-none-eabihf` (rustc only knows their
/// FPUs as LLVM features it does not expose), so the value moves through a core
/// register and `s0` is named as clobbered, which rustc accepts: the compiler keeps
/// nothing live in `s0` across the block (checked in the disassembly: a value held
/// in `s0` is moved out first) and no push or pop is needed.
///
/// Soundness: the block reads one core register and writes another and `s0`, which
/// is declared clobbered; it touches no memory and no stack (`nomem`, `nostack`).
/// Every ARM hard-float (`eabihf`) target has a VFP unit with `vsqrt.f32` (the
/// Cortex-M4F's FPv4, the M7's, M33's and M55's FPv5). IEEE 754 requires sqrt to
/// be correctly rounded, so it returns the same bits as `libm::sqrtf` on the host
/// (checked on each core by the firmware test image: `tessera-sqrt` and the
/// renders against the host's).
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
#[inline]
fn vsqrt(x: f32) -> f32 {
    let r: u32;
    // SAFETY: see the function documentation.
    unsafe {
        core::arch::asm!(
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {r}, s0",
            x = in(reg) x.to_bits(),
            r = lateout(reg) r,
            out("s0") _,
            // Not `preserves_flags`: vsqrt may set the FPSCR exception flags.
            options(pure, nomem, nostack)
        );
    }
    f32::from_bits(r)
}

/// The other audited `unsafe` spot of the core: the RISC-V F extension's square
/// root, `fsqrt.s` (see [`vsqrt`] for why asm).
///
/// Here the operands can live in FPU registers: rustc accepts the `freg` class on
/// `riscv32imafc-unknown-none-elf`, whose ABI (`ilp32f`) passes `f32`s in them, so
/// the block is the one instruction.
///
/// Soundness: the block reads one FPU register and writes another; it touches no
/// memory and no stack (`nomem`, `nostack`). `cfg(tessera_riscv_f)` is set only for
/// targets with F (core/build.rs), so the instruction exists. It rounds by the
/// dynamic rounding mode, `frm`, which is round-to-nearest-even from reset and
/// which nothing in the crate changes (every other float instruction the compiler
/// emits rounds by it too); the result is then the correctly rounded root, the
/// same bits as `libm::sqrtf` on the host (checked under qemu by the firmware test
/// image).
#[cfg(tessera_riscv_f)]
#[allow(unsafe_code)]
#[inline]
fn fsqrt(x: f32) -> f32 {
    let r: f32;
    // SAFETY: see the function documentation.
    unsafe {
        core::arch::asm!(
            "fsqrt.s {r}, {x}",
            x = in(freg) x,
            r = lateout(freg) r,
            // Not `preserves_flags`: fsqrt.s may set the `fflags` exception flags.
            options(pure, nomem, nostack)
        );
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cos_turns_matches_f64_cos() {
        let mut worst = 0.0f64;
        for i in -20_000..=20_000 {
            let x = i as f32 * 0.000_173_1 + 0.013;
            let exact = (core::f64::consts::TAU * x as f64).cos();
            worst = worst.max((cos_turns(x) as f64 - exact).abs());
        }
        assert!(worst < 4e-7, "worst error {worst}");
        assert_eq!(cos_turns(0.0), 1.0);
        assert!((cos_turns(0.5) + 1.0).abs() < 1e-7);
        assert!(cos_turns(f32::NAN).is_nan());
    }

    #[test]
    fn cos_turns_reduces_exactly_on_both_sides_of_2_pow_22() {
        // The fast rounding (below 2^22) and `roundf` (beyond) both leave the exact
        // fraction: cos of x equals cos of x - round(x), computed in f64.
        let check = |x: f32| {
            for x in [x, -x] {
                let frac = (x as f64 - libm::round(x as f64)).abs();
                let exact = libm::cos(core::f64::consts::TAU * frac);
                assert!((cos_turns(x) as f64 - exact).abs() < 4e-7, "x = {x}");
            }
        };
        for x in [f32::MIN_POSITIVE, 0.25, 0.5, 0.75, 1.5, 2.5] {
            check(x);
        }
        for e in 18..=26 {
            let p = (1u32 << e) as f32;
            for d in [-1.0f32, -0.5, -0.25, 0.0, 0.25, 0.5, 1.0, 1.5] {
                check(p + d);
                check(next_down(p) + d);
            }
        }
        // Every f32 from 2^23 on is an integer: cosine 1, and 1 at the infinities
        // too (a fringe texture far away must not give NaN); NaN stays NaN.
        for x in [8_388_608.0f32, 8_388_609.0, 1e30, f32::MAX, f32::INFINITY] {
            assert_eq!(cos_turns(x), 1.0, "x = {x}");
            assert_eq!(cos_turns(-x), 1.0, "x = {x}");
        }
        assert!(cos_turns(f32::NAN).is_nan());
        assert_eq!(sin_turns(f32::INFINITY), 0.0);
        assert_eq!(sin_turns(f32::NEG_INFINITY), 0.0);
        assert_eq!(sin_turns(f32::MAX), 0.0);
        assert!(sin_turns(f32::NAN).is_nan());
    }

    #[test]
    fn sin_turns_matches_f64_sin() {
        for i in -2_000..=2_000 {
            let x = i as f32 * 0.001_37;
            let exact = (core::f64::consts::TAU * x as f64).sin();
            assert!((sin_turns(x) as f64 - exact).abs() < 4e-7, "x = {x}");
        }
    }

    #[test]
    fn powi_matches_f64_powers() {
        for n in [
            0u32, 1, 2, 3, 7, 8, 16, 32, 48, 200, 300, 1000, 9999, 10_000,
        ] {
            // The bound of the doc: 2 n u (and a few u for the smallest n).
            let bound = f64::from(2 * n + 2) * f64::from(f32::EPSILON) * 0.5;
            for i in 1..=200 {
                let x = 1.0 - i as f32 * 0.000_037;
                let exact = f64::from(x).powi(n as i32);
                let got = f64::from(powi(x, n));
                if exact > 1e-30 {
                    let rel = (got - exact).abs() / exact;
                    assert!(rel <= bound, "x = {x}, n = {n}: {rel} > {bound}");
                }
            }
        }
        assert_eq!(powi(0.5, 3), 0.125);
        assert_eq!(powi(2.0, 10), 1024.0);
        assert_eq!(powi(0.7, 0), 1.0);
    }

    /// `powf` over the highlights' domain (`x` in `(0, 1]`, non-integer exponents:
    /// integer ones go through [`powi`]) against `f64`, as an absolute error (the
    /// highlight is at most 1, so 1/255 is one 8-bit step). Exact: libm's `powf` is
    /// within an ulp (measured 4.7e-8). `fast-pow` ([`pow_unit`]): see
    /// [`pow_unit_is_within_its_bound`].
    #[test]
    fn powf_is_within_the_builds_bound_on_highlights() {
        let bound = if cfg!(feature = "fast-pow") {
            POW_UNIT_BOUND
        } else {
            1.2e-7
        };
        let mut worst = (0.0f64, 0.0f32, 0.0f32);
        for y in [1.5f32, 2.5, 8.5, 16.5, 32.5, 64.5, 100.5] {
            for i in 1..=20_000 {
                let x = i as f32 / 20_000.0;
                // The whole interval, and the last percent below 1 (the highlight's
                // peak) more finely.
                for x in [x, 1.0 - x * 0.01] {
                    let exact = f64::from(x).powf(f64::from(y));
                    let err = (f64::from(powf(x, y)) - exact).abs();
                    if err > worst.0 {
                        worst = (err, x, y);
                    }
                }
            }
        }
        let (err, x, y) = worst;
        assert!(err <= bound, "powf({x}, {y}) off by {err:e} > {bound:e}");
        assert_eq!(powf(1.0, 32.5), 1.0);
        assert_eq!(powf(0.0, 32.5), 0.0);
        // Outside the highlights' domain, libm's `powf` in every build.
        assert_eq!(powf(2.0, 3.5), libm::powf(2.0, 3.5));
        assert_eq!(powf(0.5, -1.5), libm::powf(0.5, -1.5));
    }

    /// [`pow_unit`]'s bound, from its analysis: the logarithm's relative error
    /// `d_q` (5.7e-5) moves `y log2 x` by `|log2 v|` times it, so `v = x^y` by
    /// `v |ln v| d_q <= d_q / e` (2.1e-5), plus the exponential's relative error
    /// (3.5e-6) and the f32 roundings (a few 1e-7): 2.5e-5, rounded up.
    const POW_UNIT_BOUND: f64 = 3e-5;

    /// [`pow_unit`] against `f64` over `x` in `(0, 1]` (every 97th f32 down to
    /// 2^-20, and a fine grid below 1) and exponents from 1 to 10000 (the
    /// shininess range), integer ones included.
    #[test]
    fn pow_unit_is_within_its_bound() {
        let mut worst = (0.0f64, 0.0f32, 0.0f32);
        let xs = (0x3580_0000u32..=0x3f80_0000)
            .step_by(97)
            .map(f32::from_bits)
            .chain((0..20_000).map(|i| 1.0 - i as f32 * 1e-6));
        let ys = [
            1.0f32, 1.5, 4.0, 7.25, 32.5, 48.0, 100.5, 300.0, 1000.5, 10_000.0,
        ];
        for x in xs {
            for y in ys {
                let exact = f64::from(x).powf(f64::from(y));
                let err = (f64::from(pow_unit(x, y)) - exact).abs();
                if err > worst.0 {
                    worst = (err, x, y);
                }
            }
        }
        let (err, x, y) = worst;
        assert!(
            err <= POW_UNIT_BOUND,
            "pow_unit({x}, {y}) off by {err:e} > {POW_UNIT_BOUND:e}"
        );
        assert_eq!(pow_unit(1.0, 300.0), 1.0);
        assert_eq!(pow_unit(0.5, 0.0), 1.0);
        // Far below 2^-125: 0, never a wrapped exponent.
        assert_eq!(pow_unit(0.5, 200.0), 0.0);
        assert_eq!(pow_unit(f32::MIN_POSITIVE, 2.0), 0.0);
    }

    /// [`log2_unit`] relative to `log2` in `f64` over every 31st positive normal
    /// f32 (the polynomial's 5.6e-5 and a few roundings); exact at powers of two.
    #[test]
    fn log2_unit_is_within_its_relative_bound() {
        let mut worst = 0.0f64;
        for bits in (0x0080_0000u32..0x7f80_0000).step_by(31) {
            let x = f32::from_bits(bits);
            let exact = f64::from(x).log2();
            if exact != 0.0 {
                let rel = ((f64::from(log2_unit(x)) - exact) / exact).abs();
                worst = worst.max(rel);
            }
        }
        assert!(worst <= 5.7e-5, "log2_unit off by {worst:e} (relative)");
        for e in -126..=127 {
            assert_eq!(log2_unit(libm::ldexpf(1.0, e)), e as f32);
        }
    }

    /// [`exp2_unit`] relative to `exp2` in `f64` on `[-125, 0]` (the polynomial's
    /// 3.5e-6 and a few roundings), 0 below.
    #[test]
    fn exp2_unit_is_within_its_relative_bound() {
        let mut worst = 0.0f64;
        for i in 0..=1_250_000 {
            let z = -(i as f32) * 1e-4;
            let exact = f64::from(z).exp2();
            worst = worst.max((f64::from(exp2_unit(z)) / exact - 1.0).abs());
        }
        assert!(worst <= 3.8e-6, "exp2_unit off by {worst:e} (relative)");
        assert_eq!(exp2_unit(0.0), 1.0);
        assert_eq!(exp2_unit(-125.5), 0.0);
        assert_eq!(exp2_unit(f32::NEG_INFINITY), 0.0);
        assert_eq!(exp2_unit(f32::NAN), 0.0);
    }

    /// [`rsqrt_fast`] relative to `1 / sqrt` in `f64` over every f32 of `[1, 4)`
    /// (the error depends only on the mantissa and the exponent's parity, so this
    /// is every positive normal f32), checked again on a sample of every binade.
    /// The bound: the guess's 3.44% after two steps, `3/2 (3/2 e^2)^2` = 4.7e-6,
    /// centred (2.4e-6), plus the roundings of the last step (a few 1e-7).
    #[test]
    fn rsqrt_fast_is_within_its_relative_bound() {
        const BOUND: f64 = 2.6e-6;
        let rel = |x: f32| f64::from(rsqrt_fast(x)) * f64::from(x).sqrt() - 1.0;
        let mut worst = 0.0f64;
        for bits in 0x3f80_0000u32..0x4080_0000 {
            worst = worst.max(rel(f32::from_bits(bits)).abs());
        }
        assert!(worst <= BOUND, "rsqrt_fast off by {worst:e} (relative)");
        for bits in (0x0080_0000u32..0x7f80_0000).step_by(4099) {
            let x = f32::from_bits(bits);
            assert!(rel(x).abs() <= BOUND, "rsqrt_fast({x:e})");
        }
        // The plain steps, as documented: 3.44%, 1.75e-3, 4.74e-6, all below.
        let step = |x: f32, n: u32| (0..n).fold(rsqrt_guess(x), |y, _| rsqrt_step(0.5 * x, y));
        for (n, bound) in [(0, 3.44e-2), (1, 1.76e-3), (2, 4.75e-6)] {
            for bits in (0x3f80_0000u32..0x4080_0000).step_by(101) {
                let x = f32::from_bits(bits);
                let e = f64::from(step(x, n)) * f64::from(x).sqrt() - 1.0;
                assert!(e.abs() <= bound, "{n} steps at {x}: {e:e}");
            }
        }
    }

    /// [`rsqrt`]: outside the positive normals, `1 / sqrt(x)` in every build.
    #[test]
    fn rsqrt_falls_back_to_the_exact_root() {
        assert!(is_positive_normal(f32::MIN_POSITIVE) && is_positive_normal(f32::MAX));
        for x in [
            0.0,
            -0.0,
            1e-40,
            -1.0,
            f32::INFINITY,
            f32::NAN,
            -f32::MIN_POSITIVE,
        ] {
            assert!(!is_positive_normal(x), "{x}");
            let (got, want) = (rsqrt(x), 1.0 / sqrt(x));
            assert!(got == want || got.is_nan() && want.is_nan(), "{x}");
        }
        let bound = if cfg!(feature = "fast-rsqrt") {
            2.6e-6
        } else {
            1.2e-7
        };
        for x in [1e-30f32, 0.25, 2.0, 3.0, 7e20] {
            let e = f64::from(rsqrt(x)) * f64::from(x).sqrt() - 1.0;
            assert!(e.abs() <= bound, "{x}: {e:e}");
        }
    }

    /// [`recip_newton`]: each step squares the relative error (5.05% for the
    /// guess), down to the roundings at three steps.
    #[test]
    fn recip_newton_squares_its_error() {
        for (steps, bound) in [(0, 5.06e-2), (1, 2.56e-3), (2, 6.7e-6), (3, 1.5e-7)] {
            for bits in (0x3f80_0000u32..0x4000_0000).step_by(37) {
                let x = f32::from_bits(bits);
                let e = f64::from(recip_newton(x, steps)) * f64::from(x) - 1.0;
                assert!(e.abs() <= bound, "{steps} steps at {x}: {e:e}");
            }
        }
    }

    /// Schlick's form is another curve, not an approximation of `x^n`: equal at 0
    /// and 1, off by 0.19 at `n = 48` (what `math-report` measures).
    #[test]
    fn schlick_differs_from_the_power() {
        assert_eq!(pow_schlick(1.0, 48.0), 1.0);
        assert_eq!(pow_schlick(0.0, 48.0), 0.0);
        let worst = (1..1000)
            .map(|i| {
                let x = 1.0 - i as f32 * 1e-4;
                (f64::from(pow_schlick(x, 48.0)) - f64::from(x).powi(48)).abs()
            })
            .fold(0.0, f64::max);
        assert!((0.15..0.25).contains(&worst), "{worst}");
    }

    #[test]
    fn next_up_and_down_step_one_ulp() {
        assert_eq!(next_up(1.0), 1.0 + f32::EPSILON);
        assert_eq!(next_down(1.0), 1.0 - f32::EPSILON / 2.0);
        assert_eq!(next_up(0.0), f32::from_bits(1));
        assert_eq!(next_up(-0.0), f32::from_bits(1));
        assert_eq!(next_down(0.0), -f32::from_bits(1));
        assert_eq!(next_up(-1.0), -1.0 + f32::EPSILON / 2.0);
        assert_eq!(next_up(f32::INFINITY), f32::INFINITY);
        assert_eq!(next_up(f32::MAX), f32::INFINITY);
    }

    #[test]
    fn abs_and_copysign_are_bit_exact() {
        assert_eq!(abs(-0.0).to_bits(), 0);
        assert_eq!(abs(-3.5), 3.5);
        assert_eq!(copysign(2.0, -0.0), -2.0);
        assert!(abs(f32::NAN).is_nan());
    }

    #[test]
    fn sqrt_is_correctly_rounded() {
        // sqrt(2) rounded to nearest f32 and a perfect square.
        assert_eq!(sqrt(2.0), core::f32::consts::SQRT_2);
        assert_eq!(sqrt(6.25), 2.5);
    }

    /// `acos` clamps its argument: just outside `[-1, 1]` is the end's angle, never
    /// NaN.
    #[test]
    fn acos_clamps_to_its_domain() {
        assert_eq!(acos(1.000_001), 0.0);
        assert_eq!(acos(-1.000_001), acos(-1.0));
    }
}
