//! Dust: rock and coal dust standing in places, and the cloud the platform raises as it
//! moves (a wheeled robot's wheels; a quadrotor's downwash when it flies low).
//!
//! The particles are mineral: 5 um in radius (the respirable to inhalable sizes that stay
//! airborne for minutes), 2.6 g/cm^3 (quartz, shale), with a lidar ratio (extinction over
//! backscatter) of 40 sr, the middle of what lidar networks measure for mineral dust (35 to
//! 55 sr). 1 g/m^3 then gives an extinction of 0.115 /m, 26 m of visibility: thick dust, as a
//! robot raises in a dry drift.
//!
//! **The raised cloud** moves with the platform. A ground robot leaves an ellipsoid behind it,
//! centred 1.2 m behind and 0.4 m above its reference point on the floor, 2 m long, 1.2 m
//! wide and 0.8 m high (semi-axes), as dense as the condition's `density_mg_m3` times its
//! speed over its cruising speed: none while it stands. An aerial one's downwash raises a disc
//! under it, 2.5 m in radius and 0.8 m high, centred 0.6 m above the floor, its density
//! falling as `exp(-(h - 1 m) / 0.7 m)` with its height `h` over the floor (about half at its
//! usual 1.5 m), whether it moves or hovers. These shapes are a model, not a measurement: the
//! platform's cloud puts particle returns where real ones appear (behind and under the
//! robot, close to the sensor) at a density the study sets.

use subtgraph_core::vec3::{V3, dot, sub};

use crate::platform::{Kind, Platform};
use crate::trajectory::State;

/// Particle radius, micrometres.
pub const RADIUS_UM: f64 = 5.0;
/// Particle density, g/cm^3.
pub const G_CM3: f64 = 2.6;
/// Extinction over backscatter, sr.
pub const LIDAR_RATIO_SR: f64 = 40.0;

/// The platform's cloud at one instant: an ellipsoid turned by the platform's heading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cloud {
    /// Centre, world frame.
    pub centre: V3,
    /// Semi-axes along the heading, across it, up, metres.
    pub axes: V3,
    /// Heading, radians.
    pub yaw: f64,
    /// Its density over the condition's `density_mg_m3`, `0..=1`.
    pub strength: f64,
}

impl Cloud {
    /// The cloud `platform` raises in state `s`; `floor` is the floor's height under it (an
    /// aerial platform's), or `None` if none was found.
    pub fn raised(platform: &Platform, s: &State, floor: Option<f64>) -> Option<Cloud> {
        let p = s.pose.translation;
        let yaw = s.euler[0];
        let (sin, cos) = yaw.sin_cos();
        let cloud = match platform.kind {
            Kind::Ground => {
                let speed = (s.velocity[0].powi(2) + s.velocity[1].powi(2)).sqrt();
                Cloud {
                    centre: [p[0] - 1.2 * cos, p[1] - 1.2 * sin, p[2] + 0.4],
                    axes: [2.0, 1.2, 0.8],
                    yaw,
                    strength: (speed / platform.max_speed).min(1.0),
                }
            }
            Kind::Aerial => {
                let floor = floor?;
                let h = p[2] - floor;
                Cloud {
                    centre: [p[0], p[1], floor + 0.6],
                    axes: [2.5, 2.5, 0.8],
                    yaw,
                    strength: (-(h - 1.0) / 0.7).exp().min(1.0),
                }
            }
        };
        (cloud.strength > 0.02).then_some(cloud)
    }

    /// The ray's stretch `o + t d` (unit `d`) inside, if any.
    pub fn clip(&self, o: V3, d: V3) -> Option<(f64, f64)> {
        let (sin, cos) = self.yaw.sin_cos();
        let local = |v: V3| [cos * v[0] + sin * v[1], -sin * v[0] + cos * v[1], v[2]];
        let oc = local(sub(o, self.centre));
        let dl = local(d);
        let os = [
            oc[0] / self.axes[0],
            oc[1] / self.axes[1],
            oc[2] / self.axes[2],
        ];
        let ds = [
            dl[0] / self.axes[0],
            dl[1] / self.axes[1],
            dl[2] / self.axes[2],
        ];
        let a = dot(ds, ds);
        let b = dot(os, ds);
        let c = dot(os, os) - 1.0;
        let disc = b * b - a * c;
        if disc <= 0.0 || a <= 0.0 {
            return None;
        }
        let s = disc.sqrt();
        Some(((-b - s) / a, (-b + s) / a))
    }

    /// Whether a point is inside.
    pub fn contains(&self, p: V3) -> bool {
        let (sin, cos) = self.yaw.sin_cos();
        let v = sub(p, self.centre);
        let l = [cos * v[0] + sin * v[1], -sin * v[0] + cos * v[1], v[2]];
        (0..3).map(|k| (l[k] / self.axes[k]).powi(2)).sum::<f64>() <= 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frames::Pose;

    fn state(v: V3, yaw: f64) -> State {
        State {
            pose: Pose::from_euler([10.0, 5.0, 0.0], [yaw, 0.0, 0.0]),
            velocity: v,
            acceleration: [0.0; 3],
            angular_velocity: [0.0; 3],
            angular_acceleration: [0.0; 3],
            euler: [yaw, 0.0, 0.0],
        }
    }

    #[test]
    fn a_ground_robot_raises_dust_behind_it_only_when_it_moves() {
        let g = Platform::named("ground").unwrap();
        assert!(Cloud::raised(&g, &state([0.0; 3], 0.3), None).is_none());
        let c = Cloud::raised(&g, &state([1.0, 0.0, 0.0], 0.0), None).unwrap();
        assert!((c.strength - 0.5).abs() < 1e-12);
        assert!(c.contains([9.0, 5.0, 0.4]) && !c.contains([11.5, 5.0, 0.4]));
        // A ray from the mast backwards crosses it; its stretch agrees with contains().
        let (a, b) = c.clip([10.0, 5.0, 0.6], [-1.0, 0.0, 0.0]).unwrap();
        for t in [a + 0.01, 0.5 * (a + b), b - 0.01] {
            assert!(c.contains([10.0 - t, 5.0, 0.6]), "{t}");
        }
        assert!(!c.contains([10.0 - b - 0.01, 5.0, 0.6]));
    }

    #[test]
    fn downwash_fades_with_height() {
        let a = Platform::named("aerial").unwrap();
        let low = Cloud::raised(&a, &state([0.0; 3], 0.0), Some(-1.0)).unwrap();
        let high = Cloud::raised(&a, &state([0.0; 3], 0.0), Some(-2.5)).unwrap();
        assert!(
            low.strength == 1.0 && high.strength < 0.2,
            "{low:?} {high:?}"
        );
        assert!(Cloud::raised(&a, &state([0.0; 3], 0.0), Some(-6.0)).is_none());
    }
}
