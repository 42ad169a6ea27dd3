//! `maps/level-N.png`: a top-down picture of each level, north up. Each tile is drawn as a
//! passage from its centre to its openings, coloured by kind, so junctions, dead ends and
//! shafts stand out at a glance; the start tile has a white centre.

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::grid::{Cell, Direction};
use subtgraph_core::survey::Survey;
use subtgraph_core::tile::TileKind;

/// Writes one PNG per level.
#[derive(Clone, Copy, Debug, Default)]
pub struct LevelMaps;

/// The map colour of a tile kind (RGB).
pub const fn kind_colour(kind: TileKind) -> [u8; 3] {
    match kind {
        TileKind::DeadEnd => [230, 25, 75],
        TileKind::Straight => [170, 185, 200],
        TileKind::Corner => [67, 99, 216],
        TileKind::TJunction => [255, 225, 25],
        TileKind::Intersection => [245, 130, 49],
        TileKind::ShaftUp => [60, 180, 75],
        TileKind::ShaftLanding => [145, 30, 180],
    }
}

const BACKGROUND: [u8; 3] = [24, 24, 28];
const GRID: [u8; 3] = [40, 40, 46];
const WHITE: [u8; 3] = [255, 255, 255];

/// Palette indices: background, grid, start marker, then the tile kinds in `TileKind::ALL`
/// order. An indexed image is a third the size of RGB and encodes several times faster.
const BACKGROUND_INDEX: u8 = 0;
const GRID_INDEX: u8 = 1;
const WHITE_INDEX: u8 = 2;

fn kind_index(kind: TileKind) -> u8 {
    3 + TileKind::ALL
        .iter()
        .position(|&k| k == kind)
        .expect("listed") as u8
}

fn palette() -> Vec<u8> {
    let mut p = Vec::with_capacity(3 * 10);
    for rgb in [BACKGROUND, GRID, WHITE] {
        p.extend_from_slice(&rgb);
    }
    for k in TileKind::ALL {
        p.extend_from_slice(&kind_colour(k));
    }
    p
}

impl Exporter for LevelMaps {
    fn export(
        &self,
        world: &World,
        _survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let (rows, cols) = (world.occupancy.rows(), world.occupancy.cols());
        // About 800 pixels on the long side, at least 6 per cell.
        let s = (800 / rows.max(cols)).clamp(6, 24);
        let (w, h) = (cols * s, rows * s);
        for level in 0..world.occupancy.levels() {
            let mut img = vec![BACKGROUND_INDEX; w * h];
            for (y, row) in img.chunks_exact_mut(w).enumerate() {
                if y % s == 0 {
                    row.fill(GRID_INDEX);
                } else {
                    row.iter_mut().step_by(s).for_each(|px| *px = GRID_INDEX);
                }
            }
            let mut fill = |x0: usize, y0: usize, x1: usize, y1: usize, index: u8| {
                for y in y0..y1 {
                    img[y * w + x0..y * w + x1].fill(index);
                }
            };
            let (a, b) = (s / 4, s - s / 4); // passage band inside a cell
            for c in world.occupancy.level_cells(level) {
                let Some(t) = world.tiles.get(c) else {
                    continue;
                };
                let rgb = kind_index(t.kind);
                let (x0, y0) = (c.col * s, c.row * s);
                fill(x0 + a, y0 + a, x0 + b, y0 + b, rgb);
                for d in Direction::ALL {
                    if t.openings & d.bit() == 0 {
                        continue;
                    }
                    match d {
                        Direction::East => fill(x0 + b, y0 + a, x0 + s, y0 + b, rgb),
                        Direction::West => fill(x0, y0 + a, x0 + a, y0 + b, rgb),
                        Direction::North => fill(x0 + a, y0, x0 + b, y0 + a, rgb),
                        Direction::South => fill(x0 + a, y0 + b, x0 + b, y0 + s, rgb),
                    }
                }
                if world.start == Some(Cell::new(level, c.row, c.col)) {
                    let m = s / 2;
                    let r = (s / 8).max(1);
                    fill(x0 + m - r, y0 + m - r, x0 + m + r, y0 + m + r, WHITE_INDEX);
                }
            }
            let mut bytes = Vec::new();
            {
                let mut enc = png::Encoder::new(&mut bytes, w as u32, h as u32);
                enc.set_color(png::ColorType::Indexed);
                enc.set_depth(png::BitDepth::Eight);
                enc.set_palette(palette());
                enc.set_compression(png::Compression::Fast);
                let mut writer = enc
                    .write_header()
                    .map_err(|e| ExportError::Unsupported(format!("PNG encoding: {e}")))?;
                writer
                    .write_image_data(&img)
                    .map_err(|e| ExportError::Unsupported(format!("PNG encoding: {e}")))?;
            }
            write_file(out, &format!("maps/level-{level}.png"), &bytes)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn one_picture_per_level_with_each_tile_in_its_colour() {
        let world = crate::test_world();
        let mut out = MemoryWriter::default();
        LevelMaps
            .export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        assert_eq!(out.files.len(), world.occupancy.levels());
        let png_bytes = out.get("maps/level-0.png").unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(png_bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut img = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut img).unwrap();
        let s = info.width as usize / world.occupancy.cols();
        assert_eq!(info.height as usize / s, world.occupancy.rows());
        // The centre pixel of every occupied cell is its kind's palette entry, empty cells the
        // background.
        for c in world.occupancy.level_cells(0) {
            let (x, y) = (c.col * s + s / 2 + s / 8 + 1, c.row * s + s / 2 + s / 8 + 1);
            let px = img[y * info.line_size + x];
            match world.tiles.get(c) {
                Some(t) => assert_eq!(px, kind_index(t.kind), "{c:?}"),
                None => assert_eq!(px, BACKGROUND_INDEX, "{c:?}"),
            }
        }
    }
}
