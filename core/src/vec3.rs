//! Three-vector arithmetic on plain arrays, for the geometry the crates share (mesh normals,
//! collision slabs, the preview renderer): a few functions say it more plainly than a linear
//! algebra crate would.

/// A point or direction in metres, world frame.
pub type V3 = [f64; 3];

/// `a - b`.
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The dot product.
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product `a x b` (right-handed).
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a` scaled to length 1, or `None` when it is (nearly) zero and has no direction.
pub fn unit(a: V3) -> Option<V3> {
    let l = dot(a, a).sqrt();
    (l > 1e-12).then(|| [a[0] / l, a[1] / l, a[2] / l])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_axes_are_right_handed_and_unit_refuses_zero() {
        assert_eq!(cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(
            dot(sub([3.0, 4.0, 0.0], [0.0, 0.0, 0.0]), [3.0, 4.0, 0.0]),
            25.0
        );
        assert_eq!(unit([0.0, 3.0, 4.0]), Some([0.0, 0.6, 0.8]));
        assert_eq!(unit([0.0; 3]), None);
    }
}
