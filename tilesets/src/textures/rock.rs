//! The procedural surfaces: a height field per material made of tileable noise, and from it
//! the albedo (the material's colour, darker in cracks and hollows, speckled), a tangent-space
//! normal map and a roughness map.
//!
//! The look is chosen by the material's name, so a tile set's new materials get a texture
//! without code here: `floor` (and `shotcrete`, `concrete`) a speckled gravel floor,
//! `striated` bedded rock, `pile`/`rubble` blocky rock, `bolt`, `plate`, `duct`, `pipe`,
//! `cable`, `steel`, `metal` a smooth worn metal, `mesh` rock behind welded mesh panels,
//! anything else (walls) rock: several octaves of value noise cut by a network of cracks. A
//! tile set may ask for another look than the name's ([`super::Textures::with_look`]): the
//! mine's blasted walls add half-barrel marks. Cracks, speckle, strata, wires and marks put
//! corners a feature detector (ORB) can find in every view.

use rayon::prelude::*;

use super::noise::Tileable;

/// What a material looks like.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Look {
    /// Blasted or natural rock: fractal relief and cracks (walls, and any unknown name).
    Rock,
    /// Gravel and grit on a floor: fine speckle and pebbles.
    Floor,
    /// Bedded rock: bands across the repeat, warped, with cross joints.
    Striated,
    /// Blocks of a rock pile: domed cells with dark gaps.
    Pile,
    /// Worn metal (services): smooth, low contrast.
    Metal,
    /// Blasted rock with half-barrel marks: the halves of the perimeter holes left in the
    /// rock, 45 mm grooves along `u` (along the drift, on walls) 0.75 m apart, a blast round
    /// long, broken where the rock came away with the round.
    Blasted,
    /// Rock behind welded mesh panels: 5.6 mm galvanised wire on a 100 mm square grid, panels
    /// 3 m by 1.5 m with their overlaps, standing off the rock and shadowing it.
    Mesh,
}

/// Half-barrel marks per texture repeat across `u`.
const MARKS: usize = 4;
/// A half-barrel's radius (a 45 mm drill hole), metres.
const MARK_RADIUS: f64 = 0.0225;
/// Mesh cells per texture repeat (100 mm cells at the 3 m repeat).
const MESH_CELLS: f64 = 30.0;
/// The mesh's wire diameter, metres.
const WIRE: f64 = 0.0056;
/// Galvanised wire's colour (linear RGB).
const WIRE_COLOUR: [f64; 3] = [0.42, 0.43, 0.44];

/// What one texel samples: `h` height in about `[0, 1]`, `tone` lighter or darker than the
/// colour (about `[-1, 1]`), `rough` roughness, `wire` how much of it is mesh wire.
#[derive(Clone, Copy)]
struct Texel {
    h: f64,
    tone: f64,
    rough: f64,
    wire: f64,
}

impl Look {
    /// The look a material's name asks for.
    pub fn of(name: &str) -> Look {
        let has = |words: &[&str]| words.iter().any(|w| name.contains(w));
        if has(&["striated", "strata", "bedded"]) {
            Look::Striated
        } else if has(&["pile", "rubble", "boulder"]) {
            Look::Pile
        } else if has(&["mesh"]) {
            Look::Mesh
        } else if has(&[
            "bolt", "plate", "duct", "pipe", "cable", "steel", "metal", "light",
        ]) {
            Look::Metal
        } else if has(&["floor", "shotcrete", "concrete", "gravel", "sand"]) {
            Look::Floor
        } else {
            Look::Rock
        }
    }

    /// Metres of relief the normal map shows.
    fn depth(self) -> f64 {
        match self {
            Look::Rock | Look::Striated | Look::Blasted | Look::Mesh => 0.03,
            Look::Pile => 0.05,
            Look::Floor => 0.015,
            Look::Metal => 0.003,
        }
    }
}

