//! Building one level: place structures, route their arms to objective nodes, link the pieces
//! into one network, and check the result against what was asked.

use crate::rng::WorldRng;
use crate::route::{RouteDescriptor, Segment};
use crate::shape::{ConstraintShape, Heading, Offset, rotate_offset};
use crate::topology::{self, Counts, GridView};

use super::search::Search;

/// `owner` of an empty cell or an unreserved one.
pub const NONE: u32 = u32::MAX;
/// `owner` of a routed corridor cell.
pub const CORRIDOR: u32 = u32::MAX - 1;
/// `owner` of the landing of the shaft from the level below.
pub const LANDING: u32 = u32::MAX - 2;
/// `reserved` of a cell kept empty for the level below's ramp spiral, for the whole build.
pub const KEPT: u32 = u32::MAX - 3;

/// One level's grid while it is being built.
#[derive(Clone, Debug)]
pub struct Level {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Occupied cells.
    pub occ: Vec<bool>,
    /// Who made each cell: a structure index, [`CORRIDOR`], [`LANDING`] or [`NONE`].
    pub owner: Vec<u32>,
    /// Cells kept free for a structure's arms until they are routed.
    pub reserved: Vec<u32>,
    /// In exact mode routes may touch no corridor but their own two ends.
    pub exact: bool,
}

/// A structure placed on the level.
struct Placed<'a> {
    name: &'a str,
    shape: &'a dyn ConstraintShape,
    centre: (i32, i32),
    rotation: u8,
}

impl Level {
    fn new(rows: usize, cols: usize, exact: bool) -> Self {
        let n = rows * cols;
        Self {
            rows,
            cols,
            occ: vec![false; n],
            owner: vec![NONE; n],
            reserved: vec![NONE; n],
            exact,
        }
    }

    /// The level's cells as a topology view.
    pub fn view(&self) -> GridView<'_> {
        GridView::new(self.rows, self.cols, &self.occ)
    }

    /// The index of `(row, col)` if inside the level.
    pub fn index(&self, r: i32, c: i32) -> Option<usize> {
        topology::index(self.rows, self.cols, r, c)
    }

    fn rc(&self, i: usize) -> (i32, i32) {
        ((i / self.cols) as i32, (i % self.cols) as i32)
    }

    fn neighbours(&self, i: usize) -> impl Iterator<Item = usize> + use<> {
        topology::neighbours(self.rows, self.cols, i)
    }

    fn degree(&self, i: usize) -> usize {
        self.view().degree(i)
    }

    /// Whether a route from `s` to `g` owned by `owner` may pass through cell `v`: free, not
    /// kept for another structure's arm, and touching no occupied cell but `s` and `g`, so the
    /// route creates no junction and never runs alongside a corridor.
    pub fn route_may_use(&self, v: usize, s: usize, g: usize, owners: [u32; 2]) -> bool {
        if self.occ[v] || (self.reserved[v] != NONE && !owners.contains(&self.reserved[v])) {
            return false;
        }
        self.neighbours(v).all(|n| !self.occ[n] || n == s || n == g)
    }

    fn commit(&mut self, cells: &[usize]) {
        for &c in cells {
            self.occ[c] = true;
            self.owner[c] = CORRIDOR;
        }
    }

    /// 4-connected components: a label per cell (`u32::MAX` for empty) and their number.
    fn components(&self) -> (Vec<u32>, u32) {
        self.view().components()
    }

    /// Junction, intersection, dead-end and cycle counts of the level.
    pub fn counts(&self) -> Counts {
        self.view().counts()
    }

    /// Whether any 2 x 2 block is fully occupied (corridors fused side by side).
    fn has_fused_block(&self) -> bool {
        self.view().has_fused_block()
    }

    /// Whether the spiral block `block` beside cell `i` (see [`crate::grid::Shaft::block`])
    /// is inside the level, empty, and kept for nothing else.
    fn block_is_free(&self, i: usize, block: [i8; 2]) -> bool {
        let (r, c) = (i / self.cols, i % self.cols);
        let end = crate::grid::Cell::new(0, r, c);
        crate::grid::Shaft::block_cells(end, block, self.rows, self.cols).is_some_and(|cells| {
            cells.iter().all(|k| {
                let j = k.row * self.cols + k.col;
                !self.occ[j] && self.reserved[j] == NONE
            })
        })
    }

    fn clamp_inside(&self, [r, c]: [i32; 2]) -> (i32, i32) {
        (
            r.clamp(1, self.rows as i32 - 2),
            c.clamp(1, self.cols as i32 - 2),
        )
    }
}

