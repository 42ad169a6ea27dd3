//! `semantic-labels`: what each tile is, for scoring place categorisation and topometric
//! segmentation: `ground_truth/semantic_labels.json` and `ground_truth/semantic_labels.csv`.
//!
//! One entry per occupied cell, in raster order (level, row, column): its kind in the robotics
//! user's words (`dead-end`, `straight` = a straight corridor, `corner`, `t-junction`,
//! `intersection`, `shaft-up`, `shaft-landing`; `ramp` for both ends of a ramp between levels,
//! `world.connections = "ramp"`), the original's spatial code, its rotation
//! (quarter turns counter-clockwise from the kind's base orientation), its openings, and the
//! world position of the tile's node: on the floor of its own passage (the survey's
//! `Survey::position`; the tile centre on its level's floor without a mesh). Tiles with a hazard carry `hazard`: the floor
//! patch's material (`[hazards] friction`: `mud`, `ice`, `sand`, `wet-rock`), `rubble` or
//! `drop` (`[hazards] rubble`, `drops`), space-separated when a tile has two; the CSV then
//! has a last column `hazard` (empty on other tiles). Tiles the tile set made more of carry
//! `features`: `chamber` (a room several passage widths across at a junction or dead end) or
//! `squeeze` (a narrow or low place along a corridor, see `tilesets/src/chambers.rs`); the CSV
//! then has a column `features` after `start` (space-separated, empty on other tiles). With a
//! mesh, the JSON gives each tile's `grade_deg` (the steepest grade along its passage axis,
//! from the floor's own heights) and `slope` (true over [`SLOPE_DEG`]: sloping floors,
//! `[tileset] grade`). The CSV holds the same rows; its metadata (seed, frame) is in the JSON,
//! as CSV has no place for it.

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::grid::Direction;
use subtgraph_core::survey::Survey;

use super::FRAME;
use crate::text::{push_fixed, push_uint};

/// Writes `ground_truth/semantic_labels.json` and `.csv`.
#[derive(Clone, Copy, Debug, Default)]
pub struct SemanticLabels;

/// A tile's label (`slope`: whether its grade is over [`SLOPE_DEG`]).
type Label = subtgraph_schema::TileLabel<&'static str>;

/// Grade in degrees above which a tile is labelled a `slope`.
pub const SLOPE_DEG: f64 = 5.0;

type Document = subtgraph_schema::SemanticLabels<&'static str>;

fn direction_name(d: Direction) -> &'static str {
    match d {
        Direction::East => "east",
        Direction::North => "north",
        Direction::West => "west",
        Direction::South => "south",
    }
}

fn labels(world: &World, survey: &dyn Survey) -> Vec<Label> {
    let mut hazard: std::collections::BTreeMap<_, Vec<&'static str>> =
        std::collections::BTreeMap::new();
    for p in survey.patches().unwrap_or(&[]) {
        hazard.entry(p.cell).or_default().push(p.material.name());
    }
    for r in world.mesh().map_or(&[][..], |m| m.hazards.as_slice()) {
        hazard.entry(r.cell).or_default().push(r.kind.name());
    }
    let features: std::collections::BTreeMap<_, _> = world
        .mesh()
        .map(|m| {
            m.tiles
                .iter()
                .filter(|t| !t.labels.is_empty())
                .map(|t| (t.cell, t.labels.clone()))
                .collect()
        })
        .unwrap_or_default();
    let ramps = world.resolved.connections == subtgraph_core::config::Connections::Ramp;
    world
        .occupancy
        .cells()
        .filter_map(|c| {
            let t = world.tiles.get(c).as_ref()?;
            Some(Label {
                level: c.level,
                row: c.row,
                col: c.col,
                kind: if ramps && world.shafts.iter().any(|s| s.up == c || s.landing == c) {
                    "ramp"
                } else {
                    t.kind.name()
                },
                code: t.kind.spatial_code(),
                rotation: t.rotation,
                openings: Direction::ALL
                    .into_iter()
                    .filter(|d| t.openings & d.bit() != 0)
                    .map(direction_name)
                    .collect(),
                position: survey.position(c),
                start: world.start == Some(c),
                features: features.get(&c).cloned().unwrap_or_default(),
                hazard: hazard.get(&c).map(|h| h.join(" ")),
                grade_deg: survey.grade(c).map(|g| (g * 10.0).round() / 10.0),
                slope: survey.grade(c).is_some_and(|g| g > SLOPE_DEG),
            })
        })
        .collect()
}

