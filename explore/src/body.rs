//! A platform's body in motion: velocity commands followed within its speed, acceleration and
//! turn limits, a ground robot kept on its floor, and every motion checked against the
//! collision surface.
//!
//! The limits are the `sense` platforms' ([`subtgraph_sensors::platform::Platform`]: a
//! Jackal-sized wheeled robot and a small quadrotor), with what a closed loop needs besides:
//! how fast the turn rate may change, how far a robot may reverse, and for the ground robot
//! the step it climbs, the grade it drives and where its wheels touch.
//!
//! **Collisions are refused, never passed through.** A step's motion is cut into pieces no
//! longer than half the clearance; each piece is taken only when the clearance sphere at its
//! end is free of rock (the nearest point of the collision surface is farther than the
//! clearance) and, for a ground robot, the floor under it is one the robot can drive. The first
//! piece that is not ends the motion there: the robot stops (its speed set to zero), keeps the
//! turn (a turn in place moves no part of the sphere) and reports why ([`Refusal`]). Because a
//! piece is shorter than the clearance, a piece that would cross the surface ends with the
//! surface inside the sphere, so no motion tunnels through thin rock. The Gymnasium
//! environment may end the episode on a refusal instead (`on_collision = "end"`).
//!
//! **A ground robot follows its floor**: under the body's centre and under each wheel axle and
//! side (a cross [`Body::wheelbase`] long and [`Body::track`] wide), the floor is found by a
//! ray cast straight down from the body's centre height; the centre's floor is where the robot
//! stands, the four others give its pitch and roll. A piece is refused as a **step** when the
//! floor under the centre rises more than [`Body::max_step`], a **gap** when no floor lies within
//! [`Body::max_drop`] below the previous one (a ledge, a shaft), a **slope** when the pitch or
//! roll exceeds [`Body::max_grade_deg`] and the floor it stands on with the same heading (so a
//! robot that turned in place on a slope can still drive off it).

use subtgraph_core::raycast::RayCaster;
use subtgraph_sensors::platform::{Kind, Platform};

use crate::error::ExploreError;

/// How fast a platform's turn rate may change, rad/s^2 (not among the `sense` platforms'
/// limits: a route's turn rate follows its bends smoothly).
const YAW_ACCELERATION: f64 = 2.0;

/// A platform's limits and shape in motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// `ground` or `aerial`.
    pub name: &'static str,
    /// Ground or aerial.
    pub kind: Kind,
    /// Forward speed limit, m/s.
    pub max_speed: f64,
    /// Reverse speed limit, m/s (ground: half the forward limit; aerial: the same).
    pub max_reverse: f64,
    /// Vertical speed limit, m/s (aerial).
    pub max_climb: f64,
    /// Acceleration and braking, m/s^2.
    pub max_acceleration: f64,
    /// Sideways acceleration in turns, m/s^2 (limits the turn rate at speed).
    pub max_lateral_acceleration: f64,
    /// Turn rate limit, rad/s.
    pub max_yaw_rate: f64,
    /// How fast the turn rate may change, rad/s^2.
    pub max_yaw_acceleration: f64,
    /// Radius of the sphere about the clearance point that must be free of rock, metres.
    pub clearance: f64,
    /// Height of the clearance point above the reference (the floor for a ground robot, the
    /// body's centre for an aerial one), metres.
    pub clearance_height: f64,
    /// The LiDAR's height above the reference, metres.
    pub lidar_height: f64,
    /// Flying height above the floor at the start, metres (aerial).
    pub altitude: f64,
    /// Highest step a ground robot drives up, metres.
    pub max_step: f64,
    /// Deepest drop a ground robot drives down, metres.
    pub max_drop: f64,
    /// Steepest pitch or roll a ground robot drives, degrees.
    pub max_grade_deg: f64,
    /// Distance between a ground robot's front and rear axles, metres.
    pub wheelbase: f64,
    /// Distance between its left and right wheels, metres.
    pub track: f64,
}

/// Where a body is and how it moves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct State {
    /// The reference point: on the floor under the body (ground), the body's centre (aerial).
    pub position: [f64; 3],
    /// Heading, radians counter-clockwise from east.
    pub yaw: f64,
    /// Pitch about the body's y axis, radians, positive nose down (ROS's REP 103; ground:
    /// from its floor).
    pub pitch: f64,
    /// Roll about the body's x axis, radians, positive right side down (ground: from its
    /// floor).
    pub roll: f64,
    /// Forward speed, m/s.
    pub speed: f64,
    /// Turn rate, rad/s.
    pub yaw_rate: f64,
    /// Vertical speed, m/s (aerial).
    pub climb: f64,
}