/// The junction tiles and cycles a structure brings by itself: a footprint cell with three
/// neighbours-or-arms is a T-junction, with four an intersection.
///
/// Neighbours and arms are looked up in sorted copies (binary search), so the cost is
/// `n log n` in the footprint's cells: a room-and-pillar block of 1000 x 1000 pillars has
/// three million, where a linear search per neighbour took hours.
pub fn structure_counts(shape: &dyn ConstraintShape) -> Counts {
    let mut cells = shape.footprint();
    cells.sort_unstable();
    let mut arm_cells: Vec<Offset> = shape.arms().iter().map(|a| a.from).collect();
    arm_cells.sort_unstable();
    let mut c = Counts::default();
    let mut edges = 0;
    for &(r, k) in &cells {
        let inner = [(0, 1), (-1, 0), (0, -1), (1, 0)]
            .iter()
            .filter(|(dr, dc)| cells.binary_search(&(r + dr, k + dc)).is_ok())
            .count();
        edges += inner;
        let arms = arm_cells.partition_point(|&a| a <= (r, k))
            - arm_cells.partition_point(|&a| a < (r, k));
        match inner + arms {
            3 => c.t_junctions += 1,
            4 => c.intersections += 1,
            _ => {}
        }
    }
    c.loops = (edges / 2 + 1).saturating_sub(cells.len()) as u32;
    c
}

/// Why one attempt at a level failed; the generator retries with a derived seed and reports
/// the last one in [`crate::Error::Unsatisfiable`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LevelFailure {
    /// A structure found no free area.
    #[error("no free area left for {structure} number {number}")]
    NoRoom {
        /// Shape name.
        structure: String,
        /// 1-based count of that structure on the level.
        number: u32,
    },
    /// Two corridors ran side by side into a 2 x 2 block.
    #[error("two corridors fused side by side")]
    Fused,
    /// The grid does not have the junctions or loops the structures bring.
    #[error("asked for {want} {what} from its structures, the grid has {have}")]
    Counts {
        /// `T-junctions`, `intersections` or `loops`.
        what: &'static str,
        /// Asked for.
        want: u32,
        /// On the grid.
        have: u32,
    },
    /// The landing of the shaft from below ended up with more than one opening.
    #[error("the shaft landing is not a dead end")]
    LandingNotDeadEnd,
    /// No dead end away from the border is left for the shaft up (for a ramp: none with three
    /// empty cells beside it for the spiral).
    #[error("no dead end left for the shaft up (a ramp's needs three empty cells beside it)")]
    NoShaftFoot,
    /// A structure could not be joined to the rest.
    #[error("could not link the {structure} at row {row}, column {col} to the rest of the level")]
    Unlinked {
        /// Shape name.
        structure: String,
        /// Its centre's row.
        row: i32,
        /// Its centre's column.
        col: i32,
    },
    /// An arm of a structure found no route.
    #[error("could not route an arm of the {structure} at row {row}, column {col}")]
    Unrouted {
        /// Shape name.
        structure: String,
        /// Its centre's row.
        row: i32,
        /// Its centre's column.
        col: i32,
    },
    /// Separate pieces of the level could not be linked.
    #[error("could not link {pieces} separate pieces of the level into one network")]
    Pieces {
        /// How many pieces.
        pieces: u32,
    },
}

/// What a level needs to be built.
pub struct LevelSpec<'a> {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Structures to place, by name, one entry per structure.
    pub structures: Vec<(&'a str, &'a dyn ConstraintShape)>,
    /// The landing of the shaft from below, `(row, col)`.
    pub landing: Option<(usize, usize)>,
    /// The spiral block of the ramp from below (see [`crate::grid::Shaft::block`]): its three
    /// cells beside the landing stay empty.
    pub landing_block: Option<[i8; 2]>,
    /// Whether the shaft up is a ramp whose spiral needs a block of empty cells beside its foot.
    pub ramp_blocks: bool,
    /// Exact topology.
    pub exact: bool,
    /// Whether a shaft up must be chosen.
    pub needs_shaft_up: bool,
}

/// A finished level.
pub struct BuiltLevel {
    /// Occupied cells, row-major.
    pub occ: Vec<bool>,
    /// The foot of the shaft up.
    pub shaft_up: Option<ShaftFoot>,
    /// What the structures bring.
    pub expected: Counts,
}

