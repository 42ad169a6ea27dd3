//! `mesh-files`: tiles from your own meshes (the DARPA SubT tiles, scanned sections), mapped
//! to tile kinds by a TOML manifest.
//!
//! ```toml
//! root = "../assets/cave-type-b"  # where the files are, relative to the manifest
//! pitch = 80.0                     # metres between opposite openings in the files
//! scale = 1.0                      # file units to metres
//! up = "y"                         # the files' up axis: "y" or "z"
//! shaft_rise = 64.0                # metres a shaft tile climbs
//!
//! [[material]]                     # optional: surface materials by part name
//! name = "cave-wall"
//! match = "CaveWall"
//! colour = [0.46, 0.40, 0.33]
//!
//! [[tile]]
//! kind = "straight"                # dead-end, straight, corner, t-junction, intersection,
//! files = ["straight_01.obj"]      #   shaft-up, shaft-landing
//! # rotation = 1                   # quarter turns from the kind's base orientation, when the
//!                                  #   openings cannot be read from the mesh
//!
//! [[tile]]
//! kind = "dead-end"
//! files = ["corner_01.obj"]        # a corner...
//! cap = "cap.obj"                  # ...closed by a cap on its second opening
//! cap_faces = "north"              # which way the cap's open side faces in its file
//!
//! [[tile]]
//! kind = "shaft-up"                # its foot opens like a dead end (rotation: of the foot)
//! files = ["shaft.obj"]
//! top = "west"                     # where its top opens when its foot faces east (default
//!                                  #   "west"; "none": no side opening at the top)
//! split = 32.0                     # where it is cut, above the foot's floor, file units
//!                                  #   (default: half of shaft_rise)
//!
//! [[tile]]
//! kind = "elevation"               # a straight whose floor climbs: hills on straight runs
//! files = ["elevation.obj"]
//! rise = 32.0                      # how far the floor climbs, low opening to high, metres
//!                                  #   (file units times scale, as pitch)
//! rate = 0.3                       # share of straight runs that get a hill, 0 to 1
//! # rotation = 3                   # quarter turns from low opening west, high east (default:
//!                                  #   measured on the floor at its openings)
//! ```
//!
//! With an `elevation` tile, runs of straight tiles get hills (see `elevation.rs`): the
//! elevation tile at each end of the run, the straights between lifted by `rise`.
//! `[tileset] elevation_rate` overrides the manifest's `rate` for one world.
//!
//! A shaft tile whose top opens sideways is cut at `split` into the foot's part and the
//! landing's part, each turned for its own corridor (see `shaft.rs`); with `top = "none"` the
//! whole tile stands at the foot and the landing gets the dead end's tile.
//!
//! Each distinct file is loaded once and reused by every tile that names it. The meshes are
//! scaled uniformly so that the manifest's pitch becomes `world.tile_pitch`. A tile's file is
//! chosen by the tile's own seed, so the same world always gets the same files.

mod elevation;
mod load;
mod shaft;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use serde::Deserialize;
use subtgraph_core::Layout;
use subtgraph_core::budget::TileTriangles;
use subtgraph_core::error::ConfigError;
use subtgraph_core::grid::{Cell, Direction, Openings, rotate_openings};
use subtgraph_core::mesh::{Material, Mesh};
use subtgraph_core::params::Params;
use subtgraph_core::rng::WorldRng;
use subtgraph_core::tile::TileKind;
use subtgraph_core::tileset::{Seams, TileContext, TileGeometry, TileSet, TileSetError};

pub use load::{MeshFileError, Part, load};

/// Why a manifest cannot be opened. Each message names the manifest (and the file, for a
/// mesh) and what to change.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ManifestError {
    /// The manifest itself cannot be read.
    #[error("cannot read the manifest {}: {reason}", path.display())]
    Unreadable {
        /// The manifest.
        path: PathBuf,
        /// What the system reported.
        reason: String,
    },
    /// Not valid TOML, or a key of the wrong type or unknown: `message` is the TOML reader's,
    /// with its line and column.
    #[error("{}: {message}", path.display())]
    Syntax {
        /// The manifest.
        path: PathBuf,
        /// The reader's message.
        message: String,
    },
    /// A value out of its range: `problem` names the key, its value and the values allowed
    /// (`"scale must be positive"`).
    #[error("{}: {problem}", path.display())]
    Value {
        /// The manifest.
        path: PathBuf,
        /// The key, what is wrong with it and what to write instead.
        problem: String,
    },
    /// A `[[tile]]` entry whose `kind` is not a tile kind.
    #[error(
        "{}: unknown tile kind '{kind}'; the kinds are {} and elevation",
        path.display(),
        TileKind::ALL.map(TileKind::name).join(", ")
    )]
    UnknownKind {
        /// The manifest.
        path: PathBuf,
        /// The kind as written.
        kind: String,
    },
    /// Two `[[tile]]` entries for one kind.
    #[error("{}: two [[tile]] entries for '{kind}'", path.display())]
    DuplicateKind {
        /// The manifest.
        path: PathBuf,
        /// The kind.
        kind: String,
    },
    /// A listed file that is not there.
    #[error(
        "{}: the file {} does not exist (root is {}); fix the path or `root`",
        path.display(),
        file.display(),
        root.display()
    )]
    MissingFile {
        /// The manifest.
        path: PathBuf,
        /// The file, joined to `root`.
        file: PathBuf,
        /// The folder files are relative to.
        root: PathBuf,
    },
    /// A listed file that cannot be loaded.
    #[error("{}: {source}", path.display())]
    Mesh {
        /// The manifest.
        path: PathBuf,
        /// Why the file cannot be loaded.
        source: MeshFileError,
    },
    /// A tile file whose openings are not where its kind and the pitch put them.
    #[error(
        "{}: {file} is listed as {kind} but opens {found} at ±{half} m from its centre; check \
         the kind, `pitch` and `scale`, or give `rotation`",
        path.display()
    )]
    Openings {
        /// The manifest.
        path: PathBuf,
        /// The file, as listed.
        file: String,
        /// The kind it is listed as.
        kind: String,
        /// Where it opens (`"east and west"`, `"nowhere"`).
        found: String,
        /// Half the pitch, metres.
        half: f64,
    },
    /// A `pitch` the meshes contradict: `measured` is what they show, `suggested` the
    /// `pitch` to write (in file units when `scale` is not 1).
    #[error(
        "{}: pitch = {pitch}: the meshes' openings are {measured} m apart; set pitch = \
         {suggested}{units} (measured on the tiles that open on opposite sides)",
        path.display()
    )]
    Pitch {
        /// The manifest.
        path: PathBuf,
        /// The pitch as written.
        pitch: f64,
        /// The measured distance between openings, rounded, metres.
        measured: String,
        /// The pitch to write, rounded.
        suggested: String,
        /// `" (in file units, with scale = ...)"` or empty.
        units: String,
    },
}

