//! The passage axis a procedural tile set lays through each tile ([`PassageAxis`]): the same
//! centrelines its field sweeps the passage along ([`crate::bends`]: a corner's quarter circle,
//! a straight's meander, a junction's or dead end's half-corridors, a ramp's lead), on the
//! floor its slope lifts. The ground truth's graph follows it, so its centrelines are the
//! passage's own, not a path found again in the mesh.
//!
//! One thing differs from the field: where square bends (mine drifts) meet at a corner's
//! centre at a right angle, the axis rounds the corner with a fillet of radius [`FILLET`]
//! (at most 0.4 of half a pitch), which stays well inside the drift (its middle is 0.41 of a
//! radius from the corner point, where the drift is half its width wide on both legs): a
//! robot driving the axis from point to point turns at most 15 degrees per metre.

use subtgraph_core::Layout;
use subtgraph_core::grid::{Cell, Direction};
use subtgraph_core::tileset::PassageAxis;

use crate::bends::{self, Bends, Centreline};
use crate::passage::{Levels, Passage};

/// Radius of the fillet at a square corner, metres.
pub const FILLET: f64 = 4.0;

/// Longest step between two points of an axis, metres (the ground truth samples its
/// centrelines every metre).
const STEP: f64 = 1.0;

/// The passage axis of the tile at `cell`, as the field lays its passage (`lattice` and
/// `levels` as the field is made with, for a ramp's plan).
pub fn passage_axis(
    world: &Layout,
    cell: Cell,
    passage: &Passage,
    levels: Levels,
    lattice: f64,
) -> Option<PassageAxis> {
    let tile = world.tiles.get(cell).as_ref()?;
    let half = 0.5 * world.resolved.tile_pitch;
    let [x, y, floor] = world.cell_position(cell);
    let waves = passage.slope.level(cell.level);
    let on_floor = |p: [f64; 2]| [p[0], p[1], floor + waves.lift(p[0], p[1])];
    let face = |d: Direction| {
        let (sr, sc) = d.step();
        [x + f64::from(sc) * half, y - f64::from(sr) * half]
    };
    let open: Vec<Direction> = Direction::ALL
        .into_iter()
        .filter(|d| tile.openings & d.bit() != 0)
        .collect();
    let mut exits: [Vec<[f64; 3]>; 4] = Default::default();
    let sample = |line: &Centreline, t0: f64, t1: f64| -> Vec<[f64; 3]> {
        // From t0 (excluded) to t1 (included).
        let n = (length(line) * (t1 - t0).abs() / STEP).ceil().max(1.0) as usize;
        (1..=n)
            .map(|k| on_floor(line.at(t0 + (t1 - t0) * k as f64 / n as f64).0))
            .collect()
    };
    // A ramp's end: its lead, from where the spiral leaves the level (or, when the spiral
    // turns in a block of cells, where the lead enters this cell) to the opening. The part in
    // the block's other cells is the ramp's, not this cell's corridor's.
    if let Some(s) = crate::ramp::shaft_of(world, cell) {
        let sizing = crate::ramp::Sizing::of(world, passage, lattice, levels.coarse);
        if let Ok(h) = crate::ramp::plan(world, s, &sizing) {
            let (a, b) = h.leads()[usize::from(s.up != cell)];
            let d = open.iter().copied().find(|&d| near(face(d), b))?;
            let lead = Centreline::Segment { a, b };
            let t0 = entry(a, b, [x, y], half);
            exits[d as usize] = sample(&lead, t0, 1.0);
            return Some(PassageAxis {
                node: on_floor(lead.at(t0).0),
                exits,
            });
        }
    }
    let ends: Vec<[f64; 2]> = open.iter().map(|&d| face(d)).collect();
    let key = ((cell.level as u64) << 40) | ((cell.row as u64) << 20) | cell.col as u64;
    let sway = bends::meander(world.resolved.seed, key, passage.meander);
    let lines = if ends.is_empty() {
        Vec::new()
    } else {
        bends::centrelines([x, y], &ends, passage.bends, sway)
    };
    match (&lines[..], &open[..]) {
        // A corner's arc or a straight's meander: one line through the tile, its node in the
        // middle.
        ([line], [d0, d1]) if !matches!(line, Centreline::Segment { .. }) => {
            exits[*d0 as usize] = sample(line, 0.5, 0.0);
            exits[*d1 as usize] = sample(line, 0.5, 1.0);
            Some(PassageAxis {
                node: on_floor(line.at(0.5).0),
                exits,
            })
        }
        // Square bends at a corner: the half-corridors rounded into each other.
        ([_, _], [d0, d1]) if passage.bends == Bends::Square && !opposite(*d0, *d1) => {
            let r = FILLET.min(0.4 * half);
            let unit = |e: [f64; 2]| [(e[0] - x) / half, (e[1] - y) / half];
            let (u0, u1) = (unit(ends[0]), unit(ends[1]));
            let f0 = [x + u0[0] * r, y + u0[1] * r];
            let f1 = [x + u1[0] * r, y + u1[1] * r];
            let fillet = Centreline::Arc {
                c: [x + (u0[0] + u1[0]) * r, y + (u0[1] + u1[1]) * r],
                r,
                e: [f0, f1],
            };
            for (d, f, e, t) in [(*d0, f0, ends[0], 0.0), (*d1, f1, ends[1], 1.0)] {
                let mut path = sample(&fillet, 0.5, t);
                path.extend(sample(&Centreline::Segment { a: f, b: e }, 0.0, 1.0));
                exits[d as usize] = path;
            }
            Some(PassageAxis {
                node: on_floor(fillet.at(0.5).0),
                exits,
            })
        }
        // Junctions, dead ends and shaft ends: half-corridors from the centre.
        _ => {
            for (d, line) in open.iter().zip(&lines) {
                exits[*d as usize] = sample(line, 0.0, 1.0);
            }
            Some(PassageAxis {
                node: on_floor([x, y]),
                exits,
            })
        }
    }
}

