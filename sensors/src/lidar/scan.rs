//! Casting a scan: every ray of a model from the pose the sensor has when it fires, with range
//! noise, dropouts and intensity.
//!
//! A point is reported as a real sensor reports it: in the sensor's frame at the instant its
//! ray left (its range along its beam), with that instant's offset from the scan's start. A
//! moving sensor's scan is therefore distorted; a reader that moves each point by the pose at
//! its own time (the ground truth's, interpolated) puts it back on the rock, within the range
//! noise.
//!
//! Rays are cast in parallel over firing groups; everything a ray draws at random comes from
//! a hash of the seed, the scan and the ray's index, so a scan is the same on any number of
//! threads.

use rayon::prelude::*;
use subtgraph_core::vec3::V3;

use super::{Beam, LidarModel};
use crate::conditions::{Active, Kind};
use crate::frames::{Pose, mul};
use crate::noise;
use crate::scene::Scene;
use crate::trajectory::Trajectory;

/// One ray's return (or its absence), as the sensor reports it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Point {
    /// In the sensor frame at the ray's instant, metres (zero without a return).
    pub xyz: [f32; 3],
    /// Measured range, metres (0 without a return).
    pub range: f32,
    /// The surface's reflectivity times the cosine of the incidence angle, `0..=1`.
    pub reflectance: f32,
    /// Seconds from the scan's start to the ray's instant.
    pub time: f32,
    /// The driver's ring (beam, line).
    pub ring: u16,
    /// Whether the ray returned.
    pub valid: bool,
    /// What made the return, or took it ([`crate::conditions::Kind`]; 0, the surface, in
    /// clear air).
    pub kind: u8,
}

/// A scan: its rays' points in the model's order (group by group) and what the labels need.
#[derive(Clone, Debug, Default)]
pub struct Scan {
    /// Its index in the sequence.
    pub index: u64,
    /// When it starts, seconds.
    pub start: f64,
    /// One per ray.
    pub points: Vec<Point>,
    /// Returns (valid points).
    pub returns: usize,
    /// The point-to-plane registration Hessian of the noise-free returns, upper triangle
    /// row by row, world frame, rotations about the sensor and scaled by 1/metre (see
    /// [`crate::labels`]).
    pub hessian: [f64; 21],
    /// Sum of squared true ranges (for the rotation block's scale).
    pub range2: f64,
    /// Rays by what became of them ([`crate::conditions::Kind`]), counted under conditions.
    pub kinds: [u32; 7],
}

/// What scans a sequence: a model on a platform moving through a scene.
pub struct Scanner<'a> {
    model: &'a LidarModel,
    scene: &'a Scene,
    trajectory: &'a Trajectory,
    mount: Pose,
    seed: u64,
    /// A spinning model's beams, the same every scan, group by group (computed once: a
    /// scan's sines and cosines cost as much as a tenth of its rays).
    table: Option<Vec<Beam>>,
    /// Dust, fog, wet rock, drips: `None` in clear air.
    conditions: Option<&'a Active<'a>>,
}

/// What one task adds to its scan: the Hessian's sums, the squared ranges, the returns, the
/// rays by kind.
type Partial = ([f64; 21], f64, usize, [u32; 7]);

/// Firing groups cast by one task.
const GROUPS_PER_TASK: usize = 32;

