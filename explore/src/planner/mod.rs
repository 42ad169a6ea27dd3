//! The baseline explorer: frontier-based exploration (Yamauchi, "A frontier-based approach for
//! autonomous exploration", CIRA 1997) on each robot's own voxel map, with the coordination of
//! Burgard et al. ("Coordinated multi-robot exploration", IEEE T-RO 2005): a frontier another
//! robot is heading for is worth less to the others, as far as they have heard (goals travel
//! over the radio like everything else).
//!
//! **Where a robot can be** ([`space`]): a ground robot's places are the free voxels standing
//! on an occupied one (its floor) with no rock in the voxel above; it moves to a neighbouring
//! column's place at most one voxel up or down. An aerial robot's places are the free voxels
//! with no occupied voxel beside them (its half-metre clearance), and it moves to any of the
//! six neighbours. A **frontier** is a place next to the unknown: for a ground robot, a
//! neighbouring column with no known floor or wall at its height and some voxel unknown; for
//! an aerial one, an unknown neighbour.
//!
//! **Choosing a goal**: Dijkstra's search from the robot over its places (a place beside rock
//! costs more, so paths keep to the middle of passages) meets frontier places in order of
//! distance and groups neighbouring ones as it goes; each group of at least [`MIN_GROUP`]
//! places is scored `gain - distance`: its size (at most [`GAIN_CAP`] voxels, each worth a
//! metre of driving), less the path's length in metres, less [`CLAIMED_PENALTY`] when another
//! robot's last heard goal is within [`CLAIM_RADIUS`]. The search ends where no farther group
//! could score better. The best group's nearest place is the goal, and
//! the path to it is followed ([`follow`]) until the next plan, every [`REPLAN_S`] seconds or
//! sooner when the goal is reached or the robot is stuck (no progress for [`STUCK_S`]: the
//! goal is set aside for good, and the robot backs out the way it came for a few seconds:
//! a motion it made is one it can undo, whatever rock it has climbed).
//!
//! **Reporting**: a robot that has held an undelivered report for [`RETURN_AFTER_S`] heads
//! back to the last place it had a link to the base station, delivers, and explores on. With
//! no frontier left it goes back there too and waits.

pub mod follow;
pub mod places;
pub mod queue;
pub mod space;

use rustc_hash::FxHashMap;

use crate::body::{Body, Command, State};
use crate::map::VoxelMap;
use space::{Place, Space};

/// Frontier places a group needs to be a goal (fewer are holes between a LiDAR's rings).
pub const MIN_GROUP: usize = 6;
/// The most voxels a frontier group is worth.
pub const GAIN_CAP: usize = 40;
/// What a goal another robot heads for costs a frontier near it, metres of driving.
pub const CLAIMED_PENALTY: f64 = 40.0;
/// How near another robot's goal a frontier counts as claimed, metres.
pub const CLAIM_RADIUS: f64 = 15.0;
/// Seconds between plans.
pub const REPLAN_S: f64 = 3.0;
/// Seconds without 0.3 m of progress that make a robot stuck.
pub const STUCK_S: f64 = 5.0;
/// Seconds an undelivered report is held before its robot heads back to a link.
pub const RETURN_AFTER_S: f64 = 300.0;
/// Farthest a search goes, metres of path.
const SEARCH_LIMIT_M: f64 = 400.0;
/// Seconds a stuck robot backs away.
const BACK_OFF_S: f64 = 4.0;

/// What a robot is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// Heading for a frontier.
    Explore,
    /// Heading back to a link to deliver reports.
    Return,
    /// Nothing left to explore within reach: waiting at the last link.
    Done,
}

/// One robot's planner.
#[derive(Clone, Debug)]
pub struct Planner {
    /// What it is doing.
    pub mode: Mode,
    /// The place it heads for, world frame.
    pub goal: Option<[f64; 3]>,
    /// The path to the goal, world frame (place centres).
    pub path: Vec<[f64; 3]>,
    /// Goals set aside (the robot got stuck on the way).
    pub set_aside: Vec<[f64; 3]>,
    next_plan: f64,
    progress: (f64, [f64; 3]),
    backing_until: f64,
    retrace: Vec<[f64; 3]>,
    /// What it keeps of its map between plans.
    places: places::Places,
    /// The last search, its tables kept for the next (cleared, not freed).
    search: Search,
}

