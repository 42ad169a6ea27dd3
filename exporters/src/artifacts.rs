//! Where a world's artifacts go (`[artifacts]`, see `core/src/artifacts.rs`): seeded rules,
//! checked against the collision surface, so every format (SDF, MJCF, USD, URDF, glTF) and
//! the ground truth (`ground_truth/artifacts.json`, `.csv`) place the same objects at the same
//! poses.
//!
//! Placement draws from its own stream (`"artifact-placement"`), one artifact at a time:
//! its class in turn from `classes`, a rule from `placement`, then a tile the rule allows
//! (dead end; T-junction or intersection for a chamber; any tile but a shaft's end for wall
//! and floor) at least `min_distance_from_start` metres from the start along the graph, and a
//! spot in it. A spot is checked on the exact passages (`ground_truth/inside.rs`): every
//! vertical line under the artifact's footprint (on a raster `STEP` metres apart, then cast
//! exactly every `EXACT` metres, corners and edges included) finds
//! floor within `FLAT` metres of the highest, the artifact stands on that highest floor, and
//! its whole box plus `CLEAR` above is free, as is the rock-free margin `GAP` around it at the
//! height `PROBE_Z` above its base (height-field simulators let a wall stand up to half a
//! metre into the passage). `wall` wants rock within `WALL` metres of the margin, `floor` none
//! within `OPEN` metres. Artifacts keep `min_spacing` metres apart. A tile with no fitting
//! spot is dropped and another drawn; a rule with no tile left gives way to the next; when no
//! rule has a tile left, placement fails saying what to relax.
//!
//! Without a mesh (`--no-mesh`) the passages are the grid's cells, flat floors.

use std::collections::HashMap;
use std::f64::consts::TAU;
use std::sync::Arc;

use serde::Serialize;
use subtgraph_core::World;
use subtgraph_core::artifacts::{ArtifactClass, ArtifactsSection, Placement};
use subtgraph_core::export::ExportError;
use subtgraph_core::graph::EdgeKind;
use subtgraph_core::grid::{Cell, Direction};
use subtgraph_core::rng::WorldRng;
use subtgraph_core::tile::TileKind;

use crate::axis::Axes;
use crate::inside::{Columns, Passages, Span, cell_at};
use crate::sight;

/// Coarsest spacing of the lines sampled under an artifact, metres.
const STEP: f64 = 0.25;
/// Spacing of the exact casts under a chosen spot's footprint, metres.
const EXACT: f64 = 0.1;
/// Most the floor may vary under an artifact, metres.
const FLAT: f64 = 0.1;
/// Free space required above an artifact's top, metres.
const CLEAR: f64 = 0.05;
/// Rock-free margin around an artifact's footprint, metres.
const GAP: f64 = 0.5;
/// A `wall` artifact has rock within this distance beyond its margin, metres.
const WALL: f64 = 0.75;
/// A `floor` artifact has none within this distance beyond its margin, metres.
const OPEN: f64 = 1.0;
/// Height above an artifact's base at which its margin is checked for rock, metres.
const PROBE_Z: f64 = 0.25;
/// An artifact's base stands this far above the highest floor under it, metres.
const LIFT: f64 = 0.001;
/// How much wider than an artifact's footprint its pad is on each side, and half its
/// thickness, metres.
pub const PAD: f64 = 0.05;
/// Spots tried per tile before the tile is given up.
const TRIES: usize = 300;
/// ... and when looking for a hidden spot, which few spots of a tile are (a pocket of the
/// wall, the far side of a bend or a boulder): most fail the quick look on the raster.
const HIDDEN_TRIES: usize = 3000;

/// Where an artifact is on the graph.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum GraphPlace {
    /// In the tile of a node.
    Node {
        /// Node id in `topology.json`.
        node: usize,
    },
    /// In a corridor tile between two nodes.
    Edge {
        /// Edge id in `topology.json`.
        edge: usize,
        /// Metres along the edge from its `from` node to the tile's centre.
        along_m: f64,
    },
}

