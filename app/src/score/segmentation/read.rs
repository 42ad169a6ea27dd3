//! What `score --segmentation` reads: the labelled map (an 8-bit grey PNG or an integer 2-D
//! `.npy`), and from the world folder the level's ROS map (`ground_truth/maps/level-N.pgm` +
//! `.yaml`: the grid and its free pixels) and `ground_truth/semantic_labels.json` (each tile's
//! kind), rasterised onto that grid as the ground truth.

use std::path::Path;

use subtgraph_schema::SemanticLabels;

use crate::Error;
use crate::score::world::{self, Cells};

use super::{CLASSES, DEAD_END, INTERSECTION, JUNCTION};

/// The class of a semantic label's kind: the grouping the label table documents.
pub fn class_of_kind(kind: &str) -> u8 {
    match kind {
        "straight" | "corner" => 1,
        "t-junction" => JUNCTION,
        "intersection" => INTERSECTION,
        "dead-end" => DEAD_END,
        "shaft-up" | "shaft-landing" | "ramp" => 5,
        _ => 0,
    }
}

/// A level's map grid, as its ROS map gives it.
pub struct MapGrid {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// Metres per pixel.
    pub resolution: f64,
    /// World position of the south-west corner of the south-west pixel.
    pub origin: [f64; 2],
    /// Whether each pixel (row 0 north) is free (254).
    pub free: Vec<bool>,
}

impl MapGrid {
    /// The world position of the centre of pixel `(row, col)` (row 0 north).
    pub fn centre(&self, row: usize, col: usize) -> [f64; 2] {
        [
            self.origin[0] + (col as f64 + 0.5) * self.resolution,
            self.origin[1] + ((self.height - 1 - row) as f64 + 0.5) * self.resolution,
        ]
    }
}

/// Reads `ground_truth/maps/level-N.{pgm,yaml}`.
pub fn map(world: &Path, level: usize, levels: usize) -> Result<MapGrid, Error> {
    let base = world.join(format!("ground_truth/maps/level-{level}"));
    let (pgm_path, yaml_path) = (base.with_extension("pgm"), base.with_extension("yaml"));
    if !pgm_path.is_file() || !yaml_path.is_file() {
        if level >= levels {
            return Err(Error::Input(format!(
                "{} has {levels} level(s) (0 to {}), not level {level}: give the level of the map with --level N",
                world.display(),
                levels - 1
            )));
        }
        return Err(Error::Input(format!(
            "{} has no ground_truth/maps/level-{level}.pgm and .yaml: scoring a segmentation needs the world's ROS maps; make it again with `subtgraph generate PIPELINE --format ground-truth` (PIPELINE being its world.toml)",
            world.display()
        )));
    }
    let bad = |why: &str| {
        Error::Input(format!(
            "{}: {why}; was it edited? make the world again with `subtgraph generate`",
            pgm_path.display()
        ))
    };
    let pgm = crate::input::read(&pgm_path)?;
    // P5, width, height, maxval, each after whitespace or a `#` comment line.
    let mut at = 0;
    let mut fields = Vec::new();
    while fields.len() < 4 && at < pgm.len() {
        match pgm[at] {
            b'#' => {
                while at < pgm.len() && pgm[at] != b'\n' {
                    at += 1;
                }
            }
            c if c.is_ascii_whitespace() => at += 1,
            _ => {
                let start = at;
                while at < pgm.len() && !pgm[at].is_ascii_whitespace() {
                    at += 1;
                }
                fields.push(String::from_utf8_lossy(&pgm[start..at]).into_owned());
            }
        }
    }
    at += 1;
    let number = |s: &str| s.parse::<usize>().ok();
    let (Some("P5"), Some(width), Some(height), Some(255)) = (
        fields.first().map(String::as_str),
        fields.get(1).and_then(|s| number(s)),
        fields.get(2).and_then(|s| number(s)),
        fields.get(3).and_then(|s| number(s)),
    ) else {
        return Err(bad("not a binary 8-bit PGM (P5, maxval 255)"));
    };
    if width.checked_mul(height) != Some(pgm.len().saturating_sub(at)) {
        return Err(bad(&format!(
            "{width} x {height} pixels declared, but {} bytes follow the header",
            pgm.len().saturating_sub(at)
        )));
    }
    let free = pgm[at..].iter().map(|&v| v == 254).collect();
    let yaml = String::from_utf8_lossy(&crate::input::read(&yaml_path)?).into_owned();
    let key = |k: &str| {
        yaml.lines()
            .find_map(|l| l.strip_prefix(k))
            .map(|v| v.trim().to_owned())
    };
    let resolution = key("resolution:").and_then(|v| v.parse::<f64>().ok());
    let origin: Option<Vec<f64>> = key("origin:").and_then(|v| {
        v.trim_matches(|c| c == '[' || c == ']')
            .split(',')
            .map(|x| x.trim().parse().ok())
            .collect()
    });
    match (resolution, origin.as_deref()) {
        (Some(r), Some(&[x, y, _])) if r > 0.0 && r.is_finite() => Ok(MapGrid {
            width,
            height,
            resolution: r,
            origin: [x, y],
            free,
        }),
        _ => Err(Error::Input(format!(
            "{}: no positive `resolution:` or no `origin: [x, y, yaw]`; was it edited? make the world again with `subtgraph generate`",
            yaml_path.display()
        ))),
    }
}