/// Where a level's shaft up starts.
#[derive(Clone, Copy, Debug)]
pub struct ShaftFoot {
    /// `(row, col)`.
    pub at: (usize, usize),
    /// Its ramp's spiral block (see [`crate::grid::Shaft::block`]).
    pub block: Option<[i8; 2]>,
}

/// Tries once to build a level. The error says which constraint failed.
pub fn build_level(
    spec: &LevelSpec<'_>,
    descriptor: &dyn RouteDescriptor,
    search: &mut Search,
    rng: &mut WorldRng,
) -> Result<BuiltLevel, LevelFailure> {
    let mut lvl = Level::new(spec.rows, spec.cols, spec.exact);
    let landing = spec.landing.map(|(r, c)| {
        let i = r * spec.cols + c;
        lvl.occ[i] = true;
        lvl.owner[i] = LANDING;
        i
    });
    if let (Some((r, c)), Some(block)) = (spec.landing, spec.landing_block) {
        let end = crate::grid::Cell::new(0, r, c);
        if let Some(cells) = crate::grid::Shaft::block_cells(end, block, spec.rows, spec.cols) {
            for k in cells {
                lvl.reserved[k.row * spec.cols + k.col] = KEPT;
            }
        }
    }

    // 1. Place structures in a random order (paper: constraint node distribution).
    let mut order: Vec<(&str, &dyn ConstraintShape)> = spec.structures.clone();
    rng.shuffle(&mut order);
    // Shapes drawn per level (a room-and-pillar block's size); the others draw nothing.
    let drawn: Vec<Option<Box<dyn ConstraintShape>>> = order
        .iter()
        .map(|(_, shape)| shape.drawn(spec.rows, spec.cols, rng))
        .collect();
    let mut placed: Vec<Placed> = Vec::with_capacity(order.len());
    let mut expected = Counts::default();
    for ((name, shape), drawn) in order.into_iter().zip(&drawn) {
        let shape = drawn.as_deref().unwrap_or(shape);
        let id = placed.len() as u32;
        let p = place(&mut lvl, name, shape, id, rng).ok_or_else(|| LevelFailure::NoRoom {
            structure: name.to_string(),
            number: id + 1,
        })?;
        let c = structure_counts(shape);
        expected.t_junctions += c.t_junctions;
        expected.intersections += c.intersections;
        expected.loops += c.loops;
        placed.push(p);
    }

    // 2. Link the structures (and the landing) into a tree through their arms, nearest first,
    //    while the level is still open: a corridor from an arm of one to an arm of the other.
    let mut arms: Vec<ArmState> = Vec::new();
    for (id, p) in placed.iter().enumerate() {
        for arm in p.shape.arms() {
            let (fr, fc) = rotate_offset(arm.from, p.rotation);
            arms.push(ArmState {
                structure: id as u32,
                from: (p.centre.0 + fr, p.centre.1 + fc),
                heading: arm.heading.rotated(p.rotation),
                used: false,
            });
        }
    }
    link_structures(
        &mut lvl, search, descriptor, rng, &placed, &mut arms, landing,
    )?;

    // 3. Route every remaining arm to an objective node (paper eqs. 5-6 and 14-15).
    for arm in arms.iter().filter(|a| !a.used) {
        route_arm(
            &mut lvl,
            search,
            descriptor,
            rng,
            &placed[arm.structure as usize],
            arm,
        )?;
    }
    for r in &mut lvl.reserved {
        if *r != KEPT {
            *r = NONE;
        }
    }

    // 4. Link whatever is still apart (joins made without `exact` can leave nothing apart,
    //    but a spur never splits the level; this is the safety net).
    link_components(&mut lvl, search, descriptor, rng, landing)?;

    // 5. Check what was asked.
    if lvl.has_fused_block() {
        return Err(LevelFailure::Fused);
    }
    let got = lvl.counts();
    for (what, want, have) in [
        ("T-junctions", expected.t_junctions, got.t_junctions),
        ("intersections", expected.intersections, got.intersections),
        ("loops", expected.loops, got.loops),
    ] {
        let ok = if spec.exact {
            have == want
        } else {
            have >= want
        };
        if !ok {
            return Err(LevelFailure::Counts { what, want, have });
        }
    }
    if let Some(l) = landing {
        if lvl.degree(l) != 1 {
            return Err(LevelFailure::LandingNotDeadEnd);
        }
    }

    // 6. Choose the foot of the shaft up among the dead ends away from the border (for a
    //    ramp, with a block of three empty cells beside it for the spiral).
    let shaft_up = if spec.needs_shaft_up {
        let candidates: Vec<(usize, Option<[i8; 2]>)> = (0..lvl.occ.len())
            .filter(|&i| {
                let (r, c) = lvl.rc(i);
                lvl.occ[i]
                    && Some(i) != landing
                    && lvl.degree(i) == 1
                    && r >= 1
                    && c >= 1
                    && (r as usize) < lvl.rows - 1
                    && (c as usize) < lvl.cols - 1
            })
            .flat_map(|i| {
                let blocks: Vec<Option<[i8; 2]>> = if spec.ramp_blocks {
                    crate::grid::Shaft::BLOCKS
                        .into_iter()
                        .filter(|&b| lvl.block_is_free(i, b))
                        .map(Some)
                        .collect()
                } else {
                    vec![None]
                };
                blocks.into_iter().map(move |b| (i, b))
            })
            .collect();
        if candidates.is_empty() {
            return Err(LevelFailure::NoShaftFoot);
        }
        let (i, block) = candidates[rng.below(candidates.len() as u64) as usize];
        Some(ShaftFoot {
            at: (i / lvl.cols, i % lvl.cols),
            block,
        })
    } else {
        None
    };
    Ok(BuiltLevel {
        occ: lvl.occ,
        shaft_up,
        expected,
    })
}

