//! Parts: a large world cut into pieces a simulator can load one at a time (Gazebo levels,
//! MuJoCo includes, USD layers), per level by default or in square regions of tiles.
//!
//! A part is a list of tiles and their triangle ranges in the world meshes; its meshes are cut
//! out on demand ([`Part::visual`], [`Part::collision`]), one part at a time, so an exporter
//! never holds a second copy of the whole world. The per-part OBJ files that SDF, URDF and MJCF
//! all reference are written once per world folder by [`write_part_meshes`].
//!
//! ```toml
//! [[export]]
//! type = "sdf"
//! split = "region"     # "level" (default), "region" or "whole"
//! region_tiles = 8     # tiles per side of a region, for split = "region"
//! ```

use std::ops::Range;

use subtgraph_core::World;
use subtgraph_core::assembly::WorldMesh;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, WorldWriter, stream_file, write_file};
use subtgraph_core::mesh::Mesh;
use subtgraph_core::params::Params;

use crate::text::{mtl, write_obj};

/// How a world is cut into parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// One part: the whole world.
    Whole,
    /// One part per level (shafts belong to the level they rise from).
    Level,
    /// Square regions of `tiles` x `tiles` cells on each level.
    Region {
        /// Cells per side.
        tiles: usize,
    },
}

impl Split {
    /// The keys [`Split::from_params`] reads, for exporters that list their known keys.
    pub const KEYS: [&'static str; 2] = ["split", "region_tiles"];

    /// Reads `split` and `region_tiles` from an exporter's table (other keys are the
    /// exporter's to check). Default: per level.
    pub fn from_params(params: &Params) -> Result<Split, ConfigError> {
        let tiles = match params.raw("region_tiles") {
            None => 8,
            Some(toml::Value::Integer(n)) if (1..=4096).contains(n) => *n as usize,
            Some(_) => {
                return Err(params.error(
                    "region_tiles",
                    "region_tiles must be a whole number of tiles from 1 to 4096, like 8",
                ));
            }
        };
        match params.raw("split") {
            None => Ok(Split::Level),
            Some(toml::Value::String(s)) => match s.as_str() {
                "level" => Ok(Split::Level),
                "whole" => Ok(Split::Whole),
                "region" => Ok(Split::Region { tiles }),
                other => Err(params.error(
                    "split",
                    format!(
                        "unknown split '{other}'; use \"level\" (a part per level), \"region\" (squares of region_tiles tiles) or \"whole\" (one part)"
                    ),
                )),
            },
            Some(_) => Err(params.error(
                "split",
                "split must be a string: \"level\", \"region\" or \"whole\"",
            )),
        }
    }

    /// A short stable name for file names: `level`, `region-8`, `whole`.
    pub fn label(self) -> String {
        match self {
            Split::Whole => "whole".into(),
            Split::Level => "level".into(),
            Split::Region { tiles } => format!("region-{tiles}"),
        }
    }
}

/// A piece of a world.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Name used in files and simulator entities: `world`, `level-0`, `level-0-r1-c2`.
    pub name: String,
    /// The level, when the part lies on one.
    pub level: Option<usize>,
    /// Indices into [`WorldMesh::tiles`].
    pub tiles: Vec<usize>,
    /// Its triangles in [`WorldMesh::visual`], as ranges (consecutive tiles merged).
    pub visual_ranges: Vec<Range<usize>>,
    /// Its triangles in [`WorldMesh::collision`].
    pub collision_ranges: Vec<Range<usize>>,
}

impl Part {
    /// The part's visual mesh, cut out of the world's.
    pub fn visual(&self, mesh: &WorldMesh) -> Mesh {
        mesh.visual.extract(&self.visual_ranges)
    }

    /// The part's collision mesh, cut out of the world's.
    pub fn collision(&self, mesh: &WorldMesh) -> Mesh {
        mesh.collision.extract(&self.collision_ranges)
    }

    /// Visual triangles in the part.
    pub fn visual_triangles(&self) -> usize {
        self.visual_ranges.iter().map(|r| r.len()).sum()
    }
}

pub(crate) fn push_range(ranges: &mut Vec<Range<usize>>, r: Range<usize>) {
    if r.is_empty() {
        return;
    }
    match ranges.last_mut() {
        Some(last) if last.end == r.start => last.end = r.end,
        _ => ranges.push(r),
    }
}

/// Cuts a world's mesh into parts. Parts with no triangles are left out; the order is stable
/// (level, then region row, then region column).
pub fn parts(world: &World, mesh: &WorldMesh, split: Split) -> Vec<Part> {
    let levels = world.occupancy.levels();
    let (rows, cols) = (world.occupancy.rows(), world.occupancy.cols());
    let (per_row, per_col, size) = match split {
        Split::Region { tiles } => (rows.div_ceil(tiles), cols.div_ceil(tiles), tiles),
        _ => (1, 1, rows.max(cols).max(1)),
    };
    let key = |t: &subtgraph_core::assembly::PlacedTile| match split {
        Split::Whole => 0,
        _ => (t.cell.level * per_row + t.cell.row / size) * per_col + t.cell.col / size,
    };
    let slots = match split {
        Split::Whole => 1,
        _ => levels * per_row * per_col,
    };
    let mut out: Vec<Option<Part>> = vec![None; slots];
    for (i, t) in mesh.tiles.iter().enumerate() {
        let k = key(t);
        let part = out[k].get_or_insert_with(|| {
            let (level, name) = match split {
                Split::Whole => (None, "world".to_owned()),
                Split::Level => (Some(t.cell.level), format!("level-{}", t.cell.level)),
                Split::Region { .. } => (
                    Some(t.cell.level),
                    format!(
                        "level-{}-r{}-c{}",
                        t.cell.level,
                        t.cell.row / size,
                        t.cell.col / size
                    ),
                ),
            };
            Part {
                name,
                level,
                tiles: Vec::new(),
                visual_ranges: Vec::new(),
                collision_ranges: Vec::new(),
            }
        });
        part.tiles.push(i);
        push_range(&mut part.visual_ranges, t.visual_triangles.clone());
        push_range(&mut part.collision_ranges, t.collision_triangles.clone());
    }
    out.into_iter()
        .flatten()
        .filter(|p| p.visual_triangles() > 0 || !p.collision_ranges.is_empty())
        .collect()
}

