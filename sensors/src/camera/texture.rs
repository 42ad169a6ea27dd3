//! A material's images (albedo, normal and roughness maps, as the tile sets write them): read
//! from PNG, sampled at texture coordinates. The one place images of a world are read for
//! drawing: the cameras sample them filtered ([`Texture::bilinear`] on a level of a mip
//! pyramid chosen by the pixel's footprint), and `subtgraph preview` samples its albedos at
//! the nearest texel ([`Texture::nearest`]).
//!
//! Coordinates repeat (a texture is tileable), `v` runs up the image (rows are stored from the
//! top, `v = 1`), as OBJ and the tile sets have it. Albedo bytes are sRGB-encoded; they are
//! turned into linear reflectance by a power of 2.2 ([`linear`]), the approximation of the sRGB
//! curve the preview has always used.

use std::sync::OnceLock;

/// What a map holds, which decides how its bytes become numbers and how levels are averaged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Map {
    /// Reflectance, sRGB-encoded bytes (averaged in linear light).
    Albedo,
    /// Tangent-space normals, `(n + 1) / 2` per channel, green up (averaged, renormalised).
    Normal,
    /// Roughness in the first channel, 0 smooth to 1 rough.
    Roughness,
}

/// One level of a texture: `width` x `height` texels of three bytes, rows from the top.
#[derive(Clone, Debug)]
struct Level {
    width: usize,
    height: usize,
    texels: Vec<[u8; 3]>,
}

/// An image of a material, with its mip levels once [`Texture::with_levels`] made them.
#[derive(Clone, Debug)]
pub struct Texture {
    levels: Vec<Level>,
}

/// The largest side a camera keeps of an image (a larger one is halved until it fits): at
/// the tile sets' 3 m a repeat, 1,024 texels are 3 mm, finer than any camera here resolves
/// beyond half a metre, and a 4,096-texel image would hold 16 times the memory.
pub const MAX_SIDE: usize = 1024;

/// The linear value of an sRGB-encoded byte, `(b / 255)^2.2`.
pub fn linear(b: u8) -> f32 {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| (i as f32 / 255.0).powf(2.2)))[usize::from(b)]
}

/// The byte of a linear value, the inverse of [`linear`] (rounded).
fn encode(x: f32) -> u8 {
    (x.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8
}

impl Texture {
    /// Reads a PNG (grey, grey and alpha, RGB or RGBA; 8 or 16 bits): the first level only.
    pub fn decode(bytes: &[u8]) -> Result<Texture, String> {
        let mut dec = png::Decoder::new(std::io::Cursor::new(bytes));
        dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = dec.read_info().map_err(|e| e.to_string())?;
        // The header's size first: the pixels get memory only once it is known to fit.
        let info = reader.info();
        if let Some(why) = subtgraph_core::budget::image_too_large(info.width, info.height) {
            return Err(format!("it is {why}"));
        }
        let mut buf = vec![0; reader.output_buffer_size().unwrap_or(0)];
        let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
        let channels = info.color_type.samples();
        let texels = buf[..info.buffer_size()]
            .chunks_exact(channels)
            .map(|p| match channels {
                1 | 2 => [p[0]; 3],
                _ => [p[0], p[1], p[2]],
            })
            .collect();
        let (width, height) = (info.width as usize, info.height as usize);
        if width == 0 || height == 0 {
            return Err("an empty image".into());
        }
        Ok(Texture {
            levels: vec![Level {
                width,
                height,
                texels,
            }],
        })
    }

    /// The first level's size.
    pub fn size(&self) -> (usize, usize) {
        (self.levels[0].width, self.levels[0].height)
    }

    /// The texel nearest `(u, v)` on the first level, its bytes.
    pub fn nearest(&self, u: f64, v: f64) -> [u8; 3] {
        let l = &self.levels[0];
        let x = ((u.rem_euclid(1.0) * l.width as f64) as usize).min(l.width - 1);
        let y = (((1.0 - v.rem_euclid(1.0)) * l.height as f64) as usize).min(l.height - 1);
        l.texels[y * l.width + x]
    }

    /// The texture halved (2 x 2 averages) until no side exceeds [`MAX_SIDE`], then every
    /// further halving down to one texel, for a map of kind `map`.
    pub fn with_levels(mut self, map: Map) -> Texture {
        while self.levels[0].width.max(self.levels[0].height) > MAX_SIDE {
            let half = halve(&self.levels[0], map);
            self.levels[0] = half;
        }
        while let Some(last) = self.levels.last()
            && (last.width > 1 || last.height > 1)
        {
            let half = halve(last, map);
            self.levels.push(half);
        }
        self
    }

    /// Levels held.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// The texels per repeat of the first level along its longer side.
    pub fn texels_per_repeat(&self) -> f64 {
        self.levels[0].width.max(self.levels[0].height) as f64
    }

    /// The map's value at `(u, v)` on `level` (clamped to those held), interpolated between
    /// the four nearest texels, decoded as `map` says: linear reflectance, a unit normal in
    /// tangent space, or roughness in the first component.
    pub fn bilinear(&self, u: f64, v: f64, level: usize, map: Map) -> [f32; 3] {
        let l = &self.levels[level.min(self.levels.len() - 1)];
        // Texel coordinates (the texel centres at halves); rows run down, v up.
        let x = u * l.width as f64 - 0.5;
        let y = (1.0 - v) * l.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let (xa, xb) = (wrap(x0 as i64, l.width), wrap(x0 as i64 + 1, l.width));
        let (ya, yb) = (wrap(y0 as i64, l.height), wrap(y0 as i64 + 1, l.height));
        let at = |x: usize, y: usize| decode(l.texels[y * l.width + x], map);
        let (a, b, c, d) = (at(xa, ya), at(xb, ya), at(xa, yb), at(xb, yb));
        let mut out = [0.0; 3];
        for k in 0..3 {
            let top = a[k] + fx * (b[k] - a[k]);
            let bottom = c[k] + fx * (d[k] - c[k]);
            out[k] = top + fy * (bottom - top);
        }
        if map == Map::Normal {
            let n = (out[0] * out[0] + out[1] * out[1] + out[2] * out[2]).sqrt();
            if n > 1e-6 {
                out = out.map(|x| x / n);
            } else {
                out = [0.0, 0.0, 1.0];
            }
        }
        out
    }
}

/// A material's three maps interleaved texel by texel (albedo, normal, roughness), for maps of
/// one size: one lookup of four texels reads all three (the cameras sample them at the same
/// place and level, and three lookups cost three times the memory traffic).
#[derive(Clone, Debug)]
pub struct Stack {
    levels: Vec<StackLevel>,
}

#[derive(Clone, Debug)]
struct StackLevel {
    width: usize,
    height: usize,
    texels: Vec<[u8; 8]>,
}

/// A stack's answer at one place: linear reflectance, a unit tangent-space normal, roughness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Linear reflectance per channel.
    pub albedo: [f32; 3],
    /// Unit normal in tangent space.
    pub normal: [f32; 3],
    /// 0 smooth to 1 rough.
    pub roughness: f32,
}

