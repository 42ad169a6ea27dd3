//! What the scorer reads from a world folder: `topology.json` (cells, graph, levels),
//! `ground_truth/artifacts.json` and, for maps, `ground_truth/free_space.npy` + `.json`. Only
//! files: the world is not regenerated, so scoring takes what the world folder says.

use std::path::Path;

use subtgraph_schema::{Artifacts, Document, FreeSpace, Topology};

use crate::Error;

use super::bits::Bits;
use super::cloud::Grid;
use super::reports::Truth;

/// A graph region a voxel belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// A node's tile.
    Node(usize),
    /// An edge's corridor tiles between its nodes.
    Edge(usize),
}

/// An edge as the outputs describe it.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeInfo {
    /// Its id.
    pub id: usize,
    /// `corridor` or `shaft`.
    pub kind: String,
    /// End nodes.
    pub from: usize,
    /// End nodes.
    pub to: usize,
    /// Its level (of its first cell).
    pub level: usize,
    /// Length, metres.
    pub length_m: f64,
    /// Its cells, `[level, row, col]`.
    pub cells: Vec<[usize; 3]>,
}

/// The world's cells and which graph region each belongs to.
pub struct Cells {
    /// Levels.
    pub levels: usize,
    /// Rows per level.
    pub rows: usize,
    /// Columns per level.
    pub cols: usize,
    /// Metres between tile centres.
    pub pitch: f64,
    /// Metres between levels.
    pub level_height: f64,
    /// Per level, the `[row, col]` offset placing it in the world frame.
    pub offsets: Vec<[i64; 2]>,
    /// Region of each cell, level-major; `u32::MAX` for rock.
    region: Vec<u32>,
    /// Nodes in the graph.
    pub node_count: usize,
    /// Edges in the graph.
    pub edge_count: usize,
    /// The edges.
    pub edges: Vec<EdgeInfo>,
    /// Each node's cell `[level, row, col]`.
    pub node_cells: Vec<[usize; 3]>,
}

impl Cells {
    fn index(&self, level: usize, row: usize, col: usize) -> usize {
        (level * self.rows + row) * self.cols + col
    }

    /// The cell of `level` holding `(x, y)`, if inside the grid.
    pub fn cell_at(&self, level: usize, x: f64, y: f64) -> Option<[usize; 2]> {
        let off = self.offsets[level];
        let col = (x / self.pitch + 0.5).floor() as i64 - off[1];
        let row = self.rows as i64 - 1 - (y / self.pitch + 0.5).floor() as i64 - off[0];
        (col >= 0 && row >= 0 && (row as usize) < self.rows && (col as usize) < self.cols)
            .then_some([row as usize, col as usize])
    }

    /// Whether `[level, row, col]` is a passage.
    pub fn occupied(&self, c: [usize; 3]) -> bool {
        self.region[self.index(c[0], c[1], c[2])] != u32::MAX
    }

    /// The centre of a cell on its nominal floor.
    pub fn centre(&self, c: [usize; 3]) -> [f64; 3] {
        let off = self.offsets[c[0]];
        [
            (c[2] as f64 + off[1] as f64) * self.pitch,
            (self.rows as f64 - 1.0 - c[1] as f64 - off[0] as f64) * self.pitch,
            c[0] as f64 * self.level_height,
        ]
    }

    /// The level and graph region of a point of free space: the level whose floor is below it
    /// (by a quarter of the level height), or the one under it when that level has rock there
    /// (a shaft rising from it).
    pub fn region(&self, x: f64, y: f64, z: f64) -> Option<(usize, Region)> {
        let guess = ((z / self.level_height) + 0.25).floor().max(0.0) as usize;
        let top = guess.min(self.levels - 1);
        for level in (top.saturating_sub(1)..=top).rev() {
            if let Some([row, col]) = self.cell_at(level, x, y) {
                let r = self.region[self.index(level, row, col)];
                if r != u32::MAX {
                    let r = r as usize;
                    return Some((
                        level,
                        if r < self.node_count {
                            Region::Node(r)
                        } else {
                            Region::Edge(r - self.node_count)
                        },
                    ));
                }
            }
        }
        None
    }