/// Where a part's shared meshes are, relative to the world folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartFiles {
    /// The part's name.
    pub name: String,
    /// Visual OBJ (with `mesh/parts/materials.mtl`).
    pub visual: String,
    /// Collision OBJ.
    pub collision: String,
}

/// The folder the shared per-part meshes go to.
pub const PARTS_DIR: &str = "mesh/parts";

/// The shared meshes' paths for a part (whether or not written yet).
pub fn part_files(split: Split, part: &Part) -> PartFiles {
    let dir = format!("{PARTS_DIR}/{}", split.label());
    PartFiles {
        name: part.name.clone(),
        visual: format!("{dir}/{}.obj", part.name),
        collision: format!("{dir}/{}-collision.obj", part.name),
    }
}

/// Writes each part's visual and collision OBJ (one object per file: MuJoCo reads only the
/// first object of an OBJ) under `mesh/parts/<split>/`, unless an earlier exporter of the same
/// world folder already did, and returns their paths.
pub fn write_part_meshes(
    out: &mut dyn WorldWriter,
    mesh: &WorldMesh,
    split: Split,
    parts: &[Part],
) -> Result<Vec<PartFiles>, ExportError> {
    let mtl_path = format!("{PARTS_DIR}/{}/materials.mtl", split.label());
    if !out.contains(&mtl_path) {
        write_file(out, &mtl_path, mtl(&mesh.materials, "../../").as_bytes())?;
        crate::text::write_textures(out, mesh)?;
    }
    let mut files = Vec::with_capacity(parts.len());
    for part in parts {
        let f = part_files(split, part);
        if !out.contains(&f.visual) {
            let m = part.visual(mesh);
            stream_file(out, &f.visual, |w| {
                write_obj(w, &m, &part.name, Some((&mesh.materials, "materials.mtl")))
            })?;
        }
        if !out.contains(&f.collision) {
            let m = part.collision(mesh);
            stream_file(out, &f.collision, |w| {
                write_obj(w, &m, &format!("{}-collision", part.name), None)
            })?;
        }
        files.push(f);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_world_with_mesh;

    #[test]
    fn parts_cover_every_tile_and_triangle_once() {
        let world = test_world_with_mesh();
        let mesh = world.mesh().unwrap();
        for split in [Split::Whole, Split::Level, Split::Region { tiles: 5 }] {
            let ps = parts(&world, mesh, split);
            let tiles: usize = ps.iter().map(|p| p.tiles.len()).sum();
            assert_eq!(tiles, mesh.tiles.len(), "{split:?}");
            let vis: usize = ps.iter().map(Part::visual_triangles).sum();
            assert_eq!(vis, mesh.visual.triangle_count(), "{split:?}");
            let col: usize = ps
                .iter()
                .map(|p| p.collision_ranges.iter().map(|r| r.len()).sum::<usize>())
                .sum();
            assert_eq!(col, mesh.collision.triangle_count(), "{split:?}");
            for p in &ps {
                for &t in &p.tiles {
                    if let Some(l) = p.level {
                        assert_eq!(mesh.tiles[t].cell.level, l);
                    }
                }
            }
        }
        let levels = parts(&world, mesh, Split::Level);
        assert_eq!(levels.len(), world.occupancy.levels());
        assert!(parts(&world, mesh, Split::Region { tiles: 5 }).len() > levels.len());
    }

    #[test]
    fn a_cut_part_keeps_its_triangles_and_only_its_vertices() {
        let world = test_world_with_mesh();
        let mesh = world.mesh().unwrap();
        let p = &parts(&world, mesh, Split::Level)[1];
        let m = p.visual(mesh);
        assert_eq!(m.triangle_count(), p.visual_triangles());
        let used: std::collections::HashSet<u32> = m.triangles.iter().flatten().copied().collect();
        assert_eq!(used.len(), m.positions.len(), "no unused vertices");
        assert_eq!(m.normals.len(), m.positions.len());
        let first = p.visual_ranges[0].start;
        let orig = mesh.visual.triangles[first].map(|v| mesh.visual.positions[v as usize]);
        let cut = m.triangles[0].map(|v| m.positions[v as usize]);
        assert_eq!(orig, cut);
    }

    #[test]
    fn bad_split_settings_say_what_to_write() {
        let table = |s: &str| Params::from_table("export[0]", toml::from_str(s).unwrap());
        assert_eq!(
            Split::from_params(&table("split = \"region\"\nregion_tiles = 4")).unwrap(),
            Split::Region { tiles: 4 }
        );
        let e = Split::from_params(&table("split = \"levels\"")).unwrap_err();
        assert!(e.to_string().contains("\"level\""), "{e}");
        let e = Split::from_params(&table("region_tiles = 0")).unwrap_err();
        assert!(e.to_string().contains("1 to 4096"), "{e}");
    }
}
