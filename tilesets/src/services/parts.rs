//! The prototype meshes of the services: closed boxes and capped cylinders, in their own
//! frame, with texture coordinates.

use subtgraph_core::mesh::Mesh;

/// Metres per texture repeat on the services' metal (a bolt plate shows a part of it).
const UV_REPEAT: f32 = 1.0;

/// A closed box from `lo` to `hi`, appended to `m` (outward normals, counter-clockwise seen
/// from outside).
pub fn add_box(m: &mut Mesh, lo: [f32; 3], hi: [f32; 3]) {
    add_frustum(m, lo, hi, 1.0);
}

/// A box from `lo` to `hi` whose top (`+z`) face is shrunk about the box's axis by `top`
/// (a frustum of a square pyramid for `top < 1`), appended to `m`.
fn add_frustum(m: &mut Mesh, lo: [f32; 3], hi: [f32; 3], top: f32) {
    let base = m.positions.len() as u32;
    let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    for k in 0..8u32 {
        let s = if k & 4 == 0 { 1.0 } else { top };
        let x = if k & 1 == 0 { lo[0] } else { hi[0] };
        let y = if k & 2 == 0 { lo[1] } else { hi[1] };
        m.positions.push([
            c[0] + s * (x - c[0]),
            c[1] + s * (y - c[1]),
            if k & 4 == 0 { lo[2] } else { hi[2] },
        ]);
    }
    // Two triangles per face, wound outward.
    const FACES: [[u32; 4]; 6] = [
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
    ];
    for f in FACES {
        m.triangles.push([base + f[0], base + f[1], base + f[2]]);
        m.triangles.push([base + f[0], base + f[2], base + f[3]]);
    }
}

/// A closed cylinder along `+x` from 0 to 1, radius 1, `sides` around, capped.
pub fn cylinder(sides: u32) -> Mesh {
    let mut m = Mesh::default();
    for x in [0.0f32, 1.0] {
        for k in 0..sides {
            let a = std::f32::consts::TAU * k as f32 / sides as f32;
            m.positions.push([x, a.cos(), a.sin()]);
        }
    }
    let c0 = m.positions.len() as u32;
    m.positions.push([0.0, 0.0, 0.0]);
    m.positions.push([1.0, 0.0, 0.0]);
    for k in 0..sides {
        let (a, b) = (k, (k + 1) % sides);
        // The side, wound outward (angle grows from +y to +z, so (+x) x (+y) faces out).
        m.triangles.push([a, b, sides + b]);
        m.triangles.push([a, sides + b, sides + a]);
        // The caps: -x at x = 0, +x at x = 1.
        m.triangles.push([c0, b, a]);
        m.triangles.push([c0 + 1, sides + a, sides + b]);
    }
    finish(m)
}

/// A box part from `lo` to `hi`.
pub fn cuboid(lo: [f32; 3], hi: [f32; 3]) -> Mesh {
    let mut m = Mesh::default();
    add_box(&mut m, lo, hi);
    finish(m)
}

/// A rock bolt's domed plate, in the frame of the rock's surface: `+z` out of the rock,
/// `plate` metres square at the rock, set 3 cm into it (rock is never flat under a plate),
/// its sloping sides rising `proud` metres to a top half as wide, where the nut is. The
/// sloping sides face along the drift as well as across it: what a scan matcher holds on
/// to in a straight drift. The bolt's own end (a few centimetres of thread) is left out: a
/// LiDAR's beam is wider, and every triangle here is repeated 80 000 times in a mine.
pub fn bolt(plate: f32, proud: f32) -> Mesh {
    let h = 0.5 * plate;
    let mut m = Mesh::default();
    add_frustum(&mut m, [-h, -h, -0.03], [h, h, proud], 0.5);
    finish(m)
}

fn finish(mut m: Mesh) -> Mesh {
    m.compute_normals();
    m.compute_box_uvs(UV_REPEAT);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_part_is_closed_and_wound_outward() {
        for m in [cylinder(12), cuboid([0.0; 3], [1.0, 2.0, 3.0])] {
            assert!(m.edge_report().is_closed(), "{:?}", m.edge_report());
            // Outward: the signed volume is positive.
            let v: f32 = m
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| m.positions[i as usize]);
                    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                        + a[2] * (b[0] * c[1] - b[1] * c[0])
                })
                .sum::<f32>()
                / 6.0;
            assert!(v > 0.0, "volume {v}");
        }
        assert!(bolt(0.15, 0.04).edge_report().is_closed());
    }
}
