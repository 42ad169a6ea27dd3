//! A mission: several robots of one platform exploring a world from its entrance for a given
//! time, driven by a policy (the frontier baseline, or uniformly random commands), talking to
//! the base station over the radio and dropping breadcrumbs. What `subtgraph explore` runs.
//!
//! Each control step moves every robot (in parallel: a robot's step reads only its own map and
//! what it last heard, so the order does not matter and the run is the same on any number of
//! threads), then, once a second of simulated time, the radio: which robots reach the base
//! station ([`crate::radio`]), reports delivered over those links, maps merged between robots
//! that hear each other (directly or through others), goals heard, breadcrumbs dropped.
//!
//! **Breadcrumbs** (the SubT teams' dropped radio repeaters): a robot that reaches the base
//! station, holds a direct link to a fixed node (the base or a breadcrumb), is at least
//! [`CRUMB_SPACING`] metres from every one, and would lose every fixed node from a point
//! [`CRUMB_LOOKAHEAD`] metres further along its path, drops one where it stands (so the new
//! one is linked), while it carries any.

use rayon::prelude::*;
use subtgraph_sensors::noise;

use crate::body::{Body, Command};
use crate::detect::Detector;
use crate::error::ExploreError;
use crate::lidar::Lidar;
use crate::map::{Grid, VoxelMap};
use crate::planner::{RETURN_AFTER_S, Situation};
use crate::radio::{FixedLinks, Link, Network, Node, RadioModel};
use crate::robot::{Kit, Robot};
use crate::site::Site;

/// Least distance between breadcrumbs (and from the base station), metres.
pub const CRUMB_SPACING: f64 = 8.0;
/// How far ahead along its path a robot looks for its link, metres.
pub const CRUMB_LOOKAHEAD: f64 = 4.0;
/// Seconds between radio instants.
pub const RADIO_PERIOD: f64 = 1.0;

/// Who drives the robots.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Policy {
    /// The frontier-based baseline ([`crate::planner`]).
    Frontier,
    /// A uniformly random command every control step (what a Gymnasium agent's
    /// `action_space.sample()` does).
    Random,
}

impl Policy {
    /// The names `--planner` takes.
    pub const NAMES: [&str; 2] = ["frontier", "random"];

    /// A policy by name.
    pub fn named(name: &str) -> Result<Policy, ExploreError> {
        match name {
            "frontier" => Ok(Policy::Frontier),
            "random" => Ok(Policy::Random),
            other => Err(ExploreError::Unknown {
                what: "planner",
                name: other.to_owned(),
                known: Policy::NAMES.join(", "),
            }),
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Policy::Frontier => "frontier",
            Policy::Random => "random",
        }
    }
}

/// What a mission is asked.
#[derive(Clone, Debug)]
pub struct Options {
    /// Robots.
    pub robots: usize,
    /// The platform (`ground`, `aerial`).
    pub body: Body,
    /// The LiDAR as cast.
    pub lidar: Lidar,
    /// Simulated seconds.
    pub duration: f64,
    /// Control steps a second.
    pub control_hz: f64,
    /// The map's voxel, metres.
    pub map_voxel: f64,
    /// Who drives.
    pub policy: Policy,
    /// Breadcrumbs each robot carries.
    pub breadcrumbs: usize,
    /// The radio.
    pub radio: RadioModel,
    /// The artifact detector.
    pub detector: Detector,
    /// The seed of noise, reports and random commands.
    pub seed: u64,
    /// No range noise.
    pub noiseless: bool,
    /// The most bytes all robots' maps may take together.
    pub max_map_bytes: u64,
}