/// Places one structure: a random rotation and a random centre in `[3, n - 4]` whose
/// footprint, with its clearance, is free. Bounded tries; `None` when the level is too full.
fn place<'a>(
    lvl: &mut Level,
    name: &'a str,
    shape: &'a dyn ConstraintShape,
    id: u32,
    rng: &mut WorldRng,
) -> Option<Placed<'a>> {
    let footprint = shape.footprint();
    let clearance = shape.clearance().max(1);
    let (rmax, cmax) = ((lvl.rows as i64 - 4).max(3), (lvl.cols as i64 - 4).max(3));
    // The footprint's extent, so a centre that puts it across the border is rejected without
    // listing its cells: a large block (a room-and-pillar panel of millions of cells) fits
    // only a few of the drawn centres.
    let extent = Extent::of(&footprint);
    for _ in 0..200 {
        let rotation = rng.below(u64::from(shape.rotations().clamp(1, 4))) as u8;
        let centre = (rng.int_in(3, rmax) as i32, rng.int_in(3, cmax) as i32);
        if !extent.inside(centre, rotation, lvl.rows, lvl.cols) {
            continue;
        }
        let cells: Vec<(i32, i32)> = footprint
            .iter()
            .map(|&o| {
                let (dr, dc) = rotate_offset(o, rotation);
                (centre.0 + dr, centre.1 + dc)
            })
            .collect();
        let free = cells.iter().all(|&(r, c)| {
            (-clearance..=clearance).all(|dr| {
                (-clearance..=clearance).all(|dc| {
                    lvl.index(r + dr, c + dc)
                        .is_none_or(|i| !lvl.occ[i] && lvl.reserved[i] == NONE)
                })
            })
        });
        if !free {
            continue;
        }
        for &(r, c) in &cells {
            let i = lvl.index(r, c).expect("inside");
            lvl.occ[i] = true;
            lvl.owner[i] = id;
        }
        // Keep the first cells of each arm free until the arm is routed.
        for arm in shape.arms() {
            let (fr, fc) = rotate_offset(arm.from, rotation);
            let from = (centre.0 + fr, centre.1 + fc);
            let exits: Vec<(i32, i32)> = match arm.heading.rotated(rotation) {
                Heading::Axis(d) => {
                    let (sr, sc) = d.step();
                    vec![
                        (from.0 + sr, from.1 + sc),
                        (from.0 + 2 * sr, from.1 + 2 * sc),
                    ]
                }
                Heading::Quadrant(a, b) => {
                    let ((ar, ac), (br, bc)) = (a.step(), b.step());
                    vec![(from.0 + ar, from.1 + ac), (from.0 + br, from.1 + bc)]
                }
            };
            for (r, c) in exits {
                if let Some(i) = lvl.index(r, c) {
                    if !lvl.occ[i] {
                        lvl.reserved[i] = id;
                    }
                }
            }
        }
        return Some(Placed {
            name,
            shape,
            centre,
            rotation,
        });
    }
    None
}

