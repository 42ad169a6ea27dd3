//! The LiDAR in the loop: the columns a spinning head fires during a control step, cast from
//! the pose the body has at the end of the step into the scanned surface, on the calling
//! thread.
//!
//! The models are `sense`'s ([`LidarModel`]: `vlp-16`, `os1-32`, `mid-360`, a table...), their
//! beams, range limits, noise and grazing cut-off; what the loop changes is the **azimuth
//! resolution**. A spinning model's scan here has `columns` evenly spaced columns a turn
//! (default: [`DEFAULT_COLUMNS`], one every 2 degrees, as far apart as the VLP-16's beams are
//! vertically, a square 16 x 180 ranges image) instead of the sensor's own (1,800 for the
//! VLP-16): a step's scan then costs 2,880 rays instead of 28,800, which is what lets the
//! environment step thousands of times a second. `columns` up to the model's own gives the full
//! scan. A non-repeating pattern (Livox) fires its own frame's rays, every `stride`-th of them.
//!
//! **The head turns at its own rate, whatever the control rate.** A step of `dt` seconds casts
//! the columns whose firing instants fall within it: at 10 Hz control and a 10 Hz head, a
//! whole turn each step; at 50 Hz control, a fifth of a turn (36 columns of 180), so the map
//! grows at the LiDAR's real rate, not once per control step, and a faster control loop costs
//! no more rays a second. A step's columns leave from the pose at the end of the step (`sense`
//! models each column's own instant; a policy's observation does not need it). A non-repeating
//! pattern (Livox) fires its frame's rays over the frame the same way. Range noise is the
//! model's, drawn from a hash of the seed, the turn and the ray, so a scan is the same on any
//! thread.

use subtgraph_core::raycast::RayCaster;
use subtgraph_sensors::frames::{Mat3, mul};
use subtgraph_sensors::lidar::{Beam, LidarModel, Pattern};
use subtgraph_sensors::noise;

use crate::error::ExploreError;

/// The model the loop scans with unless told (a ground robot's usual LiDAR in SubT).
pub const DEFAULT_MODEL: &str = "vlp-16";

/// Columns a turn of a spinning model's scan by default: one every 2 degrees.
pub const DEFAULT_COLUMNS: usize = 180;

/// Rays a part of a split scan holds ([`Lidar::scan`]).
const SPLIT_RAYS: usize = 720;

/// A LiDAR model as the loop casts it.
#[derive(Clone, Debug)]
pub struct Lidar {
    /// The model.
    pub model: LidarModel,
    /// Rows of the ranges image (a spinning model's beams; 1 for a non-repeating one).
    pub rings: usize,
    /// Columns of the ranges image (the rays of a non-repeating one).
    pub columns: usize,
    /// A spinning model's beams, column by column (`columns x rings`), in the sensor frame.
    fixed: Vec<[f64; 3]>,
    /// A non-repeating model's stride through its frame's rays.
    stride: usize,
}

/// One scan's rays: where they left from, where they went, how far.
#[derive(Clone, Debug, Default)]
pub struct Scan {
    /// The sensor's position, world frame.
    pub origin: [f64; 3],
    /// Each ray's unit direction, world frame.
    pub dirs: Vec<[f64; 3]>,
    /// Each ray's measured range, metres; 0 without a return (the drivers' convention).
    pub ranges: Vec<f32>,
    /// The absolute columns cast (column `c % columns` of turn `c / columns`), each with
    /// `rings` rays in the order above.
    pub columns: Vec<u64>,
}

impl Scan {
    /// Returns.
    pub fn returns(&self) -> usize {
        self.ranges.iter().filter(|&&r| r > 0.0).count()
    }

    /// The return of ray `k` in the world frame, if it returned.
    pub fn point(&self, k: usize) -> Option<[f64; 3]> {
        let r = f64::from(self.ranges[k]);
        (r > 0.0).then(|| {
            let d = self.dirs[k];
            [
                self.origin[0] + r * d[0],
                self.origin[1] + r * d[1],
                self.origin[2] + r * d[2],
            ]
        })
    }
}