/// What a controller asks: forward speed, turn rate, vertical speed (aerial only).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Command {
    /// m/s, negative to reverse.
    pub speed: f64,
    /// rad/s, counter-clockwise.
    pub yaw_rate: f64,
    /// m/s up (ignored by a ground robot).
    pub climb: f64,
}

/// Why a motion was stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Refusal {
    /// Rock inside the clearance sphere.
    Collision,
    /// A step up higher than the robot climbs.
    Step,
    /// No floor within a step below: a drop, a gap, a shaft.
    Gap,
    /// Pitch or roll steeper than the robot drives.
    Slope,
}

impl Refusal {
    /// Its name in logs and `info`.
    pub fn name(self) -> &'static str {
        match self {
            Refusal::Collision => "collision",
            Refusal::Step => "step",
            Refusal::Gap => "gap",
            Refusal::Slope => "slope",
        }
    }
}

/// What one step of motion did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moved {
    /// Metres travelled.
    pub distance: f64,
    /// Why the motion stopped short, if it did.
    pub refused: Option<Refusal>,
}

/// The floor under a ground robot: the centre's height, pitch and roll.
struct Floor {
    z: f64,
    pitch: f64,
    roll: f64,
}

impl Body {
    /// The body of a built-in platform (`ground`, `aerial`).
    pub fn named(name: &str) -> Result<Body, ExploreError> {
        let p = Platform::named(name)?;
        Ok(Body::of(&p))
    }

    /// The body of a `sense` platform.
    pub fn of(p: &Platform) -> Body {
        let ground = p.kind == Kind::Ground;
        Body {
            name: p.name,
            kind: p.kind,
            max_speed: p.max_speed,
            max_reverse: if ground {
                0.5 * p.max_speed
            } else {
                p.max_speed
            },
            max_climb: p.max_climb,
            max_acceleration: p.max_acceleration,
            max_lateral_acceleration: p.max_lateral_acceleration,
            max_yaw_rate: p.max_yaw_rate,
            max_yaw_acceleration: YAW_ACCELERATION,
            clearance: p.clearance,
            clearance_height: p.clearance_height,
            lidar_height: p.lidar.translation[2],
            altitude: p.altitude,
            // A Clearpath Jackal: 0.26 m wheelbase, 0.38 m track, 0.1 m curbs up, 0.25 m
            // drops down, 30 degree ramps (its datasheet's "max climb grade" is 45 degrees on
            // grip; kept lower for loose rock).
            max_step: 0.1,
            max_drop: 0.25,
            max_grade_deg: 30.0,
            wheelbase: 0.26,
            track: 0.38,
        }
    }

    /// Whether it flies.
    pub fn flies(&self) -> bool {
        self.kind == Kind::Aerial
    }

    /// The clearance point of a body at `position`.
    pub fn clearance_point(&self, position: [f64; 3]) -> [f64; 3] {
        [
            position[0],
            position[1],
            position[2] + self.clearance_height,
        ]
    }

    /// Whether the clearance sphere at `position` is free of rock.
    pub fn clear(&self, caster: &RayCaster, position: [f64; 3]) -> bool {
        caster
            .nearest(self.clearance_point(position), self.clearance)
            .is_none()
    }

    /// Where a body set down near `p` (a point on a passage's floor) stands: on the floor
    /// found below 1 m above `p` (an aerial one at its altitude above it), if its clearance
    /// sphere is free there.
    pub fn settle(&self, caster: &RayCaster, p: [f64; 3]) -> Option<[f64; 3]> {
        let from = [p[0], p[1], p[2] + 1.0];
        let hit = caster.cast(from, [0.0, 0.0, -1.0], 3.0)?;
        let floor = from[2] - hit.t;
        let position = if self.flies() {
            [p[0], p[1], floor + self.altitude]
        } else {
            [p[0], p[1], floor]
        };
        self.clear(caster, position).then_some(position)
    }

    /// A command within the limits: speeds and turn rate clipped, a value that is not a
    /// number taken as zero.
    pub fn clip(&self, c: Command) -> Command {
        let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
        Command {
            speed: finite(c.speed).clamp(-self.max_reverse, self.max_speed),
            yaw_rate: finite(c.yaw_rate).clamp(-self.max_yaw_rate, self.max_yaw_rate),
            climb: if self.flies() {
                finite(c.climb).clamp(-self.max_climb, self.max_climb)
            } else {
                0.0
            },
        }
    }