/// The manifest file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// What this tile set is.
    #[serde(default)]
    pub description: String,
    /// Folder the files are in, relative to the manifest.
    #[serde(default)]
    pub root: Option<String>,
    /// Metres between opposite openings in the files (after `scale`).
    pub pitch: f64,
    /// File units to metres.
    #[serde(default = "one")]
    pub scale: f64,
    /// The files' up axis.
    #[serde(default = "z_up")]
    pub up: String,
    /// Metres a shaft tile climbs (after `scale`).
    #[serde(default)]
    pub shaft_rise: Option<f64>,
    /// Surface materials, matched to part names by prefix; the first is the fallback.
    #[serde(default, rename = "material")]
    pub materials: Vec<ManifestMaterial>,
    /// Tiles by kind.
    #[serde(rename = "tile")]
    pub tiles: Vec<ManifestTile>,
}

fn one() -> f64 {
    1.0
}
fn z_up() -> String {
    "z".into()
}

/// `[[material]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ManifestMaterial {
    /// Name in the world's files.
    pub name: String,
    /// Part-name prefix that selects it.
    #[serde(rename = "match", default)]
    pub matches: Option<String>,
    /// Diffuse colour.
    #[serde(default = "grey")]
    pub colour: [f32; 3],
}

fn grey() -> [f32; 3] {
    [0.5, 0.48, 0.45]
}

/// `[[tile]]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ManifestTile {
    /// The tile kind this entry serves.
    pub kind: String,
    /// Mesh files, one drawn per tile.
    pub files: Vec<String>,
    /// Quarter turns of the files from the kind's base orientation (default: read from the
    /// openings of the mesh).
    #[serde(default)]
    pub rotation: Option<u8>,
    /// A cap closing the second opening (dead ends made from corners).
    #[serde(default)]
    pub cap: Option<String>,
    /// The direction the cap's open side faces in its file.
    #[serde(default)]
    pub cap_faces: Option<String>,
    /// `shaft-up` only: which way the shaft's top opening faces when its foot opening faces
    /// east (the kind's base orientation): `"west"` (the default, the DARPA vertical shaft's),
    /// `"east"`, `"north"`, `"south"`, or `"none"` for a top without a side opening (the
    /// landing then gets a dead-end tile over it).
    #[serde(default)]
    pub top: Option<String>,
    /// `shaft-up` only: the height above the foot's floor (file units, like `shaft_rise`) where
    /// the tile is cut into the foot's part and the landing's part (default: half the rise).
    #[serde(default)]
    pub split: Option<f64>,
    /// `elevation` only: how far the floor climbs from the low opening to the high one
    /// (file units times `scale`: metres at the manifest's `pitch`).
    #[serde(default)]
    pub rise: Option<f64>,
    /// `elevation` only: the share of runs of straight tiles that get a hill, 0 to 1.
    #[serde(default)]
    pub rate: Option<f64>,
}

/// A loaded, oriented mesh in metres, up axis z, rotated to its kind's base orientation.
#[derive(Clone, Debug)]
struct Asset {
    mesh: Mesh,
    /// A shaft with a side opening at its top: its foot's and its landing's parts.
    shaft: Option<shaft::ShaftParts>,
}

#[derive(Clone, Debug)]
struct Entry {
    assets: Vec<Arc<Asset>>,
    cap: Option<Arc<Asset>>,
}

/// The manifest's `elevation` tile: its files (base orientation: low opening west), how far
/// they climb (metres at the manifest's pitch) and the share of straight runs that get a hill.
#[derive(Clone, Debug)]
struct Hills {
    entry: Entry,
    rise: f64,
    rate: f64,
}

/// The mesh-file tile set.
pub struct MeshFiles {
    manifest_path: PathBuf,
    manifest: Manifest,
    entries: BTreeMap<TileKind, Entry>,
    hills: Option<Hills>,
    materials: Vec<Material>,
    loads: Arc<Mutex<usize>>,
}

fn kind_named(name: &str) -> Option<TileKind> {
    TileKind::ALL.into_iter().find(|k| k.name() == name)
}

fn direction_named(name: &str) -> Option<Direction> {
    match name {
        "east" => Some(Direction::East),
        "north" => Some(Direction::North),
        "west" => Some(Direction::West),
        "south" => Some(Direction::South),
        _ => None,
    }
}

/// Rotates `(x, y)` by `q` quarter turns counter-clockwise.
fn turn(p: [f32; 3], q: u8) -> [f32; 3] {
    (0..q % 4).fold(p, |[x, y, z], _| [-y, x, z])
}

impl MeshFiles {
    /// Reads `[tileset] manifest = "..."` (relative to the pipeline file) and loads every file
    /// the manifest names, once each.
    pub fn from_params(p: &Params) -> Result<Self, ConfigError> {
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Settings {
            manifest: String,
            /// Overrides the manifest's elevation `rate`.
            #[serde(default)]
            elevation_rate: Option<f64>,
        }
        let s: Settings = p.deserialize()?;
        let path = p.resolve_path(&s.manifest);
        let mut set = Self::open(&path).map_err(|e| p.error("manifest", e.to_string()))?;
        if let Some(rate) = s.elevation_rate {
            if !(0.0..=1.0).contains(&rate) {
                return Err(p.error(
                    "elevation_rate",
                    format!(
                        "elevation_rate = {rate}: give the share of straight runs that get a \
                         hill, from 0 to 1"
                    ),
                ));
            }
            let Some(hills) = &mut set.hills else {
                return Err(p.error(
                    "elevation_rate",
                    format!(
                        "{} has no [[tile]] kind = \"elevation\" to make hills of; add one or \
                         remove elevation_rate",
                        path.display()
                    ),
                ));
            };
            hills.rate = rate;
        }
        Ok(set)
    }

