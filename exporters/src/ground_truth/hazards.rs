//! `ground_truth/hazards.json`: the floor patches of `[hazards]` (where they are, their
//! material and friction), from [`crate::hazards::patches`], the same list every simulator
//! format writes its friction from.

use serde::Serialize;
use subtgraph_core::World;
use subtgraph_core::export::{ExportError, WorldWriter};

use super::FRAME;
use crate::hazards::Patch;

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
    let p = crate::hazards::patches(world);
    let doc = Document {
        format: "subtgraph-hazards/1",
        seed: world.resolved.seed,
        frame: FRAME,
        note: "floor patches: the whole floor of each tile has the material's friction (MuJoCo: the tile's floor height field)",
        patches: &p,
    };
    crate::write_json(out, "ground_truth/hazards.json", &doc)
}
