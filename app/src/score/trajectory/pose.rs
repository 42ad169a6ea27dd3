//! Rigid poses as unit quaternions and translations: the little geometry the trajectory
//! scores need (composition, inverse, rotation angle), written out rather than taken from a
//! linear-algebra crate, since 3-vectors and quaternions are all it takes.

/// A 3-vector, metres.
pub type Vec3 = [f64; 3];

/// A unit quaternion `[w, x, y, z]`.
pub type Quat = [f64; 4];

/// A pose: the body's orientation and position in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Orientation, a unit quaternion `[w, x, y, z]`.
    pub q: Quat,
    /// Position, metres.
    pub t: Vec3,
}

/// `a - b`.
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a + b`.
pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `s a`.
pub fn scale(s: f64, a: Vec3) -> Vec3 {
    [s * a[0], s * a[1], s * a[2]]
}

/// `a · b`.
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `|a|`.
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}

/// The Hamilton product `a b`.
pub fn mul(a: Quat, b: Quat) -> Quat {
    let [aw, ax, ay, az] = a;
    let [bw, bx, by, bz] = b;
    [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]
}

/// The inverse of a unit quaternion.
pub fn conj(q: Quat) -> Quat {
    [q[0], -q[1], -q[2], -q[3]]
}

/// `q v q*`: `v` rotated by the unit quaternion `q`.
pub fn rotate(q: Quat, v: Vec3) -> Vec3 {
    let u = [q[1], q[2], q[3]];
    let w = q[0];
    // v + 2w (u × v) + 2 u × (u × v)
    let c = cross(u, v);
    let cc = cross(u, c);
    [
        v[0] + 2.0 * (w * c[0] + cc[0]),
        v[1] + 2.0 * (w * c[1] + cc[1]),
        v[2] + 2.0 * (w * c[2] + cc[2]),
    ]
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The rotation angle of a unit quaternion, radians in `[0, π]`: computed with `atan2` so it
/// stays exact for small angles, where `acos` of the matrix trace loses half the digits.
pub fn angle(q: Quat) -> f64 {
    let v = (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    2.0 * v.atan2(q[0].abs())
}

/// The unit quaternion of a rotation matrix (rows), by Shepperd's method: the largest of the
/// four candidate divisors, so no precision is lost near any angle.
pub fn from_matrix(r: [[f64; 3]; 3]) -> Quat {
    let tr = r[0][0] + r[1][1] + r[2][2];
    let q = if tr > r[0][0].max(r[1][1]).max(r[2][2]) {
        let s = 2.0 * (1.0 + tr).sqrt();
        [
            0.25 * s,
            (r[2][1] - r[1][2]) / s,
            (r[0][2] - r[2][0]) / s,
            (r[1][0] - r[0][1]) / s,
        ]
    } else if r[0][0] >= r[1][1] && r[0][0] >= r[2][2] {
        let s = 2.0 * (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt();
        [
            (r[2][1] - r[1][2]) / s,
            0.25 * s,
            (r[0][1] + r[1][0]) / s,
            (r[0][2] + r[2][0]) / s,
        ]
    } else if r[1][1] >= r[2][2] {
        let s = 2.0 * (1.0 - r[0][0] + r[1][1] - r[2][2]).sqrt();
        [
            (r[0][2] - r[2][0]) / s,
            (r[0][1] + r[1][0]) / s,
            0.25 * s,
            (r[1][2] + r[2][1]) / s,
        ]
    } else {
        let s = 2.0 * (1.0 - r[0][0] - r[1][1] + r[2][2]).sqrt();
        [
            (r[1][0] - r[0][1]) / s,
            (r[0][2] + r[2][0]) / s,
            (r[1][2] + r[2][1]) / s,
            0.25 * s,
        ]
    };
    let n = (q.iter().map(|x| x * x).sum::<f64>()).sqrt();
    q.map(|x| x / n)
}

impl Pose {
    /// `self⁻¹`.
    pub fn inverse(&self) -> Pose {
        let qi = conj(self.q);
        Pose {
            q: qi,
            t: scale(-1.0, rotate(qi, self.t)),
        }
    }

    /// `self ∘ other`: `other` expressed in the frame `self` maps to the world.
    pub fn compose(&self, other: &Pose) -> Pose {
        Pose {
            q: mul(self.q, other.q),
            t: add(rotate(self.q, other.t), self.t),
        }
    }

    /// `self⁻¹ ∘ other`: where `other` is seen from `self`.
    pub fn relative(&self, other: &Pose) -> Pose {
        self.inverse().compose(other)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pose_composed_with_its_inverse_is_the_identity() {
        let h = (0.3f64).sin();
        let p = Pose {
            q: [(0.3f64).cos(), 0.0, h * 0.6, h * 0.8],
            t: [1.0, -2.0, 3.0],
        };
        let i = p.compose(&p.inverse());
        assert!(norm(i.t) < 1e-12, "{i:?}");
        assert!(angle(i.q) < 1e-12, "{i:?}");
    }

    #[test]
    fn a_quarter_turn_about_z_maps_x_to_y_and_back_from_its_matrix() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let q = [s, 0.0, 0.0, s];
        let v = rotate(q, [1.0, 0.0, 0.0]);
        assert!(norm(sub(v, [0.0, 1.0, 0.0])) < 1e-12, "{v:?}");
        let r = from_matrix([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
        assert!((0..4).all(|k| (r[k] - q[k]).abs() < 1e-12), "{r:?}");
        assert!((angle(q) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
