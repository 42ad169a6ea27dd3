//! The room-and-pillar block: a panel of a mine worked by room-and-pillar, as a constraint shape
//! (`[[topology.structure]] type = "room-and-pillar"`).
//!
//! Room-and-pillar mines drive parallel drifts (here: rows) and crosscuts (columns) at a regular
//! spacing through a panel and leave square pillars of rock between them to hold the roof. On
//! the grid a block of `pillars = [rows, cols]` pillars is `2 rows + 1` by `2 cols + 1` cells:
//! every cell whose block row or block column is even is open, every other cell is a one-cell
//! pillar. Every drift and crosscut runs one cell past the outer ones (the face where it was
//! stopped), so every crossing, the outer ones included, is a four-way intersection and every
//! cell between two crossings a straight: the block brings `(rows + 1) x (cols + 1)`
//! intersections and `rows x cols` independent loops (one round each pillar), and the level is
//! checked for them like any structure's (exactly, in exact mode).
//!
//! The middle drift and the middle crosscut leave the block on all four sides as arms (the
//! panel's main entries), routed and linked by the generator like any structure's arms; the
//! other drift ends stay one-cell faces (dead ends). The block is never rotated, so `rows` are
//! the level's rows.
//!
//! Why a drawn size: `pillars` may be left out, and each level then draws its block from
//! [`DEFAULT_PILLARS`], as large as fits the level; each entry may also be `[low, high]`. A
//! block that cannot fit a level of the resolved size is refused before generation, naming
//! `pillars` and what to change ([`ConstraintShape::fits`]).

use crate::error::ConfigError;
use crate::grid::Direction;
use crate::params::Params;
use crate::range::IntRange;
use crate::rng::WorldRng;
use crate::shape::{Arm, ConstraintShape, Heading, Offset};

/// The pillar counts drawn when `pillars` is not given: rows and columns of pillars, each
/// `[low, high]`, capped at what fits the level.
pub const DEFAULT_PILLARS: [(u32, u32); 2] = [(2, 4), (2, 6)];

/// Free cells the generator needs on each side of a block, beyond the block and its drift
/// ends: one for the level's border, two of clearance, one for an arm to leave by. Keeping
/// them leaves at least seven centres per axis for the placement draw.
const MARGIN: u32 = 4;

/// The most pillars that fit along a side of `n` cells: the block's `2 p + 3` cells (drift
/// ends included) and four free cells on each side.
pub fn most_pillars(n: usize) -> u32 {
    (n as u32).saturating_sub(3 + 2 * MARGIN) / 2
}

/// One block of `rows x cols` pillars, as placed on a level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PillarBlock {
    /// Rows of pillars (drifts are one more).
    pub rows: u32,
    /// Columns of pillars (crosscuts are one more).
    pub cols: u32,
}

impl PillarBlock {
    /// Whether block cell `(i, j)` (from the block's north-west corner, drift ends excluded)
    /// is open: on a drift (even `i`) or a crosscut (even `j`).
    fn open(i: i32, j: i32) -> bool {
        i % 2 == 0 || j % 2 == 0
    }

    /// The offset of block cell `(i, j)` from the centre.
    fn offset(&self, i: i32, j: i32) -> Offset {
        (i - self.rows as i32, j - self.cols as i32)
    }
}

impl ConstraintShape for PillarBlock {
    fn footprint(&self) -> Vec<Offset> {
        let (h, w) = (2 * self.rows as i32, 2 * self.cols as i32);
        let mut cells = Vec::new();
        for i in -1..=h + 1 {
            for j in -1..=w + 1 {
                let inside = (0..=h).contains(&i) && (0..=w).contains(&j);
                let end = (i == -1 || i == h + 1) && (0..=w).contains(&j) && j % 2 == 0
                    || (j == -1 || j == w + 1) && (0..=h).contains(&i) && i % 2 == 0;
                if inside && Self::open(i, j) || end {
                    cells.push(self.offset(i, j));
                }
            }
        }
        cells
    }

