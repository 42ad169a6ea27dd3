//! Where a world's floor patches are (`[hazards] friction`, see `core/src/hazards.rs`): whole
//! tiles (not shaft ends, not the start tile), chosen from the world's `"hazards"` stream.
//! Found once by the survey; every format writes its friction from this one list (MuJoCo as
//! the friction of those tiles' floor height fields, SDF, USD and URDF as collision meshes of
//! their own), and the ground truth writes it as `ground_truth/hazards.json` and as labels in
//! the semantic labels.

use subtgraph_core::World;
use subtgraph_core::grid::Cell;
use subtgraph_core::hazards::Patch;
use subtgraph_core::tile::TileKind;

/// The world's floor patches, in raster order of their cells; `None` without `[hazards]`.
pub fn patches(world: &World) -> Option<Vec<Patch>> {
    let h = world.pipeline.hazards.as_ref()?;
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
    Some(out)
}
