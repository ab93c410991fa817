//! A scene file's animation evaluated in `f64`, on its own: the reference's
//! frame of a time ([`animate`]), each moved instance placed from its
//! keyframes by a binary search of their times, straight lines between
//! translations and scales, and rotations by the spherical interpolation of
//! unit quaternions (the angle from `atan2` of the quaternions' difference
//! and sum, shorter arc), degrees turned into quaternions as the product of
//! the half-angle turns about X, then Y, then Z. Nothing here comes from the
//! core or from the host's own evaluation (module `animation`).

use crate::desc::{ChannelDesc, DescError, InterpolationDesc, ScaleDesc, SceneDesc};

/// Degrees `[x, y, z]` (about the fixed X, then Y, then Z) as a unit
/// quaternion `[x, y, z, w]`.
fn quaternion_of_degrees(d: [f64; 3]) -> [f64; 4] {
    let half = d.map(|a| (a.to_radians() / 2.0).sin_cos());
    let about = |axis: usize| {
        let (s, c) = half[axis];
        let mut q = [0.0, 0.0, 0.0, c];
        q[axis] = s;
        q
    };
    product(about(2), product(about(1), about(0)))
}

/// The Hamilton product `a b` (`[x, y, z, w]`).
fn product(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let (av, aw) = ([a[0], a[1], a[2]], a[3]);
    let (bv, bw) = ([b[0], b[1], b[2]], b[3]);
    let cross = [
        av[1] * bv[2] - av[2] * bv[1],
        av[2] * bv[0] - av[0] * bv[2],
        av[0] * bv[1] - av[1] * bv[0],
    ];
    let dot = av[0] * bv[0] + av[1] * bv[1] + av[2] * bv[2];
    [
        aw * bv[0] + bw * av[0] + cross[0],
        aw * bv[1] + bw * av[1] + cross[1],
        aw * bv[2] + bw * av[2] + cross[2],
        aw * bw - dot,
    ]
}

fn unit(q: [f64; 4]) -> [f64; 4] {
    let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    q.map(|x| x / len)
}

/// `a` to `b` at `u` along the shorter great arc, at constant speed.
fn slerp(a: [f64; 4], b: [f64; 4], u: f64) -> [f64; 4] {
    let (a, mut b) = (unit(a), unit(b));
    if a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>() < 0.0 {
        b = b.map(|x| -x);
    }
    // Half the angle between them: atan2 of |a - b| and |a + b| (accurate
    // also where they nearly agree).
    let diff = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt();
    let sum = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x + y).powi(2))
        .sum::<f64>()
        .sqrt();
    let theta = 2.0 * diff.atan2(sum);
    if theta < 1e-12 {
        return a;
    }
    let (wa, wb) = (
        ((1.0 - u) * theta).sin() / theta.sin(),
        (u * theta).sin() / theta.sin(),
    );
    unit([0, 1, 2, 3].map(|i| wa * a[i] + wb * b[i]))
}

/// The scene at time `t`: each instance a `[[keyframes]]` names placed from
/// its keyframes at `t` (clamped to the first and last).
///
/// # Errors
/// A target that names no instance, or values of the wrong length.
pub fn animate(desc: &SceneDesc, t: f64) -> Result<SceneDesc, DescError> {
    let mut out = desc.clone();
    for (k, kf) in desc.keyframes.iter().enumerate() {
        let fail = |message: &str| DescError {
            item: format!("keyframes {}", k + 1),
            message: message.into(),
        };
        let i = desc
            .instances
            .iter()
            .position(|d| d.name.as_deref() == Some(kf.target.as_str()))
            .ok_or_else(|| fail("no such instance"))?;
        let value = |j: usize| -> Result<[f64; 4], DescError> {
            let v = &kf.values[j];
            Ok(match (kf.channel, v.len()) {
                (ChannelDesc::Rotation, 4) => unit([v[0], v[1], v[2], v[3]]),
                (ChannelDesc::Rotate, 3) => quaternion_of_degrees([v[0], v[1], v[2]]),
                (ChannelDesc::Scale, 1) => [v[0], v[0], v[0], 0.0],
                (ChannelDesc::Translation | ChannelDesc::Scale, 3) => [v[0], v[1], v[2], 0.0],
                _ => return Err(fail("a value of the wrong length")),
            })
        };
        let n = kf.times.len();
        if n == 0 || kf.values.len() != n {
            return Err(fail("no keyframes, or not one value a time"));
        }
        // The last keyframe at or before t.
        let (mut lo, mut hi) = (0usize, n);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if kf.times[mid] <= t {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        let rotation = matches!(kf.channel, ChannelDesc::Rotation | ChannelDesc::Rotate);
        let v = if lo == 0 {
            value(0)?
        } else if lo == n {
            value(n - 1)?
        } else {
            let (a, b) = (value(lo - 1)?, value(lo)?);
            match kf.interpolation {
                InterpolationDesc::Step => a,
                InterpolationDesc::Linear => {
                    let u = (t - kf.times[lo - 1]) / (kf.times[lo] - kf.times[lo - 1]);
                    if rotation {
                        slerp(a, b, u)
                    } else {
                        [0, 1, 2, 3].map(|c| a[c] + (b[c] - a[c]) * u)
                    }
                }
            }
        };
        let inst = &mut out.instances[i];
        match kf.channel {
            ChannelDesc::Translation => inst.translate = [v[0], v[1], v[2]],
            ChannelDesc::Scale => inst.scale = ScaleDesc::Axes([v[0], v[1], v[2]]),
            ChannelDesc::Rotation | ChannelDesc::Rotate => {
                inst.rotate = None;
                inst.quaternion = Some(v);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quarter turns about each axis, and a turn that the spherical
    /// interpolation halves: the half of 90 degrees about y is 45.
    #[test]
    fn degrees_and_slerp_turn_as_written() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let q = quaternion_of_degrees([0.0, 90.0, 0.0]);
        assert!(
            q.iter()
                .zip([0.0, h, 0.0, h])
                .all(|(a, b)| (a - b).abs() < 1e-15)
        );
        let half = slerp([0.0, 0.0, 0.0, 1.0], q, 0.5);
        let want = quaternion_of_degrees([0.0, 45.0, 0.0]);
        assert!(
            half.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-15),
            "{half:?}"
        );
        // X then Y: a point on +Z goes to +Y... checked through the product's
        // rotation of (0, 0, 1) by 90 about X: to (0, -1, 0).
        let qx = quaternion_of_degrees([90.0, 0.0, 0.0]);
        let p = product(
            product(qx, [0.0, 0.0, 1.0, 0.0]),
            [-qx[0], -qx[1], -qx[2], qx[3]],
        );
        assert!((p[1] + 1.0).abs() < 1e-15 && p[2].abs() < 1e-15, "{p:?}");
    }
}