impl Options {
    /// Checks the numbers.
    pub fn check(&self) -> Result<(), ExploreError> {
        if !(1..=16).contains(&self.robots) {
            return Err(ExploreError::bounds("--robots", self.robots, "1 to 16"));
        }
        if !(self.duration.is_finite() && self.duration > 0.0 && self.duration <= 86_400.0) {
            return Err(ExploreError::bounds(
                "--duration",
                self.duration,
                "above 0 and at most 86400 seconds",
            ));
        }
        if !(self.control_hz.is_finite() && (1.0..=1000.0).contains(&self.control_hz)) {
            return Err(ExploreError::bounds(
                "the control rate",
                self.control_hz,
                "1 to 1000 Hz",
            ));
        }
        if !(self.map_voxel.is_finite() && (0.1..=5.0).contains(&self.map_voxel)) {
            return Err(ExploreError::bounds(
                "the map voxel",
                self.map_voxel,
                "0.1 to 5 metres",
            ));
        }
        if self.breadcrumbs > 100 {
            return Err(ExploreError::bounds(
                "--breadcrumbs",
                self.breadcrumbs,
                "0 to 100 per robot",
            ));
        }
        Ok(())
    }
}

/// One line of the radio log: a link that was up at `time`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkRecord {
    /// Seconds.
    pub time: f64,
    /// The link.
    pub link: Link,
}

/// A breadcrumb dropped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crumb {
    /// Seconds.
    pub time: f64,
    /// Who dropped it.
    pub robot: usize,
    /// Its antenna.
    pub position: [f64; 3],
}

/// A mission in progress.
pub struct Mission {
    /// The world.
    pub site: Site,
    /// What was asked.
    pub options: Options,
    /// The robots.
    pub robots: Vec<Robot>,
    /// Seconds simulated.
    pub time: f64,
    /// Control steps taken.
    pub steps: u64,
    fixed: FixedLinks,
    /// Breadcrumbs dropped.
    pub crumbs: Vec<Crumb>,
    /// Links up at each radio instant (those with a robot at an end; links between fixed
    /// nodes once, when made).
    pub links: Vec<LinkRecord>,
    /// Per radio instant and robot: hops to the base station.
    pub connectivity: Vec<(f64, Vec<Option<usize>>)>,
    next_radio: f64,
    /// `[a][b]`: robot a's map clock when it last sent to robot b.
    synced: Vec<Vec<Option<u64>>>,
}

impl Mission {
    /// Sets a mission up: the robots at their spawns, each with an empty map over the site's
    /// box.
    pub fn new(site: Site, options: Options, grid: Option<Grid>) -> Result<Mission, ExploreError> {
        options.check()?;
        let grid = grid.unwrap_or_else(|| Grid::covering(site.bounds, options.map_voxel, 1.0));
        let per_robot = options.max_map_bytes / options.robots as u64;
        let empty = VoxelMap::new(grid, per_robot)?;
        let spawns = site.spawns(&options.body, options.robots)?;
        let robots = spawns
            .into_iter()
            .enumerate()
            .map(|(i, s)| {
                Robot::new(
                    i,
                    s,
                    empty.clone(),
                    site.artifacts.len(),
                    options.robots,
                    options.breadcrumbs,
                )
            })
            .collect();
        let fixed = FixedLinks::new(site.base);
        let synced = vec![vec![None; options.robots]; options.robots];
        Ok(Mission {
            site,
            options,
            robots,
            time: 0.0,
            steps: 0,
            fixed,
            crumbs: Vec::new(),
            links: Vec::new(),
            connectivity: Vec::new(),
            next_radio: 0.0,
            synced,
        })
    }

    /// Control steps the whole mission takes.
    pub fn total_steps(&self) -> u64 {
        (self.options.duration * self.options.control_hz).round() as u64
    }

    /// Runs to the end, telling `progress` the simulated seconds now and then.
    ///
    /// Between radio instants the robots do not hear each other, so each runs the steps up to
    /// the next instant on its own thread: the same steps as [`Mission::step`] one at a time,
    /// without waiting for the slowest robot at every step (a robot planning takes ten times a
    /// step's time, and the others would idle).
    pub fn run(&mut self, progress: &dyn Fn(f64)) {
        let total = self.total_steps();
        self.radio();
        while self.steps < total {
            let dt = 1.0 / self.options.control_hz;
            // The steps until the radio is due, or the next progress report, or the end.
            let mut last = self.steps + 1;
            while last < total && last % 600 != 0 && (last as f64 * dt) + 1e-9 < self.next_radio {
                last += 1;
            }
            self.robots_step(self.steps..last);
            self.steps = last;
            self.time = last as f64 * dt;
            if self.time + 1e-9 >= self.next_radio {
                self.radio();
            }
            if self.steps % 600 == 0 {
                progress(self.time);
            }
        }
    }