/// The bounding box of a footprint, `None` for an empty one.
struct Extent(Option<(Offset, Offset)>);

impl Extent {
    fn of(cells: &[Offset]) -> Self {
        Self(cells.iter().fold(None, |b, &(r, c)| {
            Some(b.map_or(((r, c), (r, c)), |((r0, c0), (r1, c1))| {
                ((r0.min(r), c0.min(c)), (r1.max(r), c1.max(c)))
            }))
        }))
    }

    /// Whether every cell of the footprint, turned by `rotation` and centred on `centre`,
    /// lies inside the level away from its border row and column (what [`place`] asks of
    /// each cell).
    fn inside(&self, centre: (i32, i32), rotation: u8, rows: usize, cols: usize) -> bool {
        let Some(((r0, c0), (r1, c1))) = self.0 else {
            return true;
        };
        [(r0, c0), (r0, c1), (r1, c0), (r1, c1)]
            .into_iter()
            .all(|corner| {
                let (dr, dc) = rotate_offset(corner, rotation);
                let (r, c) = (
                    i64::from(centre.0) + i64::from(dr),
                    i64::from(centre.1) + i64::from(dc),
                );
                r >= 1 && c >= 1 && r < rows as i64 - 1 && c < cols as i64 - 1
            })
    }
}

fn segment(lvl: &Level, a: (i32, i32), b: (i32, i32), rng: &mut WorldRng) -> Segment {
    Segment {
        start: [f64::from(a.0), f64::from(a.1)],
        end: [f64::from(b.0), f64::from(b.1)],
        rows: lvl.rows,
        cols: lvl.cols,
        side: if rng.coin() { 1.0 } else { -1.0 },
    }
}

/// An arm of a placed structure.
struct ArmState {
    structure: u32,
    from: (i32, i32),
    heading: Heading,
    used: bool,
}

/// Links every structure to the growing network through an unused arm of each, nearest pair
/// first. The landing from below joins the first structure it can reach.
fn link_structures(
    lvl: &mut Level,
    search: &mut Search,
    descriptor: &dyn RouteDescriptor,
    rng: &mut WorldRng,
    placed: &[Placed],
    arms: &mut [ArmState],
    landing: Option<usize>,
) -> Result<(), LevelFailure> {
    let n = placed.len();
    if n == 0 {
        return Ok(());
    }
    let mut linked = vec![false; n];
    let mut landing_free = landing;
    if landing.is_none() {
        linked[0] = true;
    }
    let manhattan = |a: (i32, i32), b: (i32, i32)| (a.0 - b.0).abs() + (a.1 - b.1).abs();
    while linked.iter().any(|l| !l) {
        // Candidate links: (distance, from-cell, from-arm or landing, to-arm), the 16
        // nearest.
        let mut pairs: Nearest<(i32, Option<usize>, usize)> = Nearest::new(16);
        for (j, b) in arms.iter().enumerate() {
            if b.used || linked[b.structure as usize] {
                continue;
            }
            if let Some(l) = landing_free {
                pairs.push((manhattan(lvl.rc(l), b.from), None, j));
            }
            for (i, a) in arms.iter().enumerate() {
                if !a.used && linked[a.structure as usize] {
                    pairs.push((manhattan(a.from, b.from), Some(i), j));
                }
            }
        }
        let mut done = false;
        for &(_, a, b) in &pairs.sorted() {
            let (s, owner_a) = match a {
                Some(i) => (
                    lvl.index(arms[i].from.0, arms[i].from.1).expect("inside"),
                    arms[i].structure,
                ),
                None => (landing_free.expect("landing candidate"), NONE),
            };
            let g = lvl.index(arms[b].from.0, arms[b].from.1).expect("inside");
            let seg = segment(lvl, lvl.rc(s), arms[b].from, rng);
            let guide = descriptor.guide(&seg);
            if let Some(path) = search.route(
                [lvl.rows, lvl.cols],
                s,
                g,
                &guide,
                descriptor.turn_cost(),
                |v| lvl.route_may_use(v, s, g, [owner_a, arms[b].structure]),
            ) {
                if path.is_empty() {
                    continue; // two arms touching directly would fuse their structures
                }
                lvl.commit(&path);
                match a {
                    Some(i) => arms[i].used = true,
                    None => landing_free = None,
                }
                arms[b].used = true;
                linked[arms[b].structure as usize] = true;
                done = true;
                break;
            }
        }
        if !done {
            let stuck = linked.iter().position(|l| !l).expect("some unlinked");
            let p = &placed[stuck];
            return Err(LevelFailure::Unlinked {
                structure: p.name.to_string(),
                row: p.centre.0,
                col: p.centre.1,
            });
        }
    }
    Ok(())
}