impl Stack {
    /// The three maps (each with its levels made) interleaved, or `None` when their levels'
    /// sizes differ.
    pub fn of(albedo: &Texture, normal: &Texture, roughness: &Texture) -> Option<Stack> {
        let n = albedo.levels.len();
        if normal.levels.len() != n || roughness.levels.len() != n {
            return None;
        }
        let mut levels = Vec::with_capacity(n);
        for ((a, b), c) in albedo
            .levels
            .iter()
            .zip(&normal.levels)
            .zip(&roughness.levels)
        {
            if (a.width, a.height) != (b.width, b.height)
                || (a.width, a.height) != (c.width, c.height)
            {
                return None;
            }
            let texels = a
                .texels
                .iter()
                .zip(&b.texels)
                .zip(&c.texels)
                .map(|((a, b), c)| [a[0], a[1], a[2], b[0], b[1], b[2], c[0], 0])
                .collect();
            levels.push(StackLevel {
                width: a.width,
                height: a.height,
                texels,
            });
        }
        Some(Stack { levels })
    }

    /// The texels per repeat of the first level along its longer side.
    pub fn texels_per_repeat(&self) -> f64 {
        self.levels[0].width.max(self.levels[0].height) as f64
    }

    /// The three maps at `(u, v)` on `level`, each as [`Texture::bilinear`] gives it.
    pub fn sample(&self, u: f64, v: f64, level: usize) -> Sample {
        let l = &self.levels[level.min(self.levels.len() - 1)];
        let x = u * l.width as f64 - 0.5;
        let y = (1.0 - v) * l.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let (xa, xb) = (wrap(x0 as i64, l.width), wrap(x0 as i64 + 1, l.width));
        let (ya, yb) = (wrap(y0 as i64, l.height), wrap(y0 as i64 + 1, l.height));
        let t = [
            l.texels[ya * l.width + xa],
            l.texels[ya * l.width + xb],
            l.texels[yb * l.width + xa],
            l.texels[yb * l.width + xb],
        ];
        let weights = [
            (1.0 - fx) * (1.0 - fy),
            fx * (1.0 - fy),
            (1.0 - fx) * fy,
            fx * fy,
        ];
        let mut v = [0.0f32; 7];
        for (t, w) in t.iter().zip(weights) {
            for k in 0..3 {
                v[k] += w * linear(t[k]);
                v[3 + k] += w * (f32::from(t[3 + k]) / 127.5 - 1.0);
            }
            v[6] += w * f32::from(t[6]) / 255.0;
        }
        let n = [v[3], v[4], v[5]];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        Sample {
            albedo: [v[0], v[1], v[2]],
            normal: if len > 1e-6 {
                n.map(|x| x / len)
            } else {
                [0.0, 0.0, 1.0]
            },
            roughness: v[6],
        }
    }
}

