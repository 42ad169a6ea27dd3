//! `tasks`: path-planning benchmarks in the MovingAI formats, so single-agent planners and
//! multi-agent (MAPF) solvers from that community run on a world unchanged:
//!
//! | file | what |
//! |---|---|
//! | `tasks/level-N.map` | the level's free space as an octile map: `.` free, `@` rock |
//! | `tasks/level-N.scen` | `problems` start/goal pairs with optimal lengths, by bucket |
//! | `tasks/level-N-random-K.scen` | MAPF instance K: `agents` agents, distinct starts, distinct goals |
//! | `tasks/tasks.json` | resolution, origin (cell to world metres), seed, counts per level |
//!
//! The map is the ROS map's slice (`ground_truth/maps/`, [`RosMap`]) on a grid of its own,
//! coarser by default: a cell is free where the slice 1 m above the floor is inside a passage
//! at the cell's centre, where a ground robot stands; unknown cells (an open surface) are rock.
//! `resolution` defaults to 1 m, doubled until a level has at most 4 million cells (MovingAI's
//! maps are up to about 1,000 cells across); a given one above 16 million cells is refused.
//!
//! Optimal lengths are MovingAI's: eight moves, √2 for a diagonal, no corner cutting, found
//! by A*; `.scen` files print them with 8 decimals. Every start and goal lies in one connected
//! group of free cells. Problems are drawn uniformly (start over the free cells that have
//! somewhere to go, goal over the rest of the start's group), from the world seed's streams
//! `tasks` (single-agent, index = level) and `tasks level N agents` (index = K), so the files
//! are the same for the same world.
//!
//! Not part of `ground-truth`: the other ground-truth files describe the world, these are
//! sampled problems with their own knobs and costs (an A* per problem), asked for by name.

use subtgraph_core::World;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::params::Params;
use subtgraph_core::rng::WorldRng;
use subtgraph_core::survey::Survey;
use subtgraph_schema::{Document as _, TaskLevel, Tasks as Document};

use crate::ground_truth::ros_map::{FREE, grid};
use crate::ground_truth::{FRAME, RosMap};

mod draw;
mod octile;

use draw::{Places, Problem};
use octile::Octile;

/// Default metres per cell.
const DEFAULT_RESOLUTION: f64 = 1.0;
/// The most cells a level's map has at the default resolution.
const DEFAULT_CELLS: f64 = 4e6;
/// The most cells a level's map may have at all.
const MAX_CELLS: f64 = 16e6;
/// Metres above the floor where the free space is sliced: the ROS map's default.
const SLICE: f64 = 1.0;

/// Writes `tasks/`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tasks {
    /// Metres per cell; `None` picks one from the world's size.
    pub resolution: Option<f64>,
    /// Single-agent problems per level.
    pub problems: u32,
    /// Agents per multi-agent instance.
    pub agents: u32,
    /// Multi-agent instances per level.
    pub instances: u32,
}

impl Default for Tasks {
    fn default() -> Self {
        Self {
            resolution: None,
            problems: 100,
            agents: 32,
            instances: 5,
        }
    }
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    resolution: Option<f64>,
    problems: Option<u32>,
    agents: Option<u32>,
    instances: Option<u32>,
}

impl Tasks {
    /// The keys it takes.
    pub const KEYS: [&str; 4] = ["resolution", "problems", "agents", "instances"];

    /// From an `[[export]] type = "tasks"` table.
    pub fn from_params(params: &Params) -> Result<Tasks, ConfigError> {
        params.expect_known(&Self::KEYS)?;
        let k: Keys = params.deserialize()?;
        if k.resolution.is_some_and(|r| !(r.is_finite() && r > 0.0)) {
            return Err(params.error(
                "resolution",
                "must be a positive number of metres per cell, e.g. resolution = 1.0",
            ));
        }
        let limits = [
            ("problems", k.problems, 100_000, "problems = 100"),
            ("agents", k.agents, 10_000, "agents = 32"),
            ("instances", k.instances, 100, "instances = 5"),
        ];
        for (key, v, most, example) in limits {
            if v.is_some_and(|v| v > most) {
                return Err(params.error(key, format!("must be from 0 to {most}, e.g. {example}")));
            }
        }
        let d = Tasks::default();
        Ok(Tasks {
            resolution: k.resolution,
            problems: k.problems.unwrap_or(d.problems),
            agents: k.agents.unwrap_or(d.agents),
            instances: k.instances.unwrap_or(d.instances),
        })
    }
}

/// A `.scen` file: `version 1`, then a tab-separated row per problem.
fn scen(name: &str, map: &Octile, problems: &[Problem]) -> Vec<u8> {
    let mut text = String::from("version 1\n");
    for p in problems {
        let ((sx, sy), (gx, gy)) = (map.xy(p.start), map.xy(p.goal));
        text.push_str(&format!(
            "{}\t{name}\t{}\t{}\t{sx}\t{sy}\t{gx}\t{gy}\t{:.8}\n",
            p.bucket(),
            map.width,
            map.height,
            p.length
        ));
    }
    text.into_bytes()
}

/// A `.map` file.
fn map_file(map: &Octile) -> Vec<u8> {
    let mut out = format!(
        "type octile\nheight {}\nwidth {}\nmap\n",
        map.height, map.width
    )
    .into_bytes();
    out.reserve((map.width + 1) * map.height);
    for row in map.free.chunks(map.width) {
        out.extend(row.iter().map(|&f| if f { b'.' } else { b'@' }));
        out.push(b'\n');
    }
    out
}

