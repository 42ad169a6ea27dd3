//! The procedural surfaces: a height field per material made of tileable noise, and from it
//! the albedo (the material's colour, darker in cracks and hollows, speckled), a tangent-space
//! normal map and a roughness map.
//!
//! The look is chosen by the material's name, so a tile set's new materials get a texture
//! without code here: `floor` (and `shotcrete`, `concrete`) a speckled gravel floor,
//! `striated` bedded rock, `pile`/`rubble` blocky rock, `bolt`, `plate`, `duct`, `pipe`,
//! `cable`, `mesh`, `steel`, `metal` a smooth worn metal, anything else (walls) blasted rock:
//! several octaves of value noise cut by a network of cracks. Cracks, speckle and strata put
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
}

impl Look {
    /// The look a material's name asks for.
    pub fn of(name: &str) -> Look {
        let has = |words: &[&str]| words.iter().any(|w| name.contains(w));
        if has(&["striated", "strata", "bedded"]) {
            Look::Striated
        } else if has(&["pile", "rubble", "boulder"]) {
            Look::Pile
        } else if has(&[
            "bolt", "plate", "duct", "pipe", "cable", "mesh", "steel", "metal", "light",
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
            Look::Rock | Look::Striated => 0.03,
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

/// Height in `[0, 1]`, tone (how much lighter or darker than the colour, about `[-1, 1]`)
/// and roughness at texture coordinates `(u, v)` (`grain`: this pixel's own random number).
fn sample(look: Look, n: &Tileable, u: f64, v: f64, grain: f64) -> (f64, f64, f64) {
    // A gentle warp, itself tileable, so cells and bands are not straight.
    let wu = u + 0.04 * (n.fbm(1, 3, 2, 0.5, u, v) - 0.5);
    let wv = v + 0.04 * (n.fbm(2, 3, 2, 0.5, u, v) - 0.5);
    match look {
        Look::Rock => {
            let base = n.fbm(10, 4, 5, 0.6, wu, wv);
            let (f1, f2) = n.cells(20, 7, wu, wv);
            let crack = 1.0 - smoothstep(0.0, 0.07, f2 - f1);
            let fine = smoothstep(0.55, 0.8, n.value(22, 48, u, v));
            let h =
                0.65 * base + 0.25 * (1.0 - f1.min(1.0)) + 0.06 * grain - 0.35 * crack - 0.1 * fine;
            let tone = 1.3 * (base - 0.5) + 0.3 * (grain - 0.5) - 0.55 * crack - 0.25 * fine;
            (h, tone, 0.82 + 0.2 * (base - 0.5) + 0.1 * crack)
        }
        Look::Floor => {
            let base = n.fbm(10, 6, 5, 0.6, wu, wv);
            let (f1, _) = n.cells(20, 40, u, v);
            let pebble = 1.0 - smoothstep(0.15, 0.35, f1);
            let speck = smoothstep(0.9, 0.97, grain) - smoothstep(0.1, 0.03, grain);
            let h = 0.45 * base + 0.35 * pebble + 0.2 * grain;
            let tone = 1.0 * (base - 0.5) + 0.55 * speck + 0.3 * (pebble - 0.3);
            (h, tone, 0.9 - 0.1 * pebble)
        }
        Look::Striated => {
            let w = n.fbm(50, 2, 4, 0.5, u, v);
            let beds = (std::f64::consts::TAU * (9.0 * v + 1.5 * w)).sin();
            let base = n.fbm(10, 4, 5, 0.55, wu, wv);
            let (f1, f2) = n.cells(20, 5, wu, wv);
            let joint = 1.0 - smoothstep(0.0, 0.05, f2 - f1);
            let h = 0.5 + 0.25 * beds + 0.3 * (base - 0.5) + 0.05 * grain - 0.3 * joint;
            let tone = 0.55 * beds + 1.0 * (base - 0.5) + 0.2 * (grain - 0.5) - 0.5 * joint;
            (h, tone, 0.75 + 0.1 * beds)
        }
        Look::Pile => {
            let (f1, f2) = n.cells(20, 9, wu, wv);
            let base = n.fbm(10, 8, 5, 0.55, wu, wv);
            let gap = 1.0 - smoothstep(0.0, 0.1, f2 - f1);
            let dome = (1.0 - f1).clamp(0.0, 1.0);
            let h = 0.6 * dome + 0.3 * base + 0.05 * grain - 0.4 * gap;
            let tone = 0.7 * (dome - 0.5) + 1.0 * (base - 0.5) + 0.25 * (grain - 0.5) - 0.6 * gap;
            (h, tone, 0.85 - 0.1 * dome)
        }
        Look::Metal => {
            let base = n.fbm(10, 8, 5, 0.5, u, v);
            let h = 0.5 + 0.2 * (base - 0.5);
            let tone = 0.5 * (base - 0.5) + 0.1 * (grain - 0.5);
            (h, tone, 0.45 + 0.3 * (base - 0.5))
        }
    }
}

/// The maps of a material named `name` with mean colour `colour` (linear RGB), `size` pixels
/// per `repeat` metres, from `seed`.
pub fn maps(name: &str, colour: [f32; 3], seed: u64, size: u32, repeat: f64) -> Maps {
    let look = Look::of(name);
    let n = Tileable::new(seed);
    let s = size as usize;
    let rows: Vec<Vec<(f64, f64, f64)>> = (0..s)
        .into_par_iter()
        .map(|row| {
            let v = 1.0 - (row as f64 + 0.5) / s as f64;
            (0..s)
                .map(|col| {
                    let u = (col as f64 + 0.5) / s as f64;
                    let grain = n.hash(99, col as i64, row as i64);
                    sample(look, &n, u, v, grain)
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
            let (_, tone, r) = at(row, col);
            for c in colour {
                albedo.push(srgb(f64::from(c) * (1.0 + 0.9 * tone).max(0.05)));
            }
            let dx = at(row, col + 1).0 - at(row, col + s - 1).0;
            // Rows run down the image, `v` up it.
            let dy = at(row + s - 1, col).0 - at(row + 1, col).0;
            let (nx, ny, nz) = (-k * dx, -k * dy, 1.0);
            let len = (nx * nx + ny * ny + nz * nz).sqrt();
            for c in [nx / len, ny / len, nz / len] {
                normal.push(((c + 1.0) * 0.5 * 255.0).round() as u8);
            }
            let r = (r.clamp(0.0, 1.0) * 255.0).round() as u8;
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
    }

    #[test]
    fn maps_have_contrast_and_wrap() {
        let m = maps("mine-wall", [0.4, 0.4, 0.4], 7, 64, 3.0);
        assert_eq!(m.albedo.len(), 64 * 64 * 3);
        let (lo, hi) = m
            .albedo
            .iter()
            .fold((255u8, 0u8), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(hi - lo > 60, "albedo from {lo} to {hi}");
        // Another seed, another texture.
        assert_ne!(maps("mine-wall", [0.4; 3], 8, 64, 3.0).albedo, m.albedo);
    }
}
