//! Assembly: one tile per occupied cell, made in parallel, concatenated in raster order and
//! welded into the world's visual and collision meshes.
//!
//! Every occupied cell is asked for exactly once, so grid and mesh always agree (the original
//! walks from the start tile, leaves unreachable cells without geometry and places tiles twice
//! around loops). The order of the output does not depend on the thread count.

use std::ops::Range;

use rayon::prelude::*;

use crate::budget::{Budget, MeshEstimate};
use crate::grid::Cell;
use crate::layout::Layout;
use crate::mesh::{Material, Mesh};
use crate::tile::TileKind;
use crate::tileset::{Seams, TileContext, TileGeometry, TileSet, TileSetError, tile_seed};

/// Where one tile's triangles are in the world meshes.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedTile {
    /// The cell.
    pub cell: Cell,
    /// Its kind.
    pub kind: TileKind,
    /// Its quarter turns.
    pub rotation: u8,
    /// Its triangles in [`WorldMesh::visual`] (exact: kept up to date when welding drops
    /// collapsed triangles).
    pub visual_triangles: Range<usize>,
    /// Its triangles in [`WorldMesh::collision`].
    pub collision_triangles: Range<usize>,
    /// What the tile set made of it beyond its kind ([`TileGeometry::labels`]).
    pub labels: Vec<&'static str>,
    /// How far its floor stands above its level's floor, metres, lowest and highest
    /// ([`TileSet::floor_lift`]).
    pub floor_lift: [f64; 2],
    /// Its passage axis as the tile set laid it ([`TileGeometry::axis`]), if it knows one.
    pub axis: Option<crate::tileset::PassageAxis>,
}

/// The assembled world.
#[derive(Clone, Debug, Default)]
pub struct WorldMesh {
    /// What is rendered.
    pub visual: Mesh,
    /// What physics collides with.
    pub collision: Mesh,
    /// The tile set's materials.
    pub materials: Vec<Material>,
    /// Parts placed beside the passages ([`TileSet::fixtures`]): not in `visual` nor in
    /// `collision`, which stay one closed surface each; the exporters instance or bake them,
    /// and the survey's ray caster sees them.
    pub fixtures: crate::mesh::Fixtures,
    /// The image files the materials name ([`TileSet::textures`]), to be written under the
    /// world folder's `mesh/`.
    pub textures: Vec<crate::mesh::ImageFile>,
    /// One entry per occupied cell, raster order.
    pub tiles: Vec<PlacedTile>,
    /// The tiles' rubble fields and drops (`[hazards]`), raster order of their cells.
    pub hazards: Vec<crate::hazards::HazardRegion>,
    /// With `world.connections = "ramp"`, per shaft of the layout (same order) the floor line
    /// of its ramp ([`TileSet::ramp`]); empty otherwise.
    pub ramps: Vec<Vec<[f64; 3]>>,
}

impl WorldMesh {
    /// How far the floor of the tile at `cell` stands above its level's floor, metres, lowest
    /// and highest ([`PlacedTile::floor_lift`]; `[0, 0]` for a cell without a tile).
    pub fn floor_lift(&self, cell: Cell) -> [f64; 2] {
        self.tile(cell).map_or([0.0, 0.0], |t| t.floor_lift)
    }

    /// The placed tile at `cell`, if it has one.
    pub fn tile(&self, cell: Cell) -> Option<&PlacedTile> {
        self.tiles
            .binary_search_by_key(&cell, |t| t.cell)
            .ok()
            .map(|i| &self.tiles[i])
    }
}

fn reserve(m: &mut Mesh, vertices: usize, triangles: usize) {
    m.positions.reserve(vertices);
    m.normals.reserve(vertices);
    m.uvs.reserve(vertices);
    m.triangles.reserve(triangles);
    m.materials.reserve(triangles);
}

/// Makes every tile of a layout and joins them, with no memory budget (see
/// [`assemble_within`]).
pub fn assemble(layout: &Layout, tileset: &dyn TileSet) -> Result<WorldMesh, TileSetError> {
    assemble_within(layout, tileset, &Budget::unlimited())
}

