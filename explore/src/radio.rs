//! The radio: which nodes (the base station, the robots, the breadcrumbs they drop) hear each
//! other, and which robots reach the base station through them.
//!
//! **Source**: the DARPA SubT virtual competition's communication model (osrf/subt,
//! `subt-communication`): its `VisibilityRFModel` gives the received power from a log-normal
//! path loss, `P_rx = P_tx - (L0 + 10 n log10 d)`, whose fading exponent `n` grows by
//! `visibility_cost_to_fading_exponent` (0.2) per unit of the visibility cost between the
//! two places; its communication model drops a packet of `B` bytes with probability
//! `1 - (1 - BER)^B`, `BER = erfc(sqrt(P_rx / N))` for QPSK against the noise floor `N`. The
//! numbers are the competition's (its `comms_model` settings): `P_tx` 20 dBm, `L0` 40 dB,
//! `n` 2.5, noise floor -90 dBm, range limit 500 m.
//!
//! What is ours: the visibility cost is the exact line of sight between the two antennas (one
//! ray cast against the collision surface, the cast `--format comms` makes between tiles):
//! cost 0 in sight, and no link out of sight (the competition's tile graph let a weakened
//! signal round a corner or two; here it does not, so a link that is up is a line of sight,
//! which an independent ray test can check). A link is up when its mean received power
//! delivers a [`PACKET_BYTES`]-byte packet at least half the time (about -82.4 dBm: 314 m in
//! sight); the competition drew each packet's fate and a 10 dB fading at random, which would
//! make every run's radio a lottery, so the mean decides here, the same on every run.
//!
//! Messages go hop by hop over links that are up, through robots and breadcrumbs, as the SubT
//! teams' mesh radios carried them; a robot reaches the base station when a chain of such
//! links joins them.

use subtgraph_core::raycast::RayCaster;

/// The competition's transmit power, dBm.
pub const TX_POWER_DBM: f64 = 20.0;
/// Path loss at 1 m, dB.
pub const L0_DB: f64 = 40.0;
/// Fading exponent in sight.
pub const FADING_EXPONENT: f64 = 2.5;
/// Noise floor, dBm.
pub const NOISE_FLOOR_DBM: f64 = -90.0;
/// Hard range limit, metres.
pub const MAX_RANGE_M: f64 = 500.0;
/// The packet a link must deliver at least half the time: an artifact report with its pose
/// and a little of the map, bytes.
pub const PACKET_BYTES: f64 = 1000.0;

/// The radio's numbers.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RadioModel {
    /// Transmit power, dBm.
    pub tx_power_dbm: f64,
    /// Path loss at 1 m, dB.
    pub l0_db: f64,
    /// Fading exponent in sight.
    pub fading_exponent: f64,
    /// Noise floor, dBm.
    pub noise_floor_dbm: f64,
    /// Range limit, metres.
    pub max_range_m: f64,
    /// The least received power of a link that is up, dBm (derived).
    pub threshold_dbm: f64,
}

impl Default for RadioModel {
    fn default() -> Self {
        RadioModel::new(
            TX_POWER_DBM,
            L0_DB,
            FADING_EXPONENT,
            NOISE_FLOOR_DBM,
            MAX_RANGE_M,
        )
    }
}

impl RadioModel {
    /// A model with these numbers; its threshold is the power at which a [`PACKET_BYTES`]
    /// packet gets through half the time.
    pub fn new(tx: f64, l0: f64, n: f64, noise: f64, max_range: f64) -> RadioModel {
        RadioModel {
            tx_power_dbm: tx,
            l0_db: l0,
            fading_exponent: n,
            noise_floor_dbm: noise,
            max_range_m: max_range,
            threshold_dbm: half_delivery_dbm(noise),
        }
    }

    /// Received power over `d` metres in sight, dBm.
    pub fn power_dbm(&self, d: f64) -> f64 {
        self.tx_power_dbm - (self.l0_db + 10.0 * self.fading_exponent * d.max(1.0).log10())
    }

    /// The farthest a link in sight reaches, metres.
    pub fn reach_m(&self) -> f64 {
        let d = 10f64.powf(
            (self.tx_power_dbm - self.l0_db - self.threshold_dbm) / (10.0 * self.fading_exponent),
        );
        d.min(self.max_range_m)
    }

    /// The link between antennas `a` and `b`: its received power when up, `None` when down
    /// (out of range, too weak, or rock between them).
    pub fn link(&self, caster: &RayCaster, a: [f64; 3], b: [f64; 3]) -> Option<f64> {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let dist = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if dist > self.reach_m() {
            return None;
        }
        if dist < 1e-9 {
            return Some(self.power_dbm(1.0));
        }
        let dir = d.map(|x| x / dist);
        if caster.cast(a, dir, dist).is_some() {
            return None;
        }
        let p = self.power_dbm(dist);
        (p >= self.threshold_dbm).then_some(p)
    }
}

/// The received power at which a [`PACKET_BYTES`]-byte packet is delivered half the time under
/// QPSK against `noise_dbm` (SubT's communication model), dBm.
pub fn half_delivery_dbm(noise_dbm: f64) -> f64 {
    // (1 - BER)^B = 1/2 gives the bit error rate; erfc(sqrt(P/N)) = BER gives P by bisection
    // (erfc falls monotonically).
    let ber = 1.0 - 0.5f64.powf(1.0 / PACKET_BYTES);
    let (mut lo, mut hi) = (0.0f64, 100.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if libm::erfc(mid.sqrt()) > ber {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    noise_dbm + 10.0 * (0.5 * (lo + hi)).log10()
}

/// A node of the network.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Node {
    /// The base station.
    Base,
    /// Robot `i`.
    Robot(usize),
    /// Breadcrumb `i` (in the order dropped).
    Crumb(usize),
}

impl Node {
    /// Its name in the radio log (`base`, `robot-0`, `crumb-3`).
    pub fn name(self) -> String {
        match self {
            Node::Base => "base".into(),
            Node::Robot(i) => format!("robot-{i}"),
            Node::Crumb(i) => format!("crumb-{i}"),
        }
    }
}

/// A link that is up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link {
    /// One end.
    pub a: Node,
    /// The other end.
    pub b: Node,
    /// Where `a`'s antenna is.
    pub pa: [f64; 3],
    /// Where `b`'s antenna is.
    pub pb: [f64; 3],
    /// Received power, dBm.
    pub power_dbm: f64,
}

