//! `mesh-files`: tiles from your own meshes (the DARPA SubT tiles, scanned sections), mapped
//! to tile kinds by a TOML manifest.
//!
//! ```toml
//! root = "../assets/cave-type-b"  # where the files are, relative to the manifest
//! pitch = 80.0                     # metres between opposite openings in the files
//! scale = 1.0                      # file units to metres (0.0001 to 10000)
//! up = "y"                         # the files' up axis: "y" or "z"
//! shaft_rise = 64.0                # how far a shaft tile climbs (file units, less than it is tall)
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

mod collision;
mod elevation;
mod load;
mod manifest;
mod open;
mod prepare;
mod shaft;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use subtgraph_core::Layout;
use subtgraph_core::budget::TileTriangles;
use subtgraph_core::grid::Cell;
use subtgraph_core::mesh::{Material, Mesh};
use subtgraph_core::rng::WorldRng;
use subtgraph_core::tile::TileKind;
use subtgraph_core::tileset::{Seams, TileContext, TileGeometry, TileSet, TileSetError};

use collision::onto_edges;
pub use collision::simplify;
pub use load::{MeshFileError, Part, load};
pub use manifest::{Manifest, ManifestError, ManifestMaterial, ManifestTile};
use prepare::turn;

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
    /// The materials' `texture` images.
    images: Vec<subtgraph_core::mesh::ImageFile>,
    loads: Arc<Mutex<usize>>,
}

impl MeshFiles {
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
pub(super) const ELEVATION: &str = "elevation";

/// The file a tile with this seed gets among its entry's files.
fn draw(entry: &Entry, seed: u64) -> &Asset {
    let mut rng = WorldRng::new(seed, "mesh-file", 0);
    &entry.assets[rng.below(entry.assets.len() as u64) as usize]
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
            // The files' passages are known only from their surface: the survey finds their
            // axis in the free space.
            axis: None,
        })
    }

    fn materials(&self) -> Vec<Material> {
        self.materials.clone()
    }

    fn textures(&self, _seed: u64) -> Result<Vec<subtgraph_core::mesh::ImageFile>, TileSetError> {
        Ok(self.images.clone())
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

/// The manifests shipped in this repository, by name.
pub fn shipped_manifest(name: &str) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("manifests");
    let p = dir.join(format!("{name}.toml"));
    p.is_file().then_some(p)
}
