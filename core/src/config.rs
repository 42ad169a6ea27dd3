//! The pipeline file: what world to make, declared in TOML.
//!
//! ```toml
//! [world]
//! seed = 7
//! levels = 1
//! min_length = [1000, 2000]   # metres; the grid side is floor(sqrt(min_length)) cells
//! tile_pitch = 25.0           # metres between opposite openings of a tile
//!
//! [topology]
//! loops = [0, 2]              # a number, or [low, high] drawn uniformly per level
//! t_junctions = [1, 3]
//! intersections = [1, 3]
//! exact = false
//!
//! [route]
//! type = "parabolic"
//! ```
//!
//! Unknown keys are errors, and every error names the file, line, column and key. A resolved
//! pipeline ([`Pipeline::resolve`]) has every range drawn and every level's counts written
//! out; it is what a world folder records, and it regenerates the same world.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::error::{ConfigError, Location, key_at};
use crate::params::ComponentSpec;
pub use crate::range::{FloatRange, IntRange};
use crate::rng::WorldRng;

/// A whole pipeline file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pipeline {
    /// Size, levels, seed and scale.
    #[serde(default)]
    pub world: WorldSection,
    /// Requested structures per level.
    #[serde(default)]
    pub topology: TopologySection,
    /// The route descriptor bending every corridor.
    #[serde(default = "default_route")]
    pub route: ComponentSpec,
    /// The tile set that turns tiles into geometry (filled by the tile-set stage).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tileset: Option<ComponentSpec>,
    /// Extra exporters, each `[[export]]` with a `type`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub export: Vec<ComponentSpec>,
    /// Shared libraries to load components from.
    #[serde(default, skip_serializing_if = "PluginsSection::is_empty")]
    pub plugins: PluginsSection,
    /// Objects to find (`[artifacts]`); none without the section.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub artifacts: Option<crate::artifacts::ArtifactsSection>,
    /// Floor hazards (`[hazards]`); none without the section.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hazards: Option<crate::hazards::HazardsSection>,
    /// Written by the tool into a world's `world.toml`; ignored when generating.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generated: Option<Provenance>,
}

fn default_route() -> ComponentSpec {
    ComponentSpec::named("parabolic")
}

impl Default for Pipeline {
    fn default() -> Self {
        Pipeline {
            world: WorldSection::default(),
            topology: TopologySection::default(),
            route: default_route(),
            tileset: None,
            export: Vec::new(),
            plugins: PluginsSection::default(),
            artifacts: None,
            hazards: None,
            generated: None,
        }
    }
}

/// `[world]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSection {
    /// The seed every random choice derives from (0 to 2^63 - 1).
    #[serde(default)]
    pub seed: u64,
    /// Number of levels, joined by shafts.
    #[serde(default = "one")]
    pub levels: IntRange,
    /// Minimum corridor length target in metres; the grid side is `floor(sqrt(min_length))`
    /// cells, as in the original. Give this or `rows` and `cols`; with neither, the natural
    /// cave's `[1000, 2000]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_length: Option<FloatRange>,
    /// Grid rows, instead of `min_length`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rows: Option<u32>,
    /// Grid columns, instead of `min_length`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cols: Option<u32>,
    /// Metres between opposite openings of a tile.
    #[serde(default = "default_pitch")]
    pub tile_pitch: f64,
    /// Metres between levels (default 0.8 x the pitch, the DARPA shaft's proportion).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level_height: Option<f64>,
    /// Widest tunnel in metres, for tile sets.
    #[serde(default = "default_width")]
    pub max_width: FloatRange,
    /// Attempts per level, each with a derived seed, before giving up.
    #[serde(default = "default_attempts")]
    pub attempts: u32,
    /// How levels are joined: `"shaft"` (a vertical shaft, the paper's) or `"ramp"` (a spiral
    /// decline a wheeled robot can drive). Without it, mines get ramps and the others shafts;
    /// resolution writes the value used.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub connections: Option<Connections>,
    /// The steepest grade a ramp may have, degrees (default [`DEFAULT_RAMP_GRADE`]): each ramp
    /// is as gentle as its spiral block allows, and one that needs a steeper ramp is an error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ramp_grade: Option<f64>,
}

/// How consecutive levels are joined.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Connections {
    /// A vertical shaft (the paper's; no ground robot can use it).
    #[default]
    Shaft,
    /// A spiral ramp inside the shaft's cells, at a drivable grade.
    Ramp,
}

