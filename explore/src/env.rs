//! One robot stepped by an outside policy: the core of the Python package's Gymnasium
//! environment (`subtgraph/Explore-v0`). The policy gives a command per control step; the
//! robot moves, scans, maps and detects ([`crate::robot`]), the radio carries its reports
//! home once a second (breadcrumbs dropped by the mission's rule), and the step's reward is a
//! weighted sum of named terms.
//!
//! Reward terms, per step (weights by name, [`Weights`]):
//!
//! | term | what | default weight |
//! |---|---|---|
//! | `explore` | cubic metres of the map newly known free | 0.1 |
//! | `detect` | artifacts detected for the first time | 10 |
//! | `report` | reports newly delivered to the base station | 10 |
//! | `distance` | metres driven | 0 |
//! | `collision` | 1 when the motion was refused (rock, step, gap, slope) | -1 |
//! | `time` | 1 every step | 0 |
//!
//! A refused motion is what Gymnasium's agents see of a collision by default (the robot stops
//! short, [`crate::body`]); with [`OnCollision::End`] a refusal by rock ends the episode
//! (`terminated`). An episode is truncated after its step limit.

use crate::body::{Body, Command, Refusal};
use crate::detect::Detector;
use crate::error::ExploreError;
use crate::lidar::Lidar;
use crate::map::{Grid, Voxel, VoxelMap};
use crate::mission::{RADIO_PERIOD, crumb_wanted};
use crate::radio::{FixedLinks, Network, RadioModel};
use crate::robot::{Kit, Robot, Stepped};
use crate::site::Site;

/// The reward terms' names, in the order of [`Step::terms`].
pub const TERMS: [&str; 6] = [
    "explore",
    "detect",
    "report",
    "distance",
    "collision",
    "time",
];

/// Each term's weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weights(pub [f64; 6]);

impl Default for Weights {
    fn default() -> Self {
        Weights([0.1, 10.0, 10.0, 0.0, -1.0, 0.0])
    }
}

impl Weights {
    /// Sets the weight of term `name`, refusing an unknown one.
    pub fn set(&mut self, name: &str, w: f64) -> Result<(), ExploreError> {
        let i = TERMS
            .iter()
            .position(|t| *t == name)
            .ok_or_else(|| ExploreError::Unknown {
                what: "reward term",
                name: name.to_owned(),
                known: TERMS.join(", "),
            })?;
        if !w.is_finite() {
            return Err(ExploreError::bounds(
                format!("the weight of '{name}'"),
                w,
                "a finite number",
            ));
        }
        self.0[i] = w;
        Ok(())
    }
}

/// What a refusal by rock does to an episode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnCollision {
    /// The motion stops short; the episode goes on.
    Refuse,
    /// The episode ends (`terminated`).
    End,
}

/// The environment's settings.
#[derive(Clone, Debug)]
pub struct EnvOptions {
    /// The platform.
    pub body: Body,
    /// The LiDAR as cast.
    pub lidar: Lidar,
    /// Control steps a second.
    pub control_hz: f64,
    /// Map voxel, metres.
    pub map_voxel: f64,
    /// Steps an episode lasts at most.
    pub max_steps: u64,
    /// What a collision does.
    pub on_collision: OnCollision,
    /// Reward weights.
    pub weights: Weights,
    /// Breadcrumbs the robot carries.
    pub breadcrumbs: usize,
    /// The radio.
    pub radio: RadioModel,
    /// The artifact detector.
    pub detector: Detector,
    /// No range noise.
    pub noiseless: bool,
    /// Whether the map is built (needed by the `explore` term and a map observation).
    pub build_map: bool,
    /// The most bytes the map may take.
    pub max_map_bytes: u64,
}

/// What a step gave.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Step {
    /// The weighted sum.
    pub reward: f64,
    /// Each term's value before weighting, in [`TERMS`] order.
    pub terms: [f64; 6],
    /// The episode ended (a collision with `OnCollision::End`).
    pub terminated: bool,
    /// The step limit was reached.
    pub truncated: bool,
    /// Why the motion stopped short.
    pub refused: Option<Refusal>,
    /// Artifacts (site indices) detected this step.
    pub detections: Vec<usize>,
    /// Reports delivered this step.
    pub delivered: usize,
}

