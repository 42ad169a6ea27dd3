//! `[artifacts]`: objects a robot should find and report, as in the DARPA Subterranean
//! Challenge, placed by seeded rules (where they go is found by the survey, against the
//! collision surface: `survey/src/artifacts.rs`), and the placed [`Artifact`]s every format
//! and the ground truth write.
//!
//! ```toml
//! [artifacts]
//! classes = ["survivor", "backpack", "cell-phone", "drill", "fire-extinguisher", "helmet", "rope"]
//! count = [15, 25]                  # per world: a number or [low, high]
//! min_distance_from_start = 50      # metres along the passages (the graph)
//! placement = ["dead-end", "chamber", "wall", "floor"]
//! min_spacing = 10                  # metres between any two artifacts
//! hidden = 0.3                      # share placed out of sight of their tile's passage axis
//! ```
//!
//! The section is optional: a pipeline without it makes exactly the files it made before the
//! section existed. The count is drawn from a stream of its own (`"artifacts"`), and a world's
//! `world.toml` records it fixed.
//!
//! `hidden` (default 0: placement does not look at sight lines, as before the key existed) is
//! the share of artifacts placed where the passage axis does not see them: around a bend,
//! in a pocket or behind a boulder, as DARPA's course designers hid some. A world with fewer
//! such spots than asked for gets as many as it has, and its ground truth says so.

use serde::{Deserialize, Serialize};

use crate::grid::Cell;
use crate::range::IntRange;
use crate::rng::WorldRng;
use crate::tile::TileKind;

/// The DARPA SubT artifact classes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ArtifactClass {
    /// A sitting mannequin ("Rescue Randy").
    Survivor,
    /// A red backpack.
    Backpack,
    /// A phone lying on the floor, in a rugged case 5 cm thick (thinner boxes tunnel through
    /// triangle-mesh floors in PyBullet when dropped).
    CellPhone,
    /// A power drill.
    Drill,
    /// A red fire extinguisher, lying on its side.
    FireExtinguisher,
    /// A gas source (a canister standing in for the CO2 of the DARPA worlds).
    Gas,
    /// A heater vent.
    Vent,
    /// A white helmet.
    Helmet,
    /// A coil of blue rope.
    Rope,
    /// The small cube with a radio beacon.
    Cube,
}

impl ArtifactClass {
    /// Every class, in the order the DARPA rules list them.
    pub const ALL: [ArtifactClass; 10] = [
        ArtifactClass::Survivor,
        ArtifactClass::Backpack,
        ArtifactClass::CellPhone,
        ArtifactClass::Drill,
        ArtifactClass::FireExtinguisher,
        ArtifactClass::Gas,
        ArtifactClass::Vent,
        ArtifactClass::Helmet,
        ArtifactClass::Rope,
        ArtifactClass::Cube,
    ];

