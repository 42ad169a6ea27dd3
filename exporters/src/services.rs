//! The fixtures (a mine's services, `subtgraph_core::mesh::Fixtures`) for the formats without
//! instances: baked into world coordinates, as visual geometry only. Everything a tile set
//! places is mounted above a ground robot (the mine's services at least 1.7 m over the floor),
//! so the collision surface stays the rock's and no format collides with them.
//!
//! - `mesh/services.obj`: every copy, grouped by material (`world.mtl`); written by the OBJ
//!   exporter and, when it is not asked for, by the SDF exporter, which names it.
//! - `mesh/services/<material>.obj`: one file per material, positions and faces alone, for
//!   URDF, whose `<visual>` has one colour.
//! - MJCF bakes its own, per part and material, as `.msh` (`crate::mjcf`).

use std::ops::Range;

use subtgraph_core::assembly::WorldMesh;
use subtgraph_core::export::{ExportError, WorldWriter, stream_file};
use subtgraph_core::mesh::{Fixtures, Material};

use crate::text::write_obj;

/// Where the baked services go.
pub(crate) const SERVICES_OBJ: &str = "mesh/services.obj";

/// The copies of each material that has any: `(material index, placement indices)`, by
/// material index, each list in placement order.
pub(crate) fn by_material(
    f: &Fixtures,
    placements: impl IntoIterator<Item = usize>,
) -> Vec<(u8, Vec<usize>)> {
    let mut groups: Vec<(u8, Vec<usize>)> = Vec::new();
    for i in placements {
        let m = f.prototypes[f.placements[i].prototype as usize].material;
        match groups.binary_search_by_key(&m, |g| g.0) {
            Ok(k) => groups[k].1.push(i),
            Err(k) => groups.insert(k, (m, vec![i])),
        }
    }
    groups
}

/// Cuts a list of copies into runs of at most `max` triangles (a copy is never split; one
/// larger than `max` is a run of its own).
pub(crate) fn runs(f: &Fixtures, copies: &[usize], max: usize) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let (mut start, mut room) = (0, max);
    for (k, &i) in copies.iter().enumerate() {
        let n = f.prototypes[f.placements[i].prototype as usize]
            .mesh
            .triangles
            .len();
        if n > room && k > start {
            out.push(start..k);
            (start, room) = (k, max);
        }
        room = room.saturating_sub(n);
    }
    if start < copies.len() {
        out.push(start..copies.len());
    }
    out
}

/// Writes `mesh/services.obj` (and `mesh/world.mtl` with its textures, which it names) unless
/// an earlier exporter of the world folder did, and returns its path; `None` for a world
/// without fixtures.
pub(crate) fn write_services_obj(
    out: &mut dyn WorldWriter,
    mesh: &WorldMesh,
) -> Result<Option<&'static str>, ExportError> {
    if mesh.fixtures.is_empty() {
        return Ok(None);
    }
    crate::text::write_world_mtl(out, mesh)?;
    if !out.contains(SERVICES_OBJ) {
        let f = &mesh.fixtures;
        let baked = f.baked();
        stream_file(out, SERVICES_OBJ, |w| {
            write_obj(w, &baked, "services", Some((&mesh.materials, "world.mtl")))
        })?;
    }
    Ok(Some(SERVICES_OBJ))
}

/// Writes `mesh/services/<material>.obj` per material of the services (no material library
/// and no texture coordinates: the format names the colour), unless an earlier exporter did,
/// and returns each material with its file's path, by material index.
pub(crate) fn write_material_objs<'m>(
    out: &mut dyn WorldWriter,
    mesh: &'m WorldMesh,
) -> Result<Vec<(&'m Material, String)>, ExportError> {
    let f = &mesh.fixtures;
    let mut files = Vec::new();
    for (m, copies) in by_material(f, 0..f.placements.len()) {
        let Some(material) = mesh.materials.get(usize::from(m)) else {
            continue;
        };
        let path = format!("mesh/services/{}.obj", material.name);
        if !out.contains(&path) {
            let mut baked = f.bake(copies);
            // A colour, no texture: no coordinates to read (a third of the file).
            baked.uvs.clear();
            stream_file(out, &path, |w| {
                write_obj(w, &baked, &format!("services-{}", material.name), None)
            })?;
        }
        files.push((material, path));
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::grid::Cell;
    use subtgraph_core::mesh::{Mesh, Placement, Prototype};

    fn fixtures() -> Fixtures {
        let tri = |n: usize| Mesh {
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            triangles: vec![[0, 1, 2]; n],
            ..Mesh::default()
        };
        let place = |prototype, x| Placement {
            prototype,
            cell: Cell {
                level: 0,
                row: 0,
                col: 0,
            },
            translation: [x, 0.0, 2.0],
            rotation: [0.0, 0.0, 0.0, 1.0],
            scale: [2.0, 1.0, 1.0],
        };
        Fixtures {
            prototypes: vec![
                Prototype {
                    name: "a",
                    mesh: tri(2),
                    material: 3,
                },
                Prototype {
                    name: "b",
                    mesh: tri(3),
                    material: 1,
                },
            ],
            placements: vec![place(0, 0.0), place(1, 1.0), place(0, 2.0), place(1, 3.0)],
        }
    }

    #[test]
    fn baked_copies_are_placed_in_order_without_normals() {
        let f = fixtures();
        let all = f.baked();
        // A subset is those copies of the whole, renumbered.
        let odd = f.bake([1, 3]);
        let per = f.bake([0]).positions.len();
        assert_eq!(odd.positions[..per], all.positions[per..2 * per]);
        assert_eq!(odd.triangles.len(), 6);
        assert_eq!(odd.triangles[3], [3, 4, 5]);
        assert_eq!(odd.materials, vec![1; 6]);
        assert!(all.normals.is_empty());
        let ours = all;
        // Scaled by 2 along x, then moved: the first copy at x = 0, the second at x = 1.
        assert_eq!(ours.positions[1], [2.0, 0.0, 2.0]);
        assert_eq!(ours.positions[3], [1.0, 0.0, 2.0]);
    }

    #[test]
    fn groups_by_material_and_runs_keep_copies_whole() {
        let f = fixtures();
        assert_eq!(
            by_material(&f, 0..4),
            vec![(1, vec![1, 3]), (3, vec![0, 2])]
        );
        // Three triangles a copy: two fit in six, not in five.
        assert_eq!(runs(&f, &[1, 3], 6), vec![0..2]);
        assert_eq!(runs(&f, &[1, 3], 5), vec![0..1, 1..2]);
        assert_eq!(runs(&f, &[1, 3], 1), vec![0..1, 1..2]);
        assert!(runs(&f, &[], 5).is_empty());
    }
}