/// One robot in a world, stepped from outside.
pub struct Env {
    /// The world.
    pub site: Site,
    /// The settings.
    pub options: EnvOptions,
    /// The robot.
    pub robot: Robot,
    empty: VoxelMap,
    fixed: FixedLinks,
    /// Steps since the reset.
    pub steps: u64,
    seed: u64,
    next_radio: f64,
    /// Whether the robot reached the base station at the last radio instant.
    pub linked: bool,
    /// The last step's measured specific force and angular rate (body frame).
    pub imu: [f64; 6],
    last_velocity: [f64; 3],
    last_ypr: [f64; 3],
    /// The latest range of every ray of a turn, `[ring][column]` (0: no return), as the
    /// head has swept it so far.
    pub ranges: Vec<f32>,
    /// Each ray's direction in the sensor frame when it was cast, the same layout.
    pub directions: Vec<[f32; 3]>,
}

impl Env {
    /// The environment of a site.
    pub fn new(site: Site, options: EnvOptions) -> Result<Env, ExploreError> {
        if !(options.control_hz.is_finite() && (1.0..=1000.0).contains(&options.control_hz)) {
            return Err(ExploreError::bounds(
                "control_hz",
                options.control_hz,
                "1 to 1000 Hz",
            ));
        }
        if !(options.map_voxel.is_finite() && (0.1..=5.0).contains(&options.map_voxel)) {
            return Err(ExploreError::bounds(
                "map_voxel",
                options.map_voxel,
                "0.1 to 5 metres",
            ));
        }
        if options.max_steps == 0 {
            return Err(ExploreError::bounds("max_steps", 0, "at least 1"));
        }
        let grid = Grid::covering(site.bounds, options.map_voxel, 1.0);
        let empty = VoxelMap::new(grid, options.max_map_bytes)?;
        let spawn = site.spawns(&options.body, 1)?[0];
        let robot = Robot::new(
            0,
            spawn,
            empty.clone(),
            site.artifacts.len(),
            1,
            options.breadcrumbs,
        );
        let fixed = FixedLinks::new(site.base);
        let mut env = Env {
            site,
            options,
            robot,
            empty,
            fixed,
            steps: 0,
            seed: 0,
            next_radio: 0.0,
            linked: false,
            imu: [0.0; 6],
            last_velocity: [0.0; 3],
            last_ypr: [0.0; 3],
            ranges: Vec::new(),
            directions: Vec::new(),
        };
        env.reset(0);
        Ok(env)
    }

    /// Seconds a step lasts.
    pub fn dt(&self) -> f64 {
        1.0 / self.options.control_hz
    }