    /// The name used in pipeline files, ground truth and reports.
    pub const fn name(self) -> &'static str {
        match self {
            ArtifactClass::Survivor => "survivor",
            ArtifactClass::Backpack => "backpack",
            ArtifactClass::CellPhone => "cell-phone",
            ArtifactClass::Drill => "drill",
            ArtifactClass::FireExtinguisher => "fire-extinguisher",
            ArtifactClass::Gas => "gas",
            ArtifactClass::Vent => "vent",
            ArtifactClass::Helmet => "helmet",
            ArtifactClass::Rope => "rope",
            ArtifactClass::Cube => "cube",
        }
    }

    /// The class with this name; also accepts `_` and spaces for `-` and any case
    /// (`Cell Phone`, `fire_extinguisher`), as team reports spell them.
    pub fn parse(name: &str) -> Option<ArtifactClass> {
        let n: String = name
            .trim()
            .chars()
            .map(|c| match c {
                '_' | ' ' => '-',
                c => c.to_ascii_lowercase(),
            })
            .collect();
        ArtifactClass::ALL.into_iter().find(|c| c.name() == n)
    }

    /// Box size in metres, `[length, width, height]` (x, y, z before its yaw): the DARPA
    /// models' extents as they lie (the survivor sitting with its legs out, the extinguisher
    /// and the drill on their side), never taller than wide, so a dropped artifact settles
    /// where it lands instead of toppling.
    pub const fn size(self) -> [f64; 3] {
        match self {
            ArtifactClass::Survivor => [0.9, 0.6, 0.7],
            ArtifactClass::Backpack => [0.5, 0.35, 0.25],
            ArtifactClass::CellPhone => [0.16, 0.08, 0.05],
            ArtifactClass::Drill => [0.3, 0.25, 0.15],
            ArtifactClass::FireExtinguisher => [0.55, 0.18, 0.18],
            ArtifactClass::Gas => [0.3, 0.3, 0.35],
            ArtifactClass::Vent => [0.5, 0.3, 0.3],
            ArtifactClass::Helmet => [0.3, 0.25, 0.18],
            ArtifactClass::Rope => [0.4, 0.4, 0.12],
            ArtifactClass::Cube => [0.15, 0.15, 0.15],
        }
    }

    /// Mass in kilograms, for simulators that move them.
    pub const fn mass(self) -> f64 {
        match self {
            ArtifactClass::Survivor => 20.0,
            ArtifactClass::Backpack => 5.0,
            ArtifactClass::CellPhone => 0.2,
            ArtifactClass::Drill => 1.5,
            ArtifactClass::FireExtinguisher => 6.0,
            ArtifactClass::Gas => 4.0,
            ArtifactClass::Vent => 3.0,
            ArtifactClass::Helmet => 0.5,
            ArtifactClass::Rope => 2.0,
            ArtifactClass::Cube => 0.5,
        }
    }

    /// A distinct colour (linear RGB, 0 to 1), so a camera can tell the classes apart.
    pub const fn colour(self) -> [f32; 3] {
        match self {
            ArtifactClass::Survivor => [1.0, 0.45, 0.0],
            ArtifactClass::Backpack => [0.8, 0.05, 0.05],
            ArtifactClass::CellPhone => [0.05, 0.05, 0.1],
            ArtifactClass::Drill => [1.0, 0.85, 0.0],
            ArtifactClass::FireExtinguisher => [1.0, 0.0, 0.4],
            ArtifactClass::Gas => [0.3, 0.9, 0.2],
            ArtifactClass::Vent => [0.85, 0.85, 0.85],
            ArtifactClass::Helmet => [1.0, 1.0, 1.0],
            ArtifactClass::Rope => [0.1, 0.3, 1.0],
            ArtifactClass::Cube => [0.6, 0.1, 0.9],
        }
    }
}

/// Where an artifact may go.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Placement {
    /// In a dead-end tile (not a shaft's end).
    DeadEnd,
    /// In a T-junction or an intersection, where passages meet and open up.
    Chamber,
    /// Against a wall: rock within half a metre of its footprint, at its height.
    Wall,
    /// In the open on the floor: no rock within half a metre of its footprint.
    Floor,
}

impl Placement {
    /// Every rule.
    pub const ALL: [Placement; 4] = [
        Placement::DeadEnd,
        Placement::Chamber,
        Placement::Wall,
        Placement::Floor,
    ];

    /// The name used in pipeline files and ground truth.
    pub const fn name(self) -> &'static str {
        match self {
            Placement::DeadEnd => "dead-end",
            Placement::Chamber => "chamber",
            Placement::Wall => "wall",
            Placement::Floor => "floor",
        }
    }
}

/// `[artifacts]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArtifactsSection {
    /// Classes to place, taken in turn (each class about as often as the others).
    #[serde(default = "all_classes")]
    pub classes: Vec<ArtifactClass>,
    /// How many per world.
    #[serde(default = "default_count")]
    pub count: IntRange,
    /// Least distance from the start tile, metres along the graph.
    #[serde(default = "default_distance")]
    pub min_distance_from_start: f64,
    /// Rules an artifact may be placed by, each drawn as often as the others.
    #[serde(default = "all_placements")]
    pub placement: Vec<Placement>,
    /// Least distance between two artifacts, metres.
    #[serde(default = "default_spacing")]
    pub min_spacing: f64,
    /// Share of the artifacts to place out of sight of their tile's passage axis, 0 to 1
    /// (0, the default, is not written, so worlds made before the key existed are unchanged).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub hidden: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

