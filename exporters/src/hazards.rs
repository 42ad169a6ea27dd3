//! Floor patches (`[hazards] friction`, found by the survey: `survey/src/hazards.rs`) in the
//! formats that give each collision element its own friction: SDF and USD as separate
//! collision meshes holding the patched tiles' up-facing (floor) triangles, with the
//! material's friction (`split_collision`; URDF as a fixed link per part and material,
//! since PyBullet's friction is per link).

use std::collections::BTreeMap;
use std::ops::Range;

use subtgraph_core::assembly::WorldMesh;
use subtgraph_core::export::{ExportError, WorldWriter, stream_file};
use subtgraph_core::grid::Cell;
use subtgraph_core::hazards::{FloorMaterial, Patch};

use crate::parts::{Part, push_range};

/// A collision group: its floor material (`None`: rock) and its triangles in
/// [`WorldMesh::collision`].
pub(crate) type CollisionGroup = (Option<FloorMaterial>, Vec<Range<usize>>);

/// A part's collision triangles split by floor material, for the formats that give each
/// collision element its own friction (SDF, USD): the up-facing triangles (the floor: normal
/// within 45 degrees of up) of each patched tile go to the tile's material, everything else
/// stays rock (`None`). Rock first, then the materials in name order; `None` when the part has
/// no patch, so worlds without `[hazards]` keep their single collision mesh.
pub(crate) fn split_collision(
    patches: &[Patch],
    mesh: &WorldMesh,
    part: &Part,
) -> Option<Vec<CollisionGroup>> {
    let of: BTreeMap<Cell, FloorMaterial> = patches.iter().map(|p| (p.cell, p.material)).collect();
    if !part
        .tiles
        .iter()
        .any(|&t| of.contains_key(&mesh.tiles[t].cell))
    {
        return None;
    }
    let mut groups: BTreeMap<Option<FloorMaterial>, Vec<Range<usize>>> = BTreeMap::new();
    groups.insert(None, Vec::new());
    let col = &mesh.collision;
    for &t in &part.tiles {
        let tile = &mesh.tiles[t];
        let material = of.get(&tile.cell).copied();
        for i in tile.collision_triangles.clone() {
            // In f64: the collision copy's triangles are small and hundreds of metres from the
            // origin, where an f32 cross product tilts a face by up to 1e-3 of its length,
            // enough to move one near 45 degrees across the line a reader draws in f64.
            let [a, b, c] = col.triangles[i].map(|v| col.positions[v as usize].map(f64::from));
            let (u, v) = (
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
            );
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let floor = len > 0.0 && n[2] > std::f64::consts::FRAC_1_SQRT_2 * len;
            let key = if floor { material } else { None };
            push_range(groups.entry(key).or_default(), i..i + 1);
        }
    }
    Some(groups.into_iter().collect())
}

/// The file-name word of a collision group: `rock` or the material's name.
pub(crate) fn group_name(m: Option<FloorMaterial>) -> &'static str {
    m.map_or("rock", FloorMaterial::name)
}

/// Where the split collision meshes go, shared by SDF and URDF like `mesh/parts`.
pub(crate) const HAZARDS_DIR: &str = "mesh/hazards";

/// Writes a part's split collision meshes (`mesh/hazards/<split>/<part>-collision-<rock or
/// material>.obj`), unless an earlier exporter of the same world folder already did, and
/// returns each group's material and path relative to the world folder.
pub(crate) fn write_split_meshes(
    out: &mut dyn WorldWriter,
    mesh: &WorldMesh,
    split: crate::parts::Split,
    part: &Part,
    groups: Vec<CollisionGroup>,
) -> Result<Vec<(Option<FloorMaterial>, String)>, ExportError> {
    let mut files = Vec::with_capacity(groups.len());
    for (m, ranges) in groups {
        let word = group_name(m);
        let path = format!(
            "{HAZARDS_DIR}/{}/{}-collision-{word}.obj",
            split.label(),
            part.name
        );
        if !out.contains(&path) {
            let cut = mesh.collision.extract(&ranges);
            stream_file(out, &path, |w| {
                crate::text::write_obj(w, &cut, &format!("{}-collision-{word}", part.name), None)
            })?;
        }
        files.push((m, path));
    }
    Ok(files)
}
