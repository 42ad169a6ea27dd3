//! Conditions: what the air and the rock do to a LiDAR underground. Dust (standing in
//! places, and raised by the platform), fog and mist banks, wet and dark rock with puddles,
//! dripping water, each put where a study wants it, seeded, and labelled per scan.
//!
//! `sense --conditions FILE.toml` reads `[[conditions]]` tables:
//!
//! ```toml
//! [[conditions]]
//! type = "dust"              # dust, fog, mist, wet-rock or drips
//! at = "platform"            # route, platform (dust only), "edge N", "node N" or "level N"
//! density_mg_m3 = 1500       # dust, fog, mist: particle mass a cubic metre
//!
//! [[conditions]]
//! type = "fog"
//! at = "node 4"
//! radius_m = 8               # edge and node places: how far the bank reaches (default 4)
//! density_mg_m3 = 800
//!
//! [[conditions]]
//! type = "wet-rock"
//! at = "level 1"
//! reflectance_factor = 0.3   # optional
//! puddles = 0.25             # optional: the share of its floor under water
//!
//! [[conditions]]
//! type = "drips"
//! at = "edge 12"
//! lines_per_10m = 3          # optional
//! interval_s = 0.5           # optional
//! ```
//!
//! Unknown keys, negative or absurd numbers and places the world's graph does not have are
//! refused before anything is cast. `--conditions none` (the default) is clear air: the same
//! bytes as a `sense` without the option.
//!
//! **Per ray** ([`Active::shoot`]) the conditions act on what the ray meets, whatever surface
//! the ray cast finds: the particles along it ([`medium`], after Hahner et al. 2021) dim the
//! rock's return and may return an echo of their own; a wet surface ([`wet_rock`]) returns
//! less, with more range noise, or mirrors the beam from a puddle; a falling drop
//! ([`drips`]) may return a point. Every return is labelled with what made it ([`Kind`]), in
//! a debug field: the Ouster cloud's `return_kind` (a byte in its record's padding) and a
//! SemanticKITTI-style `kitti/labels/NNNNNN.label` beside each KITTI scan. A ray no
//! condition touches returns exactly what it does in clear air.

pub mod camera;
pub mod drips;
pub mod dust;
pub mod fog;
pub mod medium;
pub mod place;
pub mod spec;
pub mod wet_rock;

use serde::Serialize;
use subtgraph_core::raycast::Tracer;
use subtgraph_core::rng::WorldRng;
use subtgraph_core::vec3::V3;

use self::medium::{Particles, Receiver, Span};
use self::place::{Place, Volume};
pub use self::spec::{Condition, ConditionKind, Conditions};
use crate::graph::RouteGraph;
use crate::platform::Platform;
use crate::route::Route;
use crate::scene::Scene;
use crate::trajectory::Trajectory;

/// What made a return: the debug field's values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Kind {
    /// The rock (or services), as in clear air, perhaps dimmed by the air on the way.
    Surface = 0,
    /// Dust particles.
    Dust = 1,
    /// Fog or mist droplets.
    Fog = 2,
    /// A falling drop.
    Drip = 3,
    /// Wet rock, dimmed.
    Wet = 4,
    /// A puddle's mirror image (the point lies under the floor).
    Puddle = 5,
    /// No return: a condition took it (the Ouster cloud's empty cells only).
    Lost = 6,
}

/// The debug field's values, by name, as `sequence.json` lists them.
pub const KIND_NAMES: [&str; 7] = ["surface", "dust", "fog", "drip", "wet", "puddle", "lost"];

/// A condition made ready for a world: its volume, its particles, its drip lines.
#[derive(Clone, Debug)]
struct Placed {
    condition: Condition,
    volume: Volume,
    particles: Option<Particles>,
}

/// The conditions of a sequence, ready to shoot rays through.
pub struct Active<'a> {
    placed: Vec<Placed>,
    /// The receiver's side of the particle model.
    pub rx: Receiver,
    seed: u64,
    drips: Vec<drips::Line>,
    reach: f64,
    platform: Platform,
    trajectory: &'a Trajectory,
    scene: &'a Scene,
}

/// What a ray's surface was, for [`Active::shoot`].
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    /// Distance, metres.
    pub t: f64,
    /// Unit normal (facing the passage).
    pub normal: V3,
    /// Reflectivity.
    pub rho: f64,
    /// The incidence angle's cosine.
    pub cos: f64,
}