/// Makes every tile of a layout and joins them, refusing first a world whose meshes would need
/// more memory than `budget`: by the tile set's estimate before any tile is made, and for tile
/// sets without one, by the first chunk of tiles extrapolated to the world.
pub fn assemble_within(
    layout: &Layout,
    tileset: &dyn TileSet,
    budget: &Budget,
) -> Result<WorldMesh, TileSetError> {
    let ramps = check(layout, tileset)?;
    let memory = MemoryCheck::new(layout, tileset, budget);
    if let Some(e) = layout.mesh_estimate(|k| tileset.estimate(layout, k)) {
        memory.check(e, "estimated")?;
    }
    let cells: Vec<Cell> = layout
        .occupancy
        .cells()
        .filter(|&c| *layout.occupancy.get(c))
        .collect();
    let make = |cell: Cell| -> Result<TileGeometry, TileSetError> {
        let tile = layout.tiles.get(cell).expect("occupied cells have tiles");
        let ctx = TileContext {
            layout,
            cell,
            tile,
            position: layout.cell_position(cell),
            seed: tile_seed(layout.resolved.seed, cell),
        };
        tileset.tile(&ctx).map_err(|e| TileSetError::Tile {
            cell,
            kind: tile.kind,
            source: Box::new(e),
        })
    };
    let mut out = WorldMesh {
        materials: tileset.materials(),
        ramps,
        ..WorldMesh::default()
    };
    // Tiles are made in parallel a chunk at a time and appended in raster order, so memory
    // holds the world plus one chunk, and the result does not depend on the thread count.
    // The textures are made meanwhile, on the threads the appending leaves idle.
    let chunk = 64 * rayon::current_num_threads().max(1);
    let mut seams: Option<(Vec<u32>, Vec<u32>)> = Some((Vec::new(), Vec::new()));
    let (textures, tiles) = rayon::join(
        || tileset.textures(layout.resolved.seed),
        || -> Result<(), TileSetError> {
            for group in cells.chunks(chunk) {
                let geometry: Vec<TileGeometry> = group
                    .par_iter()
                    .map(|&c| make(c))
                    .collect::<Result<_, _>>()?;
                if out.visual.triangles.is_empty() {
                    reserve_from_first(&mut out, &geometry, cells.len(), &memory)?;
                }
                for (&cell, g) in group.iter().zip(&geometry) {
                    let floor_lift = tileset.floor_lift(layout, cell);
                    append_tile(&mut out, &mut seams, layout, cell, g, floor_lift);
                }
            }
            Ok(())
        },
    );
    out.textures = textures?;
    tiles?;
    weld(&mut out, seams, tileset.texture_scale());
    let axes: Vec<_> = out
        .tiles
        .iter()
        .filter_map(|t| Some((t.cell, t.axis.as_ref()?)))
        .collect();
    out.fixtures = tileset.fixtures(layout, &out.visual, &axes)?;
    label_fixtures(&mut out);
    Ok(out)
}

/// Everything about a layout a tile set refuses before any tile is meshed: the tile set's own
/// [`TileSet::check`], hazards it cannot make (`hazards.rubble`, `hazards.drops`, as resolved
/// on [`Layout::floor_hazards`]) and ramps it cannot make (`world.connections = "ramp"`).
/// [`assemble_within`] starts with it, and `validate` runs it without meshing, so the two
/// refuse the same pipelines. Returns each shaft's ramp line for a world joined by ramps
/// (empty otherwise).
pub fn check(layout: &Layout, tileset: &dyn TileSet) -> Result<Vec<Vec<[f64; 3]>>, TileSetError> {
    tileset.check(layout)?;
    let h = &layout.floor_hazards;
    if h.asked() && !tileset.makes_hazards() {
        let key = if h.rubble {
            "hazards.rubble"
        } else {
            "hazards.drops"
        };
        return Err(TileSetError::Unsuited {
            what: format!(
                "{key}: this tile set does not make rubble fields or drops (only the \
                 procedural ones do: cave, mine, lava-tube)"
            ),
            fix: "remove hazards.rubble and hazards.drops, or use a procedural tile set".into(),
        });
    }
    let mut ramps = Vec::new();
    if layout.resolved.connections == crate::config::Connections::Ramp {
        for s in &layout.shafts {
            ramps.push(tileset.ramp(layout, s).ok_or_else(|| {
                TileSetError::Unsuited {
                    what: "this tile set makes no ramps between levels".into(),
                    fix: "set world.connections = \"shaft\", or use a procedural tile set \
                      (mine, cave, lava-tube)"
                        .into(),
                }
            })?);
        }
    }
    Ok(ramps)
}

/// The memory budget a world's meshes are checked against, with what to change when they do
/// not fit.
struct MemoryCheck<'a> {
    budget: &'a Budget,
    /// Bytes of the layout's own grids.
    grid: u64,
    advice: String,
}

impl<'a> MemoryCheck<'a> {
    fn new(layout: &Layout, tileset: &dyn TileSet, budget: &'a Budget) -> Self {
        let advice = match tileset.detail_advice() {
            Some(a) => format!(
                "{a}, make a smaller world (world.min_length, or world.rows and world.cols, and \
                 world.levels), or make no mesh (--no-mesh)"
            ),
            None => "make a smaller world (world.min_length, or world.rows and world.cols, and \
                     world.levels), or make no mesh (--no-mesh)"
                .to_owned(),
        };
        let grid = crate::budget::layout_bytes(
            layout.occupancy.levels(),
            layout.occupancy.rows(),
            layout.occupancy.cols(),
        );
        MemoryCheck {
            budget,
            grid,
            advice,
        }
    }

    /// Refuses meshes of `estimate` (found `how`) that do not fit the budget.
    fn check(&self, estimate: MeshEstimate, how: &str) -> Result<(), TileSetError> {
        self.budget
            .check(
                estimate.bytes.saturating_add(self.grid),
                &format!("this world's meshes ({}, {how})", estimate.describe()),
                &self.advice,
            )
            .map_err(TileSetError::TooLarge)
    }
}

