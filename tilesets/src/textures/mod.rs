//! Textures for the procedural tile sets: per material an albedo, a normal and a roughness
//! map, tileable, written once per world under `mesh/textures/` and named by the materials.
//!
//! ```toml
//! [tileset]
//! type = "mine"
//! textures = "procedural"   # the default; "none" for plain colours (no image files)
//! texture_size = 256        # pixels per texture repeat (3 m): 256 is about 12 mm a pixel
//!
//! # or: your own images for some materials (PNG, relative to this file); the others stay
//! # procedural. A path alone is the albedo; a table may give all three maps.
//! [tileset.textures]
//! mine-wall = "images/shotcrete.png"
//! mine-floor = { albedo = "floor.png", normal = "floor-normal.png", roughness = "floor-rough.png" }
//! ```
//!
//! Procedural textures come from the world seed through a stream of their own
//! (`texture:<material>`), so turning them on or off changes no other file's content.

mod noise;
pub mod rock;

use std::collections::BTreeMap;

use rayon::prelude::*;
use subtgraph_core::error::ConfigError;
use subtgraph_core::mesh::{ImageFile, Material};
use subtgraph_core::params::Params;
use subtgraph_core::rng::derive_seed;

pub use noise::Tileable;

/// Pixels per texture repeat unless `texture_size` says otherwise.
pub const DEFAULT_SIZE: u32 = 256;

/// The three maps of a material, in file-name order.
const MAPS: [&str; 3] = ["albedo", "normal", "roughness"];

/// A tile set's texture settings: whether to make procedural textures, how large, and the
/// user's own images by material.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Textures {
    procedural: bool,
    size: u32,
    /// Material name to its user images (albedo, normal, roughness; PNG bytes).
    user: BTreeMap<String, [Option<Vec<u8>>; 3]>,
    /// Material name to the look its tile set asks for, where not the one its name gives.
    looks: BTreeMap<String, rock::Look>,
}

