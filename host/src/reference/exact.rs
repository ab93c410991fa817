//! Sums of products almost exactly, for the hits of surfaces far larger than their
//! distance to the ray's origin (a triangle `10^12` wide seen from 2 units): the
//! plain `f64` formulas subtract quantities of the surface's size (its cube, for a
//! triangle's plane) to get one of the viewer's size, and keep an error of `2^-53`
//! of the largest, `10^-4` of the result at that ratio: enough to shadow a ground
//! with itself. Here every product is split into its rounded value and its exact
//! error (`mul_add`, one rounding: Dekker's TwoProduct) and the terms are summed
//! with Neumaier's compensation, so the result is within a few units of `2^-53` of
//! itself plus `2^-106` of the terms' magnitude.

use super::vec::V3;

/// `a * b` as `(p, e)`, `p + e = a b` exactly (barring underflow).
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `a - b` as `(s, e)`, `s + e = a - b` exactly (Knuth's TwoSum).
#[must_use]
pub fn two_diff(a: f64, b: f64) -> (f64, f64) {
    let s = a - b;
    let bb = s - a;
    (s, (a - (s - bb)) - (b + bb))
}

/// A sum with Neumaier's compensation.
#[derive(Clone, Copy, Debug, Default)]
struct Sum {
    sum: f64,
    carry: f64,
}

impl Sum {
    fn add(&mut self, x: f64) {
        let t = self.sum + x;
        self.carry += if self.sum.abs() >= x.abs() {
            (self.sum - t) + x
        } else {
            (x - t) + self.sum
        };
        self.sum = t;
    }

    /// Adds `a b c` exactly split into four terms.
    fn add_triple(&mut self, a: f64, b: f64, c: f64) {
        let (p, e) = two_product(a, b);
        let (p1, e1) = two_product(p, c);
        let (p2, e2) = two_product(e, c);
        for x in [p1, e1, p2, e2] {
            self.add(x);
        }
    }

    /// Adds `a b` exactly split into two terms.
    fn add_product(&mut self, a: f64, b: f64) {
        let (p, e) = two_product(a, b);
        self.add(p);
        self.add(e);
    }

    fn value(self) -> f64 {
        self.sum + self.carry
    }
}

/// The determinant `a . (b x c)`, the six products of three expanded exactly.
#[must_use]
pub fn det3(a: V3, b: V3, c: V3) -> f64 {
    let mut s = Sum::default();
    s.add_triple(a.x, b.y, c.z);
    s.add_triple(-a.x, b.z, c.y);
    s.add_triple(a.y, b.z, c.x);
    s.add_triple(-a.y, b.x, c.z);
    s.add_triple(a.z, b.x, c.y);
    s.add_triple(-a.z, b.y, c.x);
    s.value()
}

/// The dot product `a . (bh + bl)`, each product expanded exactly.
#[must_use]
pub fn dot2(a: V3, bh: V3, bl: V3) -> f64 {
    let mut s = Sum::default();
    for (x, (h, l)) in a
        .to_array()
        .into_iter()
        .zip(bh.to_array().into_iter().zip(bl.to_array()))
    {
        s.add_product(x, h);
        s.add_product(x, l);
    }
    s.value()
}

/// `|fh + fl|^2 - r^2`, each product expanded exactly: the constant of a sphere's
/// quadratic, `f` from the centre to the ray's origin, when the origin is near a
/// sphere far larger than that distance.
#[must_use]
pub fn norm2_minus(fh: V3, fl: V3, r: f64) -> f64 {
    let mut s = Sum::default();
    for (h, l) in fh.to_array().into_iter().zip(fl.to_array()) {
        s.add_product(h, h);
        s.add_product(2.0 * h, l);
        s.add_product(l, l);
    }
    s.add_product(-r, r);
    s.value()
}

/// `a^2 - c`, the square expanded exactly.
#[must_use]
pub fn square_minus(a: f64, c: f64) -> f64 {
    let mut s = Sum::default();
    s.add_product(a, a);
    s.add(-c);
    s.value()
}

/// `a - b` per component as the rounded difference and its exact error.
#[must_use]
pub fn diff(a: V3, b: V3) -> (V3, V3) {
    let (x, ex) = two_diff(a.x, b.x);
    let (y, ey) = two_diff(a.y, b.y);
    let (z, ez) = two_diff(a.z, b.z);
    (V3::new(x, y, z), V3::new(ex, ey, ez))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn det3_is_exact_where_plain_f64_cancels() {
        // Rows of magnitude 2^40 whose determinant is small: plain f64 loses it.
        let s = 2f64.powi(40);
        let a = V3::new(s, s + 1.0, 3.0);
        let b = V3::new(s + 2.0, s + 3.0, 5.0);
        let c = V3::new(1.0, 1.0, 1.0);
        // Row operations: the determinant of (a, b - a, c) is exact in integers.
        // a.(b x c) with b - a = (2, 2, 2) gives a . ((b - a) x c) = 0 for c = (1,1,1).
        assert_eq!(det3(a, b, c), 0.0);
        let c = V3::new(1.0, 2.0, 7.0);
        // Computed with i128.
        let i = |v: V3| [v.x as i128, v.y as i128, v.z as i128];
        let (a_, b_, c_) = (i(a), i(b), i(c));
        let exact = a_[0] * (b_[1] * c_[2] - b_[2] * c_[1])
            - a_[1] * (b_[0] * c_[2] - b_[2] * c_[0])
            + a_[2] * (b_[0] * c_[1] - b_[1] * c_[0]);
        assert_eq!(det3(a, b, c), exact as f64);
        assert_ne!(
            a.dot(b.cross(c)),
            exact as f64,
            "plain f64 should have lost it"
        );
    }

    #[test]
    fn norm2_minus_keeps_the_small_difference() {
        let r = 2f64.powi(40);
        let (fh, fl) = diff(V3::new(0.25, 2.0, 0.5), V3::new(0.0, -r, 0.0));
        // |(0.25, r + 2, 0.5)|^2 - r^2 = 0.0625 + 4 r + 4 + 0.25.
        assert_eq!(norm2_minus(fh, fl, r), 4.0 * r + 4.3125);
    }
}