fn all_classes() -> Vec<ArtifactClass> {
    ArtifactClass::ALL.to_vec()
}
fn default_count() -> IntRange {
    IntRange::Between(15, 25)
}
fn default_distance() -> f64 {
    50.0
}
fn all_placements() -> Vec<Placement> {
    Placement::ALL.to_vec()
}
fn default_spacing() -> f64 {
    10.0
}

impl Default for ArtifactsSection {
    fn default() -> Self {
        ArtifactsSection {
            classes: all_classes(),
            count: default_count(),
            min_distance_from_start: default_distance(),
            placement: all_placements(),
            min_spacing: default_spacing(),
            hidden: 0.0,
        }
    }
}

/// Most artifacts a world may ask for.
pub const MAX_ARTIFACTS: u32 = 1000;

impl ArtifactsSection {
    /// What is wrong with the section, as `(key, message)`: the pipeline check locates the key.
    pub fn problem(&self) -> Option<(&'static str, String)> {
        if self.classes.is_empty() {
            return Some((
                "artifacts.classes",
                "lists no class; name at least one, e.g. classes = [\"survivor\", \"backpack\"]"
                    .into(),
            ));
        }
        for (i, c) in self.classes.iter().enumerate() {
            if self.classes[..i].contains(c) {
                return Some((
                    "artifacts.classes",
                    format!("lists '{}' twice; name each class once", c.name()),
                ));
            }
        }
        if self.placement.is_empty() {
            return Some((
                "artifacts.placement",
                "lists no rule; use some of \"dead-end\", \"chamber\", \"wall\", \"floor\"".into(),
            ));
        }
        // Rules are drawn as often as each other: a rule written twice would be drawn twice
        // as often, which the key does not say it does.
        for (i, p) in self.placement.iter().enumerate() {
            if self.placement[..i].contains(p) {
                return Some((
                    "artifacts.placement",
                    format!(
                        "lists '{}' twice; name each rule once (each rule is drawn as often as \
                         the others)",
                        p.name()
                    ),
                ));
            }
        }
        if self.count.max() > MAX_ARTIFACTS {
            return Some((
                "artifacts.count",
                format!("must be at most {MAX_ARTIFACTS}"),
            ));
        }
        for (key, v) in [
            (
                "artifacts.min_distance_from_start",
                self.min_distance_from_start,
            ),
            ("artifacts.min_spacing", self.min_spacing),
        ] {
            if !(v.is_finite() && (0.0..=1e6).contains(&v)) {
                return Some((key, "must be a number of metres from 0 to 1000000".into()));
            }
        }
        if !(self.hidden.is_finite() && (0.0..=1.0).contains(&self.hidden)) {
            return Some((
                "artifacts.hidden",
                format!(
                    "is {}; it is a share of the artifacts, from 0 (none hidden) to 1 (all hidden), e.g. hidden = 0.3",
                    self.hidden
                ),
            ));
        }
        None
    }

    /// How many of `count` artifacts are to be hidden: the nearest whole number to
    /// `hidden * count`.
    pub fn hidden_count(&self, count: usize) -> usize {
        ((self.hidden * count as f64).round() as usize).min(count)
    }

    /// Draws the count from the world's `"artifacts"` stream: resolving a pipeline fixes it.
    pub fn resolve(&mut self, seed: u64) {
        let mut rng = WorldRng::new(seed, "artifacts", 0);
        self.count = IntRange::Fixed(self.count.draw(&mut rng));
    }
}

/// How much wider than an artifact's footprint its pad is on each side, and half its
/// thickness, metres ([`Artifact::pad`]).
pub const PAD: f64 = 0.05;

/// Where an artifact is on the graph.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum GraphPlace {
    /// In the tile of a node.
    Node {
        /// Node id in `topology.json`.
        node: usize,
    },
    /// In a corridor tile between two nodes.
    Edge {
        /// Edge id in `topology.json`.
        edge: usize,
        /// Metres along the edge from its `from` node to the tile's centre.
        along_m: f64,
    },
}

