//! One robot in the loop: its body's state, its map, its LiDAR's last scan, the artifacts it
//! has seen and the reports it holds. A control step ([`Robot::advance`]) moves the body, scans
//! when the LiDAR is due, carves the scan into the map and looks for artifacts in view;
//! the same step serves the Gymnasium environment and the baseline's missions.
//!
//! Besides its scans, a ground robot knows where its wheels are: after each motion the voxel
//! holding its floor is marked occupied and the voxel above it free, so the ground it drove
//! over is known even where its LiDAR's lowest ring (2.2 m out) never saw it.

use subtgraph_sensors::frames::{Mat3, mul, rotation_zyx};

use crate::body::{Body, Command, Moved, Refusal, State};
use crate::detect::{Detector, Report};
use crate::lidar::{Lidar, Scan};
use crate::map::{Added, VoxelMap};
use crate::planner::Planner;
use crate::site::{ANTENNA, Site, Spawn};

/// What every robot of a run shares: the world, the body, the sensors and the seed.
pub struct Kit<'a> {
    /// The world.
    pub site: &'a Site,
    /// The platform.
    pub body: &'a Body,
    /// The LiDAR.
    pub lidar: &'a Lidar,
    /// The artifact detector.
    pub detector: &'a Detector,
    /// Seconds a control step lasts.
    pub dt: f64,
    /// The run's seed (noise, reports, random commands).
    pub seed: u64,
    /// No range noise.
    pub noiseless: bool,
    /// Scans cast in parts on rayon's threads ([`Lidar::scan`]): what a mission of several
    /// robots wants, not an environment stepped on one thread.
    pub split_scans: bool,
}

/// A pose of the trajectory: time, position, yaw, pitch, roll.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Seconds since the start.
    pub time: f64,
    /// The reference point (floor or body centre), world frame.
    pub position: [f64; 3],
    /// Yaw, pitch, roll, radians (ROS's conventions).
    pub ypr: [f64; 3],
}

/// One robot.
#[derive(Clone, Debug)]
pub struct Robot {
    /// Its index.
    pub id: usize,
    /// Its body's state.
    pub state: State,
    /// Its map.
    pub map: VoxelMap,
    /// Its last step's scan (the columns fired in it).
    pub scan: Scan,
    frame: (u64, Vec<[f64; 3]>),
    fired: Vec<u64>,
    /// Rays cast.
    pub rays: u64,
    /// Per artifact (the site's order): whether it has detected it.
    pub detected: Vec<bool>,
    /// Its reports, delivered or not, in the order made.
    pub reports: Vec<Report>,
    /// Its poses, one per control step from the start.
    pub trajectory: Vec<Sample>,
    /// Metres driven.
    pub odometer: f64,
    /// Refused motions: collision, step, gap, slope.
    pub refusals: [u64; 4],
    /// Where it last reached the base station (its start until it does).
    pub last_link: [f64; 3],
    /// Whether it reached the base station at the last radio instant.
    pub linked: bool,
    /// Breadcrumbs it still carries.
    pub crumbs_left: usize,
    /// Its planner (the baseline's).
    pub planner: Planner,
    /// Other robots' goals as last heard (by robot).
    pub heard_goals: Vec<Option<[f64; 3]>>,
    /// Where it has been, a point every [`TRAIL_SPACING`] metres, the last [`TRAIL_POINTS`].
    pub trail: std::collections::VecDeque<[f64; 3]>,
    /// Places (voxel keys) where its motion was refused: it felt the slope, the step, the
    /// drop or the rock there, and plans around them.
    pub blocked: rustc_hash::FxHashSet<u64>,
}

/// Metres between trail points.
pub const TRAIL_SPACING: f64 = 0.3;
/// Trail points kept.
pub const TRAIL_POINTS: usize = 40;

/// What a control step did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stepped {
    /// The motion.
    pub moved: Moved,
    /// Whether a scan was taken.
    pub scanned: bool,
    /// What the map gained.
    pub added: Added,
    /// Artifacts (site indices) detected for the first time.
    pub detections: Vec<usize>,
}

impl Robot {
    /// Robot `id` at `spawn`, its map over `map`'s grid (an empty map).
    pub fn new(
        id: usize,
        spawn: Spawn,
        map: VoxelMap,
        artifacts: usize,
        robots: usize,
        crumbs: usize,
    ) -> Robot {
        let state = State {
            position: spawn.position,
            yaw: spawn.yaw,
            ..State::default()
        };
        Robot {
            id,
            state,
            map,
            scan: Scan::default(),
            frame: (0, Vec::new()),
            fired: Vec::new(),
            rays: 0,
            detected: vec![false; artifacts],
            reports: Vec::new(),
            trajectory: vec![Sample {
                time: 0.0,
                position: spawn.position,
                ypr: [spawn.yaw, 0.0, 0.0],
            }],
            odometer: 0.0,
            refusals: [0; 4],
            last_link: spawn.position,
            linked: false,
            crumbs_left: crumbs,
            planner: Planner::default(),
            heard_goals: vec![None; robots],
            trail: std::collections::VecDeque::from([spawn.position]),
            blocked: rustc_hash::FxHashSet::default(),
        }
    }

