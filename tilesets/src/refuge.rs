//! Refuge bays: recesses cut into one wall of a long drift, where a vehicle pulls in or people
//! shelter (`[tileset] refuge_spacing`, mine tile set).
//!
//! A bay is a box cut into the rock beside the drift, centred on a straight tile, its floor the
//! drift's floor: part of the field, so it is welded into the one closed surface and holds in
//! the collision mesh, and the survey's free space and widths see it. Tiles with a bay are
//! labelled `refuge-bay` in the semantic labels. Whether a straight tile has one, and on which
//! side, is drawn from the tile's own stream of the world seed, so tiles stay independent.

use subtgraph_core::Layout;
use subtgraph_core::grid::{Cell, Direction};
use subtgraph_core::rng::WorldRng;
use subtgraph_core::tile::TileKind;

use crate::passage::Passage;

/// Length of a bay along the drift, metres.
pub const LENGTH: f64 = 4.0;
/// How far a bay reaches into the wall beyond the drift's nominal half width, metres.
pub const DEPTH: f64 = 2.5;
/// Height of a bay over the drift's floor, metres.
pub const HEIGHT: f64 = 3.0;

/// One refuge bay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bay {
    /// The tile's centre in the plane.
    pub c: [f64; 2],
    /// Unit vector along the drift.
    pub along: [f64; 2],
    /// Unit vector across the drift, toward the bay's wall.
    pub toward: [f64; 2],
    /// Distance from the drift's axis to the bay's back wall, metres.
    pub reach: f64,
}

impl Bay {
    /// The bay's field at `p` (negative inside the recess), `v` metres above the floor.
    pub fn value(&self, p: [f64; 3], v: f64) -> f64 {
        self.walls(p, v).max(-v)
    }

    /// The bay's [`value`](Self::value) without its floor: its walls and back alone, which a
    /// wall finish moves (`crate::finish`; the floor it leaves where it is).
    pub fn walls(&self, p: [f64; 3], v: f64) -> f64 {
        let d = [p[0] - self.c[0], p[1] - self.c[1]];
        let a = d[0] * self.along[0] + d[1] * self.along[1];
        let b = d[0] * self.toward[0] + d[1] * self.toward[1];
        (a.abs() - 0.5 * LENGTH)
            .max(b - self.reach)
            .max(-b)
            .max(v - HEIGHT)
    }

    /// The box `(lo, hi)` in the plane the bay takes, grown by `grow`.
    pub fn bounds(&self, grow: f64) -> ([f64; 2], [f64; 2]) {
        let mut lo = [f64::MAX; 2];
        let mut hi = [f64::MIN; 2];
        for (sa, sb) in [(-1.0, 0.0), (1.0, 0.0), (-1.0, 1.0), (1.0, 1.0)] {
            for k in 0..2 {
                let x = self.c[k]
                    + sa * 0.5 * LENGTH * self.along[k]
                    + sb * self.reach * self.toward[k];
                lo[k] = lo[k].min(x - grow);
                hi[k] = hi[k].max(x + grow);
            }
        }
        (lo, hi)
    }
}

/// The refuge bay of cell `n`, if it has one: a straight tile of a world whose passages have
/// bays (`refuge_spacing` > 0), drawn with chance pitch / spacing (one bay per `spacing`
/// metres of straight drift on average), not in a squeeze, where the tile has room for it.
pub fn of_cell(
    world: &Layout,
    n: Cell,
    kind: TileKind,
    openings: u8,
    passage: &Passage,
    squeezed: bool,
) -> Option<Bay> {
    if passage.refuge_spacing <= 0.0 || kind != TileKind::Straight || squeezed {
        return None;
    }
    let key = ((n.level as u64) << 40) | ((n.row as u64) << 20) | n.col as u64;
    let mut rng = WorldRng::new(world.resolved.seed, "refuge-bays", key);
    let pitch = world.resolved.tile_pitch;
    let draw = rng.unit();
    let left = rng.coin();
    if draw >= (pitch / passage.refuge_spacing).min(1.0) {
        return None;
    }
    let d = Direction::ALL
        .into_iter()
        .find(|d| openings & d.bit() != 0)?;
    let (sr, sc) = d.step();
    let along = [f64::from(sc), -f64::from(sr)];
    let toward = if left {
        [-along[1], along[0]]
    } else {
        [along[1], -along[0]]
    };
    // The bay and its relief stay two collision lattice cells inside the tile (small pitches
    // have no room for one).
    let reach = 0.5 * passage.width + DEPTH;
    let keep = passage.roughness + 2.0 * passage.hazard_lattice;
    if reach + keep > 0.5 * pitch || 0.5 * LENGTH + keep > 0.5 * pitch {
        return None;
    }
    let [x, y, _] = world.cell_position(n);
    Some(Bay {
        c: [x, y],
        along,
        toward,
        reach,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bay_is_a_box_beside_the_drift_over_its_floor() {
        let bay = Bay {
            c: [0.0, 0.0],
            along: [1.0, 0.0],
            toward: [0.0, 1.0],
            reach: 5.7,
        };
        assert!(bay.value([0.0, 5.0, 1.0], 1.0) < 0.0, "inside the recess");
        assert!(
            bay.value([0.0, 6.0, 1.0], 1.0) > 0.0,
            "beyond its back wall"
        );
        assert!(
            bay.value([0.0, -1.0, 1.0], 1.0) > 0.0,
            "not on the other side"
        );
        assert!(bay.value([2.5, 5.0, 1.0], 1.0) > 0.0, "beyond its ends");
        assert!(
            bay.value([0.0, 5.0, -0.1], -0.1) > 0.0,
            "not below the floor"
        );
        assert!(bay.value([0.0, 5.0, 3.1], 3.1) > 0.0, "not above its roof");
        let (lo, hi) = bay.bounds(0.0);
        assert_eq!((lo, hi), ([-2.0, 0.0], [2.0, 5.7]));
    }
}
