//! The dataset index, `index.json` and `index.csv`: one row per world folder, rebuilt from the
//! folders themselves (never appended to), written to a temporary file and renamed into place,
//! so an interrupted or concurrent run never leaves a corrupt or half-written index.
//!
//! Everything in a row comes from the world folder (`topology.json`, `occupancy.npy`,
//! `world.toml`) except what differs between runs or is costly to recount: generation time
//! and triangle counts, which the run that made the world keeps in `.index/NAME.json`.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use subtgraph_core::tile::TileKind;
use subtgraph_schema::Topology;

use crate::Error;
use crate::folder::write_file_atomically;

/// What the run that made a world measured, kept outside the world folder.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunFacts {
    /// Seconds to generate the world (layout and mesh), before writing.
    pub generation_s: f64,
    /// Seconds including writing the folder.
    pub total_s: f64,
    /// Visual mesh triangles, when meshed.
    pub visual_triangles: Option<usize>,
    /// Collision mesh triangles, when meshed.
    pub collision_triangles: Option<usize>,
}

/// Folder of the run facts, inside the dataset folder.
pub const FACTS_DIR: &str = ".index";

/// Writes a world's run facts atomically.
pub fn write_facts(out: &Path, name: &str, facts: &RunFacts) -> std::io::Result<()> {
    let dir = out.join(FACTS_DIR);
    std::fs::create_dir_all(&dir)?;
    let text = serde_json::to_string_pretty(facts).expect("plain data serializes");
    write_file_atomically(&dir.join(format!("{name}.json")), text.as_bytes())
}

/// One world of the index.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Row {
    /// Folder name.
    pub name: String,
    /// The source's name (folder name without its index).
    pub source: String,
    /// Where the world's pipeline came from, as its `world.toml` records.
    pub origin: String,
    /// The world's seed.
    pub seed: u64,
    /// Levels.
    pub levels: usize,
    /// Rows per level.
    pub rows: usize,
    /// Columns per level.
    pub cols: usize,
    /// Occupied cells, all levels.
    pub occupied_cells: usize,
    /// Tiles per kind (`dead-end`, `straight`, ...), all levels.
    pub tiles: BTreeMap<String, usize>,
    /// Per structure (`t-junction`, `intersection`, `loop`): requested, summed over levels.
    pub requested: BTreeMap<String, u64>,
    /// Per structure: what the structures bring (a loop's arms add T-junctions), summed.
    pub expected: BTreeMap<String, u64>,
    /// Per structure: counted on the final grid, summed over levels.
    pub achieved: BTreeMap<String, u64>,
    /// Total passage length in metres (corridors and shafts).
    pub total_length_m: f64,
    /// Visual triangles, when meshed.
    pub visual_triangles: Option<usize>,
    /// Collision triangles, when meshed.
    pub collision_triangles: Option<usize>,
    /// Seconds to generate (not a property of the world: differs between runs).
    pub generation_s: Option<f64>,
    /// Seconds including writing the folder.
    pub total_s: Option<f64>,
}

const STRUCTURES: [(&str, &str); 3] = [
    ("t-junction", "t_junctions"),
    ("intersection", "intersections"),
    ("loop", "loops"),
];

/// Reads a world folder's row; an error says what is missing or broken.
pub fn row(out: &Path, name: &str) -> Result<Row, Error> {
    let dir = out.join(name);
    let read = |file: &str| {
        std::fs::read(dir.join(file))
            .map_err(Error::io(format!("reading {}/{file}", dir.display())))
    };
    let topo: Topology =
        subtgraph_schema::read(&read("topology.json")?).map_err(|source| Error::WorldFile {
            world: dir.clone(),
            source,
        })?;
    let world: toml::Table = toml::from_str(&String::from_utf8_lossy(&read("world.toml")?))
        .map_err(|e| Error::Input(format!("{}/world.toml is not TOML: {e}", dir.display())))?;
    let grid =
        subtgraph_core::npy::decode(&read("occupancy.npy")?).map_err(|source| Error::Npy {
            file: format!("{}/occupancy.npy", dir.display()),
            source,
        })?;
    let mut tiles: BTreeMap<String, usize> = TileKind::ALL
        .iter()
        .map(|k| (k.name().to_owned(), 0))
        .collect();
    for &v in &grid.values {
        if let Some(k) = TileKind::from_spatial_code(v as u8) {
            *tiles.entry(k.name().to_owned()).or_default() += 1;
        }
    }
    let (mut requested, mut expected, mut achieved) =
        (BTreeMap::new(), BTreeMap::new(), BTreeMap::new());
    for l in topo.per_level.iter() {
        for c in subtgraph_schema::structure_counts(l) {
            *requested.entry(c.structure.to_owned()).or_default() += c.requested;
            *expected.entry(c.structure.to_owned()).or_default() += c.expected.unwrap_or(0);
            *achieved.entry(c.structure.to_owned()).or_default() += c.achieved;
        }
    }
    let facts: Option<RunFacts> = std::fs::read(out.join(FACTS_DIR).join(format!("{name}.json")))
        .ok()
        .and_then(|b| serde_json::from_slice(&b).ok());
    let count_faces = |file: &str| -> Option<usize> {
        let f = std::fs::File::open(dir.join(file)).ok()?;
        let r = std::io::BufReader::new(f);
        Some(
            std::io::BufRead::lines(r)
                .map_while(Result::ok)
                .filter(|l| l.starts_with("f "))
                .count(),
        )
    };
    let (visual_triangles, collision_triangles) = match &facts {
        Some(f) => (f.visual_triangles, f.collision_triangles),
        None => (
            count_faces("mesh/world.obj"),
            count_faces("mesh/collision.obj"),
        ),
    };
    let source = name
        .rsplit_once('-')
        .filter(|(_, i)| i.chars().all(|c| c.is_ascii_digit()))
        .map_or(name, |(s, _)| s)
        .to_owned();
    Ok(Row {
        name: name.to_owned(),
        source,
        origin: world
            .get("generated")
            .and_then(|g| g.get("source"))
            .and_then(|s| s.as_str())
            .unwrap_or("")
            .to_owned(),
        seed: topo.seed,
        levels: topo.levels,
        rows: topo.rows,
        cols: topo.cols,
        occupied_cells: topo.occupied_cells,
        tiles,
        requested,
        expected,
        achieved,
        total_length_m: topo.total_length_m,
        visual_triangles,
        collision_triangles,
        generation_s: facts.as_ref().map(|f| f.generation_s),
        total_s: facts.as_ref().map(|f| f.total_s),
    })
}