    /// Opens a manifest and loads its meshes. The error names the file and what to change.
    pub fn open(path: &Path) -> Result<Self, ManifestError> {
        let text = std::fs::read_to_string(path).map_err(|e| ManifestError::Unreadable {
            path: path.to_owned(),
            reason: e.to_string(),
        })?;
        let manifest: Manifest = toml::from_str(&text).map_err(|e| ManifestError::Syntax {
            path: path.to_owned(),
            message: match e.span() {
                Some(_) => e.to_string().trim().to_owned(),
                // A key nested past the reader's limit, which it does not place.
                None => {
                    let (at, message) = subtgraph_core::nesting::explain(&text, None, e.message());
                    let line = text[..at].matches('\n').count() + 1;
                    format!("line {line}: {message}")
                }
            },
        })?;
        let value = |problem: String| ManifestError::Value {
            path: path.to_owned(),
            problem,
        };
        let root = path
            .parent()
            .unwrap_or(Path::new("."))
            .join(manifest.root.as_deref().unwrap_or("."));
        if !(manifest.pitch.is_finite() && manifest.pitch > 0.0) {
            return Err(value("pitch must be a positive number of metres".into()));
        }
        if !(manifest.scale.is_finite() && manifest.scale > 0.0) {
            return Err(value("scale must be positive".into()));
        }
        if manifest.up != "y" && manifest.up != "z" {
            return Err(value(format!(
                "up = \"{}\": the up axis is \"y\" or \"z\"",
                manifest.up
            )));
        }
        for t in &manifest.tiles {
            if let Some(r) = t.rotation.filter(|&r| r > 3) {
                return Err(value(format!(
                    "tile '{}': rotation = {r}: give the quarter turns as 0, 1, 2 or 3",
                    subtgraph_core::error::excerpt(&t.kind)
                )));
            }
        }
        let mut materials: Vec<Material> = manifest
            .materials
            .iter()
            .map(|m| Material::coloured(&m.name, m.colour))
            .collect();
        if materials.is_empty() {
            materials.push(Material::coloured("rock", grey()));
        }
        let loads = Arc::new(Mutex::new(0usize));
        // Every distinct file once, read in parallel.
        let mut names: Vec<&str> = manifest
            .tiles
            .iter()
            .flat_map(|t| t.files.iter().chain(t.cap.iter()))
            .map(String::as_str)
            .collect();
        names.sort_unstable();
        names.dedup();
        let matchers = materials_of(&manifest);
        let loaded: Vec<(PathBuf, Result<Arc<Mesh>, ManifestError>)> = {
            use rayon::prelude::*;
            names
                .par_iter()
                .map(|file| {
                    let full = root.join(file);
                    let mesh = if full.is_file() {
                        load(&full)
                            .map(|parts| Arc::new(to_metres(&parts, &manifest, &matchers)))
                            .map_err(|source| ManifestError::Mesh {
                                path: path.to_owned(),
                                source,
                            })
                    } else {
                        Err(ManifestError::MissingFile {
                            path: path.to_owned(),
                            file: full.clone(),
                            root: root.clone(),
                        })
                    };
                    (full, mesh)
                })
                .collect()
        };
        let mut cache: BTreeMap<PathBuf, Arc<Mesh>> = BTreeMap::new();
        for (full, mesh) in loaded {
            cache.insert(full, mesh?);
            *loads.lock().expect("not poisoned") += 1;
        }
        let read = |file: &str| -> Result<Arc<Mesh>, ManifestError> {
            Ok(cache[&root.join(file)].clone())
        };
        let mut entries = BTreeMap::new();
        let mut climbing: Option<&ManifestTile> = None;
        for t in &manifest.tiles {
            if t.kind == ELEVATION || t.rise.is_some() || t.rate.is_some() {
                if climbing.replace(t).is_some() {
                    return Err(ManifestError::DuplicateKind {
                        path: path.to_owned(),
                        kind: t.kind.clone(),
                    });
                }
                continue;
            }
            let kind = kind_named(&t.kind).ok_or_else(|| ManifestError::UnknownKind {
                path: path.to_owned(),
                kind: t.kind.clone(),
            })?;
            if t.files.is_empty() {
                return Err(value(format!("tile '{}' lists no files", t.kind)));
            }
            let shape = if t.cap.is_some() {
                TileKind::Corner
            } else {
                kind
            };
            let shaft_top = shaft_top(&manifest, t, kind).map_err(value)?;
            let mut assets = Vec::new();
            for f in &t.files {
                let mesh = read(f)?;
                let rotation = match t.rotation {
                    Some(r) => r,
                    None => {
                        let found = openings(&mesh, manifest.pitch * manifest.scale, shape);
                        (0..4)
                            .find(|&q| rotate_openings(shape.base_openings(), q) == found)
                            .ok_or_else(|| ManifestError::Openings {
                                path: path.to_owned(),
                                file: f.clone(),
                                kind: t.kind.clone(),
                                found: describe(found),
                                half: manifest.pitch * manifest.scale / 2.0,
                            })?
                    }
                };
                // Store rotated back to the base orientation.
                let mut m = (*mesh).clone();
                let back = (4 - rotation) % 4;
                for p in &mut m.positions {
                    *p = turn(*p, back);
                }
                for n in &mut m.normals {
                    *n = turn(*n, back);
                }
                let shaft = shaft_top.map(|(split, rise, top_turn)| {
                    shaft::ShaftParts::new(&m, split, rise, top_turn)
                });
                assets.push(Arc::new(Asset { mesh: m, shaft }));
            }
            let cap = match &t.cap {
                None => None,
                Some(c) => {
                    let mesh = read(c)?;
                    let faces = t.cap_faces.as_deref().unwrap_or("north");
                    let d = direction_named(faces).ok_or_else(|| {
                        value(format!(
                            "cap_faces = \"{faces}\": use east, north, west or south"
                        ))
                    })?;
                    // Turn the cap so it faces north (into a tile from its south opening), and
                    // move it onto the south opening.
                    let q = (Direction::North as u8 + 4 - d as u8) % 4;
                    let half = (0.5 * manifest.pitch * manifest.scale) as f32;
                    let mut m = (*mesh).clone();
                    for p in &mut m.positions {
                        let r = turn(*p, q);
                        *p = [r[0], r[1] - half, r[2]];
                    }
                    for n in &mut m.normals {
                        *n = turn(*n, q);
                    }
                    Some(Arc::new(Asset {
                        mesh: m,
                        shaft: None,
                    }))
                }
            };
            if entries.insert(kind, Entry { assets, cap }).is_some() {
                return Err(ManifestError::DuplicateKind {
                    path: path.to_owned(),
                    kind: t.kind.clone(),
                });
            }
        }
        check_pitch(path, &manifest, &entries)?;
        // After the pitch: the elevation tile's floors are measured at its openings.
        let hills = match climbing {
            Some(t) => Some(elevation_tile(path, &manifest, t, &read)?),
            None => None,
        };
        Ok(Self {
            manifest_path: path.to_owned(),
            manifest,
            entries,
            hills,
            materials,
            loads,
        })
    }

    /// How many files were read from disk (each distinct file once).
    pub fn files_loaded(&self) -> usize {
        *self.loads.lock().expect("not poisoned")
    }

    /// `m` (base orientation, metres) turned `q` quarter turns, scaled to the world's pitch and
    /// moved to the tile's position.
    fn place(&self, ctx: &TileContext<'_>, m: &Mesh, q: u8) -> Mesh {
        let s =
            (ctx.layout.resolved.tile_pitch / (self.manifest.pitch * self.manifest.scale)) as f32;
        let [x, y, z] = ctx.position.map(|v| v as f32);
        Mesh {
            positions: m
                .positions
                .iter()
                .map(|&p| {
                    let r = turn(p, q);
                    [x + s * r[0], y + s * r[1], z + s * r[2]]
                })
                .collect(),
            normals: m.normals.iter().map(|&n| turn(n, q)).collect(),
            uvs: m.uvs.clone(),
            triangles: m.triangles.clone(),
            materials: m.materials.clone(),
        }
    }