/// One material's three maps, each `size` x `size` RGB, rows from the top (`v` = 1).
pub struct Maps {
    /// Pixels per side.
    pub size: u32,
    /// sRGB albedo.
    pub albedo: Vec<u8>,
    /// Tangent-space normals, `(n + 1) / 2`, green towards `+v`.
    pub normal: Vec<u8>,
    /// Roughness, grey (the same in R, G and B, so glTF's green channel reads it).
    pub roughness: Vec<u8>,
}

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Linear to sRGB, as a byte.
fn srgb(c: f64) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// The texel at texture coordinates `(u, v)` (`grain`: this pixel's own random number;
/// `repeat`: metres per texture repeat; `px`: pixels per repeat).
fn sample(look: Look, n: &Tileable, u: f64, v: f64, grain: f64, repeat: f64, px: f64) -> Texel {
    // A gentle warp, itself tileable, so cells and bands are not straight.
    let wu = u + 0.04 * (n.fbm(1, 3, 2, 0.5, u, v) - 0.5);
    let wv = v + 0.04 * (n.fbm(2, 3, 2, 0.5, u, v) - 0.5);
    let texel = |h, tone, rough| Texel {
        h,
        tone,
        rough,
        wire: 0.0,
    };
    let rock = || {
        let base = n.fbm(10, 4, 5, 0.6, wu, wv);
        let (f1, f2) = n.cells(20, 7, wu, wv);
        let crack = 1.0 - smoothstep(0.0, 0.07, f2 - f1);
        let fine = smoothstep(0.55, 0.8, n.value(22, 48, u, v));
        let h = 0.65 * base + 0.25 * (1.0 - f1.min(1.0)) + 0.06 * grain - 0.35 * crack - 0.1 * fine;
        let tone = 1.3 * (base - 0.5) + 0.3 * (grain - 0.5) - 0.55 * crack - 0.25 * fine;
        texel(h, tone, 0.82 + 0.2 * (base - 0.5) + 0.1 * crack)
    };
    match look {
        Look::Rock => rock(),
        Look::Blasted => {
            let mut t = rock();
            let g = half_barrels(n, u, v, repeat, px);
            t.h -= 0.7 * g;
            t.tone -= 0.6 * g;
            t
        }
        Look::Mesh => {
            let mut t = rock();
            // The rock is in the wire's shadow a few millimetres down and to the side.
            let shade = wires(n, u + 0.004, v - 0.006, repeat, px);
            t.tone -= 0.5 * shade;
            let w = wires(n, u, v, repeat, px);
            t.h = (1.0 - w) * 0.6 * t.h + w * 0.9;
            t.rough = (1.0 - w) * t.rough + w * (0.4 + 0.2 * grain);
            t.wire = w;
            t
        }
        Look::Floor => {
            let base = n.fbm(10, 6, 5, 0.6, wu, wv);
            let (f1, _) = n.cells(20, 40, u, v);
            let pebble = 1.0 - smoothstep(0.15, 0.35, f1);
            let speck = smoothstep(0.9, 0.97, grain) - smoothstep(0.1, 0.03, grain);
            let h = 0.45 * base + 0.35 * pebble + 0.2 * grain;
            let tone = 1.0 * (base - 0.5) + 0.55 * speck + 0.3 * (pebble - 0.3);
            texel(h, tone, 0.9 - 0.1 * pebble)
        }
        Look::Striated => {
            let w = n.fbm(50, 2, 4, 0.5, u, v);
            let beds = (std::f64::consts::TAU * (9.0 * v + 1.5 * w)).sin();
            let base = n.fbm(10, 4, 5, 0.55, wu, wv);
            let (f1, f2) = n.cells(20, 5, wu, wv);
            let joint = 1.0 - smoothstep(0.0, 0.05, f2 - f1);
            let h = 0.5 + 0.25 * beds + 0.3 * (base - 0.5) + 0.05 * grain - 0.3 * joint;
            let tone = 0.55 * beds + 1.0 * (base - 0.5) + 0.2 * (grain - 0.5) - 0.5 * joint;
            texel(h, tone, 0.75 + 0.1 * beds)
        }
        Look::Pile => {
            let (f1, f2) = n.cells(20, 9, wu, wv);
            let base = n.fbm(10, 8, 5, 0.55, wu, wv);
            let gap = 1.0 - smoothstep(0.0, 0.1, f2 - f1);
            let dome = (1.0 - f1).clamp(0.0, 1.0);
            let h = 0.6 * dome + 0.3 * base + 0.05 * grain - 0.4 * gap;
            let tone = 0.7 * (dome - 0.5) + 1.0 * (base - 0.5) + 0.25 * (grain - 0.5) - 0.6 * gap;
            texel(h, tone, 0.85 - 0.1 * dome)
        }
        Look::Metal => {
            let base = n.fbm(10, 8, 5, 0.5, u, v);
            let h = 0.5 + 0.2 * (base - 0.5);
            let tone = 0.5 * (base - 0.5) + 0.1 * (grain - 0.5);
            texel(h, tone, 0.45 + 0.3 * (base - 0.5))
        }
    }
}