/// `i` wrapped into `0..n` (a mask for the usual power-of-two sides).
#[inline]
fn wrap(i: i64, n: usize) -> usize {
    if n.is_power_of_two() {
        (i as usize) & (n - 1)
    } else {
        i.rem_euclid(n as i64) as usize
    }
}

/// A texel's bytes as numbers.
#[inline]
fn decode(t: [u8; 3], map: Map) -> [f32; 3] {
    match map {
        Map::Albedo => t.map(linear),
        Map::Normal => t.map(|b| f32::from(b) / 127.5 - 1.0),
        Map::Roughness => [f32::from(t[0]) / 255.0, 0.0, 0.0],
    }
}

/// A level halved: each texel the average of the two by two it covers (one, or one by two, at
/// an odd or single side).
fn halve(l: &Level, map: Map) -> Level {
    let (w, h) = ((l.width / 2).max(1), (l.height / 2).max(1));
    let mut texels = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0.0f32; 3];
            let mut n = 0.0;
            for sy in [2 * y, (2 * y + 1).min(l.height - 1)] {
                for sx in [2 * x, (2 * x + 1).min(l.width - 1)] {
                    let v = decode(l.texels[sy * l.width + sx], map);
                    for k in 0..3 {
                        sum[k] += v[k];
                    }
                    n += 1.0;
                }
            }
            let mean = sum.map(|s| s / n);
            texels.push(match map {
                Map::Albedo => mean.map(encode),
                Map::Normal => {
                    let len = (mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2])
                        .sqrt()
                        .max(1e-6);
                    mean.map(|c| ((c / len + 1.0) * 127.5).round().clamp(0.0, 255.0) as u8)
                }
                Map::Roughness => [(mean[0] * 255.0).round() as u8; 3],
            });
        }
    }
    Level {
        width: w,
        height: h,
        texels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(width: u32, height: u32, rgb: &[u8]) -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut enc = png::Encoder::new(&mut bytes, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header().unwrap().write_image_data(rgb).unwrap();
        bytes
    }

    #[test]
    fn textures_repeat_filter_and_halve_to_one_texel() {
        // A 4 x 2 image: left half black, right half white.
        let mut rgb = Vec::new();
        for _ in 0..2 {
            for x in 0..4 {
                rgb.extend_from_slice(&[if x < 2 { 0 } else { 255 }; 3]);
            }
        }
        let t = Texture::decode(&png(4, 2, &rgb))
            .unwrap()
            .with_levels(Map::Albedo);
        assert_eq!(t.level_count(), 3);
        assert_eq!(t.nearest(0.1, 0.5), [0; 3]);
        assert_eq!(t.nearest(1.6, -0.5), [255; 3]);
        // Between the halves' centres the filter blends; the coarsest level is the mean.
        let mid = t.bilinear(0.5, 0.5, 0, Map::Albedo)[0];
        assert!(mid > 0.3 && mid < 0.7, "{mid}");
        let coarse = t.bilinear(0.2, 0.2, 9, Map::Albedo)[0];
        assert!((coarse - 0.5).abs() < 0.01, "{coarse}");
        assert!(Texture::decode(b"not a png").is_err());
    }

    #[test]
    fn a_stack_samples_what_its_three_maps_sample() {
        let (w, h) = (8u32, 4u32);
        let bytes = |k: u32| -> Vec<u8> {
            (0..w * h * 3)
                .map(|i| ((i * 37 + k * 11) % 251) as u8)
                .collect()
        };
        let [a, n, r] = [(0, Map::Albedo), (1, Map::Normal), (2, Map::Roughness)].map(|(k, m)| {
            Texture::decode(&png(w, h, &bytes(k)))
                .unwrap()
                .with_levels(m)
        });
        let stack = Stack::of(&a, &n, &r).unwrap();
        for (u, v, level) in [(0.13, 0.77, 0), (-2.4, 5.1, 1), (0.5, 0.5, 3)] {
            let s = stack.sample(u, v, level);
            let close =
                |x: [f32; 3], y: [f32; 3]| x.iter().zip(y).all(|(a, b)| (a - b).abs() < 1e-5);
            assert!(close(s.albedo, a.bilinear(u, v, level, Map::Albedo)));
            assert!(close(s.normal, n.bilinear(u, v, level, Map::Normal)));
            assert!((s.roughness - r.bilinear(u, v, level, Map::Roughness)[0]).abs() < 1e-5);
        }
    }
}