/// The file name stem of a material's maps: its name with anything but letters, digits, `-`
/// and `_` replaced.
fn stem(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn path_of(name: &str, map: usize) -> String {
    format!("textures/{}-{}.png", stem(name), MAPS[map])
}

pub use subtgraph_core::budget::{MAX_IMAGE_SIDE, image_too_large};

/// Reads one of the user's images for `key`, refusing anything but a PNG of at most
/// [`MAX_IMAGE_SIDE`] pixels a side.
pub fn read_png(params: &Params, key: &str, written: &str) -> Result<Vec<u8>, ConfigError> {
    let path = params.resolve_path(written);
    let bytes = std::fs::read(&path).map_err(|e| {
        params.error(
            key,
            format!(
                "cannot read the image `{}`: {e}; give the path of a PNG file, relative to the \
                 pipeline file",
                path.display()
            ),
        )
    })?;
    let reader = png::Decoder::new(std::io::Cursor::new(&bytes))
        .read_info()
        .map_err(|e| {
            params.error(
                key,
                format!(
                    "`{}` is not a PNG image ({e}); convert it to PNG (8-bit RGB or RGBA)",
                    path.display()
                ),
            )
        })?;
    let info = reader.info();
    if let Some(why) = image_too_large(info.width, info.height) {
        return Err(params.error(key, format!("`{}` is {why}", path.display())));
    }
    Ok(bytes)
}

impl Textures {
    /// No textures: plain colours, today's files.
    pub fn none() -> Self {
        Self::default()
    }

    /// From `[tileset] textures` and `texture_size`, for a tile set with these materials.
    pub fn from_params(params: &Params, materials: &[Material]) -> Result<Self, ConfigError> {
        let size = match params.raw("texture_size") {
            None => DEFAULT_SIZE,
            Some(v) => match v.as_integer() {
                Some(s @ 16..=4096) => s as u32,
                _ => {
                    return Err(params.error(
                        "texture_size",
                        "must be a whole number of pixels per texture repeat from 16 to 4096",
                    ));
                }
            },
        };
        let mut t = Textures {
            procedural: true,
            size,
            user: BTreeMap::new(),
            looks: BTreeMap::new(),
        };
        match params.raw("textures") {
            None => {}
            Some(toml::Value::String(s)) if s == "procedural" => {}
            Some(toml::Value::String(s)) if s == "none" => t.procedural = false,
            Some(toml::Value::Table(table)) => {
                for (name, value) in table {
                    let key = format!("textures.{name}");
                    if !materials.iter().any(|m| &m.name == name) {
                        let names: Vec<&str> = materials.iter().map(|m| m.name.as_str()).collect();
                        return Err(params.error(
                            &key,
                            format!(
                                "this tile set has no material `{name}`; its materials are {}",
                                names.join(", ")
                            ),
                        ));
                    }
                    t.user.insert(name.clone(), user_maps(params, &key, value)?);
                }
            }
            Some(_) => {
                return Err(params.error(
                    "textures",
                    "must be \"procedural\" (the default), \"none\" (plain colours), or a table \
                     of your own PNG images by material ([tileset.textures] mine-wall = \
                     \"rock.png\")",
                ));
            }
        }
        Ok(t)
    }

    /// These textures with material `name` drawn with `look` rather than the look its name
    /// gives ([`rock::Look::of`]).
    pub fn with_look(mut self, name: &str, look: rock::Look) -> Self {
        self.looks.insert(name.to_string(), look);
        self
    }

    /// Whether the world gets image files.
    pub fn any(&self) -> bool {
        self.procedural || !self.user.is_empty()
    }

    /// The materials naming their maps.
    pub fn apply(&self, materials: &[Material]) -> Vec<Material> {
        materials
            .iter()
            .map(|m| {
                let mut m = m.clone();
                if self.any() {
                    m.texture = Some(path_of(&m.name, 0));
                    m.normal_map = Some(path_of(&m.name, 1));
                    m.roughness_map = Some(path_of(&m.name, 2));
                }
                m
            })
            .collect()
    }

    /// The image files of these materials for the world with `seed`: the user's where given,
    /// the rest made, `repeat` metres per texture repeat.
    pub fn files(&self, materials: &[Material], seed: u64, repeat: f64) -> Vec<ImageFile> {
        if !self.any() {
            return Vec::new();
        }
        // Materials on threads of their own as well as each one's rows: the rows' noise is
        // most of the work, but each material's assembly and PNG encoding is serial.
        let made: Vec<Option<[Vec<u8>; 3]>> = materials
            .par_iter()
            .map(|m| {
                let user = self.user.get(&m.name);
                if user.is_some_and(|u| u.iter().all(Option::is_some)) {
                    return None;
                }
                let s = derive_seed(seed, &format!("texture:{}", m.name), 0);
                let look = self
                    .looks
                    .get(&m.name)
                    .copied()
                    .unwrap_or_else(|| rock::Look::of(&m.name));
                let maps = rock::maps(look, m.colour, s, self.size, repeat);
                Some([maps.albedo, maps.normal, maps.roughness].map(|p| rock::png(maps.size, &p)))
            })
            .collect();
        let mut out = Vec::new();
        for (m, made) in materials.iter().zip(made) {
            let user = self.user.get(&m.name);
            for k in 0..3 {
                let bytes = match (user.and_then(|u| u[k].as_ref()), &made) {
                    (Some(b), _) => b.clone(),
                    (None, Some(made)) => made[k].clone(),
                    (None, None) => unreachable!("made unless the user gave all three"),
                };
                out.push(ImageFile {
                    path: path_of(&m.name, k),
                    bytes,
                });
            }
        }
        out
    }
}

/// A material's entry in `[tileset.textures]`: a path (the albedo) or a table of maps.
fn user_maps(
    params: &Params,
    key: &str,
    value: &toml::Value,
) -> Result<[Option<Vec<u8>>; 3], ConfigError> {
    let mut maps: [Option<Vec<u8>>; 3] = [None, None, None];
    match value {
        toml::Value::String(p) => maps[0] = Some(read_png(params, key, p)?),
        toml::Value::Table(t) => {
            for (k, v) in t {
                let sub = format!("{key}.{k}");
                let Some(i) = MAPS.iter().position(|m| m == k) else {
                    return Err(params.error(
                        &sub,
                        "unknown map; give `albedo`, `normal` and/or `roughness` (PNG paths)",
                    ));
                };
                let Some(p) = v.as_str() else {
                    return Err(params.error(&sub, "must be the path of a PNG file"));
                };
                maps[i] = Some(read_png(params, &sub, p)?);
            }
        }
        _ => {
            return Err(params.error(
                key,
                "must be the path of a PNG file (the albedo) or a table { albedo = \"...\", \
                 normal = \"...\", roughness = \"...\" }",
            ));
        }
    }
    Ok(maps)
}
