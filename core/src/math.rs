//! The one math module: every square root, power and trigonometric call of the core.
//!
//! Free functions, never method syntax: on the host `x.sqrt()` would silently resolve
//! to `std` and the host would no longer compute what the chip computes.
//!
//! Backends:
//! - default (**exact**): `libm`, except `sqrt` on Cortex-M4F, which uses the FPU's
//!   `vsqrt.f32`. Both are correctly rounded (IEEE 754), so the host and the chip give
//!   the same bits.
//! - feature `fast-math`: `micromath` approximations of the per-pixel `powf`
//!   (specular highlights of a non-integer shininess: an integer one is raised by
//!   repeated squaring, [`powi`], with either backend), `atan2` and `acos` (sphere
//!   texture coordinates): a trade to be measured, fewer instructions for a larger
//!   error. `sqrt` stays exact:
//!   micromath's is a single bit trick with 5% error, which breaks ray directions and
//!   intersections rather than trading accuracy for speed; `tan` stays exact because
//!   it runs once a frame.
//!
//! Per-pixel paths use only `sqrt`, `powf`, `floor` and the polynomial
//! [`cos_turns`]; `tan`, `atan2` and `acos` run once a frame or only for textured
//! spheres (libm's `sinf`/`cosf` go through `f64`, which is software on an M4F).
#![allow(clippy::disallowed_methods)] // the one home of libm calls (core/clippy.toml)

/// Square root, correctly rounded with the exact backend.
#[inline]
#[must_use]
pub fn sqrt(x: f32) -> f32 {
    // Exact in every backend: micromath's square root is one bit trick with about
    // 5% error, which breaks every normalisation and the intersection tests
    // themselves (measured with `fast-math`: PSNR 21.6 dB, differences up to 244 LSB
    // on the default scene), while the Cortex-M4F's `vsqrt.f32` is exact and cheap.
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        vsqrt(x)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    {
        libm::sqrtf(x)
    }
}

/// `x` raised to the power `y`.
#[inline]
#[must_use]
pub fn powf(x: f32, y: f32) -> f32 {
    backend::powf(x, y)
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
    backend::atan2(y, x)
}

/// Arc cosine in radians; the argument is clamped to `[-1, 1]` first, so rounding
/// just outside the domain never yields NaN.
#[inline]
#[must_use]
pub fn acos(x: f32) -> f32 {
    backend::acos(x.clamp(-1.0, 1.0))
}

/// The larger of `a` and `b` by one comparison (if either is NaN, `b`). Not
/// `f32::max`: on the Cortex-M4F (no `vmaxnm`) that lowers to a call of the IEEE
/// `fmaxf` routine (measured: 1,374 -> 1,228 instructions per pixel on
/// chapter-direct when the sphere test stopped using it).
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

#[cfg(not(feature = "fast-math"))]
mod backend {
    #[inline]
    pub fn powf(x: f32, y: f32) -> f32 {
        libm::powf(x, y)
    }
    #[inline]
    pub fn atan2(y: f32, x: f32) -> f32 {
        libm::atan2f(y, x)
    }
    #[inline]
    pub fn acos(x: f32) -> f32 {
        libm::acosf(x)
    }
}

#[cfg(feature = "fast-math")]
mod backend {
    use micromath::F32Ext;
    /// `exp(y ln x)` with micromath's `exp` and `ln`, but with an exact reciprocal:
    /// below 1, micromath's `ln` takes the logarithm of its bit-trick reciprocal
    /// (`0x7f00_0000 - bits`), which maps `1 - e` to about `1 + 2e`, so `ln x` came
    /// out twice too large near 1 and `powf(x, y)` was about `x^(2y)`: a highlight of
    /// shininess 32.5 off by up to 61 LSB (issue 10). With `ln(1 / x)` the error is
    /// that of micromath's polynomials (about 6e-5 in `ln`, times `y`): measured at
    /// most 0.31 LSB for `y = 1.5`, 0.50 for 32.5, 1.55 for 100.5 (15 at 1000.5).
    /// Below the smallest normal `1 / x` would overflow: micromath's own path (which
    /// gives 0 there for `y >= 1`).
    #[inline]
    pub fn powf(x: f32, y: f32) -> f32 {
        if (f32::MIN_POSITIVE..1.0).contains(&x) {
            F32Ext::exp(-(y * F32Ext::ln(1.0 / x)))
        } else {
            F32Ext::powf(x, y)
        }
    }
    #[inline]
    pub fn atan2(y: f32, x: f32) -> f32 {
        F32Ext::atan2(y, x)
    }
    #[inline]
    pub fn acos(x: f32) -> f32 {
        F32Ext::acos(x)
    }
}

/// The single audited `unsafe` spot of the core: the Cortex-M4F FPU square root.
///
/// Why asm: `libm::sqrtf` is a software loop (hundreds of cycles); the FPU does it
/// in 14 cycles. `core` has no stable `f32::sqrt`, and on stable Rust 1.95 the
/// `sreg` register class (operands in FPU registers) is refused for
/// `thumbv7em-none-eabihf` (rustc only knows the FPU there as LLVM's `vfp2sp`, which
/// it does not expose), so the value moves through a core register and `s0` is
/// named as clobbered, which rustc accepts: the compiler keeps nothing live in `s0`
/// across the block (checked in the disassembly: a value held in `s0` is moved out
/// first) and no push or pop is needed.
///
/// Soundness: the block reads one core register and writes another and `s0`, which
/// is declared clobbered; it touches no memory and no stack (`nomem`, `nostack`).
/// Every ARM hard-float (`eabihf`) target has a VFP unit with `vsqrt.f32`. IEEE 754
/// requires sqrt to be correctly rounded, so it returns the same bits as
/// `libm::sqrtf` on the host (checked by the firmware test against the host).
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
    /// highlight is at most 1, so 1/255 is one 8-bit step). Exact backend: libm's
    /// `powf` is within an ulp (measured 4.7e-8). fast-math: measured 6.08e-3 (1.55
    /// LSB, at exponent 100.5; 1.97e-3 at 32.5); before the exact reciprocal in the
    /// backend it was 0.247 (63 LSB): micromath's `ln` below 1 doubled the logarithm.
    #[test]
    fn powf_is_within_the_backends_bound_on_highlights() {
        let bound = if cfg!(feature = "fast-math") {
            6.5e-3
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
    #[cfg(not(feature = "fast-math"))]
    fn sqrt_is_correctly_rounded() {
        // sqrt(2) rounded to nearest f32 and a perfect square.
        assert_eq!(sqrt(2.0), core::f32::consts::SQRT_2);
        assert_eq!(sqrt(6.25), 2.5);
        assert_eq!(acos(1.000_001), 0.0);
    }
}