/// One placed artifact.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Artifact {
    /// Index, 0 up.
    pub id: usize,
    /// `class-id`, unique in the world (`survivor-0`): the name in every format.
    pub name: String,
    /// What it is.
    pub class: ArtifactClass,
    /// The centre of its base, on the floor (world frame, metres).
    pub position: [f64; 3],
    /// Heading of its length (x before the yaw) about z, radians counter-clockwise from east.
    pub yaw: f64,
    /// Its box, `[length, width, height]` metres.
    pub size: [f64; 3],
    /// Its tile.
    pub cell: Cell,
    /// The tile's kind.
    pub tile_kind: TileKind,
    /// The rule it was placed by.
    pub placement: Placement,
    /// Node or edge of its tile.
    pub graph: GraphPlace,
    /// From the start tile's centre to its tile's centre along the graph, metres.
    pub distance_from_start_m: f64,
    /// Whether it is seen from its tile's lookout, and the eye (`sight.rs`): the ground
    /// truth's `visible_from_axis` and `sight_from`. [`place`] fills it (from the spot's own
    /// look with `[artifacts] hidden`, else by one look for all at once).
    #[serde(skip)]
    pub sight: Option<(bool, [f64; 3])>,
}

impl Artifact {
    /// The centre of its box.
    pub fn centre(&self) -> [f64; 3] {
        let p = self.position;
        [p[0], p[1], p[2] + 0.5 * self.size[2]]
    }

    /// Its pad, `(centre, size)`: a static box under it in the physics formats, `PAD` wider
    /// than its footprint on every side, its top at the artifact's base, `2 PAD` thick (so it
    /// reaches into the floor: the base is at most `FLAT` above the floor under the
    /// footprint), turned by the same yaw. Simulators collide a small box with a rough
    /// triangle mesh or height field through contact sets that change from step to step:
    /// without pads, artifacts dropped from 0.5 m in our tests bounced and slid up to 1.6 m
    /// (MuJoCo) and 1.3 m (PyBullet) from their poses; on pads they rest within centimetres
    /// (box on box is solved exactly), and a robot still finds each where the ground truth
    /// says.
    pub fn pad(&self) -> ([f64; 3], [f64; 3]) {
        let p = self.position;
        (
            [p[0], p[1], p[2] - PAD],
            [
                self.size[0] + 2.0 * PAD,
                self.size[1] + 2.0 * PAD,
                2.0 * PAD,
            ],
        )
    }

    /// Its orientation as a quaternion `[x, y, z, w]`.
    pub fn quaternion_xyzw(&self) -> [f64; 4] {
        [0.0, 0.0, (0.5 * self.yaw).sin(), (0.5 * self.yaw).cos()]
    }
}

/// The world's artifacts: none without `[artifacts]`. Placed once per world and shared by
/// every format that holds them and the ground truth ([`World::derived`]).
pub fn place(world: &World) -> Result<Arc<Vec<Artifact>>, ExportError> {
    /// The placement as a world keeps it.
    struct Placed(Result<Arc<Vec<Artifact>>, String>);
    let placed = world.derived(|world| {
        Placed(match &world.pipeline.artifacts {
            None => Ok(Arc::new(Vec::new())),
            Some(section) => {
                // One look at the free space for placement and for the sight flags.
                let passages = Passages::of(world);
                place_with(world, section, &passages)
                    .map(|mut placed| {
                        if placed.iter().any(|a| a.sight.is_none()) {
                            let seen = look(world, &passages, &placed);
                            for (a, s) in placed.iter_mut().zip(seen) {
                                a.sight = Some(s);
                            }
                        }
                        Arc::new(placed)
                    })
                    .map_err(|e| e.to_string())
            }
        })
    });
    placed.0.clone().map_err(ExportError::Unsupported)
}