/// Sizes the world's meshes from its first chunk of tiles (`first`, of `cells` in all), so
/// appending rarely reallocates, after checking that size against the memory budget.
fn reserve_from_first(
    out: &mut WorldMesh,
    first: &[TileGeometry],
    cells: usize,
    memory: &MemoryCheck,
) -> Result<(), TileSetError> {
    let factor = cells as f64 / first.len() as f64 * 1.05;
    let count = |f: fn(&TileGeometry) -> (usize, usize)| {
        let (v, t) = first
            .iter()
            .map(f)
            .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
        ((v as f64 * factor) as usize, (t as f64 * factor) as usize)
    };
    let (vv, vt) = count(|g| (g.visual.positions.len(), g.visual.triangles.len()));
    let (cv, ct) = count(|g| (g.collision.positions.len(), g.collision.triangles.len()));
    memory.check(
        MeshEstimate::of(cells as u64, (vt + ct) as f64 / 1.05),
        &format!("measured on its first {} tiles", first.len()),
    )?;
    reserve(&mut out.visual, vv, vt);
    reserve(&mut out.collision, cv, ct);
    Ok(())
}

/// Appends the geometry `g` of the tile at `cell` to the world's meshes, noting its seam
/// vertices (`seams` becomes `None` once a tile does not list them: everything is welded).
fn append_tile(
    out: &mut WorldMesh,
    seams: &mut Option<(Vec<u32>, Vec<u32>)>,
    layout: &Layout,
    cell: Cell,
    g: &TileGeometry,
    floor_lift: [f64; 2],
) {
    let tile = layout.tiles.get(cell).expect("occupied");
    let start = out.visual.triangle_count();
    let collision_start = out.collision.triangle_count();
    match (&mut *seams, &g.seams) {
        (Some((vs, cs)), Seams::Listed { visual, collision }) => {
            let vb = out.visual.positions.len() as u32;
            let cb = out.collision.positions.len() as u32;
            vs.extend(visual.iter().map(|i| i + vb));
            cs.extend(collision.iter().map(|i| i + cb));
        }
        (_, Seams::None) => {}
        _ => *seams = None,
    }
    out.visual.append(&g.visual);
    out.collision.append(&g.collision);
    out.hazards.extend(g.hazards.iter().cloned());
    out.tiles.push(PlacedTile {
        cell,
        kind: tile.kind,
        rotation: tile.rotation,
        visual_triangles: start..out.visual.triangle_count(),
        collision_triangles: collision_start..out.collision.triangle_count(),
        labels: g.labels.clone(),
        floor_lift,
        axis: g.axis.clone(),
    });
}

/// Adds each fixture's prototype name to the labels of the tile it serves (once per name, in
/// order of first placement), so the semantic labels say which tiles carry bolts, a duct, pipes...
fn label_fixtures(out: &mut WorldMesh) {
    let f = &out.fixtures;
    for p in &f.placements {
        let name = f.prototypes[p.prototype as usize].name;
        if let Ok(i) = out.tiles.binary_search_by_key(&p.cell, |t| t.cell) {
            let labels = &mut out.tiles[i].labels;
            if !labels.contains(&name) {
                labels.push(name);
            }
        }
    }
}

/// Welds the world's meshes (only the listed seam vertices, when every tile listed them),
/// moves the tiles' triangle ranges with the welding, and computes the normals and texture
/// coordinates the tile set left out (`scale`: metres per texture repeat). The visual and
/// the collision mesh are welded on two threads: each on its own is serial work.
fn weld(out: &mut WorldMesh, seams: Option<(Vec<u32>, Vec<u32>)>, scale: f32) {
    let (visual_seams, collision_seams) = match seams {
        Some((v, c)) => (Some(v), Some(c)),
        None => (None, None),
    };
    let (visual, collision) = (&mut out.visual, &mut out.collision);
    let (kept_visual, kept_collision) = rayon::join(
        || weld_one(visual, visual_seams, scale),
        || weld_one(collision, collision_seams, scale),
    );
    for t in &mut out.tiles {
        let (v, c) = (&mut t.visual_triangles, &mut t.collision_triangles);
        *v = kept_visual[v.start]..kept_visual[v.end];
        *c = kept_collision[c.start]..kept_collision[c.end];
    }
}

/// [`weld`] of one mesh: where each of its triangles went (as `Mesh::weld` says).
fn weld_one(mesh: &mut crate::mesh::Mesh, seams: Option<Vec<u32>>, scale: f32) -> Vec<usize> {
    let kept = match seams {
        Some(s) => mesh.weld_among(&s),
        None => mesh.weld(),
    };
    if mesh.normals.len() != mesh.positions.len() {
        mesh.compute_normals();
    }
    if mesh.uvs.len() != mesh.positions.len() {
        mesh.compute_box_uvs(scale);
    }
    kept
}