/// The ground truth: each free pixel's class, from the label of the tile its centre is in
/// (0 where the pixel is not free or its tile has no label).
pub fn truth(world: &Path, level: usize, cells: &Cells, grid: &MapGrid) -> Result<Vec<u8>, Error> {
    let labels: SemanticLabels = world::read_doc(
        world,
        "scoring a segmentation needs the world's semantic labels: make it again with `subtgraph generate PIPELINE --format ground-truth`",
    )?;
    let mut class = vec![0u8; cells.rows * cells.cols];
    for t in labels.tiles.iter().filter(|t| t.level == level) {
        if t.row < cells.rows && t.col < cells.cols {
            class[t.row * cells.cols + t.col] = class_of_kind(&t.kind);
        }
    }
    let mut out = vec![0u8; grid.width * grid.height];
    for (k, v) in out.iter_mut().enumerate() {
        if grid.free[k] {
            let [x, y] = grid.centre(k / grid.width, k % grid.width);
            if let Some([row, col]) = cells.cell_at(level, x, y) {
                *v = class[row * cells.cols + col];
            }
        }
    }
    Ok(out)
}

/// The labelled map at `path`: an 8-bit greyscale PNG or an integer 2-D `.npy`, of
/// `width` x `height` pixels, every value a class of the label table.
pub fn prediction(path: &Path, width: usize, height: usize) -> Result<Vec<u8>, Error> {
    let bytes = crate::input::read(path)?;
    let name = path.display();
    let mismatch = |w: usize, h: usize| {
        Error::Input(format!(
            "{name}: {w} x {h} pixels, but the level's ROS map is {width} x {height} (width x height at its resolution): draw the segmentation on that map's grid, row 0 north"
        ))
    };
    let npy = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("npy"));
    let (w, h, values): (usize, usize, Vec<f64>) = if npy {
        let info = subtgraph_core::npy::info(&bytes).map_err(|source| Error::Npy {
            file: name.to_string(),
            source,
        })?;
        let size_error = |shape: &[usize]| {
            Error::Input(format!(
                "{name}: an array of shape {shape:?}, but the level's ROS map is {width} x {height} (width x height at its resolution): save the segmentation with numpy as uint8 of shape ({height}, {width}), row 0 north"
            ))
        };
        if info.shape.len() != 2 || !matches!(info.kind, b'u' | b'i') {
            return Err(Error::Input(format!(
                "{name}: an array of shape {:?} of {}, but a segmentation is a 2-D integer array (rows north to south, as the ROS map's image): save it with numpy as uint8 of shape ({height}, {width})",
                info.shape,
                match info.kind {
                    b'f' => "floats",
                    b'b' => "booleans",
                    _ => "integers",
                }
            )));
        }
        // Checked before the values are decoded (eight bytes each).
        if info.shape != [height, width] {
            return Err(size_error(&info.shape));
        }
        let a = subtgraph_core::npy::decode(&bytes).map_err(|source| Error::Npy {
            file: name.to_string(),
            source,
        })?;
        (a.shape[1], a.shape[0], a.values)
    } else {
        let decoder = png::Decoder::new(std::io::Cursor::new(&bytes[..]));
        let mut reader = decoder.read_info().map_err(|e| {
            Error::Input(format!(
                "{name}: not a PNG ({e}); give an 8-bit greyscale PNG or an integer .npy"
            ))
        })?;
        let (color, depth) = reader.output_color_type();
        let info = reader.info();
        if color != png::ColorType::Grayscale
            || depth != png::BitDepth::Eight
            || info.palette.is_some()
        {
            return Err(Error::Input(format!(
                "{name}: a {color:?} PNG of {}-bit samples, but a segmentation is an 8-bit greyscale PNG (one label value per pixel): save it as mode \"L\" (pillow) or uint8",
                depth as u8
            )));
        }
        let (w, h) = (info.width as usize, info.height as usize);
        // The header's size against the map's, before the pixels are given memory (a header
        // may claim 200,000 x 200,000 pixels in 900 bytes).
        if (w, h) != (width, height) {
            return Err(mismatch(w, h));
        }
        let mut buf = vec![0; reader.output_buffer_size().unwrap_or(0)];
        let frame = reader
            .next_frame(&mut buf)
            .map_err(|e| Error::Input(format!("{name}: a damaged PNG ({e}); save it again")))?;
        let line = frame.line_size;
        let mut values = Vec::with_capacity(w * h);
        for r in 0..h {
            values.extend(buf[r * line..r * line + w].iter().map(|&v| f64::from(v)));
        }
        (w, h, values)
    };
    if (w, h) != (width, height) {
        return Err(mismatch(w, h));
    }
    values
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            if v >= 0.0 && v < CLASSES.len() as f64 && v.fract() == 0.0 {
                Ok(v as u8)
            } else {
                Err(Error::Input(format!(
                    "{name}: pixel (row {}, column {}) has value {v}, not a label: use 0 (not labelled), 1 corridor, 2 junction, 3 intersection, 4 dead end or 5 shaft/ramp (docs: scoring, segmentation)",
                    k / w,
                    k % w
                )))
            }
        })
        .collect()
}