/// The depth of the half-barrel marks at `(u, v)`, 1 at a groove's bottom: [`MARKS`] per
/// repeat across `u`, each starting where the last round's left off, running most of a
/// repeat, kept where the rock held (a half-cast of about 60 %).
fn half_barrels(n: &Tileable, u: f64, v: f64, repeat: f64, px: f64) -> f64 {
    // At least a pixel and a half wide, so the groove survives the pixel grid.
    let r = (MARK_RADIUS / repeat).max(0.75 / px);
    let mut depth: f64 = 0.0;
    for k in 0..MARKS {
        let centre = (k as f64 + 0.5 + 0.3 * (n.hash(60, k as i64, 0) - 0.5)) / MARKS as f64;
        // Holes are drilled at a slight angle ("lookout"): the mark climbs across its round.
        let start = n.hash(61, k as i64, 0);
        let along = (u - start).rem_euclid(1.0);
        let length = 0.6 + 0.3 * n.hash(62, k as i64, 0);
        if along > length {
            continue;
        }
        let c = centre + 0.012 * along;
        let d = (v - c + 0.5).rem_euclid(1.0) - 0.5;
        if d.abs() >= r {
            continue;
        }
        let kept = smoothstep(0.35, 0.45, n.value(63 + k as u64, 8, u, centre));
        depth = depth.max(kept * (1.0 - (d / r).powi(2)).sqrt());
    }
    depth
}

/// How much of the texel at `(u, v)` is mesh wire: a square grid of [`MESH_CELLS`] per
/// repeat, gently wavy (the mesh follows the rock loosely), with a second, offset grid over
/// the first two cells of each panel's edges where the next panel overlaps it.
fn wires(n: &Tileable, u: f64, v: f64, repeat: f64, px: f64) -> f64 {
    let half = (0.5 * WIRE / repeat).max(0.45 / px);
    let wu = u + 0.002 * (n.fbm(70, 4, 2, 0.5, u, v) - 0.5);
    let wv = v + 0.002 * (n.fbm(71, 4, 2, 0.5, u, v) - 0.5);
    // Distance, in repeats, from `x` to the nearest line of a grid offset by `shift` cells.
    let line = |x: f64, shift: f64| {
        let c = x * MESH_CELLS - shift;
        (c - c.round()).abs() / MESH_CELLS
    };
    let cover = |d: f64| 1.0 - smoothstep(half, half + 1.0 / px, d);
    let mut w = cover(line(wu, 0.0)).max(cover(line(wv, 0.0)));
    // Panels 3 m along `u` (one repeat) and 1.5 m along `v`: an overlap of two cells.
    let band = 2.0 / MESH_CELLS;
    if wu.rem_euclid(1.0) < band || wv.rem_euclid(0.5) < band {
        w = w.max(cover(line(wu, 0.35))).max(cover(line(wv, 0.35)));
    }
    w
}

