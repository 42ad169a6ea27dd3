//! Three-vector arithmetic on plain arrays, for the geometry the crates share (mesh normals,
//! collision slabs, the preview renderer, passage centrelines in the plane): a few functions say
//! it more plainly than a linear algebra crate would.

/// A point or direction in metres, world frame.
pub type V3 = [f64; 3];

/// `a - b`.
#[inline]
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The dot product.
#[inline]
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product `a x b` (right-handed).
#[inline]
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

/// The squared distance in the plane from `p` to the segment `a`-`b` (to `a` when the segment
/// is a point): squared, so a comparison with a squared bound needs no square root.
pub fn segment_distance_squared(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (qx, qy) = (a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
    qx * qx + qy * qy
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distances_reach_the_nearest_point_of_the_segment() {
        let (a, b) = ([0.0, 0.0], [4.0, 0.0]);
        assert_eq!(segment_distance_squared([2.0, 3.0], a, b), 9.0);
        assert_eq!(segment_distance_squared([7.0, 4.0], a, b), 25.0);
        assert_eq!(segment_distance_squared([-1.0, 0.0], a, b), 1.0);
        assert_eq!(segment_distance_squared([1.0, 1.0], a, a), 2.0);
    }

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