/// Routes one arm from its footprint cell to an objective node; after failed draws the reach
/// shrinks. Without `exact`, an objective next to an existing corridor joins it, as in the
/// original (arms join up). An arm that finds no room at all stays a stub where its footprint
/// cell is already a dead end; a loop's corner arm must have at least one cell.
fn route_arm(
    lvl: &mut Level,
    search: &mut Search,
    descriptor: &dyn RouteDescriptor,
    rng: &mut WorldRng,
    p: &Placed,
    arm: &ArmState,
) -> Result<(), LevelFailure> {
    let from = arm.from;
    let s = lvl.index(from.0, from.1).expect("footprint is inside");
    let id = arm.structure;
    for attempt in 0..12 {
        let mut objective =
            p.shape
                .objective([from.0, from.1], arm.heading, lvl.rows, lvl.cols, rng);
        // A descriptor that makes turns cost (mine drifts) aims an axis arm straight along
        // its axis: the shape's sideways jitter would only add a corner before the dead end.
        if let (true, Heading::Axis(d)) = (descriptor.turn_cost() > 0, arm.heading) {
            if d.step().0 != 0 {
                objective[1] = from.1;
            } else {
                objective[0] = from.0;
            }
        }
        // Shrink the reach after every few failures.
        let shrink = 1 << (attempt / 3);
        let objective = [
            from.0 + (objective[0] - from.0) / shrink,
            from.1 + (objective[1] - from.1) / shrink,
        ];
        let target = lvl.clamp_inside(objective);
        if (target.0 - from.0).abs() + (target.1 - from.1).abs() < 1 {
            continue;
        }
        let t = lvl.index(target.0, target.1).expect("clamped inside");
        let goal = if lvl.exact {
            None
        } else {
            join_candidate(lvl, target, s)
        };
        let g = match goal {
            Some(w) => w,
            None => {
                let free = !lvl.occ[t]
                    && (lvl.reserved[t] == NONE || lvl.reserved[t] == id)
                    && lvl.neighbours(t).all(|n| !lvl.occ[n] || n == s);
                if !free {
                    continue;
                }
                t
            }
        };
        let seg = segment(lvl, from, lvl.rc(g), rng);
        let guide = descriptor.guide(&seg);
        if let Some(mut path) = search.route(
            [lvl.rows, lvl.cols],
            s,
            g,
            &guide,
            descriptor.turn_cost(),
            |v| lvl.route_may_use(v, s, g, [id, NONE]),
        ) {
            if !lvl.occ[g] {
                path.push(g);
            }
            lvl.commit(&path);
            return Ok(());
        }
    }
    if lvl.degree(s) <= 1 {
        return Ok(()); // a stub: the footprint cell is the arm's dead end
    }
    Err(LevelFailure::Unrouted {
        structure: p.name.to_string(),
        row: p.centre.0,
        col: p.centre.1,
    })
}

/// A corridor cell within one cell of `target` that an arm may end on (not a structure, not
/// the landing, at most two neighbours), first in raster order.
fn join_candidate(lvl: &Level, target: (i32, i32), s: usize) -> Option<usize> {
    (-1..=1)
        .flat_map(|dr| (-1..=1).map(move |dc| (dr, dc)))
        .filter_map(|(dr, dc)| lvl.index(target.0 + dr, target.1 + dc))
        .find(|&i| lvl.occ[i] && lvl.owner[i] == CORRIDOR && lvl.degree(i) <= 2 && i != s)
}

