//! Where a world's hazards are (`[hazards]`, see `core/src/hazards.rs`): floor patches with
//! another friction, whole tiles (not shaft ends, not the start tile), chosen from the world's
//! `"hazards"` stream. MuJoCo gets them as the friction of those tiles' floor height fields;
//! the ground truth as regions in `ground_truth/hazards.json`.

use serde::Serialize;
use subtgraph_core::World;
use subtgraph_core::export::{ExportError, WorldWriter};
use subtgraph_core::grid::Cell;
use subtgraph_core::hazards::FloorMaterial;
use subtgraph_core::tile::TileKind;

/// A floor patch.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Patch {
    /// Its tile.
    pub cell: Cell,
    /// The tile's kind.
    pub tile_kind: TileKind,
    /// Its material.
    pub material: FloorMaterial,
    /// Its friction coefficient.
    pub friction: f64,
    /// The tile's square in the plane, `[x0, y0, x1, y1]`, metres.
    pub bounds: [f64; 4],
    /// The level's nominal floor, metres.
    pub floor_z: f64,
}

/// The world's floor patches, in raster order of their cells; none without `[hazards]`.
pub fn patches(world: &World) -> Vec<Patch> {
    let Some(h) = &world.pipeline.hazards else {
        return Vec::new();
    };
    let tiles: Vec<Cell> = world
        .occupancy
        .cells()
        .filter(|&c| {
            Some(c) != world.start
                && world
                    .tiles
                    .get(c)
                    .is_some_and(|t| !matches!(t.kind, TileKind::ShaftUp | TileKind::ShaftLanding))
        })
        .collect();
    let half = 0.5 * world.resolved.tile_pitch;
    let mut out: Vec<Patch> = h
        .assign(world.resolved.seed, &tiles)
        .into_iter()
        .map(|(cell, material)| {
            let [x, y, z] = world.cell_position(cell);
            Patch {
                cell,
                tile_kind: world.tiles.get(cell).map_or(TileKind::Straight, |t| t.kind),
                material,
                friction: material.friction(),
                bounds: [x - half, y - half, x + half, y + half],
                floor_z: z,
            }
        })
        .collect();
    out.sort_by_key(|p| (p.cell.level, p.cell.row, p.cell.col));
    out
}

#[derive(Serialize)]
struct Document<'a> {
    format: &'static str,
    seed: u64,
    frame: &'static str,
    note: &'static str,
    patches: &'a [Patch],
}

/// Writes `ground_truth/hazards.json`.
pub(crate) fn write(world: &World, out: &mut dyn WorldWriter) -> Result<(), ExportError> {
    let p = patches(world);
    let doc = Document {
        format: "subtgraph-hazards/1",
        seed: world.resolved.seed,
        frame: crate::ground_truth::FRAME,
        note: "floor patches: the whole floor of each tile has the material's friction (MuJoCo: the tile's floor height field)",
        patches: &p,
    };
    crate::write_json(out, "ground_truth/hazards.json", &doc)
}