/// The default steepest ramp grade, degrees: 1 in 7, a real mine decline's (1 in 7 to 1 in 9),
/// drivable by wheeled robots. A ramp's spiral turns in a 2 x 2 block of cells beside its foot
/// (see [`crate::grid::Shaft::block`]): each turn's drop must hold the passage and the rock
/// above it, and a turn round a block twice a cell wide is long enough for this grade (the mine
/// preset's, 20 m tiles and 16 m between levels, climb at about 5 degrees).
pub const DEFAULT_RAMP_GRADE: f64 = 8.13;
/// The steepest `world.ramp_grade` accepted, degrees.
pub const MAX_RAMP_GRADE: f64 = 30.0;

fn one() -> IntRange {
    IntRange::Fixed(1)
}
fn default_min_length() -> FloatRange {
    FloatRange::Between(1000.0, 2000.0)
}
fn default_pitch() -> f64 {
    25.0
}
fn default_width() -> FloatRange {
    FloatRange::Between(40.0, 50.0)
}
fn default_attempts() -> u32 {
    64
}

impl Default for WorldSection {
    fn default() -> Self {
        WorldSection {
            seed: 0,
            levels: one(),
            min_length: Some(default_min_length()),
            rows: None,
            cols: None,
            tile_pitch: default_pitch(),
            level_height: None,
            max_width: default_width(),
            attempts: default_attempts(),
            connections: None,
            ramp_grade: None,
        }
    }
}

/// `[topology]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TopologySection {
    /// Loops per level (independent cycles, each a ring with four arms).
    #[serde(default = "default_loops")]
    pub loops: IntRange,
    /// T-junctions per level.
    #[serde(default = "default_junctions")]
    pub t_junctions: IntRange,
    /// Intersections per level.
    #[serde(default = "default_junctions")]
    pub intersections: IntRange,
    /// Other structures by registered shape name: `[[topology.structure]]` with `type` and
    /// `count`.
    #[serde(default, rename = "structure", skip_serializing_if = "Vec::is_empty")]
    pub structures: Vec<ComponentSpec>,
    /// When true (the default), the final grid has exactly the requested junctions,
    /// intersections and loops: routes keep clear of corridors they are not meant to join.
    /// `false` is the original's behaviour: at least what was asked, arms that land next to a
    /// corridor join it and bring junctions and loops of their own.
    #[serde(default = "default_exact")]
    pub exact: bool,
    /// Per-level structure counts by shape name; written by resolution, and may be given by
    /// hand to fix each level's counts.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_level: Vec<BTreeMap<String, u32>>,
}

fn default_exact() -> bool {
    true
}
fn default_loops() -> IntRange {
    IntRange::Between(0, 2)
}
fn default_junctions() -> IntRange {
    IntRange::Between(1, 3)
}

impl Default for TopologySection {
    fn default() -> Self {
        TopologySection {
            loops: default_loops(),
            t_junctions: default_junctions(),
            intersections: default_junctions(),
            structures: Vec::new(),
            exact: default_exact(),
            per_level: Vec::new(),
        }
    }
}

/// `[plugins]`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PluginsSection {
    /// Shared libraries, relative to the pipeline file.
    #[serde(default)]
    pub paths: Vec<String>,
}

impl PluginsSection {
    fn is_empty(&self) -> bool {
        self.paths.is_empty()
    }
}

/// `[generated]`: what made a world.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Provenance {
    /// Tool name.
    pub tool: String,
    /// Tool version.
    pub version: String,
    /// The preset or file the world came from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
}

/// The built-in structure names and the `[topology]` keys that count them.
pub const BUILT_IN_STRUCTURES: [(&str, &str); 3] = [
    ("loop", "loops"),
    ("t-junction", "t_junctions"),
    ("intersection", "intersections"),
];

/// Limits that keep a world within what the tool is meant for.
const MAX_LEVELS: u32 = 64;
/// Shortest `world.tile_pitch` and `world.level_height`, metres.
const MIN_LENGTH: f64 = 0.5;
/// Longest `world.tile_pitch` and `world.level_height`, metres.
const MAX_LENGTH: f64 = 1000.0;
const MAX_SIDE: u32 = 2048;
const MIN_SIDE: u32 = 8;

/// The largest seed: `world.seed` is a TOML integer, at most 2^63 - 1. The one home of the
/// bound: the command line's `--seed`, the configuration's `world.seed` and a dataset's
/// derived seeds all keep to it.
pub const MAX_SEED: u64 = i64::MAX as u64;

