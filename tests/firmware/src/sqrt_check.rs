//! The check that the core's square root (`tessera_core::testing::sqrt`, the per-pixel
//! `math::sqrt`) is correctly rounded: the inputs and an exact test of a result.
//! One source for both sides: the firmware `tessera-sqrt` (`src/sqrt.rs`) runs it
//! on each core, and the host-side harness (`tessera_tests::firmware`, which
//! includes this file with `#[path]`) checks the test itself against `f64` and
//! the host's results against the chip's. `no_std`, integers only.

/// Inputs in `[1, 4)` whose square roots lie closest to a midpoint between two
/// floats (within `1e-6` ulp of it): the 32 closest of an exhaustive search of the
/// two binades, where a square root that is only faithfully rounded would most
/// likely be wrong. Scaled by `4^k` each stays as hard ([`inputs`]).
pub const HARD: [u32; 32] = [
    0x407f_ffff,
    0x3f80_0001,
    0x407f_fffd,
    0x3ffc_114a,
    0x406e_9372,
    0x3f80_0003,
    0x4055_1dbf,
    0x405a_e03b,
    0x407f_fffb,
    0x3f92_5859,
    0x3fb0_c6c3,
    0x402a_177f,
    0x4041_bc4e,
    0x3fa9_7bef,
    0x3ff0_28ab,
    0x407f_fff9,
    0x3f80_0005,
    0x3fcb_41e9,
    0x3fcd_aeb2,
    0x403b_8bcc,
    0x3fb8_cc66,
    0x3ff0_d9ce,
    0x404d_142a,
    0x400f_e042,
    0x403b_8e2a,
    0x405f_5fa5,
    0x407f_fff7,
    0x3fd4_6581,
    0x401d_c3f5,
    0x4051_5a77,
    0x3f80_0007,
    0x3fd4_61f1,
];

/// Special inputs: zeros, infinities, NaNs, negative numbers, the smallest and
/// largest subnormals, the smallest normal, the largest float, 1, 2, 4, exact
/// squares.
pub const SPECIAL: [u32; 20] = [
    0x0000_0000, // +0
    0x8000_0000, // -0
    0x7f80_0000, // +inf
    0xff80_0000, // -inf
    0x7fc0_0000, // quiet NaN
    0x7f80_0001, // signalling NaN
    0xbf80_0000, // -1
    0x8000_0001, // the negative smallest subnormal
    0x0000_0001, // the smallest subnormal
    0x0000_0002,
    0x0000_0003,
    0x007f_ffff, // the largest subnormal
    0x0080_0000, // the smallest normal
    0x7f7f_ffff, // the largest float
    0x3f80_0000, // 1
    0x4000_0000, // 2
    0x4080_0000, // 4
    0x40c8_0000, // 6.25
    0x4b7f_ffff, // 16777215
    0x4c80_0000, // 2^26
];

/// Pseudo-random positive finite inputs after the others.
pub const RANDOM: u32 = 20_000;

/// Every input, in order: each of [`HARD`] scaled by `4^k` to every exponent where
/// it stays a normal float, [`SPECIAL`], then [`RANDOM`] positive finite floats
/// from xorshift32 (seed 1), subnormals included.
pub fn inputs() -> impl Iterator<Item = f32> {
    let hard = HARD.into_iter().flat_map(|h| {
        let exp = (h >> 23) & 0xff;
        let frac = h & 0x007f_ffff;
        // Exponents of the same parity as `exp`, 1..=254.
        (1 + (exp + 1) % 2..=254)
            .step_by(2)
            .map(move |e| f32::from_bits((e << 23) | frac))
    });
    let special = SPECIAL.into_iter().map(f32::from_bits);
    let mut state = 1u32;
    let random = (0..RANDOM).map(move |_| {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        // A positive finite float: clear the sign, and an exponent of 255 becomes 254.
        let bits = state & 0x7fff_ffff;
        let bits = if bits >= 0x7f80_0000 {
            bits - 0x0080_0000
        } else {
            bits
        };
        f32::from_bits(bits)
    });
    hard.chain(special).chain(random)
}

/// `v = m * 2^e` with `m` an integer, for `v` finite and positive.
fn parts(v: f32) -> (u128, i32) {
    let bits = v.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let frac = u128::from(bits & 0x007f_ffff);
    if exp == 0 {
        (frac, -149)
    } else {
        (frac | 1 << 23, exp - 150)
    }
}

/// `a * 2^ea < b * 2^eb`, exactly (the shifted side stays below 2^128 for the
/// values [`correctly_rounded`] compares: the exponents differ by less than 80).
fn less(a: (u128, i32), b: (u128, i32)) -> bool {
    let ((a, ea), (b, eb)) = (a, b);
    if ea >= eb {
        (a << (ea - eb)) < b
    } else {
        a < (b << (eb - ea))
    }
}

/// Whether `r` is `sqrt(x)` rounded to nearest, bit for bit: for a positive
/// finite `x`, `r` is a positive float and `x` lies strictly between the squares
/// of the midpoints from `r` to its two neighbours (the square root of a float is
/// never such a midpoint, so there are no ties); `sqrt(±0) = ±0`,
/// `sqrt(+inf) = +inf`, and a NaN for a NaN or a number below zero.
#[must_use]
pub fn correctly_rounded(x: f32, r: f32) -> bool {
    if x.is_nan() || x < 0.0 {
        return r.is_nan();
    }
    if x == 0.0 || x == f32::INFINITY {
        return r.to_bits() == x.to_bits();
    }
    if !r.is_finite() || r <= 0.0 {
        return false;
    }
    let (m, e) = parts(r);
    let (mx, ex) = parts(x);
    // Squares of the midpoints: above, (2m + 1)^2 * 2^(2e - 2); below the same
    // with 2m - 1, except at a power of two (m = 2^23, r normal), whose lower
    // neighbour is half as far: (4m - 1)^2 * 2^(2e - 4).
    let high = ((2 * m + 1) * (2 * m + 1), 2 * e - 2);
    let low = if m == 1 << 23 && r.to_bits() > 0x0080_0000 {
        ((4 * m - 1) * (4 * m - 1), 2 * e - 4)
    } else {
        ((2 * m - 1) * (2 * m - 1), 2 * e - 2)
    };
    less(low, (mx, ex)) && less((mx, ex), high)
}

/// The FNV-1a hash of the results' bits, in the order of [`inputs`], NaNs as one
/// value (their payloads may differ between cores).
#[must_use]
pub fn hash(results: impl Iterator<Item = f32>) -> u32 {
    let mut h = 0x811c_9dc5_u32;
    for r in results {
        let bits = if r.is_nan() { 0x7fc0_0000 } else { r.to_bits() };
        for byte in bits.to_le_bytes() {
            h = (h ^ u32::from(byte)).wrapping_mul(0x0100_0193);
        }
    }
    h
}