/// What a plan is asked with.
pub struct Situation<'a> {
    /// Seconds since the start.
    pub time: f64,
    /// The body.
    pub body: &'a Body,
    /// Its state.
    pub state: &'a State,
    /// Its map.
    pub map: &'a VoxelMap,
    /// Other robots' goals, as last heard.
    pub claimed: &'a [[f64; 3]],
    /// Whether it holds a report older than [`RETURN_AFTER_S`].
    pub must_report: bool,
    /// Where it last had a link to the base station.
    pub last_link: [f64; 3],
    /// Where it has been lately, newest last (to back out the way it came).
    pub trail: &'a [[f64; 3]],
    /// Places it found it could not drive into.
    pub blocked: &'a rustc_hash::FxHashSet<u64>,
}

impl Default for Planner {
    fn default() -> Self {
        Planner {
            mode: Mode::Explore,
            goal: None,
            path: Vec::new(),
            set_aside: Vec::new(),
            next_plan: 0.0,
            progress: (0.0, [f64::NAN; 3]),
            backing_until: f64::NEG_INFINITY,
            retrace: Vec::new(),
            places: places::Places::default(),
            search: Search::default(),
        }
    }
}

impl Planner {
    /// The command for this control step, planning again when due.
    pub fn command(&mut self, s: &Situation<'_>) -> Command {
        let p = s.state.position;
        if s.time < self.backing_until {
            // Back along the way it came (the motion it made is one it can undo).
            return follow::back(s.body, s.state, &self.retrace);
        }
        let moved = dist(p, self.progress.1);
        // A NaN distance counts as progress (nothing to wait for).
        if moved > 0.3 || moved.is_nan() {
            self.progress = (s.time, p);
        } else if self.goal.is_some() && s.time - self.progress.0 > STUCK_S {
            if let Some(g) = self.goal.take() {
                self.set_aside.push(g);
            }
            self.path.clear();
            self.progress = (s.time, p);
            self.retrace = s.trail.to_vec();
            self.backing_until = s.time + BACK_OFF_S;
            self.next_plan = self.backing_until;
            return Command::default();
        }
        let reached = self.goal.is_some_and(|g| dist2d(g, p) < 1.0);
        if s.time >= self.next_plan || reached || self.goal.is_none() {
            self.plan(s);
            self.next_plan = s.time + REPLAN_S;
        }
        follow::command(s.body, s.state, &self.path)
    }

    /// Plans: a frontier to explore, or the way back to a link.
    fn plan(&mut self, s: &Situation<'_>) {
        let space =
            Space::around(s.map, s.body, s.state.position, s.blocked).keeping(&mut self.places);
        let Some(start) = space.place_near(s.state.position) else {
            self.goal = None;
            self.path.clear();
            return;
        };
        let search = &mut self.search;
        search.run(&space, start);
        let explore = if s.must_report {
            None
        } else {
            best_frontier(&space, search, s, &self.set_aside)
        };
        let target = match explore {
            Some(t) => {
                self.mode = Mode::Explore;
                Some(t)
            }
            None => {
                self.mode = if s.must_report {
                    Mode::Return
                } else {
                    Mode::Done
                };
                search.nearest_to(&space, s.last_link)
            }
        };
        match target {
            Some(t) => {
                self.path = search.path_to(&space, t);
                self.goal = self.path.last().copied();
            }
            None => {
                self.goal = None;
                self.path.clear();
            }
        }
    }
}

/// What Dijkstra's search found: each place's path length and parent, and the frontier
/// places in the order met, grouped.
#[derive(Clone, Debug, Default)]
struct Search {
    cost: FxHashMap<u64, (u32, u64)>,
    frontiers: Vec<(Place, u32)>,
    /// Each frontier place's group (a union-find forest over `frontiers`).
    parent: Vec<usize>,
    /// Each group root's size.
    size: Vec<usize>,
    /// Each frontier place's index in `frontiers`, by key.
    index: FxHashMap<u64, usize>,
    /// The places to visit, nearest first.
    queue: queue::Queue,
}

impl Search {
    fn root(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// Adds a frontier place, joining it to the groups of its frontier neighbours
    /// (26-connected); returns its group's size.
    fn add_frontier(&mut self, p: Place, c: u32) -> usize {
        let i = self.frontiers.len();
        self.frontiers.push((p, c));
        self.parent.push(i);
        self.size.push(1);
        self.index.insert(p.key(), i);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let q = Place([p.0[0] + dx, p.0[1] + dy, p.0[2] + dz]);
                    let Some(&j) = self.index.get(&q.key()) else {
                        continue;
                    };
                    let (a, b) = (self.root(i), self.root(j));
                    if a != b {
                        // The older root stays: a group is named by its first (nearest) place.
                        let (keep, join) = if a < b { (a, b) } else { (b, a) };
                        self.parent[join] = keep;
                        self.size[keep] += self.size[join];
                    }
                }
            }
        }
        let r = self.root(i);
        self.size[r]
    }
}