/// [`MAX_SEED`] as messages spell it.
pub const MAX_SEED_SPELLED: &str = "2^63 - 1 (9223372036854775807)";

/// What a `[world]` key with a bounded range accepts, as its refusals say it: the same
/// message for every value outside the range, whether the reader refuses it (a negative
/// number where a count or a seed is read) or the pipeline's check does (zero, too many).
fn range_of(key: &str) -> Option<String> {
    Some(match key {
        "world.seed" => format!("must be from 0 to {MAX_SEED_SPELLED}"),
        "world.levels" => {
            format!("must be between 1 and {MAX_LEVELS} (a number, or [low, high] drawn per world)")
        }
        "world.rows" | "world.cols" => format!("must be between {MIN_SIDE} and {MAX_SIDE} cells"),
        "world.min_length" => format!(
            "gives a grid side outside {MIN_SIDE}..{MAX_SIDE} cells; use {} to {} metres",
            MIN_SIDE * MIN_SIDE,
            MAX_SIDE * MAX_SIDE
        ),
        "world.attempts" => "must be between 1 and 10000".into(),
        _ => return None,
    })
}

/// The message for a value the reader refused: a bounded key's range ([`range_of`]) when the
/// reader refused a number for its sign or size, else the reader's own words.
fn reader_message(key: &str, message: String) -> String {
    let out_of_range = message.contains("must be >= 0")
        || message.starts_with("invalid value: integer")
        || message.starts_with("too large");
    match range_of(key) {
        Some(range) if out_of_range => range,
        _ => message,
    }
}

/// A pipeline's fixed numbers, as generation needs them.
#[derive(Clone, Debug, PartialEq)]
pub struct Resolved {
    /// Seed.
    pub seed: u64,
    /// Levels.
    pub levels: usize,
    /// Rows per level.
    pub rows: usize,
    /// Columns per level.
    pub cols: usize,
    /// Metres between tile centres.
    pub tile_pitch: f64,
    /// Metres between levels.
    pub level_height: f64,
    /// Widest tunnel in metres.
    pub max_width: f64,
    /// Attempts per level.
    pub attempts: u32,
    /// Structure counts per level, by shape name, in a fixed order.
    pub per_level: Vec<Vec<(String, u32)>>,
    /// Exact topology.
    pub exact: bool,
    /// How levels are joined.
    pub connections: Connections,
    /// The steepest ramp grade, degrees.
    pub ramp_grade: f64,
}

impl WorldSection {
    /// Fixes `connections` (from the tile set when not given: ramps for `mine`, shafts
    /// otherwise) and, for ramps, `ramp_grade`, so the recorded pipeline states them.
    pub fn resolve_connections(&mut self, tileset: Option<&ComponentSpec>) -> (Connections, f64) {
        let c = self.connections.unwrap_or_else(|| {
            if tileset.is_some_and(|t| t.type_name == "mine") {
                Connections::Ramp
            } else {
                Connections::Shaft
            }
        });
        self.connections = Some(c);
        let grade = self.ramp_grade.unwrap_or(DEFAULT_RAMP_GRADE);
        if c == Connections::Ramp {
            self.ramp_grade = Some(grade);
        }
        (c, grade)
    }
}

impl Pipeline {
    /// Parses a pipeline file. `file` names it in errors.
    pub fn parse(source: &str, file: &str) -> Result<Pipeline, ConfigError> {
        let file: Arc<str> = Arc::from(file);
        if source
            .lines()
            .all(|l| l.trim().is_empty() || l.trim_start().starts_with('#'))
        {
            // An empty file would silently mean seed 0 and no tile set: the built-in defaults
            // are what running without a file is for.
            return Err(ConfigError {
                location: Location {
                    file,
                    line: 1,
                    column: 1,
                },
                key: String::new(),
                message: "the pipeline file is empty (no table, no key); write at least a [world] \
                          table (see examples/cave.toml), or run without a pipeline file to use \
                          the built-in defaults (the cave preset)"
                    .into(),
            });
        }
        let mut p: Pipeline = toml::from_str(source).map_err(|e| {
            let (offset, message) =
                crate::nesting::explain(source, e.span().map(|s| s.start), e.message());
            let location = Location::of_offset(&file, source, offset);
            let key = key_at(source, offset);
            ConfigError {
                message: reader_message(&key, message),
                key,
                location,
            }
        })?;
        p.route.params.locate(&file, source, "route".into());
        if let Some(t) = &mut p.tileset {
            t.params.locate(&file, source, "tileset".into());
        }
        for (i, e) in p.export.iter_mut().enumerate() {
            e.params.locate(&file, source, format!("export[{i}]"));
        }
        for (i, s) in p.topology.structures.iter_mut().enumerate() {
            s.params
                .locate(&file, source, format!("topology.structure[{i}]"));
        }
        p.check(&file, source)?;
        Ok(p)
    }

