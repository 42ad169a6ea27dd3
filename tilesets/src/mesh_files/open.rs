//! Opening a manifest: reading and checking it, loading each distinct mesh file once (in
//! parallel), turning every tile's files to its kind's base orientation, and checking the
//! pitch the meshes measure.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use serde::Deserialize;
use subtgraph_core::error::ConfigError;
use subtgraph_core::grid::{Direction, rotate_openings};
use subtgraph_core::mesh::{Material, Mesh};
use subtgraph_core::params::Params;
use subtgraph_core::tile::TileKind;

use super::elevation::elevation_tile;
use super::load::load;
use super::manifest::{
    Manifest, ManifestError, ManifestTile, direction_named, grey, kind_named, shaft_top,
};
use super::prepare::{describe, materials_of, openings, to_metres, turn};
use super::{Asset, ELEVATION, Entry, MeshFiles, shaft};

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
        let manifest = read_manifest(path)?;
        let root = path
            .parent()
            .unwrap_or(Path::new("."))
            .join(manifest.root.as_deref().unwrap_or("."));
        let mut materials: Vec<Material> = manifest
            .materials
            .iter()
            .map(|m| Material::coloured(&m.name, m.colour))
            .collect();
        let images = material_images(path, &root, &manifest, &mut materials)?;
        if materials.is_empty() {
            materials.push(Material::coloured("rock", grey()));
        }
        let cache = load_files(path, &root, &manifest)?;
        let loads = Arc::new(Mutex::new(cache.len()));
        let read = |file: &str| -> Result<Arc<Mesh>, ManifestError> {
            Ok(cache[&root.join(file)].clone())
        };
        let mut entries = BTreeMap::new();
        let mut climbing: Option<&ManifestTile> = None;
        for t in &manifest.tiles {
            if t.kind == ELEVATION {
                if climbing.replace(t).is_some() {
                    return Err(ManifestError::DuplicateKind {
                        path: path.to_owned(),
                        kind: t.kind.clone(),
                    });
                }
                continue;
            }
            if let Some((key, v)) = [("rise", t.rise), ("rate", t.rate)]
                .into_iter()
                .find_map(|(key, v)| Some((key, v?)))
            {
                return Err(ManifestError::Value {
                    path: path.to_owned(),
                    problem: format!(
                        "tile '{}': {key} = {v}: `rise` and `rate` describe hills; remove it \
                         here and give it on the kind = \"elevation\" tile",
                        subtgraph_core::error::excerpt(&t.kind)
                    ),
                });
            }
            let kind = kind_named(&t.kind).ok_or_else(|| ManifestError::UnknownKind {
                path: path.to_owned(),
                kind: t.kind.clone(),
            })?;
            if entries
                .insert(kind, entry(path, &manifest, t, kind, &read)?)
                .is_some()
            {
                return Err(ManifestError::DuplicateKind {
                    path: path.to_owned(),
                    kind: t.kind.clone(),
                });
            }
        }
        check_pitch(path, &manifest, &entries)?;
        check_shaft_rise(path, &manifest, &entries)?;
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
            images,
            loads,
        })
    }
}

/// Smallest and largest `scale`: a unit conversion (millimetres to kilometres and some), and
/// one that keeps the files' coordinates, turned into metres, ordinary single-precision
/// numbers (an absurd scale makes tiles of no size or of infinite size).
const MIN_SCALE: f64 = 1e-4;
/// See [`MIN_SCALE`].
const MAX_SCALE: f64 = 1e4;