fn opposite(a: Direction, b: Direction) -> bool {
    (a as u8 + 2) % 4 == b as u8
}

fn near(a: [f64; 2], b: [f64; 2]) -> bool {
    (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-6
}

/// A centreline's length, metres (a meander's to first order: its chord).
fn length(line: &Centreline) -> f64 {
    match *line {
        Centreline::Segment { a, b } | Centreline::Meander { a, b, .. } => {
            (b[0] - a[0]).hypot(b[1] - a[1])
        }
        Centreline::Arc { r, .. } => std::f64::consts::FRAC_PI_2 * r,
    }
}

/// Where the segment from `a` to `b` (`b` in the cell, on its face) enters the cell of
/// half-side `half` centred at `c`, as a share of its length (0 when `a` is in the cell).
fn entry(a: [f64; 2], b: [f64; 2], c: [f64; 2], half: f64) -> f64 {
    let mut t0: f64 = 0.0;
    for k in 0..2 {
        let (lo, hi) = (c[k] - half, c[k] + half);
        let d = b[k] - a[k];
        if a[k] < lo && d > 0.0 {
            t0 = t0.max((lo - a[k]) / d);
        } else if a[k] > hi && d < 0.0 {
            t0 = t0.max((hi - a[k]) / d);
        }
    }
    t0.min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::npy::NpyArray;
    use subtgraph_core::params::Params;

    /// A layout from spatial codes (1 dead end, 2 straight, 3 corner), `[levels, rows, cols]`.
    fn layout(shape: [usize; 3], codes: &[u8]) -> Layout {
        let array = NpyArray {
            shape: shape.to_vec(),
            values: codes.iter().map(|&c| f64::from(c)).collect(),
            dtype: "|u1".into(),
        };
        let pipeline = subtgraph_core::Pipeline::parse("[world]\nseed = 3\n", "t.toml").unwrap();
        subtgraph_core::import::import_occupancy(&array, "t.npy", &pipeline, "test")
            .unwrap()
            .0
    }

    #[test]
    fn a_lead_enters_its_cell_where_it_crosses_the_cell_face() {
        // From the block's cell south of the cell centred at the origin, 20 m across.
        let t = entry([3.0, -14.0], [10.0, 10.0], [0.0, 0.0], 10.0);
        assert!((t - 4.0 / 24.0).abs() < 1e-12, "{t}");
        // From the west and the south at once: the later crossing.
        let t = entry([-12.0, -11.0], [0.0, 10.0], [0.0, 0.0], 10.0);
        assert!((t - 2.0 / 12.0).abs() < 1e-12, "{t}");
        // A lead that starts in the cell is whole.
        assert_eq!(entry([2.0, -3.0], [10.0, 0.0], [0.0, 0.0], 10.0), 0.0);
    }

    #[test]
    fn a_mine_corner_is_rounded_inside_its_drift_and_turns_gently() {
        // An L: a dead end north of a corner, a straight and a dead end east of it.
        #[rustfmt::skip]
        let world = layout([1, 3, 3], &[
            1, 0, 0,
            3, 2, 1,
            0, 0, 0,
        ]);
        let mine = crate::mine::from_params(&Params::default()).unwrap();
        let passage = mine.passage(&world);
        let levels = Levels {
            height: world.resolved.level_height,
            below_floor: 0.0,
            above_ceiling: 0.0,
            coarse: 1.0,
        };
        let corner = Cell::new(0, 1, 0);
        let axis = passage_axis(&world, corner, &passage, levels, 1.0).unwrap();
        let [x, y, _] = world.cell_position(corner);
        let half = 0.5 * world.resolved.tile_pitch;
        let open: Vec<usize> = (0..4).filter(|&d| !axis.exits[d].is_empty()).collect();
        assert_eq!(open.len(), 2, "{axis:?}");
        // Every point lies within the drift: nearer than half its width to one of the two
        // half-corridors the field sweeps (from the centre to each opening's face).
        let to_leg = |p: [f64; 3], e: [f64; 3]| {
            let (dx, dy) = (e[0] - x, e[1] - y);
            let t = (((p[0] - x) * dx + (p[1] - y) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            (p[0] - x - t * dx).hypot(p[1] - y - t * dy)
        };
        let faces: Vec<[f64; 3]> = open
            .iter()
            .map(|&d| *axis.exits[d].last().unwrap())
            .collect();
        let mut rounded = false;
        for d in &open {
            let path: Vec<[f64; 3]> = std::iter::once(axis.node)
                .chain(axis.exits[*d].iter().copied())
                .collect();
            for p in &path {
                let off = to_leg(*p, faces[0]).min(to_leg(*p, faces[1]));
                assert!(
                    off < 0.5 * passage.width - 0.5,
                    "{p:?} is {off} m off the drift"
                );
                rounded |= off > 0.5;
            }
            // Steps of at most a metre, turning at most 15 degrees each.
            for w in path.windows(3) {
                let h = |a: [f64; 3], b: [f64; 3]| (b[1] - a[1]).atan2(b[0] - a[0]);
                let step = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
                assert!(step <= STEP + 1e-9 && step > 0.0, "step {step}");
                let t = (h(w[1], w[2]) - h(w[0], w[1])).abs();
                let t = t.min(std::f64::consts::TAU - t).to_degrees();
                assert!(t <= 15.0, "turns {t} degrees at {:?}", w[1]);
            }
            // The path ends on the middle of its opening's face.
            let end = path.last().unwrap();
            assert!(
                ((end[0] - x).abs() - half).abs() < 1e-9
                    || ((end[1] - y).abs() - half).abs() < 1e-9
            );
        }
        // The corner is cut: the axis does not run through the corner point itself.
        assert!(rounded, "the corner is not rounded");
    }
}