    /// Cross-key checks that serde cannot express.
    fn check(&self, file: &Arc<str>, source: &str) -> Result<(), ConfigError> {
        let err = |key: &str, message: String| ConfigError {
            location: locate_key(file, source, key),
            key: key.to_owned(),
            message,
        };
        let w = &self.world;
        let out_of_range = |key: &str| err(key, range_of(key).unwrap_or_default());
        if w.seed > MAX_SEED {
            return Err(out_of_range("world.seed"));
        }
        if w.levels.max() == 0
            || w.levels.max() > MAX_LEVELS
            || matches!(w.levels, IntRange::Between(0, _))
        {
            return Err(out_of_range("world.levels"));
        }
        match (w.min_length, w.rows, w.cols) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                return Err(err(
                    "world.rows",
                    "give either `min_length` or `rows` and `cols`, not both".into(),
                ));
            }
            (None, r, c) if r.is_none() != c.is_none() => {
                return Err(err("world.rows", "give both `rows` and `cols`".into()));
            }
            _ => {}
        }
        for (key, v) in [("world.rows", w.rows), ("world.cols", w.cols)] {
            if v.is_some_and(|v| !(MIN_SIDE..=MAX_SIDE).contains(&v)) {
                return Err(out_of_range(key));
            }
        }
        if let Some(m) = w.min_length {
            let hi = match m {
                FloatRange::Fixed(v) | FloatRange::Between(_, v) => v,
            };
            let lo = match m {
                FloatRange::Fixed(v) | FloatRange::Between(v, _) => v,
            };
            let side = |x: f64| x.sqrt().floor() as u32;
            if side(lo) < MIN_SIDE || side(hi) > MAX_SIDE {
                return Err(out_of_range("world.min_length"));
            }
        }
        // Lengths a passage tile can physically have: from a crawlspace to a cavern. Beyond,
        // meshes lose their precision (single-precision vertices) or their meaning.
        let metres = MIN_LENGTH..=MAX_LENGTH;
        if !metres.contains(&w.tile_pitch) {
            return Err(err(
                "world.tile_pitch",
                format!("must be from {MIN_LENGTH} to {MAX_LENGTH} metres"),
            ));
        }
        if let Some(h) = w.level_height {
            if !metres.contains(&h) {
                return Err(err(
                    "world.level_height",
                    format!("must be from {MIN_LENGTH} to {MAX_LENGTH} metres"),
                ));
            }
        }
        if let Some(g) = w.ramp_grade {
            if !(g.is_finite() && (1.0..=MAX_RAMP_GRADE).contains(&g)) {
                return Err(err(
                    "world.ramp_grade",
                    format!(
                        "ramp_grade = {g}: must be from 1 to {MAX_RAMP_GRADE} degrees (the \
                         steepest grade a ramp may have; {DEFAULT_RAMP_GRADE} by default)"
                    ),
                ));
            }
        }
        if w.attempts == 0 || w.attempts > 10_000 {
            return Err(out_of_range("world.attempts"));
        }
        if let Some((key, message)) = self.hazards.as_ref().and_then(|h| h.problem()) {
            return Err(err(key, message));
        }
        if let Some((key, message)) = self.artifacts.as_ref().and_then(|a| a.problem()) {
            return Err(err(key, message));
        }
        let t = &self.topology;
        if !t.per_level.is_empty() {
            if let IntRange::Between(..) = w.levels {
                return Err(err(
                    "topology.per_level",
                    "needs a fixed `world.levels` so each level has an entry".into(),
                ));
            }
            if t.per_level.len() != w.levels.max() as usize {
                return Err(err(
                    "topology.per_level",
                    format!(
                        "has {} entries but the world has {} levels; give one table per level",
                        t.per_level.len(),
                        w.levels.max()
                    ),
                ));
            }
            for counts in &t.per_level {
                if counts.values().all(|&c| c == 0) {
                    return Err(err(
                        "topology.per_level",
                        "every level needs at least one structure; a level with none would be empty"
                            .into(),
                    ));
                }
            }
        } else {
            let mut max = t.loops.max() + t.t_junctions.max() + t.intersections.max();
            for s in &self.topology.structures {
                max += structure_count(s)?.max();
            }
            if max == 0 {
                return Err(err(
                    "topology",
                    "asks for no structures; a level needs at least one loop, T-junction or intersection"
                        .into(),
                ));
            }
        }
        Ok(())
    }

    /// Draws every range and fixes every level's counts. The draws come from their own stream,
    /// so a resolved pipeline generates exactly the world its unresolved form does.
    pub fn resolve(&self) -> Result<(Pipeline, Resolved), ConfigError> {
        let mut rng = WorldRng::new(self.world.seed, "resolve", 0);
        let mut p = self.clone();
        let levels = p.world.levels.draw(&mut rng);
        p.world.levels = IntRange::Fixed(levels);
        let (rows, cols) = match (p.world.min_length, p.world.rows, p.world.cols) {
            (Some(m), _, _) => {
                let len = m.draw(&mut rng);
                let n = (len.sqrt().floor() as u32).clamp(MIN_SIDE, MAX_SIDE);
                (n, n)
            }
            (None, Some(r), Some(c)) => (r, c),
            _ => {
                let len = default_min_length().draw(&mut rng);
                let n = (len.sqrt().floor() as u32).clamp(MIN_SIDE, MAX_SIDE);
                (n, n)
            }
        };
        p.world.min_length = None;
        p.world.rows = Some(rows);
        p.world.cols = Some(cols);
        let max_width = p.world.max_width.draw(&mut rng);
        p.world.max_width = FloatRange::Fixed(max_width);
        let level_height = p.world.level_height.unwrap_or(0.8 * p.world.tile_pitch);
        p.world.level_height = Some(level_height);
        if let Some(a) = &mut p.artifacts {
            a.resolve(p.world.seed);
        }
        let (connections, ramp_grade) = p.world.resolve_connections(p.tileset.as_ref());

        let per_level: Vec<Vec<(String, u32)>> = if p.topology.per_level.is_empty() {
            let mut ranges: Vec<(String, IntRange)> = BUILT_IN_STRUCTURES
                .iter()
                .zip([
                    p.topology.loops,
                    p.topology.t_junctions,
                    p.topology.intersections,
                ])
                .map(|((name, _), r)| ((*name).to_owned(), r))
                .collect();
            for s in &p.topology.structures {
                ranges.push((s.type_name.clone(), structure_count(s)?));
            }
            (0..levels)
                .map(|_| {
                    // A level whose drawn counts are all zero is redrawn (bounded: the ranges
                    // allow a non-zero draw, checked at parse).
                    for _ in 0..1000 {
                        let counts: Vec<(String, u32)> = ranges
                            .iter()
                            .map(|(n, r)| (n.clone(), r.draw(&mut rng)))
                            .collect();
                        if counts.iter().any(|(_, c)| *c > 0) {
                            return sorted(counts);
                        }
                    }
                    sorted(ranges.iter().map(|(n, r)| (n.clone(), r.max())).collect())
                })
                .collect()
        } else {
            p.topology
                .per_level
                .iter()
                .map(|m| m.iter().map(|(k, v)| (k.clone(), *v)).collect())
                .collect()
        };
        p.topology.per_level = per_level
            .iter()
            .map(|c| c.iter().cloned().collect())
            .collect();
        let resolved = Resolved {
            seed: p.world.seed,
            levels: levels as usize,
            rows: rows as usize,
            cols: cols as usize,
            tile_pitch: p.world.tile_pitch,
            level_height,
            max_width,
            attempts: p.world.attempts,
            per_level,
            exact: p.topology.exact,
            connections,
            ramp_grade,
        };
        Ok((p, resolved))
    }

    /// Makes the path-valued keys (`manifest` of any component, `plugins.paths`) absolute,
    /// relative to `base` (the pipeline file's folder), so a world's recorded pipeline finds
    /// the same files from wherever it is regenerated.
    pub fn anchor_paths(&mut self, base: &std::path::Path) {
        let anchor = |s: &str| -> String {
            let p = std::path::Path::new(s);
            if p.is_absolute() {
                return s.to_owned();
            }
            let joined = base.join(p);
            joined
                .canonicalize()
                .unwrap_or(joined)
                .to_string_lossy()
                .into_owned()
        };
        let mut specs: Vec<&mut ComponentSpec> = Vec::new();
        specs.extend(self.tileset.as_mut());
        specs.extend(self.export.iter_mut());
        specs.extend(self.topology.structures.iter_mut());
        for spec in specs {
            if let Some(toml::Value::String(s)) = spec.params.raw("manifest").cloned() {
                spec.params.set("manifest", toml::Value::String(anchor(&s)));
            }
        }
        for p in &mut self.plugins.paths {
            *p = anchor(p);
        }
    }

    /// The pipeline as TOML text.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a pipeline always serializes")
    }
}

