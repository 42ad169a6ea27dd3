//! The pinhole camera of a preview: where it stands and looks for each view, world points to
//! pixels, and triangles clipped where they cross the camera's plane.

use subtgraph_core::vec3::{V3, cross, dot, sub};

use super::View;
use super::scene::{Scene, used_bounds};

/// `a` scaled to length 1 (a zero vector stays zero: degenerate triangles shade black).
#[inline]
pub(super) fn norm(a: V3) -> V3 {
    let l = dot(a, a).sqrt().max(1e-12);
    [a[0] / l, a[1] / l, a[2] / l]
}

/// A pinhole camera: world points to camera coordinates (x right, y up, z forward) and to
/// pixels.
pub(super) struct Camera {
    pub eye: V3,
    pub right: V3,
    pub up: V3,
    pub forward: V3,
    /// Pixels per unit of x/z.
    pub focal: f64,
    /// The x/z and -y/z drawn at the picture's centre.
    pub centre: [f64; 2],
    pub half: [f64; 2],
}

impl Camera {
    pub fn looking(forward: V3) -> (V3, V3, V3) {
        let forward = norm(forward);
        let right = norm(cross(forward, [0.0, 0.0, 1.0]));
        (forward, right, cross(right, forward))
    }

    #[inline]
    pub fn to_camera(&self, p: V3) -> V3 {
        let d = sub(p, self.eye);
        [dot(d, self.right), dot(d, self.up), dot(d, self.forward)]
    }

    /// Pixel coordinates and depth of a camera-frame point in front of the camera.
    #[inline]
    pub fn to_screen(&self, c: V3) -> V3 {
        [
            self.half[0] + self.focal * (c[0] / c[2] - self.centre[0]),
            self.half[1] + self.focal * (-c[1] / c[2] - self.centre[1]),
            c[2],
        ]
    }

    /// The world point at depth `z` seen through pixel (`px`, `py`).
    #[inline]
    pub fn at_pixel(&self, px: f64, py: f64, z: f64) -> V3 {
        let u = (px - self.half[0]) / self.focal + self.centre[0];
        let v = -((py - self.half[1]) / self.focal + self.centre[1]);
        [0, 1, 2].map(|k| self.eye[k] + z * (u * self.right[k] + v * self.up[k] + self.forward[k]))
    }
}

/// The part of a camera-frame triangle in front of the plane `z = near` (none, a triangle or
/// a quadrilateral), in order.
#[inline]
pub(super) fn clip_near(c: [V3; 3], near: f64) -> Vec<V3> {
    let mut out = Vec::with_capacity(4);
    for k in 0..3 {
        let (p, q) = (c[k], c[(k + 1) % 3]);
        if p[2] > near {
            out.push(p);
        }
        if (p[2] > near) != (q[2] > near) {
            let s = (near - p[2]) / (q[2] - p[2]);
            out.push([0, 1, 2].map(|i| p[i] + s * (q[i] - p[i])));
        }
    }
    out
}

/// A camera above and to the south-west of the scene, framing all of it.
pub(super) fn outside_camera(scene: &Scene, view: View, width: usize, height: usize) -> Camera {
    let (lo, hi) = used_bounds(scene);
    let centre = [0, 1, 2].map(|d| 0.5 * (lo[d] + hi[d]));
    let radius = 0.5 * dot(sub(hi, lo), sub(hi, lo)).sqrt();
    let (az, el) = (
        225f64.to_radians(),
        if view == View::CloseUp { 40f64 } else { 50f64 }.to_radians(),
    );
    let dir = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
    let dist = 2.5 * radius;
    let eye = [0, 1, 2].map(|k| centre[k] + dir[k] * dist);
    let (forward, right, up) = Camera::looking(sub(centre, eye));
    let mut camera = Camera {
        eye,
        right,
        up,
        forward,
        focal: 1.0,
        centre: [0.0, 0.0],
        half: [0.5 * width as f64, 0.5 * height as f64],
    };
    // Scale and centre the picture on what is there.
    let mut used = vec![false; scene.positions.len()];
    for t in &scene.triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in scene
        .positions
        .iter()
        .zip(&used)
        .filter(|(_, u)| **u)
        .map(|(p, _)| p)
    {
        let c = camera.to_camera(p.map(f64::from));
        let q = [c[0] / c[2], -c[1] / c[2]];
        for d in 0..2 {
            min[d] = min[d].min(q[d]);
            max[d] = max[d].max(q[d]);
        }
    }
    camera.focal = 0.94
        * (width as f64 / (max[0] - min[0]).max(1e-9))
            .min(height as f64 / (max[1] - min[1]).max(1e-9));
    camera.centre = [0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1])];
    camera
}