    /// The world's box in the plane, `[x0, y0, x1, y1]`, whole cells of every level.
    pub fn extent(&self) -> [f64; 4] {
        let p = self.pitch;
        let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for off in &self.offsets {
            let (r, c) = (off[0] as f64, off[1] as f64);
            b[0] = b[0].min((c - 0.5) * p);
            b[2] = b[2].max((c + self.cols as f64 - 0.5) * p);
            b[1] = b[1].min((-r - 0.5) * p);
            b[3] = b[3].max((self.rows as f64 - r - 0.5) * p);
        }
        b
    }
}

/// Reads a file of a world folder; `hint` says what to do when it is missing.
fn read_file(world: &Path, file: &str, hint: &str) -> Result<Vec<u8>, Error> {
    let path = world.join(file);
    if !path.exists() {
        return Err(Error::Input(format!(
            "{} has no {file}: {hint}",
            world.display()
        )));
    }
    crate::input::read(&path)
}

/// Reads and checks a document of a world folder; `hint` says what to do when it is missing.
pub(crate) fn read_doc<D: Document>(world: &Path, hint: &str) -> Result<D, Error> {
    parse_doc(&read_file(world, D::PATH, hint)?, world)
}

/// Parses and checks a document of the world folder `world`.
pub fn parse_doc<D: Document>(bytes: &[u8], world: &Path) -> Result<D, Error> {
    subtgraph_schema::read(bytes).map_err(|source| Error::WorldFile {
        world: world.to_owned(),
        source,
    })
}

/// Reads `topology.json`, checked against the grid `occupancy.npy` has.
pub fn cells(world: &Path) -> Result<Cells, Error> {
    let hint = "is it a world folder written by `subtgraph generate`?";
    let t: Topology = read_doc(world, hint)?;
    let occupancy = read_file(world, "occupancy.npy", hint)?;
    let shape = subtgraph_core::npy::shape(&occupancy).map_err(|source| Error::Npy {
        file: world.join("occupancy.npy").display().to_string(),
        source,
    })?;
    cells_of(t, &shape, world)
}

/// The cells of a world from its `topology.json`, whose grid must be the `[levels, rows,
/// cols]` of its `occupancy.npy` (so the grid allocated here is one the world folder holds, not
/// a number written into a text file).
pub fn cells_of(t: Topology, occupancy: &[usize], world: &Path) -> Result<Cells, Error> {
    if occupancy != [t.levels, t.rows, t.cols] {
        return Err(Error::WorldFile {
            world: world.to_owned(),
            source: subtgraph_schema::SchemaError::invalid::<Topology>(format!(
                "its grid is {} level(s) of {} x {} cells, but occupancy.npy has shape {occupancy:?}",
                t.levels, t.rows, t.cols
            )),
        });
    }
    let mut offsets = vec![[0i64, 0i64]; t.levels];
    for (level, offset) in offsets.iter_mut().enumerate() {
        if let Some(n) = t.nodes.iter().find(|n| n.cell.level == level) {
            let col = (n.position[0] / t.tile_pitch_m).round() as i64;
            let row = t.rows as i64 - 1 - (n.position[1] / t.tile_pitch_m).round() as i64;
            *offset = [row - n.cell.row as i64, col - n.cell.col as i64];
        }
    }
    let mut region = vec![u32::MAX; t.levels * t.rows * t.cols];
    let idx = |c: &subtgraph_core::grid::Cell| (c.level * t.rows + c.row) * t.cols + c.col;
    for e in t.edges.iter() {
        for c in &e.cells {
            region[idx(c)] = (t.nodes.len() + e.id) as u32;
        }
    }
    for n in t.nodes.iter() {
        region[idx(&n.cell)] = n.id as u32;
    }
    let edges = t
        .edges
        .iter()
        .map(|e| EdgeInfo {
            id: e.id,
            kind: edge_kind(e.kind).to_owned(),
            from: e.from,
            to: e.to,
            level: e.cells.first().map_or(0, |c| c.level),
            length_m: e.length_m,
            cells: e.cells.iter().map(|c| [c.level, c.row, c.col]).collect(),
        })
        .collect();
    Ok(Cells {
        levels: t.levels,
        rows: t.rows,
        cols: t.cols,
        pitch: t.tile_pitch_m,
        level_height: t.level_height_m,
        offsets,
        region,
        node_count: t.nodes.len(),
        edge_count: t.edges.len(),
        edges,
        node_cells: t
            .nodes
            .iter()
            .map(|n| [n.cell.level, n.cell.row, n.cell.col])
            .collect(),
    })
}