    fn arms(&self) -> Vec<Arm> {
        let (h, w) = (2 * self.rows as i32, 2 * self.cols as i32);
        // The middle drift and crosscut (the lower middle of an even count).
        let (mi, mj) = (2 * (self.rows as i32 / 2), 2 * (self.cols as i32 / 2));
        [
            ((mi, w + 1), Direction::East),
            ((-1, mj), Direction::North),
            ((mi, -1), Direction::West),
            ((h + 1, mj), Direction::South),
        ]
        .into_iter()
        .map(|((i, j), d)| Arm {
            from: self.offset(i, j),
            heading: Heading::Axis(d),
        })
        .collect()
    }

    fn rotations(&self) -> u8 {
        1
    }
}

/// The structure as declared: its pillar counts, fixed or drawn per level.
#[derive(Clone, Debug)]
pub struct RoomAndPillar {
    /// `[rows, cols]` of pillars, or `None` for [`DEFAULT_PILLARS`].
    pillars: Option<[IntRange; 2]>,
    /// Its table, for errors that point at `pillars`.
    params: Params,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    pillars: Option<[IntRange; 2]>,
}

impl RoomAndPillar {
    /// The structure from its `[[topology.structure]]` table (without `count`): `pillars`, two
    /// entries of at least 1, each a number or `[low, high]`.
    pub fn from_params(params: &Params) -> Result<Self, ConfigError> {
        let at_least_one = || {
            params.error(
                "pillars",
                "rows and columns of pillars must each be at least 1 (a block of 1 x 1 pillars \
                 is a ring of drifts round one pillar), e.g. pillars = [3, 4]",
            )
        };
        // A negative count gets the message zero gets (the range reader would say ">= 0",
        // as if zero were allowed).
        let negative = |v: &toml::Value| v.as_integer().is_some_and(|i| i < 0);
        if let Some(toml::Value::Array(p)) = params.raw("pillars") {
            let mut numbers = p.iter().flat_map(|v| match v {
                toml::Value::Array(range) => range.iter().collect::<Vec<_>>(),
                v => vec![v],
            });
            if numbers.any(negative) {
                return Err(at_least_one());
            }
        }
        let keys: Keys = params.deserialize()?;
        if let Some(p) = keys.pillars {
            let low = |r: IntRange| match r {
                IntRange::Fixed(v) | IntRange::Between(v, _) => v,
            };
            if p.iter().any(|&r| low(r) == 0) {
                return Err(at_least_one());
            }
        }
        Ok(Self {
            pillars: keys.pillars,
            params: params.clone(),
        })
    }

    /// The ranges drawn on a level of `rows x cols`: as given, or the defaults capped at what
    /// fits.
    fn ranges(&self, rows: usize, cols: usize) -> [IntRange; 2] {
        self.pillars.unwrap_or_else(|| {
            let capped = |(lo, hi): (u32, u32), n: usize| {
                let most = most_pillars(n).max(1);
                IntRange::Between(lo.min(most), hi.min(most))
            };
            [
                capped(DEFAULT_PILLARS[0], rows),
                capped(DEFAULT_PILLARS[1], cols),
            ]
        })
    }

    /// The smallest block it can place, for [`ConstraintShape::footprint`] outside a level.
    fn smallest(&self) -> PillarBlock {
        let [r, c] = self
            .pillars
            .unwrap_or(DEFAULT_PILLARS.map(|(lo, hi)| IntRange::Between(lo, hi)));
        let low = |r: IntRange| match r {
            IntRange::Fixed(v) | IntRange::Between(v, _) => v,
        };
        PillarBlock {
            rows: low(r),
            cols: low(c),
        }
    }
}

impl ConstraintShape for RoomAndPillar {
    fn footprint(&self) -> Vec<Offset> {
        self.smallest().footprint()
    }

    fn arms(&self) -> Vec<Arm> {
        self.smallest().arms()
    }

    fn rotations(&self) -> u8 {
        1
    }