/// Every complete world folder of a dataset folder (a visible folder with `world.toml`), by
/// name.
pub fn world_names(out: &Path) -> Result<Vec<String>, Error> {
    let mut names = Vec::new();
    let reading = || Error::io(format!("reading {}", out.display()));
    for entry in std::fs::read_dir(out).map_err(reading())? {
        let entry = entry.map_err(reading())?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if !name.starts_with('.') && entry.path().join("world.toml").is_file() {
            names.push(name);
        }
    }
    names.sort();
    Ok(names)
}

/// Rebuilds `index.json` and `index.csv` from the world folders; returns the number of rows.
pub fn rebuild(out: &Path) -> Result<usize, Error> {
    // The facts folder marks the folder as a dataset's, even when no world was made yet.
    std::fs::create_dir_all(out.join(FACTS_DIR))
        .map_err(Error::io(format!("creating {}/{FACTS_DIR}", out.display())))?;
    let mut rows = Vec::new();
    for name in world_names(out)? {
        match row(out, &name) {
            Ok(r) => rows.push(r),
            Err(e) => eprintln!(
                "warning: leaving {name} out of the index: {}",
                crate::message(&e)
            ),
        }
    }
    let mut json = serde_json::to_string_pretty(&rows).expect("plain data serializes");
    json.push('\n');
    write_file_atomically(&out.join("index.json"), json.as_bytes())
        .map_err(Error::io(format!("writing {}/index.json", out.display())))?;
    write_file_atomically(&out.join("index.csv"), csv(&rows).as_bytes())
        .map_err(Error::io(format!("writing {}/index.csv", out.display())))?;
    Ok(rows.len())
}

fn csv(rows: &[Row]) -> String {
    let kinds: Vec<&str> = TileKind::ALL.iter().map(|k| k.name()).collect();
    let mut header = vec![
        "name",
        "source",
        "seed",
        "levels",
        "rows",
        "cols",
        "occupied_cells",
    ]
    .into_iter()
    .map(String::from)
    .collect::<Vec<_>>();
    header.extend(kinds.iter().map(|k| format!("tiles_{k}")));
    for (s, _) in STRUCTURES {
        for what in ["requested", "expected", "achieved"] {
            header.push(format!("{s}_{what}"));
        }
    }
    header.extend(
        [
            "total_length_m",
            "visual_triangles",
            "collision_triangles",
            "generation_s",
            "total_s",
        ]
        .map(String::from),
    );
    let mut text = header.join(",");
    text.push('\n');
    let opt = |v: Option<String>| v.unwrap_or_default();
    for r in rows {
        let mut cells = vec![
            r.name.clone(),
            r.source.clone(),
            r.seed.to_string(),
            r.levels.to_string(),
            r.rows.to_string(),
            r.cols.to_string(),
            r.occupied_cells.to_string(),
        ];
        cells.extend(kinds.iter().map(|k| r.tiles[*k].to_string()));
        for (s, _) in STRUCTURES {
            cells.push(r.requested[s].to_string());
            cells.push(r.expected[s].to_string());
            cells.push(r.achieved[s].to_string());
        }
        cells.push(format!("{:.1}", r.total_length_m));
        cells.push(opt(r.visual_triangles.map(|v| v.to_string())));
        cells.push(opt(r.collision_triangles.map(|v| v.to_string())));
        cells.push(opt(r.generation_s.map(|v| format!("{v:.4}"))));
        cells.push(opt(r.total_s.map(|v| format!("{v:.4}"))));
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    text
}