/// Which nodes reach which at one instant.
#[derive(Clone, Debug, Default)]
pub struct Network {
    /// Every link that is up.
    pub links: Vec<Link>,
    /// Per robot: hops to the base station, if it reaches it.
    pub hops: Vec<Option<usize>>,
    /// Per robot: the group of nodes it hears through any chain (an index shared by every
    /// robot of the same group).
    pub group: Vec<usize>,
}

/// Links among fixed nodes (the base station and breadcrumbs), kept between instants: they do
/// not move.
#[derive(Clone, Debug, Default)]
pub struct FixedLinks {
    /// The fixed nodes' antennas: the base station first, then each breadcrumb.
    pub antennas: Vec<[f64; 3]>,
    /// Links that are up between them.
    pub links: Vec<Link>,
}

impl FixedLinks {
    /// Fixed nodes with only the base station at `base`.
    pub fn new(base: [f64; 3]) -> FixedLinks {
        FixedLinks {
            antennas: vec![base],
            links: Vec::new(),
        }
    }

    fn node(i: usize) -> Node {
        if i == 0 {
            Node::Base
        } else {
            Node::Crumb(i - 1)
        }
    }

    /// Adds a breadcrumb at `p`, linking it to every fixed node it hears; returns its links.
    pub fn drop_crumb(&mut self, model: &RadioModel, caster: &RayCaster, p: [f64; 3]) -> Vec<Link> {
        let id = self.antennas.len();
        let mut new = Vec::new();
        for (i, &q) in self.antennas.iter().enumerate() {
            if let Some(power_dbm) = model.link(caster, q, p) {
                new.push(Link {
                    a: Self::node(i),
                    b: Self::node(id),
                    pa: q,
                    pb: p,
                    power_dbm,
                });
            }
        }
        self.antennas.push(p);
        self.links.extend_from_slice(&new);
        new
    }

    /// Breadcrumbs dropped.
    pub fn crumbs(&self) -> usize {
        self.antennas.len() - 1
    }
}

impl Network {
    /// The network of robots whose antennas are at `robots`, with the fixed nodes.
    pub fn of(
        model: &RadioModel,
        caster: &RayCaster,
        fixed: &FixedLinks,
        robots: &[[f64; 3]],
    ) -> Network {
        let nf = fixed.antennas.len();
        let n = nf + robots.len();
        let node = |i: usize| {
            if i < nf {
                FixedLinks::node(i)
            } else {
                Node::Robot(i - nf)
            }
        };
        let at = |i: usize| {
            if i < nf {
                fixed.antennas[i]
            } else {
                robots[i - nf]
            }
        };
        let mut links = Vec::new();
        for (r, &p) in robots.iter().enumerate() {
            let i = nf + r;
            for j in 0..i {
                if let Some(power_dbm) = model.link(caster, at(j), p) {
                    links.push(Link {
                        a: node(j),
                        b: node(i),
                        pa: at(j),
                        pb: p,
                        power_dbm,
                    });
                }
            }
        }
        let index = |m: Node| match m {
            Node::Base => 0,
            Node::Crumb(c) => c + 1,
            Node::Robot(r) => nf + r,
        };
        let mut adjacent = vec![Vec::new(); n];
        for l in fixed.links.iter().chain(&links) {
            let (a, b) = (index(l.a), index(l.b));
            adjacent[a].push(b);
            adjacent[b].push(a);
        }
        // Breadth first from each unvisited node: groups, and hops from the base station.
        let mut group = vec![usize::MAX; n];
        let mut hops = vec![None; n];
        let mut g = 0;
        for s in 0..n {
            if group[s] != usize::MAX {
                continue;
            }
            let mut queue = std::collections::VecDeque::from([s]);
            group[s] = g;
            if s == 0 {
                hops[0] = Some(0);
            }
            while let Some(u) = queue.pop_front() {
                for &v in &adjacent[u] {
                    if group[v] == usize::MAX {
                        group[v] = g;
                        if let Some(h) = hops[u] {
                            hops[v] = Some(h + 1);
                        }
                        queue.push_back(v);
                    }
                }
            }
            g += 1;
        }
        Network {
            links,
            hops: hops[nf..].to_vec(),
            group: group[nf..].to_vec(),
        }
    }

    /// Whether robot `r` reaches the base station.
    pub fn reaches_base(&self, r: usize) -> bool {
        self.hops[r].is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_competitions_numbers_give_a_link_of_about_300_m_in_sight() {
        let m = RadioModel::default();
        // QPSK, 1000 bytes, half delivered: about 7.6 dB above the noise floor.
        assert!(
            (m.threshold_dbm + 82.43).abs() < 0.05,
            "{}",
            m.threshold_dbm
        );
        let reach = m.reach_m();
        assert!((reach - 314.0).abs() < 2.0, "{reach}");
        assert!((m.power_dbm(10.0) - (20.0 - 40.0 - 25.0)).abs() < 1e-12);
        assert!(m.power_dbm(reach) >= m.threshold_dbm - 1e-9);
    }
}
