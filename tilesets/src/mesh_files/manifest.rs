//! The manifest file of the `mesh-files` tile set (see the module above): its keys, and why
//! one cannot be opened.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use subtgraph_core::grid::Direction;
use subtgraph_core::tile::TileKind;

use super::load::MeshFileError;

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
    /// An albedo image (PNG) for it, relative to the manifest's `root`: copied into the world
    /// folder's `mesh/textures/` and named by every format, on the tiles' own texture
    /// coordinates.
    #[serde(default)]
    pub texture: Option<String>,
}

pub(super) fn grey() -> [f32; 3] {
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

/// The tile kind a `[[tile]]` entry names.
pub(super) fn kind_named(name: &str) -> Option<TileKind> {
    TileKind::ALL.into_iter().find(|k| k.name() == name)
}

pub(super) fn direction_named(name: &str) -> Option<Direction> {
    match name {
        "east" => Some(Direction::East),
        "north" => Some(Direction::North),
        "west" => Some(Direction::West),
        "south" => Some(Direction::South),
        _ => None,
    }
}

/// For a `shaft-up` tile with a side opening at its top: where to cut it (metres above the
/// foot's floor), how far it climbs (metres) and the quarter turns that take its top opening
/// east. `None` for other kinds and for `top = "none"`; the problem, naming the key, for
/// `top` or `split` on another kind, an unknown direction, or a split outside the climb.
pub(super) fn shaft_top(
    path: &Path,
    manifest: &Manifest,
    t: &ManifestTile,
    kind: TileKind,
) -> Result<Option<(f32, f32, u8)>, ManifestError> {
    let value = |problem: String| ManifestError::Value {
        path: path.to_owned(),
        problem,
    };
    let name = subtgraph_core::error::excerpt(&t.kind);
    if kind != TileKind::ShaftUp {
        return match (&t.top, t.split) {
            (None, None) => Ok(None),
            _ => Err(value(format!(
                "tile '{name}': `top` and `split` describe a shaft; give them on the \
                 kind = \"shaft-up\" tile only"
            ))),
        };
    }
    let top = t.top.as_deref().unwrap_or("west");
    if top == "none" {
        return match t.split {
            None => Ok(None),
            Some(_) => Err(value(format!(
                "tile '{name}': split = {}: a shaft with top = \"none\" is not cut; remove \
                 `split` or say which way the top opens",
                t.split.unwrap_or_default()
            ))),
        };
    }
    let d = direction_named(top).ok_or_else(|| {
        value(format!(
            "tile '{name}': top = \"{top}\": use east, north, west, south or none"
        ))
    })?;
    let Some(rise) = manifest.shaft_rise else {
        return Err(value(format!(
            "tile '{name}': its top opens {top} (top = \"{top}\", the default), so the landing \
             gets the upper part of the shaft: set shaft_rise (how far the shaft climbs, file \
             units), or top = \"none\" if the top has no side opening"
        )));
    };
    if !(rise.is_finite() && rise > 0.0) {
        return Err(value(format!(
            "shaft_rise = {rise}: give the climb as a positive number"
        )));
    }
    let split = t.split.unwrap_or(0.5 * rise);
    if !(split.is_finite() && split > 0.0 && split < rise) {
        return Err(value(format!(
            "tile '{name}': split = {split}: cut the shaft between its foot and its top, \
             above 0 and below shaft_rise = {rise}"
        )));
    }
    let turns = (4 - d as u8) % 4;
    Ok(Some((
        (split * manifest.scale) as f32,
        (rise * manifest.scale) as f32,
        turns,
    )))
}