/// One ray, as the scanner shoots it.
#[derive(Clone, Copy, Debug)]
pub struct Shot {
    /// Where it leaves, world frame.
    pub origin: V3,
    /// Its unit direction, world frame.
    pub dir: V3,
    /// The ray's key (its index and its scan's) for the draws.
    pub key: u64,
    /// The surface it hit in range, if any.
    pub surface: Option<Surface>,
    /// The model's farthest range, metres.
    pub far: f64,
    /// The model's range noise, metres.
    pub sigma: f64,
    /// The ray's standard normal draw (the one the clear-air range noise takes).
    pub normal_draw: f64,
}

/// What became of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    /// No condition touched it: cast it as in clear air.
    Untouched,
    /// A return: its measured range, reflectance and kind (a surface's keeps the surface's
    /// true distance for the labels' Hessian in `surface`).
    Return {
        /// Measured range, metres.
        range: f64,
        /// Reflectance as reported.
        reflectance: f64,
        /// What made it.
        kind: Kind,
        /// Whether it is the surface the ray hit (for the Hessian).
        surface: bool,
    },
    /// The return a clear-air sensor would have had is gone.
    Lost,
}

/// The conditions about the platform at one instant (a firing group's): its dust cloud and
/// the drops near it.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    cloud: Option<(dust::Cloud, Particles)>,
    drops: Vec<V3>,
}