    /// One control step of every robot, and the radio when due.
    pub fn step(&mut self) {
        let dt = 1.0 / self.options.control_hz;
        self.robots_step(self.steps..self.steps + 1);
        self.steps += 1;
        self.time = self.steps as f64 * dt;
        if self.time + 1e-9 >= self.next_radio {
            self.radio();
        }
    }

    /// Control steps `steps` of every robot (the radio not due before the last), each robot
    /// on a thread of its own.
    fn robots_step(&mut self, steps: std::ops::Range<u64>) {
        let dt = 1.0 / self.options.control_hz;
        let kit = Kit {
            site: &self.site,
            body: &self.options.body,
            lidar: &self.options.lidar,
            detector: &self.options.detector,
            dt,
            seed: self.options.seed,
            noiseless: self.options.noiseless,
            split_scans: true,
        };
        let policy = self.options.policy;
        let seed = self.options.seed;
        let first_now = self.time;
        self.robots.par_iter_mut().for_each(|r| {
            for step in steps.clone() {
                // The time now as `step` has always set it: after step s, (s + 1) x dt.
                let now = if step == steps.start {
                    first_now
                } else {
                    step as f64 * dt
                };
                let t = (step + 1) as f64 * dt;
                let command = match policy {
                    Policy::Frontier => {
                        let claimed: Vec<[f64; 3]> =
                            r.heard_goals.iter().flatten().copied().collect();
                        let must_report = r.pending().any(|p| now - p.detected >= RETURN_AFTER_S);
                        let trail: Vec<[f64; 3]> = r.trail.iter().copied().collect();
                        let s = Situation {
                            trail: &trail,
                            blocked: &r.blocked,
                            time: now,
                            body: kit.body,
                            state: &r.state,
                            map: &r.map,
                            claimed: &claimed,
                            must_report,
                            last_link: r.last_link,
                        };
                        r.planner.command(&s)
                    }
                    Policy::Random => random_command(kit.body, seed, r.id, step),
                };
                r.advance(&kit, command, t, step);
            }
        });
    }

    /// The radio instant: links, deliveries, merged maps, heard goals, breadcrumbs.
    fn radio(&mut self) {
        let t = self.time;
        self.next_radio = t + RADIO_PERIOD;
        let body = &self.options.body;
        let antennas: Vec<[f64; 3]> = self.robots.iter().map(|r| r.antenna(body)).collect();
        let net = Network::of(
            &self.options.radio,
            &self.site.collision,
            &self.fixed,
            &antennas,
        );
        for l in &net.links {
            self.links.push(LinkRecord { time: t, link: *l });
        }
        self.connectivity.push((t, net.hops.clone()));
        for (i, r) in self.robots.iter_mut().enumerate() {
            r.linked = net.reaches_base(i);
            if r.linked {
                r.last_link = r.state.position;
                for rep in r.reports.iter_mut().filter(|p| p.delivered.is_none()) {
                    rep.delivered = Some(t);
                }
            }
        }
        self.share_within_groups(&net);
        self.drop_crumbs(&net);
    }

    /// Maps merged and goals heard among robots that hear each other: each robot sends each
    /// other of its group the chunks it changed since it last sent to that one.
    fn share_within_groups(&mut self, net: &Network) {
        let n = self.robots.len();
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for i in 0..n {
            match groups.iter_mut().find(|g| net.group[g[0]] == net.group[i]) {
                Some(g) => g.push(i),
                None => groups.push(vec![i]),
            }
        }
        for g in groups.iter().filter(|g| g.len() > 1) {
            for &a in g {
                for &b in g.iter().filter(|&&b| b != a) {
                    let patch = self.robots[a].map.patch_since(self.synced[a][b]);
                    self.robots[b].map.apply(&patch);
                    let goal = self.robots[a].planner.goal;
                    self.robots[b].heard_goals[a] = goal;
                }
                let sent = self.robots[a].map.mark();
                for &b in g.iter().filter(|&&b| b != a) {
                    self.synced[a][b] = Some(sent);
                }
            }
        }
    }