    /// A shaft's foot or landing from a shaft tile cut in two (see [`shaft`]): the foot's part
    /// turned for the foot's corridor, or the landing's part (with the collar to the foot's
    /// part) turned for the landing's. Both draw the file the foot draws. `None` when the
    /// manifest's shaft is not cut, or for a shaft end with more than one opening (only
    /// imported grids have those): then the whole shaft stands at the foot, as a dead end's
    /// tile does at the landing.
    fn shaft_part(&self, ctx: &TileContext<'_>) -> Option<Mesh> {
        let kind = ctx.tile.kind;
        let s = match kind {
            TileKind::ShaftUp => ctx.layout.shafts.iter().find(|s| s.up == ctx.cell)?,
            TileKind::ShaftLanding => ctx.layout.shafts.iter().find(|s| s.landing == ctx.cell)?,
            _ => return None,
        };
        let foot = (*ctx.layout.tiles.get(s.up))?;
        let landing = (*ctx.layout.tiles.get(s.landing))?;
        if foot.openings.count_ones() != 1 || landing.openings.count_ones() != 1 {
            return None;
        }
        let entry = self.entries.get(&TileKind::ShaftUp)?;
        let parts = draw(entry, ctx.seed_of(s.up)).shaft.as_ref()?;
        Some(if kind == TileKind::ShaftUp {
            self.place(ctx, &parts.foot, foot.rotation)
        } else {
            let r = (foot.rotation + 4 - landing.rotation) % 4;
            let mut m = self.place(ctx, &parts.landing, landing.rotation);
            m.append(&self.place(ctx, &parts.collars[usize::from(r)], landing.rotation));
            m
        })
    }

    /// The part of a hill the tile at `cell` is, if any (see [`elevation`]).
    fn hill_part(&self, layout: &Layout, cell: Cell) -> Option<elevation::Part> {
        elevation::part(layout, cell, self.hills.as_ref()?.rate)
    }

    /// How far a tile that is `part` of a hill has its floor lifted, lowest and highest
    /// (metres in the world: the manifest's rise scaled with the tiles).
    fn lift(&self, layout: &Layout, part: Option<elevation::Part>) -> [f64; 2] {
        let (Some(h), Some(part)) = (&self.hills, part) else {
            return [0.0, 0.0];
        };
        let rise =
            h.rise * layout.resolved.tile_pitch / (self.manifest.pitch * self.manifest.scale);
        match part {
            elevation::Part::Climb(_) => [0.0, rise],
            elevation::Part::Raised => [rise, rise],
        }
    }

    fn entry(&self, kind: TileKind) -> Option<&Entry> {
        self.entries.get(&kind).or(match kind {
            TileKind::ShaftUp | TileKind::ShaftLanding => self.entries.get(&TileKind::DeadEnd),
            _ => None,
        })
    }
}

/// The manifest's name for the elevation tile, and the label of a hill's ends.
const ELEVATION: &str = "elevation";

/// The `elevation` tile: its files turned so the low opening faces west (the given `rotation`,
/// or the one the floors at its openings show), checked against `rise` and `rate`.
fn elevation_tile(
    path: &Path,
    manifest: &Manifest,
    t: &ManifestTile,
    read: &dyn Fn(&str) -> Result<Arc<Mesh>, ManifestError>,
) -> Result<Hills, ManifestError> {
    let value = |problem: String| ManifestError::Value {
        path: path.to_owned(),
        problem,
    };
    let name = subtgraph_core::error::excerpt(&t.kind);
    if t.kind != ELEVATION {
        return Err(value(format!(
            "tile '{name}': `rise` and `rate` describe hills; give them on the kind = \
             \"elevation\" tile only"
        )));
    }
    if t.cap.is_some() || t.cap_faces.is_some() || t.top.is_some() || t.split.is_some() {
        return Err(value(
            "tile 'elevation': `cap`, `cap_faces`, `top` and `split` are not for the elevation \
             tile; remove them"
                .into(),
        ));
    }
    if t.files.is_empty() {
        return Err(value("tile 'elevation' lists no files".into()));
    }
    let Some(rise) = t.rise else {
        return Err(value(
            "tile 'elevation': give rise, how far its floor climbs from the low opening to the \
             high one (metres, file units times scale)"
                .into(),
        ));
    };
    if !(rise.is_finite() && rise > 0.0) {
        return Err(value(format!(
            "tile 'elevation': rise = {rise}: give the climb as a positive number of metres"
        )));
    }
    let Some(rate) = t.rate else {
        return Err(value(
            "tile 'elevation': give rate, the share of straight runs that get a hill (0 to 1)"
                .into(),
        ));
    };
    if !(0.0..=1.0).contains(&rate) {
        return Err(value(format!(
            "tile 'elevation': rate = {rate}: give the share of straight runs that get a hill, \
             from 0 to 1"
        )));
    }
    let pitch = manifest.pitch * manifest.scale;
    let rise = rise * manifest.scale;
    let mut assets = Vec::new();
    for f in &t.files {
        let mesh = read(f)?;
        let turned = |q: u8| {
            let mut m = (*mesh).clone();
            let back = (4 - q) % 4;
            for p in &mut m.positions {
                *p = turn(*p, back);
            }
            for n in &mut m.normals {
                *n = turn(*n, back);
            }
            m
        };
        // The openings say east-west or north-south; the floors say which end is low.
        let q0 = match t.rotation {
            Some(r) => r,
            None => {
                let found = openings(&mesh, pitch, TileKind::Straight);
                (0..2)
                    .find(|&q| rotate_openings(TileKind::Straight.base_openings(), q) == found)
                    .ok_or_else(|| ManifestError::Openings {
                        path: path.to_owned(),
                        file: f.clone(),
                        kind: t.kind.clone(),
                        found: describe(found),
                        half: pitch / 2.0,
                    })?
            }
        };
        let m = turned(q0);
        let Some([west, east]) = elevation::end_floors(&m, pitch) else {
            return Err(value(format!(
                "tile 'elevation': {f} has no floor near one of its openings (turned {q0} \
                 quarter turns); check `pitch`, `up` and `rotation`"
            )));
        };
        let (m, climb) = match t.rotation {
            _ if east > west => (m, east - west),
            None => (turned(q0 + 2), west - east),
            Some(r) => {
                return Err(value(format!(
                    "tile 'elevation': rotation = {r} puts {f}'s high opening west (floor {west:.1} \
                     m, east {east:.1} m); the base orientation is low west, high east: give \
                     rotation = {}",
                    (r + 2) % 4
                )));
            }
        };
        // Measured a few metres in from the openings, where the floor still climbs.
        if (climb - rise).abs() > 0.25 * rise {
            return Err(value(format!(
                "tile 'elevation': rise = {}: {f}'s floor climbs {climb:.1} m between its \
                 openings (measured); set rise to what the tile climbs",
                rise / manifest.scale
            )));
        }
        assets.push(Arc::new(Asset {
            mesh: m,
            shaft: None,
        }));
    }
    Ok(Hills {
        entry: Entry { assets, cap: None },
        rise,
        rate,
    })
}