    /// Moves `s` for `dt` seconds toward command `c` (clipped), within the accelerations, the
    /// floor and the rock (see the module's doc).
    pub fn step(&self, caster: &RayCaster, s: &mut State, c: Command, dt: f64) -> Moved {
        let c = self.clip(c);
        let toward =
            |now: f64, want: f64, rate: f64| now + (want - now).clamp(-rate * dt, rate * dt);
        s.speed = toward(s.speed, c.speed, self.max_acceleration);
        s.yaw_rate = toward(s.yaw_rate, c.yaw_rate, self.max_yaw_acceleration);
        if s.speed.abs() > 1e-9 {
            let most = self.max_lateral_acceleration / s.speed.abs();
            s.yaw_rate = s.yaw_rate.clamp(-most, most);
        }
        s.climb = if self.flies() {
            toward(s.climb, c.climb, self.max_acceleration)
        } else {
            0.0
        };
        let length = (s.speed.powi(2) + s.climb.powi(2)).sqrt() * dt;
        let pieces = ((length / (0.5 * self.clearance)).ceil() as usize).max(1);
        let h = dt / pieces as f64;
        let mut moved = Moved::default();
        for _ in 0..pieces {
            let yaw = s.yaw + 0.5 * s.yaw_rate * h;
            let mut p = [
                s.position[0] + s.speed * yaw.cos() * h,
                s.position[1] + s.speed * yaw.sin() * h,
                s.position[2] + s.climb * h,
            ];
            let floor = if self.flies() {
                None
            } else {
                match self.floor_for(caster, s, p, yaw) {
                    Ok(f) => {
                        p[2] = f.z;
                        Some(f)
                    }
                    Err(r) => {
                        moved.refused = Some(r);
                        break;
                    }
                }
            };
            if !self.clear(caster, p) {
                moved.refused = Some(Refusal::Collision);
                break;
            }
            moved.distance += ((p[0] - s.position[0]).powi(2)
                + (p[1] - s.position[1]).powi(2)
                + (p[2] - s.position[2]).powi(2))
            .sqrt();
            s.position = p;
            s.yaw = wrap(s.yaw + s.yaw_rate * h);
            if let Some(f) = floor {
                s.pitch = f.pitch;
                s.roll = f.roll;
            }
        }
        if moved.refused.is_some() {
            // Stopped where the last piece ended; the turn goes on (it moves no part of the
            // sphere), the floor's pitch and roll are those the robot stands on.
            let done = moved.distance / length.max(1e-12);
            s.yaw = wrap(s.yaw + s.yaw_rate * dt * (1.0 - done.min(1.0)));
            s.speed = 0.0;
            s.climb = 0.0;
        }
        moved
    }

    /// The floor under a ground robot whose centre moves to `p` (x, y) from a floor at `z0`,
    /// facing `yaw`; or why it cannot stand there.
    fn floor(&self, caster: &RayCaster, p: [f64; 3], z0: f64, yaw: f64) -> Result<Floor, Refusal> {
        let top = z0 + self.clearance_height;
        let reach = self.clearance_height + self.max_drop;
        let down = |x: f64, y: f64| -> Option<f64> {
            caster
                .cast([x, y, top], [0.0, 0.0, -1.0], reach)
                .map(|h| top - h.t)
        };
        let z = down(p[0], p[1]).ok_or(Refusal::Gap)?;
        if z - z0 > self.max_step {
            return Err(Refusal::Step);
        }
        let (c, s) = (yaw.cos(), yaw.sin());
        let (a, b) = (0.5 * self.wheelbase, 0.5 * self.track);
        let at = |u: f64, v: f64| down(p[0] + u * c - v * s, p[1] + u * s + v * c);
        let (front, back) = (at(a, 0.0), at(-a, 0.0));
        let (left, right) = (at(0.0, b), at(0.0, -b));
        let (Some(front), Some(back), Some(left), Some(right)) = (front, back, left, right) else {
            return Err(Refusal::Gap);
        };
        let pitch = -((front - back) / self.wheelbase).atan();
        let roll = ((left - right) / self.track).atan();
        Ok(Floor { z, pitch, roll })
    }

    /// The floor under a ground robot moving from `s` to `p` facing `yaw`, or why it cannot
    /// stand there: [`Body::floor`], and a slope refused when steeper than the limit and than
    /// the floor it stands on now with the same heading (a robot that has turned on a slope
    /// may drive off it).
    fn floor_for(
        &self,
        caster: &RayCaster,
        s: &State,
        p: [f64; 3],
        yaw: f64,
    ) -> Result<Floor, Refusal> {
        let f = self.floor(caster, p, s.position[2], yaw)?;
        let grade = |f: &Floor| f.pitch.abs().max(f.roll.abs());
        if grade(&f) <= self.max_grade_deg.to_radians() {
            return Ok(f);
        }
        match self.floor(caster, s.position, s.position[2], yaw) {
            Ok(here) if grade(&f) <= grade(&here) + 1e-6 => Ok(f),
            _ => Err(Refusal::Slope),
        }
    }
}

