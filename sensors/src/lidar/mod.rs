//! LiDAR models: how a sensor's beams are laid out and fired, its range limits and noise, and
//! which driver's messages it publishes.
//!
//! The built-ins, as `--lidar` names them: `os1-32`, `os1-64`, `os1-128` ([`ouster`]),
//! `vlp-16` ([`velodyne`]) and `mid-360` ([`livox`]); any other value is read as a LiDAR
//! table, a TOML file describing a spinning sensor ([`table`]). A model yields its rays in
//! *firing groups* (a column of a spinning head, a millisecond of a Livox pattern): the rays
//! of a group leave at the same instant, from the pose the sensor has then, so a moving sensor's
//! scan is distorted as a real one's is; [`scan`] casts them.

pub mod livox;
pub mod ouster;
pub mod scan;
pub mod table;
pub mod velodyne;

use serde::Serialize;
use subtgraph_core::vec3::V3;

use crate::error::SenseError;

/// Whose driver's messages a model publishes: the `PointCloud2` fields, the frame name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Driver {
    /// ouster-ros: `x y z intensity t reflectivity ring ambient range`, organized (a row per
    /// beam), `t` in nanoseconds from the scan's start.
    Ouster,
    /// velodyne_pointcloud: `x y z intensity ring time`, `time` in seconds from the scan's
    /// start.
    Velodyne,
    /// livox_ros_driver2 (PointCloud2 output): `x y z intensity tag line timestamp`,
    /// `timestamp` absolute in nanoseconds.
    Livox,
}

impl Driver {
    /// The frame the driver publishes points in.
    pub fn frame_id(self) -> &'static str {
        match self {
            Driver::Ouster => "os_sensor",
            Driver::Velodyne => "velodyne",
            Driver::Livox => "livox_frame",
        }
    }
}

/// How the beams are laid out.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Pattern {
    /// A spinning head: beams at fixed elevations, fired together column by column, the
    /// columns evenly spaced over a turn.
    Spinning {
        /// Elevation of each beam, degrees, in the driver's channel order (its `ring`).
        elevations_deg: Vec<f64>,
        /// Azimuth offset of each beam from its column's, degrees.
        azimuth_offsets_deg: Vec<f64>,
        /// Columns per turn.
        columns: usize,
    },
    /// A non-repeating pattern (Livox): `lines` lasers swept in azimuth once a frame while
    /// their elevation sweeps up and down many times, at frequencies that never line up, so
    /// no two frames cover the same directions and the field of view fills in over time.
    NonRepeating {
        /// Lasers (the `line` field).
        lines: usize,
        /// Points per second, all lines together.
        points_per_second: f64,
        /// Lowest and highest elevation, degrees.
        elevation_deg: [f64; 2],
        /// Elevation sweeps per second.
        sweeps_per_second: f64,
    },
}

/// A LiDAR model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LidarModel {
    /// Its name (`os1-32`, or a table's `name`).
    pub name: String,
    /// Whose messages it publishes.
    pub driver: Driver,
    /// The beams.
    pub pattern: Pattern,
    /// Scans per second.
    pub rate_hz: f64,
    /// Nearest and farthest return, metres.
    pub range_m: [f64; 2],
    /// Range noise, one standard deviation, metres.
    pub range_noise_m: f64,
    /// Incidence angle beyond which a surface returns nothing, degrees from its normal.
    pub grazing_deg: f64,
    /// Where the numbers come from.
    pub source: String,
}

/// A built-in model: its name and what makes it.
type BuiltIn = (&'static str, fn() -> LidarModel);

/// The built-in models, by the names `--lidar` takes: the one place they are listed.
const BUILT_IN: [BuiltIn; 5] = [
    ("os1-32", || ouster::os1(32)),
    ("os1-64", || ouster::os1(64)),
    ("os1-128", || ouster::os1(128)),
    ("vlp-16", velodyne::vlp16),
    ("mid-360", livox::mid360),
];

/// The built-in names `--lidar` takes.
pub const NAMES: [&str; 5] = {
    let mut names = [""; 5];
    let mut i = 0;
    while i < names.len() {
        names[i] = BUILT_IN[i].0;
        i += 1;
    }
    names
};

/// The model `sense` and `dataset --sense` scan with unless told.
pub const DEFAULT: &str = NAMES[0];

/// What `--lidar` takes, as the command line's help says it.
pub const CHOICES: &str = "os1-32, os1-64, os1-128, vlp-16, mid-360, or a LiDAR table FILE.toml";

/// The same, for the commands whose cameras can go alone.
pub const CHOICES_OR_NONE: &str =
    "os1-32, os1-64, os1-128, vlp-16, mid-360, a LiDAR table FILE.toml, or none (cameras alone)";

/// One ray of a scan, in the sensor's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beam {
    /// Unit direction.
    pub dir: V3,
    /// The driver's ring (channel, line).
    pub ring: u16,
}