/// For a `shaft-up` tile with a side opening at its top: where to cut it (metres above the
/// foot's floor), how far it climbs (metres) and the quarter turns that take its top opening
/// east. `None` for other kinds and for `top = "none"`; the problem, naming the key, for
/// `top` or `split` on another kind, an unknown direction, or a split outside the climb.
fn shaft_top(
    manifest: &Manifest,
    t: &ManifestTile,
    kind: TileKind,
) -> Result<Option<(f32, f32, u8)>, String> {
    let name = subtgraph_core::error::excerpt(&t.kind);
    if kind != TileKind::ShaftUp {
        return match (&t.top, t.split) {
            (None, None) => Ok(None),
            _ => Err(format!(
                "tile '{name}': `top` and `split` describe a shaft; give them on the \
                 kind = \"shaft-up\" tile only"
            )),
        };
    }
    let top = t.top.as_deref().unwrap_or("west");
    if top == "none" {
        return match t.split {
            None => Ok(None),
            Some(_) => Err(format!(
                "tile '{name}': split = {}: a shaft with top = \"none\" is not cut; remove \
                 `split` or say which way the top opens",
                t.split.unwrap_or_default()
            )),
        };
    }
    let d = direction_named(top).ok_or_else(|| {
        format!("tile '{name}': top = \"{top}\": use east, north, west, south or none")
    })?;
    let Some(rise) = manifest.shaft_rise else {
        return Err(format!(
            "tile '{name}': its top opens {top} (top = \"{top}\", the default), so the landing \
             gets the upper part of the shaft: set shaft_rise (how far the shaft climbs, file \
             units), or top = \"none\" if the top has no side opening"
        ));
    };
    if !(rise.is_finite() && rise > 0.0) {
        return Err(format!(
            "shaft_rise = {rise}: give the climb as a positive number"
        ));
    }
    let split = t.split.unwrap_or(0.5 * rise);
    if !(split.is_finite() && split > 0.0 && split < rise) {
        return Err(format!(
            "tile '{name}': split = {split}: cut the shaft between its foot and its top, \
             above 0 and below shaft_rise = {rise}"
        ));
    }
    let turns = (4 - d as u8) % 4;
    Ok(Some((
        (split * manifest.scale) as f32,
        (rise * manifest.scale) as f32,
        turns,
    )))
}

/// The file a tile with this seed gets among its entry's files.
fn draw(entry: &Entry, seed: u64) -> &Asset {
    let mut rng = WorldRng::new(seed, "mesh-file", 0);
    &entry.assets[rng.below(entry.assets.len() as u64) as usize]
}

/// Metres between opposite openings as the meshes have them: the extent of every file that
/// opens on two opposite sides (straights, T-junctions, intersections, in their base
/// orientation) along that axis. Rock may cross the tile boundary but a passage reaches both
/// its openings, so each extent is at least the pitch: the smallest is the measurement.
/// `None` when no listed kind opens on opposite sides.
fn measured_pitch(entries: &BTreeMap<TileKind, Entry>) -> Option<f64> {
    let mut extents = Vec::new();
    for (kind, entry) in entries {
        if entry.cap.is_some() {
            continue;
        }
        let open = kind.base_openings();
        let through = |a: Direction, b: Direction| open & a.bit() != 0 && open & b.bit() != 0;
        for asset in &entry.assets {
            let Some((lo, hi)) = asset.mesh.bounds() else {
                continue;
            };
            if through(Direction::East, Direction::West) {
                extents.push(f64::from(hi[0] - lo[0]));
            }
            if through(Direction::North, Direction::South) {
                extents.push(f64::from(hi[1] - lo[1]));
            }
        }
    }
    extents.into_iter().filter(|e| *e > 0.0).reduce(f64::min)
}

/// Refuses a `pitch` the meshes contradict, saying what the meshes measure: a wrong pitch
/// would otherwise surface later as a shaft that does not fit, or place tiles overlapping or
/// apart.
fn check_pitch(
    path: &Path,
    manifest: &Manifest,
    entries: &BTreeMap<TileKind, Entry>,
) -> Result<(), ManifestError> {
    let Some(measured) = measured_pitch(entries) else {
        return Ok(());
    };
    let declared = manifest.pitch * manifest.scale;
    if (measured / declared - 1.0).abs() <= 0.1 {
        return Ok(());
    }
    let round = |v: f64| {
        if v >= 10.0 {
            format!("{}", v.round())
        } else {
            format!("{}", (v * 100.0).round() / 100.0)
        }
    };
    let units = if manifest.scale == 1.0 {
        String::new()
    } else {
        format!(" (in file units, with scale = {})", manifest.scale)
    };
    Err(ManifestError::Pitch {
        path: path.to_owned(),
        pitch: manifest.pitch,
        measured: round(measured),
        suggested: round(measured / manifest.scale),
        units,
    })
}

fn materials_of(m: &Manifest) -> Vec<(String, u8)> {
    m.materials
        .iter()
        .enumerate()
        .filter_map(|(i, mat)| mat.matches.clone().map(|p| (p, i as u8)))
        .collect()
}

/// The parts of a file as one mesh in metres, z up, materials matched by part name.
fn to_metres(parts: &[Part], manifest: &Manifest, matchers: &[(String, u8)]) -> Mesh {
    let s = manifest.scale as f32;
    let y_up = manifest.up == "y";
    let convert = |p: [f32; 3]| {
        if y_up {
            [p[0] * s, -p[2] * s, p[1] * s]
        } else {
            [p[0] * s, p[1] * s, p[2] * s]
        }
    };
    let mut mesh = Mesh::default();
    for part in parts {
        let material = matchers
            .iter()
            .find(|(prefix, _)| part.name.starts_with(prefix.as_str()))
            .map_or(0, |(_, i)| *i);
        let base = mesh.positions.len() as u32;
        mesh.positions
            .extend(part.positions.iter().map(|&p| convert(p)));
        let unit = |n: [f32; 3]| {
            let n = convert(n);
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-12);
            [n[0] / l, n[1] / l, n[2] / l]
        };
        if part.normals.len() == part.positions.len() {
            mesh.normals.extend(part.normals.iter().map(|&n| unit(n)));
        }
        if part.uvs.len() == part.positions.len() {
            mesh.uvs.extend_from_slice(&part.uvs);
        }
        mesh.triangles
            .extend(part.triangles.iter().map(|t| t.map(|i| i + base)));
        mesh.materials.resize(mesh.triangles.len(), material);
    }
    if mesh.normals.len() != mesh.positions.len() {
        mesh.normals.clear();
    }
    if mesh.uvs.len() != mesh.positions.len() {
        mesh.uvs.clear();
    }
    reindex(mesh)
}