/// Whether each artifact is seen from its tile's passage axis, and the eye it is looked at
/// from (`sight.rs`): the ground truth's `visible_from_axis` and `sight_from`. With `hidden`,
/// from where a robot first comes near.
pub(crate) fn look(
    world: &World,
    passages: &Passages,
    artifacts: &[Artifact],
) -> Vec<(bool, [f64; 3])> {
    if matches!(passages, Passages::Grid(_)) {
        return artifacts
            .iter()
            .map(|a| (true, world.cell_position(a.cell)))
            .collect();
    }
    let mut cells: Vec<_> = artifacts.iter().map(|a| a.cell).collect();
    cells.sort();
    cells.dedup();
    let axes = Axes::of_cells(world, passages, &cells);
    // With `hidden`, from where a robot first comes near (see `sight.rs`).
    let approach = world
        .pipeline
        .artifacts
        .as_ref()
        .is_some_and(|s| s.hidden > 0.0);
    let distances = if approach {
        distances(world)
    } else {
        HashMap::new()
    };
    let lookouts: HashMap<Cell, Lookout> = cells
        .iter()
        .map(|&c| (c, Lookout::of(world, &axes, &distances, c, approach)))
        .collect();
    artifacts
        .iter()
        .map(|a| {
            let target = a.centre();
            let eye = lookouts[&a.cell].eye(target);
            (sight::clear(passages, eye, target), eye)
        })
        .collect()
}

/// Graph distance from the start and graph place of every occupied cell of a corridor or node.
fn cell_places(world: &World) -> Vec<(Cell, GraphPlace, f64)> {
    let g = &world.graph;
    let start = world
        .start
        .and_then(|s| g.nodes.iter().position(|n| n.cell == s));
    let mut dist = vec![f64::INFINITY; g.nodes.len()];
    if let Some(s) = start {
        dist[s] = 0.0;
        // Bellman-Ford rounds: graphs are small (hundreds of nodes) and this is exact.
        let mut changed = true;
        while changed {
            changed = false;
            for e in &g.edges {
                for (a, b) in [(e.from, e.to), (e.to, e.from)] {
                    let d = dist[a] + e.length_m;
                    if d < dist[b] {
                        dist[b] = d;
                        changed = true;
                    }
                }
            }
        }
    }
    let mut out: Vec<(Cell, GraphPlace, f64)> = g
        .nodes
        .iter()
        .map(|n| (n.cell, GraphPlace::Node { node: n.id }, dist[n.id]))
        .collect();
    for e in g.edges.iter().filter(|e| e.kind == EdgeKind::Corridor) {
        let n = e.cells.len();
        if n < 3 {
            continue;
        }
        let per = e.length_m / (n - 1) as f64;
        for (k, &c) in e.cells.iter().enumerate().take(n - 1).skip(1) {
            let along = k as f64 * per;
            let d = (dist[e.from] + along).min(dist[e.to] + e.length_m - along);
            out.push((
                c,
                GraphPlace::Edge {
                    edge: e.id,
                    along_m: along,
                },
                d,
            ));
        }
    }
    out.sort_by_key(|(c, _, _)| (c.level, c.row, c.col));
    out.dedup_by_key(|(c, _, _)| *c);
    out
}

/// Graph distance from the start of every occupied cell of a corridor or node.
pub(crate) fn distances(world: &World) -> HashMap<Cell, f64> {
    cell_places(world)
        .into_iter()
        .map(|(c, _, d)| (c, d))
        .collect()
}

/// Where the lines of sight to artifacts in one tile start (`sight.rs`).
pub(crate) struct Lookout {
    /// The tile's axis points (anchor first).
    points: Vec<[f64; 3]>,
    /// With `[artifacts] hidden`, the robot's way through the tile from the opening nearest
    /// the start; `None` without the key, or for a tile entered from no known opening.
    walk: Option<Vec<[f64; 3]>>,
}