/// One placed artifact.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Artifact {
    /// Index, 0 up.
    pub id: usize,
    /// `class-id`, unique in the world (`survivor-0`): the name in every format.
    pub name: String,
    /// What it is.
    pub class: ArtifactClass,
    /// The centre of its base, on the floor (world frame, metres).
    pub position: [f64; 3],
    /// Heading of its length (x before the yaw) about z, radians counter-clockwise from east.
    pub yaw: f64,
    /// Its box, `[length, width, height]` metres.
    pub size: [f64; 3],
    /// Its tile.
    pub cell: Cell,
    /// The tile's kind.
    pub tile_kind: TileKind,
    /// The rule it was placed by.
    pub placement: Placement,
    /// Node or edge of its tile.
    pub graph: GraphPlace,
    /// From the start tile's centre to its tile's centre along the graph, metres.
    pub distance_from_start_m: f64,
    /// Whether it is seen from its tile's lookout (`survey/src/sight.rs`): the ground truth's
    /// `visible_from_axis`.
    #[serde(skip)]
    pub visible_from_axis: bool,
    /// The eye it is looked at from: the ground truth's `sight_from`.
    #[serde(skip)]
    pub sight_from: [f64; 3],
}

impl Artifact {
    /// The centre of its box.
    pub fn centre(&self) -> [f64; 3] {
        let p = self.position;
        [p[0], p[1], p[2] + 0.5 * self.size[2]]
    }

    /// Its pad, `(centre, size)`: a static box under it in the physics formats, [`PAD`] wider
    /// than its footprint on every side, its top at the artifact's base, `2 PAD` thick (so it
    /// reaches into the floor: the base is at most 0.1 m above the floor under the
    /// footprint), turned by the same yaw. Simulators collide a small box with a rough
    /// triangle mesh or height field through contact sets that change from step to step:
    /// without pads, artifacts dropped from 0.5 m in our tests bounced and slid up to 1.6 m
    /// (MuJoCo) and 1.3 m (PyBullet) from their poses; on pads they rest within centimetres
    /// (box on box is solved exactly), and a robot still finds each where the ground truth
    /// says.
    pub fn pad(&self) -> ([f64; 3], [f64; 3]) {
        let p = self.position;
        (
            [p[0], p[1], p[2] - PAD],
            [
                self.size[0] + 2.0 * PAD,
                self.size[1] + 2.0 * PAD,
                2.0 * PAD,
            ],
        )
    }

    /// Its orientation as a quaternion `[x, y, z, w]`.
    pub fn quaternion_xyzw(&self) -> [f64; 4] {
        [0.0, 0.0, (0.5 * self.yaw).sin(), (0.5 * self.yaw).cos()]
    }
}

/// A world's artifacts as the survey placed them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlacedArtifacts {
    /// Every artifact, by id.
    pub artifacts: Vec<Artifact>,
    /// With `[artifacts] hidden`: how many were asked to be out of sight (fewer may be, when
    /// the world has too few hidden spots); `None` without the key.
    pub hidden: Option<HiddenAsked>,
}

/// What `[artifacts] hidden` asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HiddenAsked {
    /// The share, 0 to 1.
    pub share: f64,
    /// How many artifacts that is ([`ArtifactsSection::hidden_count`]).
    pub count: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn class_names_round_trip_and_reports_may_spell_them_loosely() {
        for c in ArtifactClass::ALL {
            assert_eq!(ArtifactClass::parse(c.name()), Some(c));
        }
        assert_eq!(
            ArtifactClass::parse(" Fire_Extinguisher "),
            Some(ArtifactClass::FireExtinguisher)
        );
        assert_eq!(
            ArtifactClass::parse("Cell Phone"),
            Some(ArtifactClass::CellPhone)
        );
        assert_eq!(ArtifactClass::parse("phone"), None);
        let colours: std::collections::BTreeSet<[u32; 3]> = ArtifactClass::ALL
            .iter()
            .map(|c| c.colour().map(|x| (x * 100.0) as u32))
            .collect();
        assert_eq!(colours.len(), ArtifactClass::ALL.len(), "distinct colours");
    }
}
