//! Poses and rotations: what the trajectory, the sensors and the writers pass around.
//!
//! Conventions (REP 103): metres, right-handed, x forward, y left, z up in a body frame; the
//! world frame is the world folder's (x east, y north, z up). Orientations are ZYX Euler angles
//! (yaw about z, then pitch about the new y, then roll about the new x), matrices map body
//! vectors into the world, quaternions are `[x, y, z, w]` as ROS messages order them.

use subtgraph_core::vec3::V3;

/// A rotation matrix (rows), mapping body vectors into the parent frame.
pub type Mat3 = [[f64; 3]; 3];

/// A rigid transform: where a frame is and how it is turned, in its parent frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// The frame's origin in the parent frame, metres.
    pub translation: V3,
    /// Body-to-parent rotation.
    pub rotation: Mat3,
}

impl Pose {
    /// The identity.
    pub const IDENTITY: Pose = Pose {
        translation: [0.0; 3],
        rotation: IDENTITY3,
    };

    /// A pose from a translation and ZYX Euler angles `[yaw, pitch, roll]`, radians.
    pub fn from_euler(translation: V3, ypr: [f64; 3]) -> Pose {
        Pose {
            translation,
            rotation: rotation_zyx(ypr),
        }
    }

    /// A pure translation.
    pub fn translated(translation: V3) -> Pose {
        Pose {
            translation,
            rotation: IDENTITY3,
        }
    }

    /// `self * other`: `other` given in this frame, expressed in this frame's parent.
    pub fn then(&self, other: &Pose) -> Pose {
        Pose {
            translation: add(self.translation, mul(&self.rotation, other.translation)),
            rotation: matmul(&self.rotation, &other.rotation),
        }
    }

    /// A point of this frame in the parent frame.
    pub fn apply(&self, p: V3) -> V3 {
        add(self.translation, mul(&self.rotation, p))
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Pose {
        let rt = transpose(&self.rotation);
        let t = mul(&rt, self.translation);
        Pose {
            translation: [-t[0], -t[1], -t[2]],
            rotation: rt,
        }
    }

    /// The rotation as a unit quaternion `[x, y, z, w]` with `w >= 0`.
    pub fn quaternion(&self) -> [f64; 4] {
        quaternion(&self.rotation)
    }

    /// The 3 x 4 matrix `[R | t]`, row by row (KITTI's pose lines).
    pub fn matrix_3x4(&self) -> [f64; 12] {
        let (r, t) = (&self.rotation, &self.translation);
        [
            r[0][0], r[0][1], r[0][2], t[0], r[1][0], r[1][1], r[1][2], t[1], r[2][0], r[2][1],
            r[2][2], t[2],
        ]
    }
}

/// The identity rotation.
pub const IDENTITY3: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// `Rz(yaw) Ry(pitch) Rx(roll)`.
pub fn rotation_zyx([yaw, pitch, roll]: [f64; 3]) -> Mat3 {
    let (sy, cy) = yaw.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sr, cr) = roll.sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// A rotation's unit quaternion `[x, y, z, w]`, `w >= 0` (Shepperd's method).
pub fn quaternion(r: &Mat3) -> [f64; 4] {
    let trace = r[0][0] + r[1][1] + r[2][2];
    let q = if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        [
            (r[2][1] - r[1][2]) / s,
            (r[0][2] - r[2][0]) / s,
            (r[1][0] - r[0][1]) / s,
            0.25 * s,
        ]
    } else if r[0][0] > r[1][1] && r[0][0] > r[2][2] {
        let s = (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt() * 2.0;
        [
            0.25 * s,
            (r[0][1] + r[1][0]) / s,
            (r[0][2] + r[2][0]) / s,
            (r[2][1] - r[1][2]) / s,
        ]
    } else if r[1][1] > r[2][2] {
        let s = (1.0 + r[1][1] - r[0][0] - r[2][2]).sqrt() * 2.0;
        [
            (r[0][1] + r[1][0]) / s,
            0.25 * s,
            (r[1][2] + r[2][1]) / s,
            (r[0][2] - r[2][0]) / s,
        ]
    } else {
        let s = (1.0 + r[2][2] - r[0][0] - r[1][1]).sqrt() * 2.0;
        [
            (r[0][2] + r[2][0]) / s,
            (r[1][2] + r[2][1]) / s,
            0.25 * s,
            (r[1][0] - r[0][1]) / s,
        ]
    };
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let sign = if q[3] < 0.0 { -1.0 } else { 1.0 };
    q.map(|x| sign * x / n)
}

/// `a + b`.
pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `s a`.
pub fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `m v`.
pub fn mul(m: &Mat3, v: V3) -> V3 {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// `m^T v`.
pub fn mul_t(m: &Mat3, v: V3) -> V3 {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}

/// `a b`.
pub fn matmul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    m
}

/// `m^T`.
pub fn transpose(m: &Mat3) -> Mat3 {
    [
        [m[0][0], m[1][0], m[2][0]],
        [m[0][1], m[1][1], m[2][1]],
        [m[0][2], m[1][2], m[2][2]],
    ]
}

/// The Euclidean norm.
pub fn norm(a: V3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn euler_angles_quaternions_and_inverses_agree() {
        let p = Pose::from_euler([1.0, -2.0, 3.0], [0.7, -0.3, 0.2]);
        let q = p.quaternion();
        // Rotating x by the quaternion equals the matrix's first column.
        let [x, y, z, w] = q;
        let col0 = [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y + z * w),
            2.0 * (x * z - y * w),
        ];
        for k in 0..3 {
            assert!((col0[k] - p.rotation[k][0]).abs() < 1e-12);
        }
        let back = p.then(&p.inverse());
        for i in 0..3 {
            assert!(back.translation[i].abs() < 1e-12);
            for j in 0..3 {
                assert!((back.rotation[i][j] - IDENTITY3[i][j]).abs() < 1e-12);
            }
        }
        // Yaw turns x towards y (right-handed, z up).
        let yawed = rotation_zyx([std::f64::consts::FRAC_PI_2, 0.0, 0.0]);
        let v = mul(&yawed, [1.0, 0.0, 0.0]);
        assert!((v[1] - 1.0).abs() < 1e-12);
        // Negative pitch lifts the nose.
        let v = mul(&rotation_zyx([0.0, -0.1, 0.0]), [1.0, 0.0, 0.0]);
        assert!(v[2] > 0.0);
    }
}
