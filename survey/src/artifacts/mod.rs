//! Where a world's artifacts go (`[artifacts]`, see `core/src/artifacts.rs`): seeded rules,
//! checked against the collision surface, so every format (SDF, MJCF, USD, URDF, glTF) and
//! the ground truth (`ground_truth/artifacts.json`, `.csv`) place the same objects at the same
//! poses.
//!
//! Placement draws from its own stream (`"artifact-placement"`), one artifact at a time:
//! its class in turn from `classes`, a rule from `placement`, then a tile the rule allows
//! (dead end; T-junction or intersection for a chamber; any tile but a shaft's end for wall
//! and floor) at least `min_distance_from_start` metres from the start along the graph, and a
//! spot in it (`spot`). A spot is checked on the exact passages ([`crate::passages`]): every
//! vertical line under the artifact's footprint (on a raster `STEP` metres apart, then cast
//! exactly every `EXACT` metres, corners and edges included) finds
//! floor within `FLAT` metres of the highest, the artifact stands on that highest floor, and
//! its whole box plus `CLEAR` above is free, as is the rock-free margin `GAP` around it at the
//! height `PROBE_Z` above its base (height-field simulators let a wall stand up to half a
//! metre into the passage). `wall` wants rock within `WALL` metres of the margin, `floor` none
//! within `OPEN` metres. Artifacts keep `min_spacing` metres apart, and never overlap whatever
//! the spacing (their boxes and pads, even with `min_spacing = 0`). A tile with no fitting
//! spot is dropped and another drawn; a rule with no tile left gives way to the next; when no
//! rule has a tile left, placement fails saying what to relax.
//!
//! Without a mesh (`--no-mesh`) the passages are the grid's cells, flat floors.
//!
//! Placed once per world, when its survey is made ([`crate::WorldSurvey::new`]): every format
//! and the ground truth read the same [`PlacedArtifacts`].

mod lookout;
mod spot;

use std::collections::HashMap;

use subtgraph_core::World;
use subtgraph_core::artifacts::{
    Artifact, ArtifactsSection, GraphPlace, HiddenAsked, PlacedArtifacts, Placement,
};
use subtgraph_core::graph::EdgeKind;
use subtgraph_core::grid::Cell;
use subtgraph_core::rng::WorldRng;
use subtgraph_core::tile::TileKind;

use crate::SurveyError;
use crate::axis::Axes;
use crate::passages::Passages;
use lookout::{Lookout, look};
use spot::{Request, spot_in};

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
/// Spots tried per tile before the tile is given up.
const TRIES: usize = 300;
/// ... and when looking for a hidden spot, which few spots of a tile are (a pocket of the
/// wall, the far side of a bend or a boulder): most fail the quick look on the raster.
const HIDDEN_TRIES: usize = 3000;

/// The world's artifacts, with whether each is seen from its tile's passage axis and from
/// where (`sight.rs`); `None` without `[artifacts]`.
pub(crate) fn place(
    world: &World,
    passages: &Passages,
    axes: &Axes,
) -> Result<Option<PlacedArtifacts>, SurveyError> {
    let Some(section) = &world.pipeline.artifacts else {
        return Ok(None);
    };
    let mut placed = place_with(world, section, passages, axes)?;
    // Spots placed without looking at their sight (all of them without `hidden`) are looked
    // at now, all at once: one look for every artifact, as the ground truth reports it.
    if placed.iter().any(|p| p.looked.is_none()) {
        let targets: Vec<(Cell, [f64; 3])> = placed
            .iter()
            .map(|p| (p.artifact.cell, p.artifact.centre()))
            .collect();
        let seen = look(world, passages, axes, &targets, section.hidden > 0.0);
        for (p, s) in placed.iter_mut().zip(seen) {
            p.looked = Some(s);
        }
    }
    let artifacts: Vec<Artifact> = placed
        .into_iter()
        .map(|p| {
            let (visible_from_axis, sight_from) = p.looked.expect("every artifact looked at");
            Artifact {
                visible_from_axis,
                sight_from,
                ..p.artifact
            }
        })
        .collect();
    let hidden = (section.hidden > 0.0).then(|| HiddenAsked {
        share: section.hidden,
        count: section.hidden_count(artifacts.len()),
    });
    Ok(Some(PlacedArtifacts { artifacts, hidden }))
}