/// The maps of a material with `look` and mean colour `colour` (linear RGB), `size` pixels
/// per `repeat` metres, from `seed`.
pub fn maps(look: Look, colour: [f32; 3], seed: u64, size: u32, repeat: f64) -> Maps {
    let n = Tileable::new(seed);
    let s = size as usize;
    let rows: Vec<Vec<Texel>> = (0..s)
        .into_par_iter()
        .map(|row| {
            let v = 1.0 - (row as f64 + 0.5) / s as f64;
            (0..s)
                .map(|col| {
                    let u = (col as f64 + 0.5) / s as f64;
                    let grain = n.hash(99, col as i64, row as i64);
                    sample(look, &n, u, v, grain, repeat, f64::from(size))
                })
                .collect()
        })
        .collect();
    let at = |row: usize, col: usize| rows[row % s][col % s];
    // Height differences per pixel to slopes: relief `depth` metres over pixels of
    // `repeat / size` metres.
    let k = look.depth() * s as f64 / (2.0 * repeat);
    let mut albedo = Vec::with_capacity(3 * s * s);
    let mut normal = Vec::with_capacity(3 * s * s);
    let mut roughness = Vec::with_capacity(3 * s * s);
    for row in 0..s {
        for col in 0..s {
            let t = at(row, col);
            for (c, w) in colour.iter().zip(WIRE_COLOUR) {
                let rock = f64::from(*c) * (1.0 + 0.9 * t.tone).max(0.05);
                let wire = w * (1.0 + 0.3 * t.tone).max(0.05);
                albedo.push(srgb(rock + t.wire * (wire - rock)));
            }
            let dx = at(row, col + 1).h - at(row, col + s - 1).h;
            // Rows run down the image, `v` up it.
            let dy = at(row + s - 1, col).h - at(row + 1, col).h;
            let (nx, ny, nz) = (-k * dx, -k * dy, 1.0);
            let len = (nx * nx + ny * ny + nz * nz).sqrt();
            for c in [nx / len, ny / len, nz / len] {
                normal.push(((c + 1.0) * 0.5 * 255.0).round() as u8);
            }
            let r = (t.rough.clamp(0.0, 1.0) * 255.0).round() as u8;
            roughness.extend_from_slice(&[r, r, r]);
        }
    }
    Maps {
        size,
        albedo,
        normal,
        roughness,
    }
}

/// An 8-bit RGB PNG of `size` x `size` pixels.
pub fn png(size: u32, rgb: &[u8]) -> Vec<u8> {
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, size, size);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Fast);
        let mut w = enc
            .write_header()
            .expect("a PNG header into memory cannot fail");
        w.write_image_data(rgb)
            .expect("an image of the header's size into memory cannot fail");
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looks_by_name_with_rock_for_the_rest() {
        assert_eq!(Look::of("mine-floor"), Look::Floor);
        assert_eq!(Look::of("striated-rock"), Look::Striated);
        assert_eq!(Look::of("rock-pile"), Look::Pile);
        assert_eq!(Look::of("rock-bolt"), Look::Metal);
        assert_eq!(Look::of("mine-wall"), Look::Rock);
        assert_eq!(Look::of("anything"), Look::Rock);
        assert_eq!(Look::of("meshed-wall"), Look::Mesh);
    }

    #[test]
    fn half_barrels_only_darken_the_rock_along_thin_lines() {
        let rock = maps(Look::Rock, [0.4; 3], 7, 128, 3.0);
        let marked = maps(Look::Blasted, [0.4; 3], 7, 128, 3.0);
        let differs: Vec<usize> = (0..128 * 128)
            .filter(|&i| rock.albedo[3 * i] != marked.albedo[3 * i])
            .collect();
        // Four grooves of 45 mm (about 2 pixels each) over some of their length: a few
        // percent of the pixels, each darker.
        let share = differs.len() as f64 / (128.0 * 128.0);
        assert!((0.01..0.12).contains(&share), "{share}");
        assert!(
            differs
                .iter()
                .all(|&i| marked.albedo[3 * i] < rock.albedo[3 * i])
        );
    }

    #[test]
    fn mesh_wires_cross_every_row_and_column() {
        let size = 300;
        let m = maps(Look::Mesh, [0.4; 3], 7, size, 3.0);
        let n = size as usize;
        // Every row and every column meets the wires of the 30 cells across (10 pixels each).
        let bright = |i: usize| m.roughness[3 * i] < 150;
        for k in 0..n {
            let in_row = (0..n).filter(|&c| bright(k * n + c)).count();
            let in_col = (0..n).filter(|&r| bright(r * n + k)).count();
            assert!(in_row >= 25 && in_col >= 25, "{k}: {in_row} {in_col}");
        }
    }

    #[test]
    fn maps_have_contrast_and_wrap() {
        let m = maps(Look::Rock, [0.4, 0.4, 0.4], 7, 64, 3.0);
        assert_eq!(m.albedo.len(), 64 * 64 * 3);
        let (lo, hi) = m
            .albedo
            .iter()
            .fold((255u8, 0u8), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(hi - lo > 60, "albedo from {lo} to {hi}");
        // Another seed, another texture.
        assert_ne!(maps(Look::Rock, [0.4; 3], 8, 64, 3.0).albedo, m.albedo);
    }
}