    /// The body's rotation (body to world).
    pub fn rotation(&self) -> Mat3 {
        rotation_zyx([self.state.yaw, self.state.pitch, self.state.roll])
    }

    /// The LiDAR's position, world frame.
    pub fn sensor(&self, body: &Body) -> [f64; 3] {
        let r = self.rotation();
        let up = mul(&r, [0.0, 0.0, body.lidar_height]);
        let p = self.state.position;
        [p[0] + up[0], p[1] + up[1], p[2] + up[2]]
    }

    /// The radio antenna, world frame: [`ANTENNA`] above a ground robot's floor, at an aerial
    /// robot's body.
    pub fn antenna(&self, body: &Body) -> [f64; 3] {
        let p = self.state.position;
        if body.flies() {
            p
        } else {
            [p[0], p[1], p[2] + ANTENNA]
        }
    }

    /// Control step `step` (ending at time `t`): the motion, the columns the LiDAR fires in
    /// it, the map, the artifacts in view.
    pub fn advance(&mut self, kit: &Kit<'_>, command: Command, t: f64, step: u64) -> Stepped {
        self.advance_with(kit, command, t, step, true)
    }

    /// [`advance`](Self::advance), building the map only when `build_map`.
    pub fn advance_with(
        &mut self,
        kit: &Kit<'_>,
        command: Command,
        t: f64,
        step: u64,
        build_map: bool,
    ) -> Stepped {
        let moved = kit
            .body
            .step(&kit.site.collision, &mut self.state, command, kit.dt);
        self.odometer += moved.distance;
        let p = self.state.position;
        if self
            .trail
            .back()
            .is_none_or(|q| (q[0] - p[0]).hypot(q[1] - p[1]) >= TRAIL_SPACING)
        {
            self.trail.push_back(p);
            if self.trail.len() > TRAIL_POINTS {
                self.trail.pop_front();
            }
        }
        if moved.refused.is_some() {
            // The place just ahead, the way it tried to go.
            let ahead = 0.35 * command.speed.signum();
            let g = self.map.grid;
            let q = [
                p[0] + ahead * self.state.yaw.cos(),
                p[1] + ahead * self.state.yaw.sin(),
                p[2] + if kit.body.flies() { 0.0 } else { 0.5 * g.voxel },
            ];
            if let Some(v) = g.voxel_of(q) {
                self.blocked.insert(crate::planner::space::Place(v).key());
            }
        }
        if let Some(r) = moved.refused {
            let k = match r {
                Refusal::Collision => 0,
                Refusal::Step => 1,
                Refusal::Gap => 2,
                Refusal::Slope => 3,
            };
            self.refusals[k] += 1;
        }
        self.trajectory.push(Sample {
            time: t,
            position: self.state.position,
            ypr: [self.state.yaw, self.state.pitch, self.state.roll],
        });
        if build_map && !kit.body.flies() {
            self.feel_floor();
        }
        let mut out = Stepped {
            moved,
            ..Stepped::default()
        };
        let mut fired = std::mem::take(&mut self.fired);
        kit.lidar.fired(step, kit.dt, &mut fired);
        let (added, detections) = self.sense(kit, t, &fired, build_map);
        self.fired = fired;
        out.scanned = !self.scan.columns.is_empty();
        out.added = added;
        out.detections = detections;
        out
    }

    /// A scan of `columns` (absolute, see [`Lidar::fired`]) from where the robot stands at
    /// time `t`: carved into the map when `build_map`, artifacts in view detected. Returns
    /// what the map gained and the new detections.
    pub fn sense(
        &mut self,
        kit: &Kit<'_>,
        t: f64,
        columns: &[u64],
        build_map: bool,
    ) -> (Added, Vec<usize>) {
        let origin = self.sensor(kit.body);
        let rotation = self.rotation();
        kit.lidar.scan(
            &kit.site.scanned,
            origin,
            &rotation,
            columns,
            kit.seed ^ (self.id as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15),
            kit.noiseless,
            &mut self.frame,
            kit.split_scans,
            &mut self.scan,
        );
        self.rays += self.scan.dirs.len() as u64;
        let added = if build_map {
            self.map.insert(&self.scan)
        } else {
            Added::default()
        };
        let found: Vec<usize> = kit
            .detector
            .visible(&kit.site.collision, origin, &kit.site.artifacts)
            .filter(|&i| !self.detected[i])
            .collect();
        for &i in &found {
            self.detected[i] = true;
            self.reports.push(
                kit.detector
                    .report(kit.seed, self.id, &kit.site.artifacts[i], t),
            );
        }
        (added, found)
    }

    /// Marks the floor under a ground robot occupied and the voxel above it free.
    fn feel_floor(&mut self) {
        let p = self.state.position;
        let g = self.map.grid;
        if let Some(v) = g.voxel_of([p[0], p[1], p[2] - 0.05]) {
            self.map.set_occupied_at(v, p[2]);
            let above = [v[0], v[1], v[2] + 1];
            if g.contains(above) {
                self.map.set_free(above);
            }
        }
    }

    /// Reports not yet delivered.
    pub fn pending(&self) -> impl Iterator<Item = &Report> {
        self.reports.iter().filter(|r| r.delivered.is_none())
    }
}