    /// Seconds since the reset.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.dt()
    }

    /// Starts an episode: the robot at the spawn, an empty map, no breadcrumbs dropped, noise
    /// drawn from `seed`; the first scan taken.
    pub fn reset(&mut self, seed: u64) {
        let spawn = self
            .site
            .spawns(&self.options.body, 1)
            .expect("found when made")[0];
        self.robot = Robot::new(
            0,
            spawn,
            self.empty.clone(),
            self.site.artifacts.len(),
            1,
            self.options.breadcrumbs,
        );
        self.fixed = FixedLinks::new(self.site.base);
        self.steps = 0;
        self.seed = seed;
        self.next_radio = 0.0;
        self.linked = false;
        self.last_velocity = [0.0; 3];
        self.last_ypr = [spawn.yaw, 0.0, 0.0];
        // The first scan, standing still.
        let kit = Kit {
            site: &self.site,
            body: &self.options.body,
            lidar: &self.options.lidar,
            detector: &self.options.detector,
            dt: 1.0 / self.options.control_hz,
            seed: self.seed,
            noiseless: self.options.noiseless,
            split_scans: false,
        };
        let all: Vec<u64> = (0..self.options.lidar.columns as u64).collect();
        let _ = self.robot.sense(&kit, 0.0, &all, self.options.build_map);
        let n = self.options.lidar.rays();
        self.ranges = vec![0.0; n];
        self.directions = vec![[0.0; 3]; n];
        self.take_scan();
        self.imu = [0.0, 0.0, 9.81, 0.0, 0.0, 0.0];
        self.radio();
    }

    /// One control step.
    pub fn step(&mut self, command: Command) -> Step {
        let t = (self.steps + 1) as f64 * self.dt();
        let voxel3 = self.options.map_voxel.powi(3);
        let kit = Kit {
            site: &self.site,
            body: &self.options.body,
            lidar: &self.options.lidar,
            detector: &self.options.detector,
            dt: 1.0 / self.options.control_hz,
            seed: self.seed,
            noiseless: self.options.noiseless,
            split_scans: false,
        };
        let stepped: Stepped =
            self.robot
                .advance_with(&kit, command, t, self.steps, self.options.build_map);
        self.steps += 1;
        self.take_scan();
        self.measure_imu();
        let mut delivered = 0;
        if t + 1e-9 >= self.next_radio {
            delivered = self.radio();
        }
        let terms = [
            stepped.added.free as f64 * voxel3,
            stepped.detections.len() as f64,
            delivered as f64,
            stepped.moved.distance,
            if stepped.moved.refused.is_some() {
                1.0
            } else {
                0.0
            },
            1.0,
        ];
        let reward = terms
            .iter()
            .zip(self.options.weights.0)
            .map(|(v, w)| v * w)
            .sum();
        let terminated = self.options.on_collision == OnCollision::End
            && stepped.moved.refused == Some(Refusal::Collision);
        Step {
            reward,
            terms,
            terminated,
            truncated: !terminated && self.steps >= self.options.max_steps,
            refused: stepped.moved.refused,
            detections: stepped.detections,
            delivered,
        }
    }

    /// Copies the last step's columns into the ranges image.
    fn take_scan(&mut self) {
        let (rings, columns) = (self.options.lidar.rings, self.options.lidar.columns);
        let r = self.robot.rotation();
        let scan = &self.robot.scan;
        for (j, &c) in scan.columns.iter().enumerate() {
            let col = (c % columns as u64) as usize;
            for ring in 0..rings {
                let k = j * rings + ring;
                let at = ring * columns + col;
                self.ranges[at] = scan.ranges[k];
                let d = subtgraph_sensors::frames::mul_t(&r, scan.dirs[k]);
                self.directions[at] = d.map(|v| v as f32);
            }
        }
    }

    /// The ranges image as points in the sensor frame, `[ring][column][xyz]` (zeros without
    /// a return), into `out`.
    pub fn points(&self, out: &mut [f32]) {
        for (k, (r, d)) in self.ranges.iter().zip(&self.directions).enumerate() {
            for a in 0..3 {
                out[3 * k + a] = r * d[a];
            }
        }
    }

    /// The radio instant: the link, deliveries, a breadcrumb; returns reports delivered.
    fn radio(&mut self) -> usize {
        self.next_radio = self.time() + RADIO_PERIOD;
        let body = &self.options.body;
        let antenna = [self.robot.antenna(body)];
        let net = Network::of(
            &self.options.radio,
            &self.site.collision,
            &self.fixed,
            &antenna,
        );
        self.linked = net.reaches_base(0);
        let mut delivered = 0;
        if self.linked {
            let t = self.time();
            self.robot.last_link = self.robot.state.position;
            for r in self
                .robot
                .reports
                .iter_mut()
                .filter(|r| r.delivered.is_none())
            {
                r.delivered = Some(t);
                delivered += 1;
            }
        }
        if crumb_wanted(
            &self.robot,
            0,
            body,
            &net,
            &self.fixed,
            &self.options.radio,
            &self.site.collision,
        ) {
            let here = self.robot.antenna(body);
            self.fixed
                .drop_crumb(&self.options.radio, &self.site.collision, here);
            self.robot.crumbs_left -= 1;
        }
        self.robot.linked = self.linked;
        delivered
    }

    /// The IMU's reading of the last step: specific force and angular rate in the body frame
    /// (exact: the noise is added by the caller that wants it, see [`Env::imu_noisy`]).
    fn measure_imu(&mut self) {
        let tr = &self.robot.trajectory;
        let n = tr.len();
        let dt = self.dt();
        let (a, b) = (tr[n - 2], tr[n - 1]);
        let v = [0, 1, 2].map(|k| (b.position[k] - a.position[k]) / dt);
        let acc = [0, 1, 2].map(|k| (v[k] - self.last_velocity[k]) / dt);
        self.last_velocity = v;
        let r = self.robot.rotation();
        let f = subtgraph_sensors::frames::mul_t(&r, [acc[0], acc[1], acc[2] + 9.81]);
        let last = self.last_ypr;
        let d = |k: usize| crate::body::wrap(b.ypr[k] - last[k]) / dt;
        // Small-angle rates: roll about x, pitch about y, yaw about z.
        self.imu = [f[0], f[1], f[2], d(2), d(1), d(0)];
        self.last_ypr = b.ypr;
    }

    /// The IMU reading with the ADIS16448's white noise (EuRoC calibration) at the control
    /// rate, drawn from the episode's seed and the step.
    pub fn imu_noisy(&self) -> [f64; 6] {
        let rate = self.options.control_hz.sqrt();
        let (acc, gyro) = (2.0e-3 * rate, 1.6968e-4 * rate);
        let mut out = self.imu;
        if self.options.noiseless {
            return out;
        }
        for (k, v) in out.iter_mut().enumerate() {
            let sigma = if k < 3 { acc } else { gyro };
            *v += sigma
                * subtgraph_sensors::noise::normal(self.seed ^ 0x1e0, (self.steps << 3) | k as u64);
        }
        out
    }

    /// The pose relative to the spawn: `[x, y, z, yaw, pitch, roll]` (metres, radians).
    pub fn pose(&self) -> [f64; 6] {
        let s = &self.robot.state;
        let o = self.robot.trajectory[0].position;
        [
            s.position[0] - o[0],
            s.position[1] - o[1],
            s.position[2] - o[2],
            s.yaw,
            s.pitch,
            s.roll,
        ]
    }

    /// The map around the robot into `out` (`[nz, ny, nx]`, C order, world-aligned, centred
    /// on the robot's voxel): 0 unknown, 1 free, 2 occupied.
    pub fn local_map(&self, n: [usize; 3], out: &mut [u8]) {
        let g = self.robot.map.grid;
        let p = self.robot.state.position;
        let c = [0, 1, 2].map(|k| ((p[k] - g.origin[k]) / g.voxel).floor() as i32);
        let [nx, ny, nz] = n;
        let mut i = 0;
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let v = [
                        c[0] + x as i32 - (nx / 2) as i32,
                        c[1] + y as i32 - (ny / 2) as i32,
                        c[2] + z as i32 - (nz / 2) as i32,
                    ];
                    out[i] = match self.robot.map.get(v) {
                        Voxel::Unknown => 0,
                        Voxel::Free => 1,
                        Voxel::Occupied => 2,
                    };
                    i += 1;
                }
            }
        }
    }

    /// The artifacts in view now, nearest first, at most `max`: their centres in the body
    /// frame and classes.
    pub fn in_view(&self, max: usize) -> Vec<([f64; 3], subtgraph_core::artifacts::ArtifactClass)> {
        let eye = self.robot.sensor(&self.options.body);
        let r = self.robot.rotation();
        let p = self.robot.state.position;
        let mut seen: Vec<(f64, [f64; 3], subtgraph_core::artifacts::ArtifactClass)> = self
            .options
            .detector
            .visible(&self.site.collision, eye, &self.site.artifacts)
            .map(|i| {
                let a = &self.site.artifacts[i];
                let d = [a.centre[0] - p[0], a.centre[1] - p[1], a.centre[2] - p[2]];
                let local = subtgraph_sensors::frames::mul_t(&r, d);
                (
                    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt(),
                    local,
                    a.class,
                )
            })
            .collect();
        seen.sort_by(|a, b| a.0.total_cmp(&b.0));
        seen.into_iter().take(max).map(|(_, l, c)| (l, c)).collect()
    }

    /// Breadcrumbs dropped this episode.
    pub fn crumbs(&self) -> usize {
        self.fixed.crumbs()
    }
}