fn edge_kind(k: subtgraph_core::graph::EdgeKind) -> &'static str {
    use subtgraph_core::graph::EdgeKind;
    match k {
        EdgeKind::Corridor => "corridor",
        EdgeKind::Shaft => "shaft",
        EdgeKind::Ramp => "ramp",
    }
}

/// A graph node as the segmentation score matches it.
#[derive(Clone, Debug, PartialEq)]
pub struct GraphNode {
    /// Its id.
    pub id: usize,
    /// Its level.
    pub level: usize,
    /// Its tile kind (`t-junction`, `dead-end`, ...).
    pub kind: &'static str,
    /// Its world position in the plane, metres.
    pub xy: [f64; 2],
}

/// The graph's nodes from `topology.json`.
pub fn nodes(world: &Path) -> Result<Vec<GraphNode>, Error> {
    let t: Topology = read_doc(
        world,
        "is it a world folder written by `subtgraph generate`?",
    )?;
    Ok(t.nodes
        .iter()
        .map(|n| GraphNode {
            id: n.id,
            level: n.cell.level,
            kind: n.kind.name(),
            xy: [n.position[0], n.position[1]],
        })
        .collect())
}

/// Reads `ground_truth/artifacts.json`.
pub fn artifacts(world: &Path) -> Result<Vec<Truth>, Error> {
    let doc: Artifacts = read_doc(
        world,
        "the world was made without [artifacts]; add an [artifacts] section to its pipeline and generate it again",
    )?;
    Ok(truth_of(doc))
}

/// The ground-truth artifacts of an `artifacts.json`.
pub fn truth_of(doc: Artifacts) -> Vec<Truth> {
    doc.artifacts
        .into_iter()
        .map(|a| Truth {
            id: a.id,
            class: a.class,
            name: a.name.into_owned(),
            position: a.position,
            level: a.cell.level,
        })
        .collect()
}

/// Reads `ground_truth/free_space.npy` and its `.json`: the grid and its free voxels.
pub fn free_space(world: &Path) -> Result<(Grid, Bits), Error> {
    let hint = "scoring a map needs the world's free space: make it again with `subtgraph generate PIPELINE --format free-space` (or ground-truth), PIPELINE being its world.toml";
    let doc: FreeSpace = read_doc(world, hint)?;
    let file = "ground_truth/free_space.npy";
    let bytes = read_file(world, file, hint)?;
    free_space_of(&doc, &bytes, &world.join(file))
}

/// The grid `free_space.json` describes and the free voxels of its `free_space.npy` (`bytes`):
/// an array of `uint8` of its `packed_shape`, read from just after the header.
pub fn free_space_of(doc: &FreeSpace, bytes: &[u8], path: &Path) -> Result<(Grid, Bits), Error> {
    let info = subtgraph_core::npy::info(bytes).map_err(|source| Error::Npy {
        file: path.display().to_string(),
        source,
    })?;
    if info.shape != doc.packed_shape || info.size != 1 || !matches!(info.kind, b'u' | b'b') {
        return Err(Error::Input(format!(
            "{}: an array of shape {:?} and {}-byte values, but free_space.json says uint8 of shape {:?}; was it edited? make the world again with `subtgraph generate`",
            path.display(),
            info.shape,
            info.size,
            doc.packed_shape
        )));
    }
    let [nz, ny, nx] = doc.shape;
    let grid = Grid {
        origin: doc.origin,
        voxel: doc.voxel_m,
        n: [nx, ny, nz],
    };
    let data = &bytes[info.data_start..info.data_start + info.count];
    let free = Bits::from_packed(grid.n, data);
    Ok((grid, free))
}