    /// Breadcrumbs dropped where robots are about to lose their link (see the module's doc).
    fn drop_crumbs(&mut self, net: &Network) {
        let model = self.options.radio;
        for i in 0..self.robots.len() {
            let wanted = crumb_wanted(
                &self.robots[i],
                i,
                &self.options.body,
                net,
                &self.fixed,
                &model,
                &self.site.collision,
            );
            if !wanted {
                continue;
            }
            let here = self.robots[i].antenna(&self.options.body);
            let new = self.fixed.drop_crumb(&model, &self.site.collision, here);
            for l in new {
                self.links.push(LinkRecord {
                    time: self.time,
                    link: l,
                });
            }
            self.crumbs.push(Crumb {
                time: self.time,
                robot: i,
                position: here,
            });
            self.robots[i].crumbs_left -= 1;
        }
    }

    /// Every robot's map merged: what the robots bring back.
    pub fn union_map(&self) -> VoxelMap {
        let mut all = self.robots[0].map.clone();
        for r in &self.robots[1..] {
            all.merge(&r.map);
        }
        all
    }
}

/// Whether robot `r` (index `i` in `net`) drops a breadcrumb now (see the module's doc).
pub fn crumb_wanted(
    r: &Robot,
    i: usize,
    body: &Body,
    net: &Network,
    fixed: &FixedLinks,
    model: &RadioModel,
    caster: &subtgraph_core::raycast::RayCaster,
) -> bool {
    if r.crumbs_left == 0 || !net.reaches_base(i) {
        return false;
    }
    let here = r.antenna(body);
    let spaced = fixed
        .antennas
        .iter()
        .all(|q| dist(*q, here) >= CRUMB_SPACING);
    let direct = net
        .links
        .iter()
        .any(|l| l.b == Node::Robot(i) && matches!(l.a, Node::Base | Node::Crumb(_)));
    if !spaced || !direct {
        return false;
    }
    let ahead = look_ahead(r, body, CRUMB_LOOKAHEAD);
    !fixed
        .antennas
        .iter()
        .any(|&q| model.link(caster, q, ahead).is_some())
}

/// A robot's antenna `d` metres further along its path (or straight ahead without one).
fn look_ahead(r: &Robot, body: &Body, d: f64) -> [f64; 3] {
    let here = r.state.position;
    let lift = r.antenna(body)[2] - here[2];
    let along = r
        .planner
        .path
        .iter()
        .find(|q| (q[0] - here[0]).hypot(q[1] - here[1]) >= d)
        .copied();
    let p = along.unwrap_or([
        here[0] + d * r.state.yaw.cos(),
        here[1] + d * r.state.yaw.sin(),
        here[2],
    ]);
    let floor_to_antenna = if body.flies() {
        0.0
    } else {
        lift - 0.5 * r.map.grid.voxel
    };
    let z = if along.is_some() {
        p[2] + floor_to_antenna
    } else {
        p[2] + lift
    };
    [p[0], p[1], z]
}

/// A command drawn uniformly from the body's limits (speed, turn rate, climb), from a hash of
/// the seed, the robot and the step.
pub fn random_command(body: &Body, seed: u64, robot: usize, step: u64) -> Command {
    let key = |k: u64| (step << 8) | ((robot as u64) << 2) | k;
    let u = |k: u64| noise::uniform(seed ^ 0x7261_6e64, key(k));
    let span = |lo: f64, hi: f64, x: f64| lo + (hi - lo) * x;
    Command {
        speed: span(-body.max_reverse, body.max_speed, u(0)),
        yaw_rate: span(-body.max_yaw_rate, body.max_yaw_rate, u(1)),
        climb: if body.flies() {
            span(-body.max_climb, body.max_climb, u(2))
        } else {
            0.0
        },
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