/// An artifact as placement found it, with what its sight was checked to be (`None`: not
/// looked at yet).
#[derive(Clone, Debug, PartialEq)]
struct Placed {
    artifact: Artifact,
    looked: Option<(bool, [f64; 3])>,
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

/// The artifacts of `section`, placed one at a time in `passages` (see the module's doc), by
/// id; the sight of those placed with an aim (`hidden`) is what their spot was checked to
/// have.
fn place_with(
    world: &World,
    section: &ArtifactsSection,
    passages: &Passages,
    axes: &Axes,
) -> Result<Vec<Placed>, SurveyError> {
    let mut rng = WorldRng::new(world.resolved.seed, "artifact-placement", 0);
    let count = section.count.max() as usize; // fixed once resolved
    let places = cell_places(world);
    let mut search = Search {
        world,
        section,
        passages,
        axes,
        // Per aim (`Aim as usize`), the tiles each rule may still find a spot in: a tile
        // without room for any spot is dropped from all three, one without a hidden (or
        // seen) spot only from that aim's.
        remaining: {
            let tiles = candidate_tiles(world, section, &places);
            [tiles.clone(), tiles.clone(), tiles]
        },
        places,
        lookouts: HashMap::new(),
        distances: if section.hidden > 0.0 {
            distances(world)
        } else {
            HashMap::new()
        },
    };
    let offset = rng.below(section.classes.len() as u64) as usize;
    let (aims, order) = aims_and_order(world, section, count);
    let mut placed: Vec<Artifact> = Vec::with_capacity(count);
    let mut looks: Vec<Option<(bool, [f64; 3])>> = Vec::with_capacity(count);
    for id in order {
        let class = section.classes[(offset + id) % section.classes.len()];
        let first = rng.below(section.placement.len() as u64) as usize;
        // A hidden artifact that finds no hidden spot anywhere is placed where it fits.
        let tries: &[Aim] = match aims[id] {
            Aim::Hidden => &[Aim::Hidden, Aim::Any],
            Aim::Seen => &[Aim::Seen, Aim::Any],
            Aim::Any => &[Aim::Any],
        };
        let found = tries
            .iter()
            .find_map(|&aim| search.find(aim, first, class, &placed, &mut rng));
        let Some(found) = found else {
            return Err(SurveyError::ArtifactsDoNotFit {
                placed: placed.len(),
                count,
                rules: section.placement.iter().map(|p| p.name()).collect(),
                min_distance_from_start: section.min_distance_from_start,
                class: class.name(),
                min_spacing: section.min_spacing,
            });
        };
        let Found {
            cell,
            graph,
            distance,
            rule,
            spot: (position, yaw, looked),
        } = found;
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
            distance_from_start_m: distance,
            visible_from_axis: false,
            sight_from: [0.0; 3],
        });
        looks.push(looked);
    }
    let mut out: Vec<Placed> = placed
        .into_iter()
        .zip(looks)
        .map(|(artifact, looked)| Placed { artifact, looked })
        .collect();
    out.sort_by_key(|p| p.artifact.id);
    Ok(out)
}

/// Per placement rule of `section`, the indices into `places` of the tiles it allows: not the
/// start, at least `min_distance_from_start` from it along the graph.
fn candidate_tiles(
    world: &World,
    section: &ArtifactsSection,
    places: &[(Cell, GraphPlace, f64)],
) -> Vec<Vec<usize>> {
    section
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
        .collect()
}

/// What each artifact aims for, and the order they are placed in. With `hidden`, which
/// artifacts are hidden comes from a stream of its own, and they are placed first (while the
/// others' spacing leaves them the most room); without it the artifacts are placed in order,
/// by the same draws as before the key existed.
fn aims_and_order(
    world: &World,
    section: &ArtifactsSection,
    count: usize,
) -> (Vec<Aim>, Vec<usize>) {
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
    (aims, order)
}