impl LidarModel {
    /// A built-in model, or a table read from the file `name` names (its text in `read`).
    pub fn named(
        name: &str,
        read: impl FnOnce(&str) -> Option<String>,
    ) -> Result<LidarModel, SenseError> {
        let model = if let Some((_, built_in)) = BUILT_IN.iter().find(|(n, _)| *n == name) {
            built_in()
        } else if name.ends_with(".toml") {
            let text = read(name).ok_or_else(|| SenseError::BadLidarTable {
                path: name.to_owned(),
                why: "cannot be read".into(),
            })?;
            table::parse(&text, name)?
        } else {
            return Err(SenseError::Unknown {
                what: "LiDAR model",
                name: name.to_owned(),
                known: CHOICES.to_owned(),
            });
        };
        model.check()?;
        Ok(model)
    }

    /// Refuses numbers no real sensor has.
    pub fn check(&self) -> Result<(), SenseError> {
        let oob = |what: &str, value: String, bounds: &str| {
            Err(SenseError::OutOfBounds {
                what: format!("{} of LiDAR '{}'", what, self.name),
                value,
                bounds: bounds.to_owned(),
            })
        };
        if !(self.rate_hz >= 1.0 && self.rate_hz <= 50.0) {
            return oob(
                "rate_hz",
                self.rate_hz.to_string(),
                "1 to 50 scans a second",
            );
        }
        let [lo, hi] = self.range_m;
        if !(lo >= 0.0 && lo < hi && hi <= 500.0) {
            return oob(
                "range_m",
                format!("[{lo}, {hi}]"),
                "[nearest, farthest] with 0 <= nearest < farthest <= 500 metres",
            );
        }
        if !(self.range_noise_m >= 0.0 && self.range_noise_m <= 0.5) {
            return oob(
                "range_noise_m",
                self.range_noise_m.to_string(),
                "0 to 0.5 metres",
            );
        }
        if !(self.grazing_deg > 0.0 && self.grazing_deg <= 90.0) {
            return oob(
                "grazing_deg",
                self.grazing_deg.to_string(),
                "above 0 and at most 90 degrees",
            );
        }
        match &self.pattern {
            Pattern::Spinning {
                elevations_deg,
                azimuth_offsets_deg,
                columns,
            } => {
                if elevations_deg.is_empty() || elevations_deg.len() > 512 {
                    return oob(
                        "elevations_deg",
                        format!("({} beams)", elevations_deg.len()),
                        "1 to 512 beams",
                    );
                }
                if elevations_deg.iter().any(|e| e.is_nan() || e.abs() > 90.0) {
                    return oob(
                        "elevations_deg",
                        format!("{elevations_deg:?}"),
                        "angles within -90 to 90 degrees",
                    );
                }
                if azimuth_offsets_deg.len() != elevations_deg.len()
                    || azimuth_offsets_deg
                        .iter()
                        .any(|a| a.is_nan() || a.abs() > 180.0)
                {
                    return oob(
                        "azimuth_offsets_deg",
                        format!("{azimuth_offsets_deg:?}"),
                        "one angle within -180 to 180 degrees per beam",
                    );
                }
                if !(16..=8192).contains(columns) {
                    return oob("columns", columns.to_string(), "16 to 8192 a turn");
                }
                // About 5 M points a second is what the densest sensors sold deliver.
                let pps = (*columns * elevations_deg.len()) as f64 * self.rate_hz;
                if pps > 6e6 {
                    return oob(
                        "points a second (columns x beams x rate)",
                        format!("{pps:.0}"),
                        "at most 6 million",
                    );
                }
            }
            Pattern::NonRepeating {
                lines,
                points_per_second,
                elevation_deg,
                sweeps_per_second,
            } => {
                let rate_ok = *points_per_second > 0.0 && *points_per_second <= 6e6;
                if !(1..=16).contains(lines) || !rate_ok {
                    return oob(
                        "lines or points_per_second",
                        format!("{lines}, {points_per_second}"),
                        "1 to 16 lines, up to 6 million points a second",
                    );
                }
                if !(elevation_deg[0] < elevation_deg[1]
                    && elevation_deg[0] >= -90.0
                    && elevation_deg[1] <= 90.0)
                {
                    return oob(
                        "elevation_deg",
                        format!("{elevation_deg:?}"),
                        "[lowest, highest] within -90 to 90 degrees",
                    );
                }
                if sweeps_per_second.is_nan() || *sweeps_per_second <= 0.0 {
                    return oob(
                        "sweeps_per_second",
                        sweeps_per_second.to_string(),
                        "positive",
                    );
                }
            }
        }
        Ok(())
    }

    /// How long one scan takes, seconds.
    pub fn period(&self) -> f64 {
        1.0 / self.rate_hz
    }

