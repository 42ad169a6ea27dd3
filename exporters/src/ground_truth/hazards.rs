//! `ground_truth/hazards.json`: the floor patches of `[hazards]` (where they are, their
//! material and friction), as the survey found them, the same list every simulator format
//! writes its friction from; and the rubble fields and drops (`regions`: tile, kind,
//! box in the plane, floor and height range, a rubble field's rocks and lane), as the tile set
//! made them in the geometry every format exports (`WorldMesh::hazards`).

use std::borrow::Cow;

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, WorldWriter};
use subtgraph_core::hazards::Patch;
use subtgraph_schema::HazardPatch;

use super::FRAME;

type Document<'a> = subtgraph_schema::Hazards<'a, &'static str>;

/// Writes `ground_truth/hazards.json`.
pub(crate) fn write(
    world: &World,
    patches: &[Patch],
    out: &mut dyn WorldWriter,
) -> Result<(), ExportError> {
    let doc = Document {
        format: "subtgraph-hazards/1",
        seed: world.resolved.seed,
        frame: FRAME,
        note: "floor patches: the whole floor of each tile has the material's friction (MuJoCo: the tile's floor height field); regions: rubble fields (rocks as x, y, z, radius; gap: the lane kept free) and drops (z: the pit's bottom and the floor), part of every format's collision and visual meshes",
        patches: patches
            .iter()
            .map(|p| HazardPatch {
                cell: p.cell,
                tile_kind: p.tile_kind,
                material: p.material,
                friction: p.friction,
                bounds: p.bounds,
                floor_z: p.floor_z,
            })
            .collect(),
        regions: Cow::Borrowed(world.mesh().map_or(&[], |m| m.hazards.as_slice())),
    };
    crate::write_json(out, "ground_truth/hazards.json", &doc)
}