impl<'a> Active<'a> {
    /// The conditions `spec` lists, placed in a world along `route`, for a LiDAR whose
    /// returns span `range_m` (nearest, farthest) on `platform`, their draws from `seed`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        spec: &Conditions,
        graph: &RouteGraph,
        scene: &'a Scene,
        route: &'a Route,
        range_m: [f64; 2],
        platform: &Platform,
        seed: u64,
    ) -> Active<'a> {
        let rx = Receiver::of_range(range_m[0], range_m[1]);
        let mut rng = WorldRng::new(seed, "conditions", 0);
        let mut placed = Vec::new();
        let mut lines = Vec::new();
        for c in &spec.list {
            let volume = Volume::of(c.at, graph, c.radius_m);
            if c.kind == ConditionKind::Drips {
                let edges = drip_edges(c.at, graph, route);
                let keep = |p: V3| volume.contains([p[0], p[1], p[2] + 1.5]);
                lines.extend(drips::lines(
                    graph,
                    scene,
                    &edges,
                    c.lines_per_10m,
                    c.interval_s,
                    &keep,
                    &mut rng,
                ));
            }
            placed.push(Placed {
                particles: c.particles(),
                condition: c.clone(),
                volume,
            });
        }
        Active {
            placed,
            rx,
            seed,
            reach: drips::reach(&rx),
            drips: lines,
            platform: platform.clone(),
            trajectory: &route.trajectory,
            scene,
        }
    }

    /// The resolved conditions, for `sequence.json`: each with its particles' extinction,
    /// backscatter and visibility, and the receiver's numbers.
    pub fn describe(&self) -> serde_json::Value {
        let list: Vec<serde_json::Value> = self
            .placed
            .iter()
            .map(|p| {
                let mut v = serde_json::to_value(&p.condition).expect("plain data");
                if let Some(q) = p.particles {
                    v["alpha_per_m"] = q.alpha.into();
                    v["beta_per_m_sr"] = q.beta.into();
                    v["visibility_m"] = q.visibility_m().into();
                }
                v
            })
            .collect();
        serde_json::json!({
            "list": list,
            "receiver": self.rx,
            "drip_lines": self.drips.len(),
            "return_kinds": KIND_NAMES,
            "model": "particles after Hahner et al., ICCV 2021, with speckle; see docs/src/conditions.md",
        })
    }

    /// The conditions at time `t` about the sensor at `at`.
    pub fn frame(&self, t: f64, at: V3) -> Frame {
        let mut f = Frame::default();
        for p in &self.placed {
            if p.condition.at == Place::Platform
                && let Some(q) = p.particles
            {
                let s = self.trajectory.state(t);
                let floor = self.floor_under(s.pose.translation);
                if let Some(c) = dust::Cloud::raised(&self.platform, &s, floor) {
                    let scaled = Particles {
                        alpha: q.alpha * c.strength,
                        beta: q.beta * c.strength,
                    };
                    f.cloud = Some((c, scaled));
                }
            }
        }
        for line in &self.drips {
            let (dx, dy) = (line.xy[0] - at[0], line.xy[1] - at[1]);
            if dx * dx + dy * dy <= self.reach * self.reach {
                line.drops(t, &mut f.drops);
            }
        }
        f
    }

    fn floor_under(&self, p: V3) -> Option<f64> {
        if self.platform.kind != crate::platform::Kind::Aerial {
            return None;
        }
        self.scene
            .caster
            .cast(p, [0.0, 0.0, -1.0], 6.0)
            .map(|h| p[2] - h.t)
    }

    /// The media along the ray `o + t d` up to `end`, as sorted spans that do not overlap
    /// (where media overlap, their coefficients add; the kind is the larger extinction's).
    pub fn spans(&self, f: &Frame, o: V3, d: V3, end: f64, out: &mut Vec<Span>) {
        out.clear();
        let mut parts: Vec<(f64, f64, Particles, u8)> = Vec::new();
        let mut cut = Vec::new();
        for p in &self.placed {
            let Some(q) = p.particles else { continue };
            let kind = p.condition.kind.return_kind() as u8;
            if p.condition.at == Place::Platform {
                if let Some((c, scaled)) = &f.cloud
                    && let Some((a, b)) = c.clip(o, d)
                {
                    let (a, b) = (a.max(0.0), b.min(end));
                    if b > a {
                        parts.push((a, b, *scaled, kind));
                    }
                }
                continue;
            }
            cut.clear();
            p.volume.clip(o, d, end, &mut cut);
            for &(a, b) in &cut {
                parts.push((a, b, q, kind));
            }
        }
        if parts.is_empty() {
            return;
        }
        let mut edges: Vec<f64> = parts.iter().flat_map(|p| [p.0, p.1]).collect();
        edges.sort_by(f64::total_cmp);
        edges.dedup();
        for w in edges.windows(2) {
            let mid = 0.5 * (w[0] + w[1]);
            let (mut alpha, mut beta, mut kind, mut top) = (0.0, 0.0, 0u8, 0.0);
            for &(a, b, q, k) in &parts {
                if a <= mid && mid < b {
                    alpha += q.alpha;
                    beta += q.beta;
                    if q.alpha > top {
                        top = q.alpha;
                        kind = k;
                    }
                }
            }
            if alpha > 0.0 {
                out.push(Span {
                    a: w[0],
                    b: w[1],
                    alpha,
                    beta,
                    kind,
                });
            }
        }
    }

    /// The wet condition the point `p` is in, if any: its reflectance factor and puddle share.
    fn wet_at(&self, p: V3) -> Option<(f64, f64)> {
        self.placed
            .iter()
            .filter(|c| c.condition.kind == ConditionKind::WetRock)
            .find(|c| c.volume.contains(p))
            .map(|c| (c.condition.reflectance_factor, c.condition.puddles))
    }

    /// What becomes of one ray in these conditions, at `f`; `tracer` casts a puddle's mirrored
    /// ray.
    pub fn shoot(&self, f: &Frame, shot: &Shot, tracer: &mut Tracer<'_>) -> Outcome {
        let end = shot.surface.map_or(shot.far, |s| s.t);
        let mut spans = Vec::new();
        self.spans(f, shot.origin, shot.dir, end, &mut spans);
        let drip = drips::echo(&f.drops, shot.origin, shot.dir, end, &self.rx);
        // The surface's return as this place makes it: wet, a puddle's mirror image.
        let mut touched = !spans.is_empty() || drip.is_some();
        let mut hard: Option<(f64, f64, Kind)> = None; // range, reflectance, kind
        let mut true_surface = false;
        if let Some(s) = shot.surface {
            let p = along(shot.origin, shot.dir, s.t);
            match self.wet_at(p) {
                Some((factor, share))
                    if wet_rock::is_floor(s.normal) && wet_rock::puddle_at(self.seed, p, share) =>
                {
                    touched = true;
                    let m = wet_rock::mirror(shot.dir, s.normal);
                    let from = along(p, s.normal, 1e-4);
                    hard = tracer.cast(from, m, shot.far - s.t).map(|h| {
                        let n = h.normal.map(f64::from);
                        let cos = (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]).abs();
                        let rho = f64::from(self.scene.reflectivity_of(h.triangle));
                        (
                            s.t + h.t,
                            rho * factor * cos * wet_rock::fresnel(s.cos),
                            Kind::Puddle,
                        )
                    });
                }
                Some((factor, _)) => {
                    touched = true;
                    hard = Some((s.t, s.rho * factor * s.cos, Kind::Wet));
                    true_surface = true;
                }
                None => {
                    hard = Some((s.t, s.rho * s.cos, Kind::Surface));
                    true_surface = true;
                }
            }
        }
        if !touched {
            return Outcome::Untouched;
        }
        let tau_end = medium::depth(&spans, end);
        let hard_signal = hard.map(|(r, rho, _)| (r, rho, self.rx.hard(rho, r, tau_end)));
        let floor = hard_signal.map_or(self.rx.s_min, |(_, _, h)| h.max(self.rx.s_min));
        let echo = medium::strongest_echo(&spans, &self.rx, end, floor, self.seed, shot.key);
        let drip = drip
            .map(|(r, s)| (r, s * (-2.0 * medium::depth(&spans, r)).exp()))
            .filter(|&(_, s)| s > floor && echo.is_none_or(|(_, e, _)| s > e));
        let particle = match (drip, echo) {
            (Some((r, s)), _) => Some((r, s, Kind::Drip as u8)),
            (None, e) => e,
        };
        let noisy = |r: f64, draw: f64, scale: f64| (r + shot.sigma * scale * draw).max(0.0);
        if let Some((r, signal, kind)) = particle {
            let draw = crate::noise::normal(self.seed, shot.key ^ 0xd057);
            let reflectance = (signal * std::f64::consts::PI * r * r).min(1.0);
            let kind = match kind {
                1 => Kind::Dust,
                2 => Kind::Fog,
                _ => Kind::Drip,
            };
            return Outcome::Return {
                range: noisy(r, draw, wet_rock::noise_scale(&self.rx, signal)),
                reflectance,
                kind,
                surface: false,
            };
        }
        match hard_signal {
            Some((r, rho, h)) if h >= self.rx.s_min => Outcome::Return {
                range: noisy(r, shot.normal_draw, wet_rock::noise_scale(&self.rx, h)),
                reflectance: rho * (-2.0 * tau_end).exp(),
                kind: hard.map_or(Kind::Surface, |x| x.2),
                surface: true_surface,
            },
            Some(_) => Outcome::Lost,
            // Nothing hit, and no particle echo: as in clear air.
            None => Outcome::Untouched,
        }
    }

    /// The label of a scan taken at time `t` with the sensor at `at`: the conditions it is
    /// in, and its returns by kind (`kinds`, indexed by [`Kind`]) over its `rays`.
    pub fn label(&self, t: f64, at: V3, kinds: &[u32; 7], rays: usize) -> ScanConditions {
        let f = self.frame(t, at);
        let mut inside = Vec::new();
        for (i, p) in self.placed.iter().enumerate() {
            let here = match p.condition.at {
                Place::Platform => f.cloud.is_some(),
                _ => p.volume.contains(at),
            };
            if here {
                inside.push(i);
            }
        }
        let taken = kinds[Kind::Dust as usize]
            + kinds[Kind::Fog as usize]
            + kinds[Kind::Drip as usize]
            + kinds[Kind::Lost as usize];
        ScanConditions {
            inside,
            dust: kinds[Kind::Dust as usize],
            fog: kinds[Kind::Fog as usize],
            drip: kinds[Kind::Drip as usize],
            wet: kinds[Kind::Wet as usize],
            puddle: kinds[Kind::Puddle as usize],
            lost: kinds[Kind::Lost as usize],
            obscured: ((taken as f64 / rays.max(1) as f64) * 1e4).round() / 1e4,
        }
    }
}