/// Structure counts in name order: the canonical order generation sees, whether the counts
/// were drawn or read back from a resolved pipeline.
fn sorted(mut counts: Vec<(String, u32)>) -> Vec<(String, u32)> {
    counts.sort();
    counts
}

/// The `count` of a `[[topology.structure]]` entry.
pub fn structure_count(spec: &ComponentSpec) -> Result<IntRange, ConfigError> {
    match spec.params.raw("count") {
        None => Err(spec.params.error(
            "count",
            "missing `count`: how many of this structure per level, a number or [low, high]",
        )),
        Some(v) => IntRange::deserialize(v.clone())
            .map_err(|e| spec.params.error("count", e.to_string().trim().to_owned())),
    }
}

/// Where a dotted key is written, or the start of its section, or the file's start.
fn locate_key(file: &Arc<str>, source: &str, dotted: &str) -> Location {
    let (section, key) = dotted.rsplit_once('.').unwrap_or((dotted, ""));
    let mut in_section = false;
    let mut section_offset = None;
    let mut offset = 0;
    for line in source.split_inclusive('\n') {
        let t = line.trim();
        if t.starts_with('[') {
            in_section = t.trim_matches(|c| c == '[' || c == ']').trim() == section;
            if in_section && section_offset.is_none() {
                section_offset = Some(offset);
            }
        } else if in_section && !key.is_empty() {
            if let Some((k, _)) = t.split_once('=') {
                if k.trim() == key {
                    return Location::of_offset(
                        file,
                        source,
                        offset + (line.len() - line.trim_start().len()),
                    );
                }
            }
        }
        offset += line.len();
    }
    Location::of_offset(file, source, section_offset.unwrap_or(0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_keys_are_errors_with_line_and_key() {
        let src = "[world]\nseed = 3\nlevles = 2\n";
        let e = Pipeline::parse(src, "my.toml").unwrap_err();
        assert_eq!(e.location.line, 3, "{e}");
        assert_eq!(e.location.column, 1, "{e}");
        assert_eq!(e.key, "world.levles");
        assert!(e.to_string().starts_with("my.toml:3:1:"), "{e}");
        assert!(e.message.contains("unknown field"), "{e}");
    }

    #[test]
    fn bad_ranges_point_at_their_value() {
        let e = Pipeline::parse("[topology]\nloops = [3, 1]\n", "p.toml").unwrap_err();
        assert_eq!(e.location.line, 2);
        assert_eq!(e.key, "topology.loops");
        assert!(e.message.contains("low <= high"), "{e}");
        let e = Pipeline::parse("[topology]\nloops = 1.5\n", "p.toml").unwrap_err();
        assert!(e.message.contains("whole number"), "{e}");
    }

    #[test]
    fn conflicting_sizes_are_refused() {
        let e = Pipeline::parse(
            "[world]\nmin_length = 1000\nrows = 30\ncols = 30\n",
            "p.toml",
        )
        .unwrap_err();
        assert_eq!(e.key, "world.rows");
        assert_eq!(e.location.line, 3);
    }

    #[test]
    fn a_resolved_pipeline_resolves_to_itself() {
        let p = Pipeline::parse("[world]\nseed = 11\nlevels = [2, 4]\n", "p.toml").unwrap();
        let (fixed, r) = p.resolve().unwrap();
        let again = Pipeline::parse(&fixed.to_toml(), "w.toml").unwrap();
        let (fixed2, r2) = again.resolve().unwrap();
        assert_eq!(r, r2);
        assert_eq!(fixed.to_toml(), fixed2.to_toml());
        assert!((31..=44).contains(&r.rows));
        for level in &r.per_level {
            assert!(level.iter().any(|(_, c)| *c > 0));
        }
    }

    #[test]
    fn no_structures_is_refused() {
        let e = Pipeline::parse(
            "[topology]\nloops = 0\nt_junctions = 0\nintersections = 0\n",
            "p.toml",
        )
        .unwrap_err();
        assert_eq!(e.key, "topology");
        assert_eq!(e.location.line, 1);
    }
}