impl<'a> Scanner<'a> {
    /// A scanner of `model` mounted at `mount` on a platform moving along `trajectory`
    /// through `scene`, its noise drawn from `seed`.
    pub fn new(
        model: &'a LidarModel,
        scene: &'a Scene,
        trajectory: &'a Trajectory,
        mount: Pose,
        seed: u64,
    ) -> Scanner<'a> {
        let table = matches!(model.pattern, super::Pattern::Spinning { .. }).then(|| {
            let (groups, _) = model.groups();
            let mut all = Vec::with_capacity(model.rays_per_scan());
            let mut beams = Vec::new();
            for g in 0..groups {
                model.beams(0, g, &mut beams);
                all.extend_from_slice(&beams);
            }
            all
        });
        Scanner {
            model,
            scene,
            trajectory,
            mount,
            seed,
            table,
            conditions: None,
        }
    }

    /// The same scanner in `conditions`.
    pub fn with_conditions(mut self, conditions: Option<&'a Active<'a>>) -> Scanner<'a> {
        self.conditions = conditions;
        self
    }

    /// The sensor's pose at time `t`.
    pub fn pose(&self, t: f64) -> Pose {
        self.trajectory.pose(t).then(&self.mount)
    }

    /// Casts scan `index` (starting at `start` seconds) into `out`, reusing its buffers.
    pub fn scan(&self, index: u64, start: f64, out: &mut Scan) {
        let (groups, per_group) = self.model.groups();
        out.index = index;
        out.start = start;
        // Every point is written by its ray (a miss included), so the buffer is only resized.
        out.points.resize(groups * per_group, Point::default());
        let partials: Vec<Partial> = out
            .points
            .par_chunks_mut(GROUPS_PER_TASK * per_group)
            .enumerate()
            .map(|(task, points)| self.task(index, start, task, points))
            .collect();
        out.hessian = [0.0; 21];
        out.range2 = 0.0;
        out.returns = 0;
        out.kinds = [0; 7];
        for (h, r2, n, kinds) in partials {
            for (a, b) in out.hessian.iter_mut().zip(h) {
                *a += b;
            }
            out.range2 += r2;
            out.returns += n;
            for (a, b) in out.kinds.iter_mut().zip(kinds) {
                *a += b;
            }
        }
    }

    /// One task's groups of a scan: their poses first, then the rays beam by beam across the
    /// groups (neighbouring columns' rays run nearly parallel and visit the same boxes, so
    /// the hierarchy stays in cache).
    fn task(&self, index: u64, start: f64, task: usize, points: &mut [Point]) -> Partial {
        let (_, per_group) = self.model.groups();
        let cos_grazing = self.model.grazing_deg.to_radians().cos();
        let [near, far] = self.model.range_m;
        let sigma = self.model.range_noise_m;
        let count = points.len() / per_group;
        let first = task * GROUPS_PER_TASK;
        let poses: Vec<(f64, Pose)> = (first..first + count)
            .map(|g| {
                let dt = self.model.group_time(g);
                (dt, self.pose(start + dt))
            })
            .collect();
        // A spinning model's beams are read from its table in place, not copied for every
        // task; a non-repeating pattern's are drawn for this scan.
        let drawn: Vec<Beam>;
        let beams: &[Beam] = match &self.table {
            Some(t) => &t[first * per_group..(first + count) * per_group],
            None => {
                let mut all = Vec::with_capacity(count * per_group);
                let mut scratch = Vec::with_capacity(per_group);
                for g in first..first + count {
                    self.model.beams(index, g, &mut scratch);
                    all.extend_from_slice(&scratch);
                }
                drawn = all;
                &drawn
            }
        };
        let mut h = [0.0; 21];
        let mut r2 = 0.0;
        let mut returns = 0;
        let mut kinds = [0u32; 7];
        let mut tracer = self.scene.caster.tracer();
        let frames: Vec<crate::conditions::Frame> = match self.conditions {
            Some(c) => poses
                .iter()
                .map(|(dt, pose)| c.frame(start + dt, pose.translation))
                .collect(),
            None => Vec::new(),
        };
        for j in 0..per_group {
            for (k, (dt, pose)) in poses.iter().enumerate() {
                let i = k * per_group + j;
                let (beam, p) = (&beams[i], &mut points[i]);
                let d = mul(&pose.rotation, beam.dir);
                *p = Point {
                    ring: beam.ring,
                    time: *dt as f32,
                    ..Point::default()
                };
                let hit = tracer.cast(pose.translation, d, far);
                if let Some(c) = self.conditions {
                    let ray = ((first * per_group + i) as u64) | (index << 32);
                    let kind =
                        self.condition_ray(c, &frames[k], ray, pose, d, beam, hit, p, &mut tracer);
                    kinds[kind as usize] += 1;
                    if p.valid {
                        returns += 1;
                        if let Some(hit) =
                            hit.filter(|_| kind == Kind::Surface as u8 || kind == Kind::Wet as u8)
                        {
                            let n = hit.normal.map(f64::from);
                            accumulate(&mut h, [hit.t * d[0], hit.t * d[1], hit.t * d[2]], n);
                            r2 += hit.t * hit.t;
                        }
                    }
                    continue;
                }
                let Some(hit) = hit else {
                    continue;
                };
                let n = hit.normal.map(f64::from);
                let cos = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).abs();
                if hit.t < near || cos < cos_grazing {
                    continue;
                }
                let ray = ((first * per_group + i) as u64) | (index << 32);
                let range = if sigma > 0.0 {
                    (hit.t + sigma * noise::normal(self.seed, ray)).max(0.0)
                } else {
                    hit.t
                };
                let rho = self.scene.reflectivity_of(hit.triangle);
                p.xyz = [
                    (range * beam.dir[0]) as f32,
                    (range * beam.dir[1]) as f32,
                    (range * beam.dir[2]) as f32,
                ];
                p.range = range as f32;
                p.reflectance = (f64::from(rho) * cos) as f32;
                p.valid = true;
                returns += 1;
                // The true return, for the registration Hessian.
                let q = [hit.t * d[0], hit.t * d[1], hit.t * d[2]];
                accumulate(&mut h, q, n);
                r2 += hit.t * hit.t;
            }
        }
        (h, r2, returns, kinds)
    }

    /// One ray in conditions: fills `p` as the conditions make it and says what made it
    /// ([`Kind`]). A ray they do not touch comes out as in clear air.
    #[allow(clippy::too_many_arguments)]
    fn condition_ray(
        &self,
        c: &Active<'_>,
        frame: &crate::conditions::Frame,
        ray: u64,
        pose: &Pose,
        d: V3,
        beam: &Beam,
        hit: Option<subtgraph_core::raycast::Hit>,
        p: &mut Point,
        tracer: &mut subtgraph_core::raycast::Tracer<'_>,
    ) -> u8 {
        use crate::conditions::{Outcome, Shot, Surface};
        let m = self.model;
        let cos_grazing = m.grazing_deg.to_radians().cos();
        let surface = hit.and_then(|hit| {
            let n = hit.normal.map(f64::from);
            let cos = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).abs();
            let rho = self.scene.reflectivity_of(hit.triangle);
            (hit.t >= m.range_m[0] && cos >= cos_grazing).then(|| Surface {
                t: hit.t,
                normal: n,
                rho: f64::from(rho),
                cos,
            })
        });
        let sigma = m.range_noise_m;
        let normal_draw = if sigma > 0.0 {
            noise::normal(self.seed, ray)
        } else {
            0.0
        };
        let shot = Shot {
            origin: pose.translation,
            dir: d,
            key: ray,
            surface,
            far: m.range_m[1],
            sigma,
            normal_draw,
        };
        let (range, reflectance, kind) = match c.shoot(frame, &shot, tracer) {
            Outcome::Untouched => match surface {
                None => return Kind::Surface as u8,
                Some(s) if sigma > 0.0 => (
                    (s.t + sigma * normal_draw).max(0.0),
                    s.rho * s.cos,
                    Kind::Surface,
                ),
                Some(s) => (s.t, s.rho * s.cos, Kind::Surface),
            },
            Outcome::Return {
                range,
                reflectance,
                kind,
                ..
            } => (range, reflectance, kind),
            Outcome::Lost => {
                p.kind = Kind::Lost as u8;
                return Kind::Lost as u8;
            }
        };
        p.xyz = [
            (range * beam.dir[0]) as f32,
            (range * beam.dir[1]) as f32,
            (range * beam.dir[2]) as f32,
        ];
        p.range = range as f32;
        p.reflectance = reflectance as f32;
        p.valid = true;
        p.kind = kind as u8;
        kind as u8
    }

    /// A point of scan `scan` moved into the world by the sensor's pose at its time (what a
    /// reader of the sequence does with the ground truth).
    pub fn to_world(&self, scan: &Scan, p: &Point) -> V3 {
        let pose = self.pose(scan.start + f64::from(p.time));
        pose.apply(p.xyz.map(f64::from))
    }
}