/// Shares vertices that are identical in position, normal and texture coordinate (loaders
/// hand out one vertex per triangle corner; a tile is copied hundreds of times, so this
/// matters).
fn reindex(mesh: Mesh) -> Mesh {
    use std::collections::HashMap;
    use subtgraph_core::mesh::BuildFastHash;
    type Key = ([u32; 3], [u32; 3], [u32; 2]);
    let mut map: HashMap<Key, u32, BuildFastHash> =
        HashMap::with_capacity_and_hasher(mesh.positions.len() / 2, BuildFastHash::default());
    let mut out = Mesh {
        materials: mesh.materials.clone(),
        ..Mesh::default()
    };
    let has_n = !mesh.normals.is_empty();
    let has_uv = !mesh.uvs.is_empty();
    let remap: Vec<u32> = (0..mesh.positions.len())
        .map(|i| {
            let key = (
                mesh.positions[i].map(f32::to_bits),
                if has_n {
                    mesh.normals[i].map(f32::to_bits)
                } else {
                    [0; 3]
                },
                if has_uv {
                    mesh.uvs[i].map(f32::to_bits)
                } else {
                    [0; 2]
                },
            );
            *map.entry(key).or_insert_with(|| {
                out.positions.push(mesh.positions[i]);
                if has_n {
                    out.normals.push(mesh.normals[i]);
                }
                if has_uv {
                    out.uvs.push(mesh.uvs[i]);
                }
                out.positions.len() as u32 - 1
            })
        })
        .collect();
    out.triangles = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
    out
}

/// Which sides of the tile square (side `pitch`) the mesh crosses: the sides with vertices at
/// the tile boundary. A shaft is read on its lower half.
fn openings(mesh: &Mesh, pitch: f64, kind: TileKind) -> Openings {
    let half = (0.5 * pitch) as f32;
    let tol = (0.04 * pitch) as f32;
    let zmax = mesh
        .bounds()
        .map_or(0.0, |(lo, hi)| lo[2] + 0.4 * (hi[2] - lo[2]));
    let low = |p: &&[f32; 3]| kind != TileKind::ShaftUp || p[2] <= zmax;
    let mut counts = [0usize; 4];
    let mut total = 0usize;
    for p in mesh.positions.iter().filter(low) {
        total += 1;
        for d in Direction::ALL {
            let (r, c) = d.step();
            let along = p[0] * c as f32 - p[1] * r as f32;
            if (along - half).abs() <= tol {
                counts[d as usize] += 1;
            }
        }
    }
    let threshold = (total / 200).max(3);
    Direction::ALL
        .into_iter()
        .filter(|d| counts[*d as usize] >= threshold)
        .fold(0, |m, d| m | d.bit())
}

fn describe(o: Openings) -> String {
    let names: Vec<&str> = Direction::ALL
        .into_iter()
        .filter(|d| o & d.bit() != 0)
        .map(|d| match d {
            Direction::East => "east",
            Direction::North => "north",
            Direction::West => "west",
            Direction::South => "south",
        })
        .collect();
    if names.is_empty() {
        "nowhere".into()
    } else {
        names.join(" and ")
    }
}

impl TileSet for MeshFiles {
    fn tile(&self, ctx: &TileContext<'_>) -> Result<TileGeometry, TileSetError> {
        let kind = ctx.tile.kind;
        let place = |m: &Mesh, q: u8| self.place(ctx, m, q);
        let hill = self.hill_part(ctx.layout, ctx.cell);
        let lift = self.lift(ctx.layout, hill)[0] as f32;
        let visual = match (self.shaft_part(ctx), hill, &self.hills) {
            (Some(visual), _, _) => visual,
            (None, Some(elevation::Part::Climb(q)), Some(h)) => {
                place(&draw(&h.entry, ctx.seed).mesh, q)
            }
            (None, _, _) => {
                let entry = self.entry(kind).ok_or_else(|| TileSetError::MissingKinds {
                    tileset: self.manifest_path.display().to_string(),
                    kinds: vec![kind.name().to_owned()],
                })?;
                let asset = draw(entry, ctx.seed);
                let q = ctx.tile.rotation;
                let mut visual = place(&asset.mesh, q);
                if let Some(cap) = &entry.cap {
                    if matches!(kind, TileKind::DeadEnd | TileKind::ShaftLanding)
                        || (kind == TileKind::ShaftUp
                            && !self.entries.contains_key(&TileKind::ShaftUp))
                    {
                        visual.append(&place(&cap.mesh, q));
                    }
                }
                for p in &mut visual.positions {
                    p[2] += lift;
                }
                visual
            }
        };
        let [x, y, z] = ctx.position.map(|v| v as f32);
        let z = z + lift;
        // The snapping grid starts at the tile's south-west corner, so its lines fall on the
        // tile's edges: both tiles of a seam snap their edge vertices onto the seam itself.
        // (On a grid from the world's origin an 80 m tile's edges fall half way between lines,
        // 25 cells of 3.2 m to a tile, and the vertices each side of a seam rounded away from
        // it: a 3.2 m gap in the floor, or rock across the passage, at many seams.)
        let pitch = ctx.layout.resolved.tile_pitch as f32;
        let origin = [x - 0.5 * pitch, y - 0.5 * pitch, z];
        let collision = match hill {
            // A climb snapped to the coarse grid is a staircase of flat and 45-degree pieces
            // a body cannot climb: the climbing tile keeps its own (light) surface, with only
            // the vertices next to its edges put on them, so its seams meet its neighbours'.
            Some(elevation::Part::Climb(_)) => onto_edges(&visual, 0.02 * pitch, origin, pitch),
            _ => simplify(&visual, 0.04 * pitch, origin),
        };
        Ok(TileGeometry {
            visual,
            collision,
            // Mesh tiles are not designed to weld: nothing to merge.
            seams: Seams::None,
            labels: match hill {
                Some(elevation::Part::Climb(_)) => vec![ELEVATION],
                Some(elevation::Part::Raised) => vec!["raised"],
                None => Vec::new(),
            },
            // No rubble or drops (`makes_hazards` is false: assembly refuses a pipeline
            // asking for them, naming the key).
            hazards: Vec::new(),
        })
    }

    fn materials(&self) -> Vec<Material> {
        self.materials.clone()
    }

    fn pitch(&self) -> Option<f64> {
        Some(self.manifest.pitch * self.manifest.scale)
    }