    fn fits(&self, rows: usize, cols: usize) -> Result<(), ConfigError> {
        let [r, c] = self.ranges(rows, cols);
        for (want, n, axis, what) in [
            (r.max(), rows, "rows", "rows"),
            (c.max(), cols, "cols", "columns"),
        ] {
            let most = most_pillars(n);
            if want > most {
                let need = 2 * want + 3 + 2 * MARGIN;
                let message = if self.pillars.is_some() {
                    format!(
                        "{want} {what} of pillars need a level of at least {need} {what} (the \
                         block spans 2 x {want} + 3 cells with its drift ends, and {MARGIN} cells \
                         are kept free on each side), but the level has {n}, room for at most \
                         {most}; ask for fewer pillars, or raise world.{axis} (or \
                         world.min_length)"
                    )
                } else {
                    format!(
                        "a room-and-pillar block needs a level of at least {need} {what} (one \
                         pillar, its drift ends and {MARGIN} free cells on each side), but the \
                         level has {n}; raise world.{axis} (or world.min_length)"
                    )
                };
                return Err(self.params.error("pillars", message));
            }
        }
        Ok(())
    }

    fn drawn(
        &self,
        rows: usize,
        cols: usize,
        rng: &mut WorldRng,
    ) -> Option<Box<dyn ConstraintShape>> {
        let [r, c] = self.ranges(rows, cols);
        Some(Box::new(PillarBlock {
            rows: r.draw(rng),
            cols: c.draw(rng),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::structure_counts;

    #[test]
    fn a_block_brings_its_crossings_and_a_loop_per_pillar() {
        for (rows, cols) in [(1, 1), (2, 3), (3, 4), (4, 2)] {
            let b = PillarBlock { rows, cols };
            let c = structure_counts(&b);
            assert_eq!(c.intersections, (rows + 1) * (cols + 1), "{b:?}");
            assert_eq!(c.t_junctions, 0, "{b:?}");
            assert_eq!(c.loops, rows * cols, "{b:?}");
            let cells = b.footprint();
            for arm in b.arms() {
                assert!(cells.contains(&arm.from), "{b:?}: {arm:?}");
            }
            // No pillar cell is open, and every open cell in the block is a drift or crosscut.
            for i in 0..=2 * rows as i32 {
                for j in 0..=2 * cols as i32 {
                    assert_eq!(
                        cells.contains(&b.offset(i, j)),
                        i % 2 == 0 || j % 2 == 0,
                        "{b:?} ({i}, {j})"
                    );
                }
            }
        }
    }

    /// Issue 21 item 8: counting a block's crossings and loops cost the square of its cells
    /// (a linear search per neighbour), hours for the largest block a 2048-cell level holds.
    #[test]
    fn the_largest_block_is_counted_in_near_linear_time() {
        let b = PillarBlock {
            rows: 1000,
            cols: 999,
        };
        let c = structure_counts(&b);
        assert_eq!(
            (c.intersections, c.t_junctions, c.loops),
            (1001 * 1000, 0, 1000 * 999)
        );
    }

    #[test]
    fn too_many_pillars_are_refused_naming_the_key() {
        let params = Params::from_table(
            "topology.structure[0]",
            toml::from_str("pillars = [3, 12]").unwrap(),
        );
        let s = RoomAndPillar::from_params(&params).unwrap();
        assert!(s.fits(30, 40).is_ok());
        let e = s.fits(40, 30).unwrap_err();
        assert_eq!(e.key, "topology.structure[0].pillars");
        assert!(e.message.contains("world.cols"), "{e}");
        let zero = Params::from_table(
            "topology.structure[0]",
            toml::from_str("pillars = [0, 2]").unwrap(),
        );
        let e = RoomAndPillar::from_params(&zero).unwrap_err();
        assert_eq!(e.key, "topology.structure[0].pillars");
    }

    #[test]
    fn default_blocks_fit_the_level() {
        let s = RoomAndPillar::from_params(&Params::default()).unwrap();
        let mut rng = WorldRng::new(1, "t", 0);
        for n in [13, 16, 31, 44] {
            assert!(s.fits(n, n).is_ok(), "{n}");
            for _ in 0..20 {
                let b = s.drawn(n, n, &mut rng).unwrap();
                let extent = b.footprint().iter().map(|o| o.0).max().unwrap();
                assert!(2 * extent + 1 + 2 * MARGIN as i32 <= n as i32, "{n}");
            }
        }
        assert!(s.fits(12, 40).is_err());
    }
}