impl Search {
    /// Dijkstra's search from `start` over the places, frontier places grouped as they are
    /// met. It stops [`GAIN_CAP`] + [`CLAIMED_PENALTY`] metres of path beyond the first group
    /// of [`MIN_GROUP`] places (no group farther can score better: a group is worth at most
    /// [`GAIN_CAP`]), or at [`SEARCH_LIMIT_M`].
    fn run(&mut self, space: &Space<'_>, start: Place) {
        let per_metre = 10.0 / space.voxel();
        let mut limit = (SEARCH_LIMIT_M * per_metre) as u32;
        let beyond = ((GAIN_CAP as f64 + CLAIMED_PENALTY) * per_metre) as u32;
        self.cost.clear();
        self.frontiers.clear();
        self.parent.clear();
        self.size.clear();
        self.index.clear();
        self.queue.clear();
        let found = self;
        let k0 = start.key();
        found.cost.insert(k0, (0, k0));
        found.queue.push(0, k0);
        let mut near = Vec::with_capacity(26);
        let mut grouped = false;
        while let Some((c, k)) = found.queue.pop() {
            if found.cost.get(&k).is_some_and(|&(best, _)| best < c) {
                continue;
            }
            if c > limit {
                break;
            }
            let u = Place::from_key(k);
            // Frontier places are ends: the unknown beyond is not driven through.
            if space.visit(u, k != k0, &mut near) {
                let size = found.add_frontier(u, c);
                if !grouped && size >= MIN_GROUP {
                    grouped = true;
                    limit = limit.min(c.saturating_add(beyond));
                }
                continue;
            }
            for &(v, step) in &near {
                let nc = c + step;
                let kv = v.key();
                if found.cost.get(&kv).is_none_or(|&(best, _)| nc < best) {
                    found.cost.insert(kv, (nc, k));
                    found.queue.push(nc, kv);
                }
            }
        }
    }
}

impl Search {
    /// The path from the start to `to`, place centres in the world frame.
    fn path_to(&self, space: &Space<'_>, to: Place) -> Vec<[f64; 3]> {
        let mut keys = vec![to.key()];
        let mut k = to.key();
        while let Some(&(_, parent)) = self.cost.get(&k) {
            if parent == k {
                break;
            }
            keys.push(parent);
            k = parent;
        }
        keys.reverse();
        keys.into_iter()
            .map(|k| space.centre(Place::from_key(k)))
            .collect()
    }

    /// The place reached nearest `p`.
    fn nearest_to(&self, space: &Space<'_>, p: [f64; 3]) -> Option<Place> {
        self.cost
            .keys()
            .map(|&k| Place::from_key(k))
            .map(|q| (dist(space.centre(q), p), q.key(), q))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map(|(_, _, q)| q)
    }
}

/// The best frontier group's nearest place: groups of at least [`MIN_GROUP`] places scored
/// `min(size, GAIN_CAP) - metres - claimed`.
fn best_frontier(
    space: &Space<'_>,
    search: &mut Search,
    s: &Situation<'_>,
    set_aside: &[[f64; 3]],
) -> Option<Place> {
    let voxel = space.voxel();
    let mut best: Option<(f64, u64, Place)> = None;
    for i in 0..search.frontiers.len() {
        if search.root(i) != i || search.size[i] < MIN_GROUP {
            continue;
        }
        let (place, c) = search.frontiers[i];
        let at = space.centre(place);
        if set_aside.iter().any(|g| dist(*g, at) < 2.0) {
            continue;
        }
        let metres = f64::from(c) / 10.0 * voxel;
        let claimed = s.claimed.iter().any(|g| dist(*g, at) < CLAIM_RADIUS);
        let score = search.size[i].min(GAIN_CAP) as f64
            - metres
            - if claimed { CLAIMED_PENALTY } else { 0.0 };
        let better = best.is_none_or(|(b, k, _)| score > b || (score == b && place.key() < k));
        if better {
            best = Some((score, place.key(), place));
        }
    }
    best.map(|(_, _, p)| p)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn dist2d(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}