impl Lookout {
    /// The lookout of `cell`, from its axis; `approach` with `[artifacts] hidden`.
    pub(crate) fn of(
        world: &World,
        axes: &Axes,
        distances: &HashMap<Cell, f64>,
        cell: Cell,
        approach: bool,
    ) -> Lookout {
        let walk = approach
            .then(|| {
                Direction::ALL
                    .into_iter()
                    .filter_map(|d| {
                        let n = world.occupancy.neighbour(cell, d)?;
                        let dist = *distances.get(&n)?;
                        let walk = axes.walk_from(cell, d)?;
                        dist.is_finite().then_some((dist, walk))
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, walk)| walk)
            })
            .flatten();
        Lookout {
            points: axes.tile_points(world, cell),
            walk,
        }
    }

    /// The eye looking at `target`.
    pub(crate) fn eye(&self, target: [f64; 3]) -> [f64; 3] {
        match &self.walk {
            Some(walk) => sight::approach_eye(walk, target),
            None => sight::eye(&self.points, target),
        }
    }
}

fn allowed(rule: Placement, kind: TileKind) -> bool {
    match rule {
        Placement::DeadEnd => kind == TileKind::DeadEnd,
        Placement::Chamber => matches!(kind, TileKind::TJunction | TileKind::Intersection),
        Placement::Wall | Placement::Floor => {
            !matches!(kind, TileKind::ShaftUp | TileKind::ShaftLanding)
        }
    }
}

/// What a spot's line of sight from its tile's passage axis must be (`sight.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Aim {
    /// Not looked at (`hidden = 0`, as before the key existed).
    Any,
    /// Seen from the axis.
    Seen,
    /// Out of the axis's sight.
    Hidden,
}