impl Lidar {
    /// A model by `sense`'s names (or a LiDAR table's path, whose text `read` gives), cast at
    /// `columns` (see [`Lidar::of`]).
    pub fn named(
        name: &str,
        columns: Option<usize>,
        read: impl FnOnce(&str) -> Option<String>,
    ) -> Result<Lidar, ExploreError> {
        Lidar::of(LidarModel::named(name, read)?, columns)
    }

    /// A model cast at `columns` a turn (spinning: 16 to the model's own, default
    /// [`DEFAULT_COLUMNS`] or the model's own when fewer; non-repeating: the rays of a frame
    /// kept, default a tenth of them).
    pub fn of(model: LidarModel, columns: Option<usize>) -> Result<Lidar, ExploreError> {
        match &model.pattern {
            Pattern::Spinning {
                elevations_deg,
                azimuth_offsets_deg,
                columns: own,
            } => {
                let columns = columns.unwrap_or(DEFAULT_COLUMNS.min(*own));
                if !(16..=*own).contains(&columns) {
                    return Err(ExploreError::bounds(
                        format!("the columns of a {} scan", model.name),
                        columns,
                        &format!("16 to {own} (the model's own) a turn"),
                    ));
                }
                let rings = elevations_deg.len();
                let mut fixed = Vec::with_capacity(columns * rings);
                for c in 0..columns {
                    // Clockwise from straight behind, as the heads turn (the sense models').
                    let az =
                        std::f64::consts::PI - std::f64::consts::TAU * c as f64 / columns as f64;
                    for (el, off) in elevations_deg.iter().zip(azimuth_offsets_deg) {
                        let (el, a) = (el.to_radians(), az + off.to_radians());
                        fixed.push([el.cos() * a.cos(), el.cos() * a.sin(), el.sin()]);
                    }
                }
                Ok(Lidar {
                    rings,
                    columns,
                    fixed,
                    stride: 1,
                    model,
                })
            }
            Pattern::NonRepeating { .. } => {
                let all = model.rays_per_scan();
                let columns = columns.unwrap_or(all.div_ceil(10));
                if !(16..=all).contains(&columns) {
                    return Err(ExploreError::bounds(
                        format!("the rays of a {} scan", model.name),
                        columns,
                        &format!("16 to {all} (a frame's own)"),
                    ));
                }
                Ok(Lidar {
                    rings: 1,
                    stride: all / columns,
                    columns,
                    fixed: Vec::new(),
                    model,
                })
            }
        }
    }

    /// Rays a scan casts.
    pub fn rays(&self) -> usize {
        self.rings * self.columns
    }

    /// Columns the head fires per second.
    pub fn columns_per_second(&self) -> f64 {
        self.columns as f64 * self.model.rate_hz
    }

    /// The columns fired during control step `step` of `dt` seconds, as absolute counts
    /// (column `c` of turn `c / columns`), in firing order, into `out`: the columns whose
    /// firing instants fall in the step, at most one whole turn (the last).
    pub fn fired(&self, step: u64, dt: f64, out: &mut Vec<u64>) {
        let cps = self.columns_per_second();
        let a = (step as f64 * dt * cps).floor() as u64;
        let b = ((step + 1) as f64 * dt * cps).floor() as u64;
        let a = a.max(b.saturating_sub(self.columns as u64));
        out.clear();
        out.extend(a..b);
    }

    /// The sensor-frame beams of absolute column `c` into `out` (`rings` of them), using
    /// `frame` to keep a non-repeating pattern's frame between calls.
    fn column_beams(&self, c: u64, frame: &mut (u64, Vec<[f64; 3]>), out: &mut [[f64; 3]]) {
        let col = (c % self.columns as u64) as usize;
        if !self.fixed.is_empty() {
            out.copy_from_slice(&self.fixed[col * self.rings..(col + 1) * self.rings]);
            return;
        }
        let turn = c / self.columns as u64;
        if frame.1.is_empty() || frame.0 != turn {
            frame.0 = turn;
            frame.1.clear();
            let (groups, _) = self.model.groups();
            let mut group: Vec<Beam> = Vec::new();
            let mut k = 0usize;
            for g in 0..groups {
                self.model.beams(turn, g, &mut group);
                for b in &group {
                    if k % self.stride == 0 && frame.1.len() < self.columns {
                        frame.1.push(b.dir);
                    }
                    k += 1;
                }
            }
            while frame.1.len() < self.columns {
                frame.1.push([1.0, 0.0, 0.0]);
            }
        }
        out[0] = frame.1[col];
    }

