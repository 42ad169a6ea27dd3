//! Artifacts in view: what a robot's detector reports, and the reports it keeps until a link
//! carries them to the base station.
//!
//! An artifact is **in view** of a sensor when its box's centre is within
//! [`Detector::range_m`] (10 m: the distance at which the survey judges an artifact in reach
//! of a robot's sensors, `subtgraph_survey::sight::NEAR`) and the straight line from the sensor
//! to the centre meets no rock before the last [`subtgraph_survey::sight::SIGHT_END`] (where the
//! artifact touches a wall or the floor). It is then **detected**, once per robot: the report
//! gives its class, always right (a detector's confusions are not modelled), and its centre
//! with an error of [`Detector::error_m`] per axis (0.3 m, one standard deviation), drawn
//! from a hash of the seed, the robot and the artifact, so the same run reports the same
//! positions. A report scores only once it reaches the base station (DARPA's rule):
//! the robot holds it ([`crate::robot`]) until it has a link.

use subtgraph_core::artifacts::ArtifactClass;
use subtgraph_core::raycast::RayCaster;
use subtgraph_sensors::noise;
use subtgraph_survey::sight::SIGHT_END;

use crate::site::Artifact;

/// What a robot's detector sees.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Detector {
    /// Farthest detection, metres.
    pub range_m: f64,
    /// Reported position error, one standard deviation per axis, metres.
    pub error_m: f64,
}

impl Default for Detector {
    fn default() -> Self {
        Detector {
            range_m: subtgraph_survey::sight::NEAR,
            error_m: 0.3,
        }
    }
}

/// One artifact report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report {
    /// The robot that made it.
    pub robot: usize,
    /// The artifact's id (kept for the logs; a real team would not know it).
    pub artifact: usize,
    /// Reported class.
    pub class: ArtifactClass,
    /// Reported position, world frame.
    pub position: [f64; 3],
    /// When it was detected, seconds.
    pub detected: f64,
    /// When it reached the base station, seconds (`None` until it has).
    pub delivered: Option<f64>,
}

impl Detector {
    /// Whether an artifact centred at `centre` is in view of a sensor at `eye`.
    pub fn in_view(&self, caster: &RayCaster, eye: [f64; 3], centre: [f64; 3]) -> bool {
        let d = [centre[0] - eye[0], centre[1] - eye[1], centre[2] - eye[2]];
        let dist = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if dist > self.range_m {
            return false;
        }
        if dist <= SIGHT_END {
            return true;
        }
        let dir = d.map(|x| x / dist);
        caster.cast(eye, dir, dist - SIGHT_END).is_none()
    }

    /// The artifacts in view of a sensor at `eye` (indices into `artifacts`).
    pub fn visible<'a>(
        &'a self,
        caster: &'a RayCaster,
        eye: [f64; 3],
        artifacts: &'a [Artifact],
    ) -> impl Iterator<Item = usize> + 'a {
        artifacts
            .iter()
            .enumerate()
            .filter(move |(_, a)| self.in_view(caster, eye, a.centre))
            .map(|(i, _)| i)
    }

    /// The report robot `robot` makes of `a` at time `t`.
    pub fn report(&self, seed: u64, robot: usize, a: &Artifact, t: f64) -> Report {
        let key = |axis: u64| ((robot as u64) << 40) | ((a.id as u64) << 2) | axis;
        let e = |axis: u64| self.error_m * noise::normal(seed ^ 0xa57f_ac75, key(axis));
        Report {
            robot,
            artifact: a.id,
            class: a.class,
            position: [a.centre[0] + e(0), a.centre[1] + e(1), a.centre[2] + e(2)],
            detected: t,
            delivered: None,
        }
    }
}