/// [`place`] with the section and passages given.
pub(crate) fn place_with(
    world: &World,
    section: &ArtifactsSection,
    passages: &Passages,
) -> Result<Vec<Artifact>, ExportError> {
    let mut rng = WorldRng::new(world.resolved.seed, "artifact-placement", 0);
    let count = section.count.max() as usize; // fixed once resolved
    let places = cell_places(world);
    let tiles: Vec<Vec<usize>> = section
        .placement
        .iter()
        .map(|&rule| {
            (0..places.len())
                .filter(|&k| {
                    let (c, _, d) = places[k];
                    Some(c) != world.start
                        && d >= section.min_distance_from_start
                        && d.is_finite()
                        && world.tiles.get(c).is_some_and(|t| allowed(rule, t.kind))
                })
                .collect()
        })
        .collect();
    // Per aim (`Aim as usize`), the tiles each rule may still find a spot in: a tile without
    // room for any spot is dropped from all three, one without a hidden (or seen) spot only
    // from that aim's.
    let mut remaining: [Vec<Vec<usize>>; 3] = [tiles.clone(), tiles.clone(), tiles];
    let offset = rng.below(section.classes.len() as u64) as usize;
    // With `hidden`, which artifacts are hidden comes from a stream of its own, and they are
    // placed first (while the others' spacing leaves them the most room); without it the
    // artifacts are placed in order, by the same draws as before the key existed.
    let want_hidden = section.hidden_count(count);
    let mut aims = vec![Aim::Any; count];
    let mut order: Vec<usize> = (0..count).collect();
    if section.hidden > 0.0 {
        let mut ids = order.clone();
        WorldRng::new(world.resolved.seed, "artifact-hidden", 0).shuffle(&mut ids);
        for (k, &id) in ids.iter().enumerate() {
            aims[id] = if k < want_hidden {
                Aim::Hidden
            } else {
                Aim::Seen
            };
        }
        order.sort_by_key(|&id| (aims[id] != Aim::Hidden, id));
    }
    // Each tile's lookout, found when a spot's sight is first looked at there.
    let mut lookouts: HashMap<Cell, Lookout> = HashMap::new();
    let distances = if section.hidden > 0.0 {
        distances(world)
    } else {
        HashMap::new()
    };
    let mut placed: Vec<Artifact> = Vec::with_capacity(count);
    for id in order {
        let class = section.classes[(offset + id) % section.classes.len()];
        let first = rng.below(section.placement.len() as u64) as usize;
        let mut found = None;
        // A hidden artifact that finds no hidden spot anywhere is placed where it fits.
        let tries: &[Aim] = match aims[id] {
            Aim::Hidden => &[Aim::Hidden, Aim::Any],
            Aim::Seen => &[Aim::Seen, Aim::Any],
            Aim::Any => &[Aim::Any],
        };
        'aims: for &aim in tries {
            for r in 0..section.placement.len() {
                let ri = (first + r) % section.placement.len();
                let rule = section.placement[ri];
                while !remaining[aim as usize][ri].is_empty() {
                    let pick = rng.below(remaining[aim as usize][ri].len() as u64) as usize;
                    let k = remaining[aim as usize][ri][pick];
                    let (cell, graph, dist) = places[k];
                    let sight = match aim {
                        Aim::Any => None,
                        Aim::Seen | Aim::Hidden => Some((
                            aim == Aim::Seen,
                            &*lookouts.entry(cell).or_insert_with(|| {
                                let axes = Axes::of_cells(world, passages, &[cell]);
                                Lookout::of(world, &axes, &distances, cell, true)
                            }),
                        )),
                    };
                    let request = Request {
                        cell,
                        class,
                        rule,
                        sight,
                    };
                    match spot_in(world, passages, &request, section, &placed, &mut rng) {
                        Some((position, yaw, looked)) => {
                            found = Some((cell, graph, dist, rule, position, yaw, looked));
                            break 'aims;
                        }
                        None => {
                            let drop = |list: &mut Vec<usize>| {
                                if let Some(at) = list.iter().position(|&x| x == k) {
                                    list.remove(at);
                                }
                            };
                            if aim == Aim::Any {
                                for lists in &mut remaining {
                                    drop(&mut lists[ri]);
                                }
                            } else {
                                remaining[aim as usize][ri].remove(pick);
                            }
                        }
                    }
                }
            }
        }
        let Some((cell, graph, dist, rule, position, yaw, looked)) = found else {
            let rules: Vec<&str> = section.placement.iter().map(|p| p.name()).collect();
            return Err(ExportError::Unsupported(format!(
                "artifacts: placed {} of {count}: no tile allowed by placement = {rules:?} at least {} m from the start along the passages has room for a {} {} m from the others; lower artifacts.count, artifacts.min_spacing or artifacts.min_distance_from_start, or allow more placement rules",
                placed.len(),
                section.min_distance_from_start,
                class.name(),
                section.min_spacing
            )));
        };
        placed.push(Artifact {
            id,
            name: format!("{}-{id}", class.name()),
            class,
            position,
            yaw,
            size: class.size(),
            cell,
            tile_kind: world.tiles.get(cell).map_or(TileKind::Straight, |t| t.kind),
            placement: rule,
            graph,
            distance_from_start_m: dist,
            sight: looked,
        });
    }
    placed.sort_by_key(|a| a.id);
    Ok(placed)
}

/// A spot [`spot_in`] found: base centre, yaw, and what its sight was checked to be.
type Spot = ([f64; 3], f64, Option<(bool, [f64; 3])>);

/// What [`spot_in`] looks for.
struct Request<'a> {
    cell: Cell,
    class: ArtifactClass,
    rule: Placement,
    /// Whether the spot must be seen (`true`) or hidden (`false`) from the tile's lookout;
    /// `None`: not looked at.
    sight: Option<(bool, &'a Lookout)>,
}