/// A spot found, and where it is.
struct Found {
    cell: Cell,
    graph: GraphPlace,
    distance: f64,
    rule: Placement,
    spot: spot::Spot,
}

/// What placement keeps from one artifact to the next: the tiles left per aim and rule, and
/// the lookouts found so far.
struct Search<'a> {
    world: &'a World,
    section: &'a ArtifactsSection,
    passages: &'a Passages<'a>,
    axes: &'a Axes<'a>,
    places: Vec<(Cell, GraphPlace, f64)>,
    remaining: [Vec<Vec<usize>>; 3],
    /// Each tile's lookout, found when a spot's sight is first looked at there.
    lookouts: HashMap<Cell, Lookout>,
    distances: HashMap<Cell, f64>,
}

impl Search<'_> {
    /// A spot with `aim` for an artifact of `class`: the rules from the `first` on, in turn;
    /// for each, tiles drawn from those left until one has room (a tile without is dropped).
    fn find(
        &mut self,
        aim: Aim,
        first: usize,
        class: subtgraph_core::artifacts::ArtifactClass,
        placed: &[Artifact],
        rng: &mut WorldRng,
    ) -> Option<Found> {
        let rules = self.section.placement.len();
        for r in 0..rules {
            let ri = (first + r) % rules;
            let rule = self.section.placement[ri];
            while !self.remaining[aim as usize][ri].is_empty() {
                let pick = rng.below(self.remaining[aim as usize][ri].len() as u64) as usize;
                let k = self.remaining[aim as usize][ri][pick];
                let (cell, graph, distance) = self.places[k];
                let (world, axes, distances) = (self.world, self.axes, &self.distances);
                let sight = match aim {
                    Aim::Any => None,
                    Aim::Seen | Aim::Hidden => Some((
                        aim == Aim::Seen,
                        &*self
                            .lookouts
                            .entry(cell)
                            .or_insert_with(|| Lookout::of(world, axes, distances, cell, true)),
                    )),
                };
                let request = Request {
                    cell,
                    class,
                    rule,
                    sight,
                };
                let min_spacing = self.section.min_spacing;
                if let Some(spot) =
                    spot_in(world, self.passages, &request, min_spacing, placed, rng)
                {
                    return Some(Found {
                        cell,
                        graph,
                        distance,
                        rule,
                        spot,
                    });
                }
                if aim == Aim::Any {
                    for lists in &mut self.remaining {
                        if let Some(at) = lists[ri].iter().position(|&x| x == k) {
                            lists[ri].remove(at);
                        }
                    }
                } else {
                    self.remaining[aim as usize][ri].remove(pick);
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::artifacts::ArtifactsSection;
    use subtgraph_core::config::IntRange;

    use crate::axis::AxisCache;

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
        let world = crate::tests::world_with_mesh();
        let passages = Passages::of(&world);
        let cache = AxisCache::new(&world);
        let axes = Axes::new(&world, &passages, &cache);
        let s = section(12);
        let placed = |s: &ArtifactsSection| -> Result<Vec<Artifact>, SurveyError> {
            Ok(place_with(&world, s, &passages, &axes)?
                .into_iter()
                .map(|p| p.artifact)
                .collect())
        };
        let a = placed(&s).unwrap();
        assert_eq!(a.len(), 12);
        assert_eq!(a, placed(&s).unwrap(), "deterministic");
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
                world.cell_at(x.cell.level, x.position[0], x.position[1]),
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
        let Err(err) = placed(&too_many) else {
            panic!("200 artifacts 60 m apart fit in a 24 x 24 grid")
        };
        assert!(
            matches!(err, SurveyError::ArtifactsDoNotFit { count: 200, .. }),
            "{err}"
        );
        assert!(err.to_string().contains("lower artifacts.count"), "{err}");
    }
}