    /// Rings (beams, lines).
    pub fn rings(&self) -> usize {
        match &self.pattern {
            Pattern::Spinning { elevations_deg, .. } => elevations_deg.len(),
            Pattern::NonRepeating { lines, .. } => *lines,
        }
    }

    /// Firing groups per scan, and rays per group.
    pub fn groups(&self) -> (usize, usize) {
        match &self.pattern {
            Pattern::Spinning {
                elevations_deg,
                columns,
                ..
            } => (*columns, elevations_deg.len()),
            Pattern::NonRepeating {
                points_per_second, ..
            } => {
                // A group a millisecond.
                let per_scan = (points_per_second / self.rate_hz).round() as usize;
                let groups = (self.period() * 1000.0).round().max(1.0) as usize;
                (groups, per_scan.div_ceil(groups))
            }
        }
    }

    /// Rays a scan casts.
    pub fn rays_per_scan(&self) -> usize {
        let (g, r) = self.groups();
        g * r
    }

    /// When group `g` of a scan fires, seconds after the scan starts.
    pub fn group_time(&self, g: usize) -> f64 {
        let (groups, _) = self.groups();
        self.period() * g as f64 / groups as f64
    }

    /// The beams of group `g` of scan `scan`, in the sensor frame (x forward, z up).
    pub fn beams(&self, scan: u64, g: usize, out: &mut Vec<Beam>) {
        out.clear();
        match &self.pattern {
            Pattern::Spinning {
                elevations_deg,
                azimuth_offsets_deg,
                columns,
            } => {
                // Clockwise seen from above, from straight behind, as Ouster and Velodyne heads
                // turn and split their scans (readers that rebuild point times from azimuth,
                // as FAST-LIO's and GenZ-LIO's do without a time field, assume it).
                let az = std::f64::consts::PI - std::f64::consts::TAU * g as f64 / *columns as f64;
                for (ring, (el, off)) in elevations_deg.iter().zip(azimuth_offsets_deg).enumerate()
                {
                    let (el, a) = (el.to_radians(), az + off.to_radians());
                    out.push(Beam {
                        dir: [el.cos() * a.cos(), el.cos() * a.sin(), el.sin()],
                        ring: ring as u16,
                    });
                }
            }
            Pattern::NonRepeating {
                lines,
                points_per_second,
                elevation_deg,
                sweeps_per_second,
            } => {
                let (_, per_group) = self.groups();
                let [lo, hi] = elevation_deg.map(f64::to_radians);
                // The golden ratio's fraction moves each scan's sweep phase, so no scan
                // repeats another.
                let drift = (scan as f64 * 0.618_033_988_749_895).fract();
                let t0 = scan as f64 * self.period() + self.group_time(g);
                for k in 0..per_group {
                    let i = g * per_group + k;
                    let line = i % lines;
                    let t = t0 + k as f64 / points_per_second;
                    let phase = sweeps_per_second * t + line as f64 / *lines as f64 + drift;
                    // A triangle wave: the elevation spends equal time at every height.
                    let tri = 1.0 - 2.0 * (phase.fract() - 0.5).abs();
                    let el = lo + (hi - lo) * tri;
                    let a = std::f64::consts::TAU
                        * (self.rate_hz * t + line as f64 / *lines as f64 + 0.37 * drift);
                    out.push(Beam {
                        dir: [el.cos() * a.cos(), el.cos() * a.sin(), el.sin()],
                        ring: line as u16,
                    });
                }
            }
        }
    }
}

/// Parameters a command line may change on a model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Scans per second.
    pub rate_hz: Option<f64>,
    /// Farthest return, metres.
    pub max_range_m: Option<f64>,
    /// No range noise.
    pub noiseless: bool,
}

impl Overrides {
    /// Applies these to a model and checks it again.
    pub fn apply(&self, mut m: LidarModel) -> Result<LidarModel, SenseError> {
        if let Some(r) = self.rate_hz {
            m.rate_hz = r;
        }
        if let Some(r) = self.max_range_m {
            m.range_m[1] = r;
        }
        if self.noiseless {
            m.range_noise_m = 0.0;
        }
        m.check()?;
        Ok(m)
    }
}

#[cfg(test)]
mod names {
    use super::*;

    #[test]
    fn the_help_lists_every_built_in_model_and_each_name_makes_its_model() {
        let listed = format!("{}, or a LiDAR table FILE.toml", NAMES.join(", "));
        assert_eq!(CHOICES, listed);
        let or_none = format!(
            "{}, a LiDAR table FILE.toml, or none (cameras alone)",
            NAMES.join(", ")
        );
        assert_eq!(CHOICES_OR_NONE, or_none);
        assert!(NAMES.contains(&DEFAULT));
        for name in NAMES {
            let model = LidarModel::named(name, |_| None).unwrap();
            assert_eq!(model.name, name);
        }
    }
}