    fn estimate(&self, _world: &Layout, kind: TileKind) -> Option<TileTriangles> {
        // The files' own triangles (the mean over a kind's files, plus its cap); collision is
        // the same surface snapped to a coarser grid, measured at about a third of it on the
        // DARPA tiles, counted at half to stay on the safe side. A landing that gets the upper
        // part of a cut shaft is counted as the whole shaft.
        let cut = self
            .entries
            .get(&TileKind::ShaftUp)
            .filter(|e| e.assets.iter().any(|a| a.shaft.is_some()));
        let entry = match (kind, cut) {
            (TileKind::ShaftLanding, Some(e)) => e,
            _ => self.entry(kind)?,
        };
        let files = entry
            .assets
            .iter()
            .map(|a| a.mesh.triangle_count() as f64)
            .sum::<f64>()
            / entry.assets.len().max(1) as f64;
        let cap = entry
            .cap
            .as_ref()
            .map_or(0.0, |c| c.mesh.triangle_count() as f64);
        Some(TileTriangles {
            visual: files + cap,
            collision: 0.5 * (files + cap),
        })
    }

    fn floor_lift(&self, layout: &Layout, cell: Cell) -> [f64; 2] {
        self.lift(layout, self.hill_part(layout, cell))
    }

    fn check(&self, world: &Layout) -> Result<(), TileSetError> {
        let mut missing = Vec::new();
        for c in world.occupancy.cells() {
            if let Some(t) = world.tiles.get(c) {
                if self.entry(t.kind).is_none() && !missing.contains(&t.kind.name()) {
                    missing.push(t.kind.name());
                }
            }
        }
        if !missing.is_empty() {
            return Err(TileSetError::MissingKinds {
                tileset: self.manifest_path.display().to_string(),
                kinds: missing.into_iter().map(str::to_owned).collect(),
            });
        }
        if let Some(rise) = self.manifest.shaft_rise {
            let scaled = rise * self.manifest.scale * world.resolved.tile_pitch
                / (self.manifest.pitch * self.manifest.scale);
            if world.resolved.levels > 1
                && (scaled - world.resolved.level_height).abs() > 1e-6 * scaled.max(1.0)
            {
                // Suggest only a level height a pipeline accepts (0.5 to 1000 m).
                let fix = if (0.5..=1000.0).contains(&scaled) {
                    format!("set world.level_height = {scaled}")
                } else {
                    format!(
                        "no level height can match that: set world.tile_pitch nearer the tiles' \
                         own {} m",
                        self.manifest.pitch * self.manifest.scale
                    )
                };
                return Err(TileSetError::Unsuited {
                    what: format!(
                        "{}: shaft tiles climb {scaled} m at this pitch but levels are {} m apart",
                        self.manifest_path.display(),
                        world.resolved.level_height
                    ),
                    fix,
                });
            }
        }
        Ok(())
    }
}

/// A lighter copy for collision: vertices snapped to a grid of `cell` metres from `origin` and
/// merged, triangles that collapse dropped, and so are the *fins* the snapping leaves: a bump
/// of the floor whose top snaps down onto the floor keeps its front as a vertical triangle up to
/// a cell high, standing in the passage with free space on both sides. Rays cast down do not
/// see it, but it stops a body (PyBullet's ball on the DARPA cave, at 1842.6, 382.4).
pub fn simplify(mesh: &Mesh, cell: f32, origin: [f32; 3]) -> Mesh {
    let mut out = snap(mesh, cell, origin);
    let flat = Flat::new(&out, cell);
    let fins: Vec<bool> = out
        .triangles
        .iter()
        .map(|&t| is_fin(&out, &flat, t, cell))
        .collect();
    let mut k = 0;
    out.triangles.retain(|_| {
        k += 1;
        !fins[k - 1]
    });
    out
}

/// `mesh`'s surface (positions and triangles, as [`simplify`] gives them) with every vertex
/// within `near` metres of a line of the tile's edges (the square of side `pitch` from
/// `origin`, its south-west corner) moved onto it.
fn onto_edges(mesh: &Mesh, near: f32, origin: [f32; 3], pitch: f32) -> Mesh {
    let mut out = Mesh {
        positions: mesh.positions.clone(),
        triangles: mesh.triangles.clone(),
        ..Mesh::default()
    };
    for p in &mut out.positions {
        for a in 0..2 {
            for edge in [origin[a], origin[a] + pitch] {
                if (p[a] - edge).abs() <= near {
                    p[a] = edge;
                }
            }
        }
    }
    out
}

/// Whether triangle `t` of `mesh` stands vertical with free space on both sides of it half way
/// up (free: between a floor below and a ceiling above, by the facing of the triangles crossed
/// along the vertical line; normals point into the passage).
fn is_fin(mesh: &Mesh, flat: &Flat, t: [u32; 3], cell: f32) -> bool {
    let p = t.map(|i| mesh.positions[i as usize].map(f64::from));
    use subtgraph_core::vec3::{cross, sub};
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let h = (n[0] * n[0] + n[1] * n[1]).sqrt();
    if h == 0.0 || n[2].abs() > 1e-6 * h {
        return false;
    }
    let c = [0, 1, 2].map(|a| (p[0][a] + p[1][a] + p[2][a]) / 3.0);
    // Off the grid's lines and diagonals, so the probe lines cross the floor inside triangles.
    let (off, along) = (0.2371 * f64::from(cell), 0.0137 * f64::from(cell));
    let (nx, ny) = (n[0] / h, n[1] / h);
    [1.0, -1.0].iter().all(|&side| {
        let q = [
            c[0] + side * off * nx - along * ny,
            c[1] + side * off * ny + along * nx,
        ];
        flat.free_at(q, c[2])
    })
}

/// The triangles of a mesh that a vertical line can cross (not vertical), bucketed by squares
/// of the snapping grid for the probes of [`is_fin`].
struct Flat {
    cell: f64,
    triangles: Vec<[[f64; 3]; 3]>,
    buckets: std::collections::HashMap<[i64; 2], Vec<u32>>,
}

impl Flat {
    fn new(mesh: &Mesh, cell: f32) -> Flat {
        let cell = f64::from(cell);
        let mut flat = Flat {
            cell,
            triangles: Vec::new(),
            buckets: std::collections::HashMap::new(),
        };
        for t in &mesh.triangles {
            let p = t.map(|i| mesh.positions[i as usize].map(f64::from));
            if area(&p) == 0.0 {
                continue;
            }
            let k = flat.triangles.len() as u32;
            let lo = [0, 1].map(|a| (p[0][a].min(p[1][a]).min(p[2][a]) / cell).floor() as i64);
            let hi = [0, 1].map(|a| (p[0][a].max(p[1][a]).max(p[2][a]) / cell).floor() as i64);
            for bx in lo[0]..=hi[0] {
                for by in lo[1]..=hi[1] {
                    flat.buckets.entry([bx, by]).or_default().push(k);
                }
            }
            flat.triangles.push(p);
        }
        flat
    }