impl Exporter for Tasks {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let px = grid(
            world,
            self.resolution,
            DEFAULT_RESOLUTION,
            DEFAULT_CELLS,
            MAX_CELLS,
            "tasks",
        )?;
        let slicer = RosMap {
            resolution: Some(px.step),
            height: SLICE,
        };
        let raster = slicer.slices(world, survey, &px);
        let seed = world.resolved.seed;
        let mut levels = Vec::new();
        for level in 0..world.occupancy.levels() {
            // Raster rows run south to north; a map's row 0 is north.
            let free = raster
                .rows
                .iter()
                .rev()
                .flat_map(|rows| rows[level].iter().map(|&v| v == FREE))
                .collect();
            let map = Octile {
                width: px.nx,
                height: px.ny,
                free,
            };
            let groups = map.groups();
            let places = Places::new(&map, &groups);
            let name = format!("level-{level}");
            write_file(out, &format!("tasks/{name}.map"), &map_file(&map))?;
            let map_name = format!("{name}.map");
            let mut rng = WorldRng::new(seed, "tasks", level as u64);
            let problems = places.problems(&mut rng, self.problems);
            write_file(
                out,
                &format!("tasks/{name}.scen"),
                &scen(&map_name, &map, &problems),
            )?;
            let mut instances = Vec::new();
            let mut agents = self.agents;
            for k in 1..=self.instances {
                let label = format!("tasks level {level} agents");
                let mut rng = WorldRng::new(seed, &label, u64::from(k));
                let instance = places.instance(&mut rng, self.agents);
                agents = agents.min(instance.len() as u32);
                let file = format!("{name}-random-{k}.scen");
                write_file(
                    out,
                    &format!("tasks/{file}"),
                    &scen(&map_name, &map, &instance),
                )?;
                instances.push(file);
            }
            levels.push(TaskLevel {
                level,
                map: map_name,
                scen: format!("{name}.scen"),
                instances,
                width: map.width,
                height: map.height,
                z_m: level as f64 * world.resolved.level_height + SLICE,
                free_cells: map.free.iter().filter(|&&f| f).count() as u64,
                components: groups.cells.len() as u64,
                largest_component: groups.cells.iter().map(Vec::len).max().unwrap_or(0) as u64,
                problems: problems.len() as u32,
                agents: if self.instances == 0 { 0 } else { agents },
            });
        }
        let doc = Document {
            format: Document::FORMAT,
            seed,
            frame: FRAME,
            source: survey.source().name(),
            resolution_m: px.step,
            origin: [px.x0, px.y0],
            cell_centre: "cell (x, y) of a .map (x the column from the west, y the row from the north, both from 0) has its centre at world x = origin[0] + (x + 0.5) * resolution_m, y = origin[1] + (height - y - 0.5) * resolution_m, on its level's floor; z_m is the slice's height",
            slice_height_m: SLICE,
            movement: "octile: 8 moves, 1 straight, sqrt(2) diagonal; no corner cutting (a diagonal move needs both cells beside it free); lengths in cells (times resolution_m for metres)",
            sampling: "start uniform over free cells whose connected group has 2 or more cells, goal uniform over the rest of that group; .scen rows sorted by bucket = floor(length / 4); MAPF instances draw distinct starts and distinct goals, agents in draw order",
            problems_requested: self.problems,
            agents_requested: self.agents,
            instances: self.instances,
            levels,
        };
        crate::write_json(out, Document::PATH, &doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    fn export(world: &World, tasks: Tasks) -> MemoryWriter {
        let mut out = MemoryWriter::default();
        tasks
            .export(world, &crate::survey_of(world), &mut out)
            .unwrap();
        out
    }

    #[test]
    fn map_cells_are_free_exactly_over_the_grids_passages_and_seeds_repeat() {
        let world = crate::test_world();
        let tasks = Tasks {
            resolution: Some(2.0),
            ..Tasks::default()
        };
        let out = export(&world, tasks);
        let text = String::from_utf8(out.get("tasks/level-1.map").unwrap().to_vec()).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("type octile"));
        let h: usize = lines.next().unwrap()[7..].parse().unwrap();
        let w: usize = lines.next().unwrap()[6..].parse().unwrap();
        assert_eq!(lines.next(), Some("map"));
        // Read back through the schema, as a reader would.
        let doc: Document = subtgraph_schema::read(out.get("tasks/tasks.json").unwrap()).unwrap();
        assert_eq!((doc.levels[1].width, doc.levels[1].height), (w, h));
        assert_eq!(doc.levels[1].problems, 100);
        let origin = doc.origin;
        for (y, row) in lines.enumerate() {
            assert_eq!(row.len(), w);
            for (x, ch) in row.bytes().enumerate() {
                let cx = origin[0] + (x as f64 + 0.5) * 2.0;
                let cy = origin[1] + ((h - y) as f64 - 0.5) * 2.0;
                let cell = world.cell_at(1, cx, cy).unwrap();
                assert_eq!(ch == b'.', *world.occupancy.get(cell), "cell ({x}, {y})");
            }
        }
        let scen = String::from_utf8(out.get("tasks/level-1.scen").unwrap().to_vec()).unwrap();
        assert!(scen.starts_with("version 1\n"));
        assert_eq!(scen.lines().count(), 101);
        let again = export(&world, tasks);
        assert_eq!(out.files.len(), 2 * (2 + 5) + 1);
        for (path, bytes) in &out.files {
            assert_eq!(again.get(path), Some(bytes.as_slice()), "{path}");
        }
    }

    #[test]
    fn too_fine_a_resolution_is_refused_naming_it() {
        let world = crate::test_world();
        let tasks = Tasks {
            resolution: Some(0.001),
            ..Tasks::default()
        };
        let e = tasks
            .export(
                &world,
                &crate::survey_of(&world),
                &mut MemoryWriter::default(),
            )
            .unwrap_err();
        assert!(e.to_string().contains("resolution = 0.001"), "{e}");
    }
}