/// `v` as a message quotes it: in exponent form when it is very large or very small
/// (`1e-45`, not 45 zeros).
fn number(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e6 || v.abs() < 1e-3) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// The manifest at `path`, its keys checked one by one.
fn read_manifest(path: &Path) -> Result<Manifest, ManifestError> {
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
    if !(manifest.pitch.is_finite() && manifest.pitch > 0.0) {
        return Err(value("pitch must be a positive number of metres".into()));
    }
    if !(manifest.scale.is_finite() && (MIN_SCALE..=MAX_SCALE).contains(&manifest.scale)) {
        return Err(value(format!(
            "scale = {}: scale turns file units into metres (1 for files in metres, 0.01 in \
             centimetres, 0.001 in millimetres, 0.0254 in inches); give a number from {MIN_SCALE} \
             to {MAX_SCALE}, like scale = 1",
            number(manifest.scale)
        )));
    }
    if let Some(rise) = manifest.shaft_rise.filter(|r| !(r.is_finite() && *r > 0.0)) {
        return Err(value(format!(
            "shaft_rise = {}: give how far the shaft tile's floor climbs from its foot to its \
             top, a positive number of file units (the DARPA vertical shaft's: 64)",
            number(rise)
        )));
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
    Ok(manifest)
}

/// Every distinct file the manifest names (tiles and caps), read once each, in parallel, as
/// meshes in metres, z up, by their path under `root`.
fn load_files(
    path: &Path,
    root: &Path,
    manifest: &Manifest,
) -> Result<BTreeMap<PathBuf, Arc<Mesh>>, ManifestError> {
    use rayon::prelude::*;
    let mut names: Vec<&str> = manifest
        .tiles
        .iter()
        .flat_map(|t| t.files.iter().chain(t.cap.iter()))
        .map(String::as_str)
        .collect();
    names.sort_unstable();
    names.dedup();
    let matchers = materials_of(manifest);
    let loaded: Vec<(PathBuf, Result<Arc<Mesh>, ManifestError>)> = names
        .par_iter()
        .map(|file| {
            let full = root.join(file);
            let mesh = if full.is_file() {
                load(&full)
                    .map(|parts| Arc::new(to_metres(&parts, manifest, &matchers)))
                    .map_err(|source| ManifestError::Mesh {
                        path: path.to_owned(),
                        source,
                    })
            } else {
                Err(ManifestError::MissingFile {
                    path: path.to_owned(),
                    file: full.clone(),
                    root: root.to_owned(),
                })
            };
            (full, mesh)
        })
        .collect();
    let mut cache = BTreeMap::new();
    for (full, mesh) in loaded {
        cache.insert(full, mesh?);
    }
    Ok(cache)
}

/// The files of one `[[tile]]` entry of `kind`, each turned back to the kind's base
/// orientation (by its `rotation`, or the one its openings show), a shaft's cut in two, and its
/// cap turned onto the south opening.
fn entry(
    path: &Path,
    manifest: &Manifest,
    t: &ManifestTile,
    kind: TileKind,
    read: &dyn Fn(&str) -> Result<Arc<Mesh>, ManifestError>,
) -> Result<Entry, ManifestError> {
    let value = |problem: String| ManifestError::Value {
        path: path.to_owned(),
        problem,
    };
    if t.files.is_empty() {
        return Err(value(format!("tile '{}' lists no files", t.kind)));
    }
    let shape = if t.cap.is_some() {
        TileKind::Corner
    } else {
        kind
    };
    let shaft_top = shaft_top(path, manifest, t, kind)?;
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
        let shaft = shaft_top
            .map(|(split, rise, top_turn)| shaft::ShaftParts::new(&m, split, rise, top_turn));
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
            // Turn the cap so it faces north (into a tile from its south opening), and move
            // it onto the south opening.
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
    Ok(Entry { assets, cap })
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

/// Refuses a `shaft_rise` the shaft tile cannot climb: more than the tile's files are tall
/// (the climb is from the foot's floor to the top's floor, both inside the file).
fn check_shaft_rise(
    path: &Path,
    manifest: &Manifest,
    entries: &BTreeMap<TileKind, Entry>,
) -> Result<(), ManifestError> {
    let (Some(rise), Some(shaft)) = (manifest.shaft_rise, entries.get(&TileKind::ShaftUp)) else {
        return Ok(());
    };
    let tall = shaft
        .assets
        .iter()
        .filter_map(|a| a.mesh.bounds())
        .map(|(lo, hi)| f64::from(hi[2] - lo[2]))
        .fold(f64::INFINITY, f64::min)
        / manifest.scale;
    if !tall.is_finite() || rise < tall {
        return Ok(());
    }
    let round = |v: f64| (v * 10.0).round() / 10.0;
    Err(ManifestError::Value {
        path: path.to_owned(),
        problem: format!(
            "shaft_rise = {}: the shaft tile's files are {} file units tall, so its floor \
             cannot climb that far; give how far it climbs from the foot's floor to the top's, \
             below {} (the DARPA vertical shaft, 108 units tall, climbs 64)",
            number(rise),
            round(tall),
            round(tall)
        ),
    })
}

/// The `[[material]] texture` images, read and checked (PNG), each named by its material as
/// `textures/<name>-albedo.png` under the world folder's `mesh/`.
fn material_images(
    path: &Path,
    root: &Path,
    manifest: &Manifest,
    materials: &mut [Material],
) -> Result<Vec<subtgraph_core::mesh::ImageFile>, ManifestError> {
    let mut images = Vec::new();
    for (m, material) in manifest.materials.iter().zip(materials.iter_mut()) {
        let Some(file) = &m.texture else { continue };
        let full = root.join(file);
        let problem = |why: String| ManifestError::Value {
            path: path.to_owned(),
            problem: format!(
                "material '{}': texture = \"{file}\": {why}",
                subtgraph_core::error::excerpt(&m.name)
            ),
        };
        let bytes = std::fs::read(&full).map_err(|e| {
            problem(format!(
                "cannot read {} ({e}); give a PNG file relative to the manifest's root",
                full.display()
            ))
        })?;
        let reader = png::Decoder::new(std::io::Cursor::new(&bytes))
            .read_info()
            .map_err(|e| problem(format!("not a PNG image ({e}); convert it to PNG")))?;
        let (w, h) = (reader.info().width, reader.info().height);
        if let Some(why) = crate::textures::image_too_large(w, h) {
            return Err(problem(why));
        }
        let name: String = m
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let at = format!("textures/{name}-albedo.png");
        material.texture = Some(at.clone());
        images.push(subtgraph_core::mesh::ImageFile { path: at, bytes });
    }
    Ok(images)
}