/// An angle brought into `(-pi, pi]`.
pub fn wrap(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let w = a - t * (a / t).round();
    if w <= -std::f64::consts::PI { w + t } else { w }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::mesh::Mesh;

    /// A closed box from `lo` to `hi`, wound facing in.
    fn room(lo: [f32; 3], hi: [f32; 3]) -> Mesh {
        let p = |i: usize| {
            [
                if i & 1 == 0 { lo[0] } else { hi[0] },
                if i & 2 == 0 { lo[1] } else { hi[1] },
                if i & 4 == 0 { lo[2] } else { hi[2] },
            ]
        };
        let quads = [
            [0, 1, 3, 2],
            [4, 6, 7, 5],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 5, 7, 3],
        ];
        let mut triangles = Vec::new();
        for q in quads {
            triangles.push([q[0], q[1], q[2]]);
            triangles.push([q[0], q[2], q[3]]);
        }
        Mesh {
            positions: (0..8).map(p).collect(),
            triangles,
            ..Mesh::default()
        }
    }

    #[test]
    fn a_ground_robot_stops_at_the_wall_and_never_passes_it() {
        let caster = RayCaster::new(&room([0.0, 0.0, 0.0], [10.0, 4.0, 3.0]));
        let body = Body::named("ground").unwrap();
        let mut s = State {
            position: [5.0, 2.0, 0.0],
            ..State::default()
        };
        let mut refused = None;
        for _ in 0..200 {
            let m = body.step(
                &caster,
                &mut s,
                Command {
                    speed: 5.0,
                    ..Command::default()
                },
                0.1,
            );
            assert!(s.position[0] <= 10.0 - body.clearance, "{s:?}");
            refused = refused.or(m.refused);
        }
        assert_eq!(refused, Some(Refusal::Collision));
        assert!(s.position[0] > 10.0 - body.clearance - 0.5 * body.clearance);
        assert!(s.speed.abs() < 1e-12);
        // The speed limit and the acceleration held: 2 m/s at most, reached after 2 s.
        let mut s = State {
            position: [1.0, 2.0, 0.0],
            ..State::default()
        };
        let go = Command {
            speed: 9.0,
            yaw_rate: f64::NAN,
            climb: 3.0,
        };
        body.step(&caster, &mut s, go, 0.5);
        assert!((s.speed - 0.5).abs() < 1e-12, "{s:?}");
        // 2.5 s more: up to 2 m/s by 2 s, then held, 4 m along the 10 m room (short of its
        // far wall, where the robot would stop).
        for _ in 0..5 {
            body.step(&caster, &mut s, go, 0.5);
        }
        assert!(
            (s.speed - 2.0).abs() < 1e-12 && s.position[2].abs() < 1e-6,
            "{s:?}"
        );
    }

    /// A horizontal quad from `(x0, y0)` to `(x1, y1)` at height `z`, facing up.
    fn floor_quad(x0: f32, y0: f32, x1: f32, y1: f32, z: f32) -> Mesh {
        Mesh {
            positions: vec![[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            ..Mesh::default()
        }
    }

    #[test]
    fn a_ground_robot_stops_at_a_ledge_and_climbs_small_steps() {
        // A floor at 0 to x = 6, one 5 cm higher to x = 9, then a drop of a metre.
        let mut mesh = floor_quad(0.0, 0.0, 6.0, 4.0, 0.0);
        mesh.append(&floor_quad(6.0, 0.0, 9.0, 4.0, 0.05));
        mesh.append(&floor_quad(9.0, 0.0, 14.0, 4.0, -1.0));
        let caster = RayCaster::new(&mesh);
        let body = Body::named("ground").unwrap();
        let mut s = State {
            position: [3.0, 2.0, 0.0],
            ..State::default()
        };
        let mut refused = None;
        for _ in 0..100 {
            let m = body.step(
                &caster,
                &mut s,
                Command {
                    speed: 1.0,
                    ..Command::default()
                },
                0.1,
            );
            refused = refused.or(m.refused);
        }
        assert_eq!(refused, Some(Refusal::Gap));
        assert!(s.position[0] > 8.0 && s.position[0] < 9.0, "{s:?}");
        assert!((s.position[2] - 0.05).abs() < 1e-6, "{s:?}");
        // A flying body crosses the same ledge.
        let air = Body::named("aerial").unwrap();
        let mut s = State {
            position: [3.0, 2.0, 1.5],
            ..State::default()
        };
        for _ in 0..100 {
            let m = air.step(
                &caster,
                &mut s,
                Command {
                    speed: 1.0,
                    ..Command::default()
                },
                0.1,
            );
            assert_eq!(m.refused, None);
        }
        assert!(s.position[0] > 11.0, "{s:?}");
    }

    #[test]
    fn angles_wrap() {
        assert!((wrap(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap(-0.5) + 0.5).abs() < 1e-15);
    }
}