/// The 24 nearest pairs of cells `(distance, inside, outside)` that may be linked, nearest
/// first: free ends (the landing, or an arm's dead end) inside the linked piece `root` and
/// outside it. With `joins`, plain corridor cells count too.
fn candidate_links(lvl: &Level, label: &[u32], root: u32, joins: bool) -> Vec<(i32, usize, usize)> {
    let usable = |i: usize| {
        lvl.occ[i]
            && match lvl.owner[i] {
                LANDING => lvl.degree(i) == 0,
                CORRIDOR => lvl.degree(i) == 1 || (joins && lvl.degree(i) == 2),
                _ => false,
            }
    };
    let ends = |inside: bool| -> Vec<usize> {
        (0..lvl.occ.len())
            .filter(|&i| usable(i) && (label[i] == root) == inside)
            .collect()
    };
    let (a_ends, b_ends) = (ends(true), ends(false));
    let mut pairs = Nearest::new(24);
    for &a in &a_ends {
        let (ar, ac) = lvl.rc(a);
        for &b in &b_ends {
            let (br, bc) = lvl.rc(b);
            pairs.push(((ar - br).abs() + (ac - bc).abs(), a, b));
        }
    }
    pairs.sorted()
}

/// The `k` smallest of the values pushed, kept as they come: the candidate links are every
/// pair of free ends (or arms), which on a large level with many pieces runs to billions, of
/// which only the nearest few are tried. Memory stays at `k`, and the result is what sorting
/// them all and taking the first `k` gives (the pairs are distinct, so the order is total).
struct Nearest<T> {
    k: usize,
    heap: std::collections::BinaryHeap<T>,
}

impl<T: Ord> Nearest<T> {
    fn new(k: usize) -> Self {
        Self {
            k,
            heap: std::collections::BinaryHeap::with_capacity(k + 1),
        }
    }

    fn push(&mut self, value: T) {
        if self.heap.len() == self.k {
            match self.heap.peek() {
                Some(top) if value < *top => {
                    self.heap.pop();
                }
                _ => return,
            }
        }
        self.heap.push(value);
    }

    /// The values kept, smallest first.
    fn sorted(self) -> Vec<T> {
        self.heap.into_sorted_vec()
    }
}

/// Links every piece of the level to the piece holding the landing (or the first structure),
/// nearest piece first, always between free ends so no junction is made. Without `exact`, a
/// piece with no free end may also be joined onto a corridor.
fn link_components(
    lvl: &mut Level,
    search: &mut Search,
    descriptor: &dyn RouteDescriptor,
    rng: &mut WorldRng,
    landing: Option<usize>,
) -> Result<(), LevelFailure> {
    loop {
        let (label, n) = lvl.components();
        if n <= 1 {
            return Ok(());
        }
        let root = landing
            .map(|l| label[l])
            .unwrap_or_else(|| label[lvl.owner.iter().position(|&o| o == 0).unwrap_or(0)]);
        let mut linked = false;
        for pass in 0..2 {
            if pass == 1 && lvl.exact {
                break;
            }
            let pairs = candidate_links(lvl, &label, root, pass == 1);
            for &(_, a, b) in &pairs {
                let seg = segment(lvl, lvl.rc(a), lvl.rc(b), rng);
                let guide = descriptor.guide(&seg);
                if let Some(path) = search.route(
                    [lvl.rows, lvl.cols],
                    a,
                    b,
                    &guide,
                    descriptor.turn_cost(),
                    |v| lvl.route_may_use(v, a, b, [NONE; 2]),
                ) {
                    lvl.commit(&path);
                    linked = true;
                    break;
                }
            }
            if linked {
                break;
            }
        }
        if !linked {
            return Err(LevelFailure::Pieces { pieces: n });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::{Intersection, Loop, TJunction};

    #[test]
    fn structures_bring_their_own_junctions() {
        let t = structure_counts(&TJunction);
        assert_eq!((t.t_junctions, t.intersections, t.loops), (1, 0, 0));
        let x = structure_counts(&Intersection);
        assert_eq!((x.t_junctions, x.intersections, x.loops), (0, 1, 0));
        let l = structure_counts(&Loop);
        assert_eq!((l.t_junctions, l.intersections, l.loops), (4, 0, 1));
    }

    #[test]
    fn routes_keep_clear_of_other_corridors() {
        let mut lvl = Level::new(10, 10, true);
        // A corridor along row 5.
        for c in 2..8 {
            lvl.occ[5 * 10 + c] = true;
            lvl.owner[5 * 10 + c] = CORRIDOR;
        }
        // Row 4 touches it; row 3 does not.
        assert!(!lvl.route_may_use(4 * 10 + 4, 0, 99, [NONE; 2]));
        assert!(lvl.route_may_use(3 * 10 + 4, 0, 99, [NONE; 2]));
        // Unless the corridor cell it touches is the route's own end.
        assert!(lvl.route_may_use(4 * 10 + 2, 5 * 10 + 2, 99, [NONE; 2]));
    }
}