    /// Whether height `z` on the vertical line through `q` lies between a floor and a ceiling.
    fn free_at(&self, q: [f64; 2], z: f64) -> bool {
        let key = [0, 1].map(|a| (q[a] / self.cell).floor() as i64);
        let Some(bucket) = self.buckets.get(&key) else {
            return false;
        };
        let hits = line_crossings(bucket.iter().map(|&k| &self.triangles[k as usize]), q);
        let mut floor = None;
        for (h, up) in hits {
            if up {
                floor = Some(h);
            } else if let Some(f) = floor.take() {
                if f < z && z < h {
                    return true;
                }
            }
        }
        false
    }
}

/// Where the vertical line through `q` crosses `triangles` (none of them vertical): each
/// crossing's height and whether its triangle faces up (a floor) or down (a ceiling), from the
/// bottom up, a ceiling before a floor at the same height.
fn line_crossings<'a>(
    triangles: impl IntoIterator<Item = &'a [[f64; 3]; 3]>,
    q: [f64; 2],
) -> Vec<(f64, bool)> {
    let mut hits: Vec<(f64, bool)> = Vec::new();
    for p in triangles {
        let a = area(p);
        let w = [
            ((p[1][0] - q[0]) * (p[2][1] - q[1]) - (p[1][1] - q[1]) * (p[2][0] - q[0])) / a,
            ((p[2][0] - q[0]) * (p[0][1] - q[1]) - (p[2][1] - q[1]) * (p[0][0] - q[0])) / a,
        ];
        let w = [w[0], w[1], 1.0 - w[0] - w[1]];
        if w.iter().all(|&b| b >= 0.0) {
            hits.push((w[0] * p[0][2] + w[1] * p[1][2] + w[2] * p[2][2], a > 0.0));
        }
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    hits
}

/// Twice the signed area of a triangle seen from above (positive: its normal points up).
fn area(p: &[[f64; 3]; 3]) -> f64 {
    (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0])
}

/// Vertices snapped to a grid of `cell` metres from `origin` and merged, triangles that
/// collapse (or repeat) dropped.
fn snap(mesh: &Mesh, cell: f32, origin: [f32; 3]) -> Mesh {
    use std::collections::HashMap;
    use subtgraph_core::mesh::BuildFastHash;
    let mut index: HashMap<[i32; 3], u32, BuildFastHash> =
        HashMap::with_capacity_and_hasher(mesh.positions.len() / 4, BuildFastHash::default());
    let mut out = Mesh::default();
    let remap: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let key = [0, 1, 2].map(|a| ((p[a] - origin[a]) / cell).round() as i32);
            *index.entry(key).or_insert_with(|| {
                out.positions
                    .push([0, 1, 2].map(|a| origin[a] + key[a] as f32 * cell));
                out.positions.len() as u32 - 1
            })
        })
        .collect();
    let mut seen: std::collections::HashSet<[u32; 3], BuildFastHash> =
        std::collections::HashSet::with_capacity_and_hasher(
            mesh.triangles.len() / 4,
            BuildFastHash::default(),
        );
    for t in &mesh.triangles {
        let t = t.map(|i| remap[i as usize]);
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            let mut k = t;
            k.sort_unstable();
            if seen.insert(k) {
                out.triangles.push(t);
            }
        }
    }
    out
}

/// The manifests shipped in this repository, by name.
pub fn shipped_manifest(name: &str) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("manifests");
    let p = dir.join(format!("{name}.toml"));
    p.is_file().then_some(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A floor (facing up) and a ceiling 4 m above it (facing down) over `[x0, x1] x [0, 8]`.
    fn slab(m: &mut Mesh, x0: f32, x1: f32) {
        let b = m.positions.len() as u32;
        for z in [0.0, 4.0] {
            for p in [[x0, 0.0], [x1, 0.0], [x1, 8.0], [x0, 8.0]] {
                m.positions.push([p[0], p[1], z]);
            }
        }
        m.triangles.extend([[b, b + 1, b + 2], [b, b + 2, b + 3]]);
        m.triangles
            .extend([[b + 4, b + 6, b + 5], [b + 4, b + 7, b + 6]]);
    }

    fn vertical(m: &mut Mesh, tri: [[f32; 3]; 3]) -> [f32; 3] {
        let b = m.positions.len() as u32;
        m.positions.extend(tri);
        m.triangles.push([b, b + 1, b + 2]);
        tri[2]
    }

    #[test]
    fn the_collision_copy_drops_fins_and_keeps_walls() {
        let mut m = Mesh::default();
        slab(&mut m, 0.0, 8.0);
        // A bump's front snapped vertical, standing in the room; a wall on the room's edge.
        let fin = vertical(&mut m, [[4.0, 2.0, 0.0], [4.0, 6.0, 0.0], [4.1, 4.0, 1.2]]);
        let wall = vertical(&mut m, [[0.0, 2.0, 0.0], [0.0, 6.0, 0.0], [0.1, 4.0, 2.1]]);
        let out = simplify(&m, 1.0, [0.0; 3]);
        let apexes: Vec<[f32; 3]> = out
            .triangles
            .iter()
            .filter_map(|t| {
                let p = t.map(|i| out.positions[i as usize]);
                (p[0][0] == p[1][0] && p[1][0] == p[2][0]).then_some(p[2])
            })
            .collect();
        assert_eq!(
            apexes,
            vec![[0.0, 4.0, 2.0]],
            "{fin:?} dropped, {wall:?} kept"
        );
        assert_eq!(out.triangles.len(), 5);
    }

    #[test]
    fn tiles_snapped_from_their_corners_meet_at_the_seam() {
        // Two tiles 4 m wide whose seam is at x = 4.5, half way between the lines of a grid
        // from the origin; their edges carry rounding noise either side of it.
        let (mut a, mut b) = (Mesh::default(), Mesh::default());
        slab(&mut a, 0.5, 4.4999);
        slab(&mut b, 4.5001, 8.5);
        let edge = |m: &Mesh, max: bool| {
            let xs = m.positions.iter().map(|p| p[0]);
            if max {
                xs.fold(f32::MIN, f32::max)
            } else {
                xs.fold(f32::MAX, f32::min)
            }
        };
        let (sa, sb) = (
            simplify(&a, 1.0, [0.5, 0.0, 0.0]),
            simplify(&b, 1.0, [4.5, 0.0, 0.0]),
        );
        assert_eq!((edge(&sa, true), edge(&sb, false)), (4.5, 4.5));
        // From the world's origin the seam opens a cell wide.
        let (sa, sb) = (simplify(&a, 1.0, [0.0; 3]), simplify(&b, 1.0, [0.0; 3]));
        assert_eq!((edge(&sa, true), edge(&sb, false)), (4.0, 5.0));
    }
}