/// Adds one return's point-to-plane row `J = [q x n, n]` (the point `q` relative to the
/// sensor, the normal `n`) to the upper triangle of `J^T J`.
pub(crate) fn accumulate(h: &mut [f64; 21], q: V3, n: V3) {
    let r = [
        q[1] * n[2] - q[2] * n[1],
        q[2] * n[0] - q[0] * n[2],
        q[0] * n[1] - q[1] * n[0],
    ];
    let j = [r[0], r[1], r[2], n[0], n[1], n[2]];
    let mut k = 0;
    for a in 0..6 {
        for b in a..6 {
            h[k] += j[a] * j[b];
            k += 1;
        }
    }
}

/// One scan of `model` from a sensor standing still at `pose` (world frame): its returns in
/// the sensor's frame, with range noise drawn from `seed` when `noise` is set. For learning
/// pipelines that render their own views (the Python `World.lidar_scan`).
pub fn still_scan(
    scene: &Scene,
    model: &LidarModel,
    pose: Pose,
    noise: bool,
    seed: u64,
) -> Vec<[f64; 3]> {
    let mut model = model.clone();
    if !noise {
        model.range_noise_m = 0.0;
    }
    let trajectory = Trajectory::new(1.0, vec![[0.0; 6]; 6]);
    let scanner = Scanner::new(&model, scene, &trajectory, pose, seed);
    let mut scan = Scan::default();
    scanner.scan(0, 0.0, &mut scan);
    scan.points
        .iter()
        .filter(|p| p.valid)
        .map(|p| p.xyz.map(f64::from))
        .collect()
}
