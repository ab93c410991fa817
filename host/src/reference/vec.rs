//! A plain `f64` 3-vector for the reference renderer (independent of the core's
//! `f32` `Vec3`).

use std::ops::{Add, Mul, Neg, Sub};

/// A vector (or point, or RGB colour) of three `f64`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct V3 {
    /// First component (x, or red).
    pub x: f64,
    /// Second component (y, or green).
    pub y: f64,
    /// Third component (z, or blue).
    pub z: f64,
}

impl V3 {
    /// The zero vector.
    pub const ZERO: Self = Self::new(0.0, 0.0, 0.0);
    /// The unit x axis.
    pub const X: Self = Self::new(1.0, 0.0, 0.0);
    /// The unit y axis.
    pub const Y: Self = Self::new(0.0, 1.0, 0.0);
    /// The unit z axis.
    pub const Z: Self = Self::new(0.0, 0.0, 1.0);

    /// A vector from its components.
    #[must_use]
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }

    /// A vector from an array, as in the scene description.
    #[must_use]
    pub const fn from_array(a: [f64; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }

    /// The components as an array.
    #[must_use]
    pub const fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }

    /// Component `i` (0, 1 or 2).
    #[must_use]
    pub fn get(self, i: usize) -> f64 {
        match i {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }

    /// Dot product.
    #[must_use]
    pub fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    #[must_use]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Euclidean length.
    #[must_use]
    pub fn length(self) -> f64 {
        self.dot(self).sqrt()
    }

    /// The unit vector along `self` (NaN components for the zero vector).
    #[must_use]
    pub fn normalize(self) -> Self {
        self * (1.0 / self.length())
    }

    /// Component-wise product (colours).
    #[must_use]
    pub fn times(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }

    /// Component-wise absolute value.
    #[must_use]
    pub fn abs(self) -> Self {
        Self::new(self.x.abs(), self.y.abs(), self.z.abs())
    }

    /// The largest component.
    #[must_use]
    pub fn max_component(self) -> f64 {
        self.x.max(self.y).max(self.z)
    }

    /// True when every component is finite.
    #[must_use]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

impl Add for V3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl Sub for V3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Neg for V3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl Mul<f64> for V3 {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_and_length() {
        assert_eq!(V3::X.cross(V3::Y), V3::Z);
        assert_eq!(V3::Y.cross(V3::Z), V3::X);
        assert_eq!(V3::new(1.0, 2.0, 3.0).dot(V3::new(4.0, -5.0, 6.0)), 12.0);
        assert_eq!(V3::new(3.0, 4.0, 0.0).length(), 5.0);
        assert_eq!(V3::new(0.0, 0.0, -2.0).normalize(), -V3::Z);
        assert!(!V3::ZERO.normalize().is_finite());
    }
}