/// The CSV; with `features` (some tile has any) a column `features` after `start`, and with
/// `hazards` (the world has a `[hazards]` section) a last column `hazard`: the patch material,
/// empty on other tiles. Worlds without them keep their columns.
fn csv(labels: &[Label], hazards: bool) -> Vec<u8> {
    let features = labels.iter().any(|l| !l.features.is_empty());
    let mut s = b"level,row,col,kind,code,rotation,openings,x,y,z,start".to_vec();
    if features {
        s.extend_from_slice(b",features");
    }
    if hazards {
        s.extend_from_slice(b",hazard");
    }
    s.push(b'\n');
    for l in labels {
        for v in [l.level, l.row, l.col] {
            push_uint(&mut s, v as u64);
            s.push(b',');
        }
        s.extend_from_slice(l.kind.as_bytes());
        s.push(b',');
        push_uint(&mut s, u64::from(l.code));
        s.push(b',');
        push_uint(&mut s, u64::from(l.rotation));
        s.push(b',');
        // Openings joined by spaces: no quoting needed.
        s.extend_from_slice(l.openings.join(" ").as_bytes());
        for v in l.position {
            s.push(b',');
            push_fixed(&mut s, v as f32);
        }
        s.extend_from_slice(if l.start { b",1" } else { b",0" });
        if features {
            s.push(b',');
            s.extend_from_slice(l.features.join(" ").as_bytes());
        }
        if hazards {
            s.push(b',');
            s.extend_from_slice(l.hazard.as_deref().unwrap_or("").as_bytes());
        }
        s.push(b'\n');
    }
    s
}

impl Exporter for SemanticLabels {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let doc = Document {
            format: "subtgraph-semantic-labels/1",
            seed: world.resolved.seed,
            frame: FRAME,
            units: "metres; rotation in quarter turns counter-clockwise seen from above",
            tile_pitch_m: world.resolved.tile_pitch,
            level_height_m: world.resolved.level_height,
            kinds: {
                let k = subtgraph_core::tile::TileKind::ALL.map(|k| k.name());
                [k[0], k[1], k[2], k[3], k[4], k[5], k[6], "ramp"]
            },
            tiles: labels(world, survey),
        };
        let hazards = survey.patches().is_some();
        write_file(
            out,
            "ground_truth/semantic_labels.csv",
            &csv(&doc.tiles, hazards),
        )?;
        crate::write_json(out, "ground_truth/semantic_labels.json", &doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn one_label_per_occupied_cell_in_both_files() {
        let world = crate::test_world();
        let mut out = MemoryWriter::default();
        SemanticLabels
            .export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let doc: serde_json::Value =
            serde_json::from_slice(out.get("ground_truth/semantic_labels.json").unwrap()).unwrap();
        let tiles = doc["tiles"].as_array().unwrap();
        assert_eq!(tiles.len(), world.occupancy.occupied_count());
        let csv = String::from_utf8(
            out.get("ground_truth/semantic_labels.csv")
                .unwrap()
                .to_vec(),
        )
        .unwrap();
        assert_eq!(csv.lines().count(), tiles.len() + 1);
        for (line, t) in csv.lines().skip(1).zip(tiles) {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!(f[3], t["kind"].as_str().unwrap());
            assert_eq!(
                f[6].split(' ').count(),
                t["openings"].as_array().unwrap().len()
            );
        }
    }
}