/// A spot in `cell` for an artifact of `class` by `rule`: its base centre and yaw.
fn spot_in(
    world: &World,
    passages: &Passages,
    request: &Request,
    section: &ArtifactsSection,
    placed: &[Artifact],
    rng: &mut WorldRng,
) -> Option<Spot> {
    let Request {
        cell,
        class,
        rule,
        sight,
    } = *request;
    let pitch = world.resolved.tile_pitch;
    let lh = world.resolved.level_height;
    let [cx, cy, nominal] = world.cell_position(cell);
    // Where the tile set lifted the tile's floor (a hill's tiles), the band moves up with it.
    let [low, high] = world.floor_lift(cell);
    let size = class.size();
    let half_diag = 0.5 * size[0].hypot(size[1]);
    let reach = half_diag + GAP + WALL.max(OPEN);
    // Most lines a tile's raster may have: 400 a side (finer for small pitches).
    let step = STEP.max(pitch / 400.0);
    let b = [
        cx - 0.5 * pitch - reach,
        cy - 0.5 * pitch - reach,
        cx + 0.5 * pitch + reach,
        cy + 0.5 * pitch + reach,
    ];
    let cols = Columns {
        x0: b[0],
        y0: b[1],
        step,
        nx: ((b[2] - b[0]) / step).ceil() as usize,
        ny: ((b[3] - b[1]) / step).ceil() as usize,
    };
    let rows = passages
        .raster_within(&cols, b, |_, spans, open| {
            spans
                .iter()
                .filter(|s| open.binary_search(&s.i).is_err())
                .copied()
                .collect::<Vec<Span>>()
        })
        .rows;
    let (nx, ny) = (cols.nx, cols.ny);
    // Each line's stretch of this level: the lowest free stretch reaching 0.3 m above the
    // nominal floor whose floor is below half the level height.
    let mut level_span: Vec<Option<[f64; 2]>> = vec![None; nx * ny];
    for (j, row) in rows.iter().enumerate() {
        for s in row {
            let slot = &mut level_span[j * nx + s.i as usize];
            if slot.is_none() && s.z1 >= nominal + low + 0.3 && s.z0 <= nominal + high + 0.5 * lh {
                *slot = Some([s.z0, s.z1]);
            }
        }
    }
    // With a sight to look for, every free stretch of each line: a quick look along a
    // spot's line of sight before the exact one.
    let mut free: Vec<Vec<[f64; 2]>> = Vec::new();
    if sight.is_some() {
        free = vec![Vec::new(); nx * ny];
        for (j, row) in rows.iter().enumerate() {
            for s in row {
                free[j * nx + s.i as usize].push([s.z0, s.z1]);
            }
        }
    }
    let index = |x: f64, y: f64| -> Option<usize> {
        let i = ((x - cols.x0) / step).floor();
        let j = ((y - cols.y0) / step).floor();
        (i >= 0.0 && j >= 0.0 && (i as usize) < nx && (j as usize) < ny)
            .then(|| j as usize * nx + i as usize)
    };
    let mut candidates: Vec<usize> = (0..nx * ny)
        .filter(|&k| {
            level_span[k].is_some()
                && cell_at(world, cell.level, cols.x(k % nx), cols.y(k / nx)) == Some(cell)
        })
        .collect();
    rng.shuffle(&mut candidates);
    let samples = |n: f64| ((n / step).ceil() as usize).max(1) + 1;
    let (su, sv) = (samples(size[0]), samples(size[1]));
    // Line offsets around a spot by their distance beyond the footprint's circle, nearest first.
    let r = (reach / step).ceil() as i64;
    let mut ring: Vec<(f64, i64, i64)> = (-r..=r)
        .flat_map(|dj| (-r..=r).map(move |di| (di, dj)))
        .map(|(di, dj)| {
            (
                ((di * di + dj * dj) as f64).sqrt() * step - half_diag,
                di,
                dj,
            )
        })
        .filter(|o| o.0 <= GAP + WALL.max(OPEN))
        .collect();
    ring.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    let look = match rule {
        Placement::Wall => GAP + WALL,
        Placement::Floor => GAP + OPEN,
        Placement::DeadEnd | Placement::Chamber => GAP,
    };
    let tries = match sight {
        Some((false, _)) => HIDDEN_TRIES,
        _ => TRIES,
    };
    for &k in candidates.iter().take(tries) {
        let (x, y) = (cols.x(k % nx), cols.y(k / nx));
        let yaw = rng.unit() * TAU;
        let (sin, cos) = yaw.sin_cos();
        let mut lines = Vec::with_capacity(su * sv);
        let mut ok = true;
        for u in 0..su {
            for v in 0..sv {
                let lx = size[0] * (u as f64 / (su - 1) as f64 - 0.5);
                let ly = size[1] * (v as f64 / (sv - 1) as f64 - 0.5);
                match index(x + cos * lx - sin * ly, y + sin * lx + cos * ly) {
                    Some(l) if level_span[l].is_some() => lines.push(l),
                    _ => {
                        ok = false;
                        break;
                    }
                }
            }
        }
        if !ok {
            continue;
        }
        let floors = lines.iter().map(|&l| level_span[l].expect("checked")[0]);
        let (lo, hi) = floors.fold((f64::MAX, f64::MIN), |(a, b), f| (a.min(f), b.max(f)));
        if hi - lo > FLAT {
            continue;
        }
        let top = hi + size[2] + CLEAR;
        if lines
            .iter()
            .any(|&l| level_span[l].expect("checked")[1] < top)
        {
            continue;
        }
        if placed.iter().any(|a| {
            let p = a.position;
            (p[0] - x).hypot(p[1] - y).hypot(p[2] - hi) < section.min_spacing
        }) {
            continue;
        }
        // Rock around it at the probe height, by distance beyond the footprint's circle.
        let z = hi + PROBE_Z;
        let rock = |l: usize| !level_span[l].is_some_and(|s| s[0] <= z && z <= s[1]);
        let (ci, cj) = ((k % nx) as i64, (k / nx) as i64);
        // The nearest rock line, looked for only as far as the rule needs.
        let mut nearest = f64::INFINITY;
        for &(d, di, dj) in &ring[..ring.partition_point(|r| r.0 <= look)] {
            let (i, j) = (ci + di, cj + dj);
            let outside = i < 0 || j < 0 || i as usize >= nx || j as usize >= ny;
            if outside || rock(j as usize * nx + i as usize) {
                nearest = d;
                break;
            }
        }
        let fits = nearest > GAP
            && match rule {
                Placement::Wall => nearest <= GAP + WALL,
                Placement::Floor => nearest > GAP + OPEN,
                Placement::DeadEnd | Placement::Chamber => true,
            };
        if !fits {
            continue;
        }
        // The line of sight on the raster (each point on its nearest line; a point outside
        // the raster is left to the exact look): a spot that looks the wrong way there is
        // not cast exactly.
        if let Some((seen, lookout)) = sight {
            let target = [x, y, hi + LIFT + 0.5 * size[2]];
            let rock: Vec<bool> = sight::samples(lookout.eye(target), target)
                .iter()
                .map(|p| {
                    index(p[0], p[1])
                        .is_some_and(|l| !free[l].iter().any(|s| s[0] <= p[2] && p[2] <= s[1]))
                })
                .collect();
            if !sight::as_aimed(seen, &rock) {
                continue;
            }
        }
        // The raster's lines are `step` apart: the floor between them, under the footprint's
        // exact corners and edges, may stand a little higher. Cast there and stand on the
        // highest, a millimetre above it.
        // Every `EXACT` metres at most, quarters of each side included.
        let exact = |n: f64| 4 * ((n / (4.0 * EXACT)).ceil() as usize).max(1) + 1;
        let (eu, ev) = (exact(size[0]), exact(size[1]));
        let mut points = Vec::with_capacity(eu * ev);
        for u in 0..eu {
            for v in 0..ev {
                let lx = size[0] * (u as f64 / (eu - 1) as f64 - 0.5);
                let ly = size[1] * (v as f64 / (ev - 1) as f64 - 0.5);
                points.push([x + cos * lx - sin * ly, y + sin * lx + cos * ly]);
            }
        }
        let stretches: Vec<Option<[f64; 2]>> = passages
            .columns_at(&points)
            .into_iter()
            .map(|column| {
                column
                    .into_iter()
                    .find(|s| s[0] <= hi + FLAT && hi + FLAT <= s[1])
            })
            .collect();
        let Some((low, exact)) = stretches
            .iter()
            .map(|s| s.map(|s| s[0]))
            .try_fold((lo, hi), |(a, b), f| f.map(|f| (a.min(f), b.max(f))))
        else {
            continue;
        };
        let base = exact + LIFT;
        if base - low > FLAT
            || stretches
                .iter()
                .flatten()
                .any(|s| s[1] < base + size[2] + CLEAR)
        {
            continue;
        }
        let mut looked = None;
        if let Some((seen, lookout)) = sight {
            let target = [x, y, base + 0.5 * size[2]];
            let eye = lookout.eye(target);
            let rock = sight::blocked(passages, eye, target);
            if !sight::as_aimed(seen, &rock) {
                continue;
            }
            looked = Some((seen, eye));
        }
        return Some(([x, y, base], yaw, looked));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::artifacts::ArtifactsSection;
    use subtgraph_core::config::IntRange;

    fn section(count: u32) -> ArtifactsSection {
        ArtifactsSection {
            count: IntRange::Fixed(count),
            min_distance_from_start: 20.0,
            min_spacing: 5.0,
            ..ArtifactsSection::default()
        }
    }

    #[test]
    fn artifacts_stand_on_the_floor_in_free_space_by_their_rules() {
        let world = crate::ground_truth::tests::world_with_mesh();
        let passages = Passages::of(&world);
        let s = section(12);
        let a = place_with(&world, &s, &passages).unwrap();
        assert_eq!(a.len(), 12);
        assert_eq!(
            a,
            place_with(&world, &s, &passages).unwrap(),
            "deterministic"
        );
        for x in &a {
            // The floor under its centre is at most FLAT below its base, and its box is free.
            let col = passages.column(x.position[0], x.position[1]);
            let s = col
                .iter()
                .find(|s| s[0] <= x.position[2] + 1e-9 && x.position[2] - FLAT - 1e-9 <= s[0])
                .unwrap_or_else(|| panic!("{} not on a floor: {col:?}", x.name));
            assert!(s[1] >= x.position[2] + x.size[2], "{} in rock", x.name);
            assert!(x.distance_from_start_m >= 20.0);
            assert_eq!(
                cell_at(&world, x.cell.level, x.position[0], x.position[1]),
                Some(x.cell)
            );
            assert!(allowed(x.placement, x.tile_kind));
            for y in &a[..x.id] {
                let d = (0..3)
                    .map(|k| (x.position[k] - y.position[k]).powi(2))
                    .sum::<f64>();
                assert!(d.sqrt() >= 5.0, "{} and {} too close", x.name, y.name);
            }
        }
        // The batched exact casts agree with casting line by line.
        let pts: Vec<[f64; 2]> = a
            .iter()
            .flat_map(|x| {
                let p = x.position;
                [[p[0] + 0.03, p[1] - 0.02], [p[0] - 0.31, p[1] + 0.17]]
            })
            .collect();
        let one_by_one: Vec<Vec<[f64; 2]>> =
            pts.iter().map(|p| passages.column(p[0], p[1])).collect();
        assert_eq!(passages.columns_at(&pts[..2]), one_by_one[..2]);
        for (p, want) in pts.iter().zip(&one_by_one) {
            assert_eq!(&passages.columns_at(&[*p])[0], want);
        }
        let too_many = ArtifactsSection {
            min_spacing: 60.0,
            ..section(200)
        };
        let Err(err) = place_with(&world, &too_many, &passages) else {
            panic!("200 artifacts 60 m apart fit in a 24 x 24 grid")
        };
        assert!(err.to_string().contains("lower artifacts.count"), "{err}");
    }
}
