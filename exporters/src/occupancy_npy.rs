//! `occupancy.npy`: `uint8 [levels, rows, cols]` with the original SubTGraph's spatial codes
//! (0 empty, 1 dead end, 2 straight, 3 corner, 4 T-junction, 5 intersection, 11 shaft up,
//! 111 shaft landing), readable with `numpy.load`.

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::npy;
use subtgraph_core::survey::Survey;

/// Writes `occupancy.npy`.
#[derive(Clone, Copy, Debug, Default)]
pub struct OccupancyNpy;

impl Exporter for OccupancyNpy {
    fn export(
        &self,
        world: &World,
        _survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let bytes = npy::encode_u8(&world.occupancy.shape(), &world.spatial_codes());
        write_file(out, "occupancy.npy", &bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn the_grid_reads_back_with_its_spatial_codes() {
        let world = crate::test_world();
        let mut out = MemoryWriter::default();
        OccupancyNpy
            .export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let a = npy::decode(out.get("occupancy.npy").unwrap()).unwrap();
        assert_eq!(a.shape, world.occupancy.shape().to_vec());
        let codes: Vec<f64> = world
            .spatial_codes()
            .iter()
            .map(|&c| f64::from(c))
            .collect();
        assert_eq!(a.values, codes);
        assert!(
            a.values.contains(&11.0) && a.values.contains(&111.0),
            "shafts coded"
        );
    }
}