/// What the conditions did to one scan, in its label.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScanConditions {
    /// The conditions (their indices in `sequence.json`'s `conditions.list`) the sensor was
    /// in at the scan's start.
    pub inside: Vec<usize>,
    /// Returns from dust.
    pub dust: u32,
    /// Returns from fog or mist.
    pub fog: u32,
    /// Returns from drops.
    pub drip: u32,
    /// Returns from wet rock.
    pub wet: u32,
    /// Puddles' mirror images.
    pub puddle: u32,
    /// Rays whose return a condition took.
    pub lost: u32,
    /// The share of rays whose surface return was replaced by particles or drops, or lost.
    pub obscured: f64,
}

/// The edges drips are placed along for a place.
fn drip_edges(at: Place, graph: &RouteGraph, route: &Route) -> Vec<usize> {
    let mut edges: Vec<usize> = match at {
        Place::Edge(e) => vec![e],
        Place::Node(n) => graph.neighbours(n).map(|(e, _)| e).collect(),
        Place::Level(l) => graph
            .edges
            .iter()
            .filter(|e| graph.nodes[e.from].level == l || graph.nodes[e.to].level == l)
            .map(|e| e.id)
            .collect(),
        Place::Route | Place::Platform => route.legs.iter().map(|l| l.edge).collect(),
    };
    edges.sort_unstable();
    edges.dedup();
    edges
}

fn along(o: V3, d: V3, t: f64) -> V3 {
    [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]]
}