    /// Casts the absolute columns `columns` from a sensor at `origin` turned by `rotation`
    /// (sensor to world) into `caster`, noise drawn from `seed` unless `noiseless`; `frame`
    /// keeps a non-repeating pattern's frame between calls. With `split`, the rays are cast
    /// in parts on rayon's threads (a mission's robots share two cores unevenly: three robots
    /// on two threads leave one idle a third of the time unless it can take part of a scan);
    /// each ray is cast alone, so the scan is the same either way.
    #[allow(clippy::too_many_arguments)]
    pub fn scan(
        &self,
        caster: &RayCaster,
        origin: [f64; 3],
        rotation: &Mat3,
        columns: &[u64],
        seed: u64,
        noiseless: bool,
        frame: &mut (u64, Vec<[f64; 3]>),
        split: bool,
        out: &mut Scan,
    ) {
        let rings = self.rings;
        let n = columns.len() * rings;
        out.origin = origin;
        out.columns.clear();
        out.columns.extend_from_slice(columns);
        out.dirs.resize(n, [0.0; 3]);
        out.ranges.resize(n, 0.0);
        let mut beams = vec![[0.0; 3]; rings];
        for (j, &c) in columns.iter().enumerate() {
            self.column_beams(c, frame, &mut beams);
            for (r, beam) in beams.iter().enumerate() {
                out.dirs[j * rings + r] = mul(rotation, *beam);
            }
        }
        let cut = Cut {
            range_m: self.model.range_m,
            cos_grazing: self.model.grazing_deg.to_radians().cos(),
            sigma: if noiseless {
                0.0
            } else {
                self.model.range_noise_m
            },
            seed,
        };
        let cast = |first: usize, ranges: &mut [f32]| {
            let mut tracer = caster.tracer();
            for (i, range) in ranges.iter_mut().enumerate() {
                let k = first + i;
                let column = columns[k / rings];
                *range = self.range(&mut tracer, origin, out.dirs[k], column, k % rings, &cut);
            }
        };
        if split && n >= 2 * SPLIT_RAYS {
            use rayon::prelude::*;
            out.ranges
                .par_chunks_mut(SPLIT_RAYS)
                .enumerate()
                .for_each(|(i, part)| cast(i * SPLIT_RAYS, part));
        } else {
            cast(0, &mut out.ranges);
        }
    }

    /// The range ray `ring` of absolute column `column` measures along `d` (world frame) from
    /// `origin`; 0 without a return.
    fn range(
        &self,
        tracer: &mut subtgraph_core::raycast::Tracer<'_>,
        origin: [f64; 3],
        d: [f64; 3],
        column: u64,
        ring: usize,
        cut: &Cut,
    ) -> f32 {
        let [near, far] = cut.range_m;
        let Some(hit) = tracer.cast(origin, d, far) else {
            return 0.0;
        };
        let nrm = hit.normal.map(f64::from);
        let cos = (nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2]).abs();
        if hit.t < near || cos < cut.cos_grazing {
            return 0.0;
        }
        let range = if cut.sigma > 0.0 {
            let turn = column / self.columns as u64;
            let col = column % self.columns as u64;
            let key = (col * self.rings as u64 + ring as u64) | (turn << 32);
            (hit.t + cut.sigma * noise::normal(cut.seed, key)).max(near)
        } else {
            hit.t
        };
        range as f32
    }
}

/// What a scan's returns are held to: the model's ranges, its grazing cut-off (as a cosine),
/// its range noise (0: none) and the noise's seed.
struct Cut {
    range_m: [f64; 2],
    cos_grazing: f64,
    sigma: f64,
    seed: u64,
}
