//! MuJoCo MJCF: `mujoco/world.xml` including one `mujoco/<part>.xml` per part (per level by
//! default), metres and Z up as MuJoCo's own frame.
//!
//! MuJoCo collides every mesh geom as its convex hull, so the world's collision surface as one
//! mesh would be a solid block. By default each tile gets two height fields instead
//! (`subtgraph_survey::heightfields`): a floor, and a roof turned upside down, sampled `step` metres
//! apart on vertical lines through the closed collision surface; between them is the passage.
//! That is two geoms per tile with no hull to build: MuJoCo 4.0 also spends time quadratic in
//! the number of geoms while it reads a model (every geom added resets its lists of all
//! geoms), so the 45,000 convex slabs of a cave took 10 s to load and the 170,000 of a lava
//! tube 90 s. `collision = "slabs"` keeps the older export: the surface cut into thin convex
//! slabs in the rock (`subtgraph_survey::convex_pieces`), each an inline `<mesh vertex>`, which follows
//! overhangs a height field cannot, for small worlds.
//!
//! The visual mesh is a part's own `mujoco/meshes/<part>-<k>.msh` (MuJoCo's binary mesh format,
//! read twice as fast as OBJ text), a static geom with `contype="0" conaffinity="0"` in group
//! 1, with `inertia="shell"` so an open surface never fails MuJoCo's volume check. Each visual
//! geom gets the colour of the part's most used tile-set material (MuJoCo has no per-face
//! materials).
//!
//! MuJoCo builds a bounding-volume hierarchy over every mesh's faces while it loads, whatever
//! the geom's contacts, in time and memory that grow with the face count (perf: most of the
//! load is `mjCBoundingVolumeHierarchy::MakeBVH`, sorting and page faults; the cave's 763,000
//! visual triangles take 1.2 s of CPU and 800 MB as one mesh, its collision height fields
//! 0.08 s). MuJoCo compiles the meshes on a thread pool, one mesh per task, so each part's
//! visual mesh is written in pieces of 65,536 triangles (`<part>-<k>.msh`): every core
//! works, and smaller hierarchies cost about 15 % less. Since the load grows with the face
//! count, the default `visual = "coarse"` snaps the visual vertices to a `visual_cell` grid
//! (0.5 m; `Mesh::clustered`) and drops the triangles that collapse: about half of a cave's
//! triangles, and half its load time, with the shape kept within 0.43 m (the collision height
//! fields, sampled every 0.5 m, are no finer). Snapping to fixed grid points, not to averages,
//! keeps neighbouring pieces and parts meeting exactly. `visual = "full"` writes every triangle,
//! `visual = "none"` leaves the visual meshes out for loops that never render (the height
//! fields stay, drawn in group 3).
//!
//! A world with fixtures (a mine's services) bakes them per part and material into
//! `mujoco/meshes/<part>-services-<material>-<k>.msh` (pieces of the same size), each a
//! visual-only geom in group 1 with its material's colour: they are mounted above a robot, so
//! nothing collides with them. `visual = "none"` leaves them out too.
//!
//! A ramp between levels (`world.connections = "ramp"`) is a spiral with several floors over
//! one point, which no height field holds: its two tiles collide as convex slabs
//! ([`convex_pieces`](subtgraph_survey::convex_pieces)), cut from those tiles' collision triangles alone, and the rest of the
//! world keeps its fields.
//!
//! Every part file is a complete model (`<mujoco>` root, its own `<compiler meshdir="..">`,
//! which resolves against the folder of the file MuJoCo opened, `mujoco/` in both cases), so
//! `mujoco/level-2.xml` loads one level alone (with `split = "whole"`, the one part is
//! `mujoco/whole.xml`). Collision geoms are in group 3 (hidden in the viewer by default).
//! Nothing moves: the file holds the world only, no robot.
//!
//! ```toml
//! [[export]]
//! type = "mjcf"
//! collision = "heightfields"   # or "slabs"
//! step = 0.5         # m between height samples (a whole number of them spans the pitch)
//! thickness = 0.5    # m each slab, or each field's base, reaches into the rock
//! tolerance = 0.1    # m a collision slab may stand proud of the surface (slabs only)
//! split = "level"    # or "region" (with region_tiles) or "whole"
//! visual = "coarse"  # or "full" (every triangle) or "none": no visual mesh, loads in a tenth of the time
//! visual_cell = 0.5  # m, the grid "coarse" snaps visual vertices to
//! ```

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::assembly::WorldMesh;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, stream_file, write_file};
use subtgraph_core::hazards::Patch;
use subtgraph_core::mesh::{Clustering, Grid, Material, Mesh};
use subtgraph_core::params::Params;
use subtgraph_core::survey::Survey;

use crate::parts::{Part, Split, parts};
use crate::text::{push_fixed, push_uint, write_lines, xml_escape};
use subtgraph_survey::convex_pieces::{Piece, PieceSettings, convex_pieces};
use subtgraph_survey::heightfields::{TileField, tile_fields};

/// What MuJoCo collides with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Collision {
    /// A floor and a roof `hfield` per tile (`subtgraph_survey::heightfields`), samples `step` metres
    /// apart: a few geoms per tile, no hull to build, so large worlds load in seconds.
    Heightfields {
        /// Metres between samples (rounded so a whole number of them spans the pitch).
        step: f64,
    },
    /// Thin convex slabs in the rock (`subtgraph_survey::convex_pieces`): follows overhangs and walls
    /// within `tolerance`, but MuJoCo builds a hull per slab and its loader slows down with
    /// the geom count (tens of thousands per preset world).
    Slabs,
}

/// Writes the world for MuJoCo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mjcf {
    /// How the world is cut into included files.
    pub split: Split,
    /// Height fields or convex slabs.
    pub collision: Collision,
    /// How the collision surface is cut into convex slabs (`thickness` is also the depth of a
    /// height field's base).
    pub pieces: PieceSettings,
    /// Whether each part's visual mesh is written and included (`visual = "coarse"`, the
    /// default, or `"full"`) or left out (`visual = "none"`).
    pub visual: bool,
    /// The grid (metres) the visual vertices are snapped to (`visual = "coarse"`, with
    /// `visual_cell`); `None` writes the full visual mesh.
    pub visual_cell: Option<f64>,
}

impl Default for Mjcf {
    fn default() -> Self {
        Mjcf {
            split: Split::Level,
            collision: Collision::Heightfields { step: 0.5 },
            pieces: PieceSettings::default(),
            visual: true,
            visual_cell: Some(0.5),
        }
    }
}

/// Reads a length in metres from an exporter's table.
pub(crate) fn metres(
    params: &Params,
    key: &str,
    default: f64,
    range: (f64, f64),
    example: &str,
) -> Result<f64, ConfigError> {
    let v = match params.raw(key) {
        None => return Ok(default),
        Some(toml::Value::Float(f)) => *f,
        Some(toml::Value::Integer(i)) => *i as f64,
        Some(_) => f64::NAN,
    };
    if v.is_finite() && v > range.0 && v <= range.1 {
        Ok(v)
    } else {
        Err(params.error(
            key,
            format!(
                "{key} must be a length in metres above {} and at most {}, like {key} = {example}",
                range.0, range.1
            ),
        ))
    }
}

impl Mjcf {
    /// The keys of an `[[export]] type = "mjcf"` table.
    pub const KEYS: [&'static str; 8] = [
        "split",
        "region_tiles",
        "collision",
        "step",
        "tolerance",
        "thickness",
        "visual",
        "visual_cell",
    ];

    /// From an `[[export]] type = "mjcf"` table.
    pub fn from_params(params: &Params) -> Result<Mjcf, ConfigError> {
        params.expect_known(&Self::KEYS)?;
        let d = PieceSettings::default();
        let step = metres(params, "step", 0.5, (0.0, 10.0), "0.5")?;
        let collision = match params.raw("collision") {
            None => Collision::Heightfields { step },
            Some(toml::Value::String(s)) if s == "heightfields" => Collision::Heightfields { step },
            Some(toml::Value::String(s)) if s == "slabs" => Collision::Slabs,
            Some(_) => {
                return Err(params.error(
                    "collision",
                    "collision must be \"heightfields\" (a floor and a roof hfield per tile: fast to load) or \"slabs\" (convex slabs in the rock: follows overhangs, slow to load for large worlds)",
                ));
            }
        };
        let cell = metres(params, "visual_cell", 0.5, (0.0, 10.0), "0.5")?;
        let (visual, visual_cell) = match params.raw("visual") {
            None => (true, Some(cell)),
            Some(toml::Value::String(s)) if s == "coarse" => (true, Some(cell)),
            Some(toml::Value::String(s)) if s == "full" => (true, None),
            Some(toml::Value::String(s)) if s == "none" => (false, None),
            Some(_) => {
                return Err(params.error(
                    "visual",
                    "visual must be \"coarse\" (the visual mesh with its vertices snapped to a visual_cell grid: about half the triangles and load time), \"full\" (every visual triangle in group 1) or \"none\" (collision only: loads about ten times faster, for loops that never render)",
                ));
            }
        };
        Ok(Mjcf {
            split: Split::from_params(params)?,
            visual,
            visual_cell,
            collision,
            pieces: PieceSettings {
                tolerance: metres(params, "tolerance", d.tolerance, (0.0, 1.0), "0.1")?,
                thickness: metres(params, "thickness", d.thickness, (0.0, 10.0), "0.5")?,
            },
        })
    }
}

/// The `r g b a` of the material most of a part's visual triangles use.
pub(crate) fn part_colour(mesh: &WorldMesh, part: &Part) -> [f32; 3] {
    part_material(mesh, part).map_or([0.6, 0.55, 0.5], |m| m.colour)
}

/// The material most of a part's visual triangles use.
fn part_material<'m>(mesh: &'m WorldMesh, part: &Part) -> Option<&'m Material> {
    let mut count = vec![0usize; mesh.materials.len().max(1)];
    for r in &part.visual_ranges {
        for t in r.clone() {
            let m = mesh.visual.materials.get(t).copied().unwrap_or(0);
            if let Some(c) = count.get_mut(usize::from(m)) {
                *c += 1;
            }
        }
    }
    // The first of the most used, so ties break the same way every time.
    let best = (0..count.len())
        .rev()
        .max_by_key(|&i| count[i])
        .unwrap_or(0);
    mesh.materials.get(best)
}

fn push_colour(buf: &mut Vec<u8>, c: [f32; 3], alpha: f32) {
    for v in c.into_iter().chain([alpha]) {
        push_fixed(buf, v);
        buf.push(b' ');
    }
    buf.pop();
}

/// The name of slab `i` of a part: the asset and the geom that uses it must agree.
fn push_piece_name(buf: &mut Vec<u8>, part: &str, i: usize) {
    buf.extend_from_slice(part.as_bytes());
    buf.extend_from_slice(b"-rock-");
    push_uint(buf, i as u64);
}

fn piece_asset(buf: &mut Vec<u8>, part: &str, i: usize, p: &Piece) {
    if p.points.is_empty() {
        return;
    }
    buf.extend_from_slice(b"    <mesh name=\"");
    push_piece_name(buf, part, i);
    buf.extend_from_slice(b"\" vertex=\"");
    for (k, q) in p.points.iter().enumerate() {
        if k > 0 {
            buf.push(b' ');
        }
        for (j, v) in q.iter().enumerate() {
            if j > 0 {
                buf.push(b' ');
            }
            push_fixed(buf, *v);
        }
    }
    buf.extend_from_slice(b"\"/>\n");
}

fn piece_geom(buf: &mut Vec<u8>, part: &str, i: usize, p: &Piece) {
    if p.points.is_empty() {
        return;
    }
    buf.extend_from_slice(b"    <geom type=\"mesh\" mesh=\"");
    push_piece_name(buf, part, i);
    buf.extend_from_slice(b"\" group=\"3\" rgba=\"0.5 0.5 0.5 0.4\"/>\n");
}

/// Triangles per visual mesh. MuJoCo compiles the meshes of a model on a thread pool, one
/// mesh per task, and a mesh's bounding volume hierarchy costs more per face the larger the
/// mesh: a part's visual mesh in pieces of this size loads on every core and about 15 %
/// faster per core than as one mesh.
const VISUAL_PIECE: usize = 1 << 16;

/// A part's visual triangles (ranges into the world's visual mesh) in pieces of at most
/// [`VISUAL_PIECE`] triangles, in order.
fn visual_pieces(part: &Part) -> Vec<Vec<std::ops::Range<usize>>> {
    let mut pieces = Vec::new();
    let mut piece: Vec<std::ops::Range<usize>> = Vec::new();
    let mut room = VISUAL_PIECE;
    for r in &part.visual_ranges {
        let mut start = r.start;
        while start < r.end {
            let end = r.end.min(start + room);
            piece.push(start..end);
            room -= end - start;
            start = end;
            if room == 0 {
                pieces.push(std::mem::take(&mut piece));
                room = VISUAL_PIECE;
            }
        }
    }
    if !piece.is_empty() {
        pieces.push(piece);
    }
    pieces
}

/// Writes each part's visual mesh as `mujoco/meshes/<part>-<k>.msh`, in pieces of at most
/// [`VISUAL_PIECE`] triangles, MuJoCo's binary mesh format (little-endian: vertex, normal,
/// texture coordinate and face counts as `i32`, then the positions, normals and coordinates
/// as `f32`, then the faces as `i32`). MuJoCo reads it more than twice as fast as the same
/// mesh in OBJ text, and the visual mesh is most of a world's loading time. Returns each
/// part's paths, relative to the world folder.
fn write_visual_meshes(
    out: &mut dyn WorldWriter,
    mesh: &WorldMesh,
    parts: &[Part],
    cell: Option<f64>,
) -> Result<Vec<Vec<String>>, ExportError> {
    let mut files = Vec::with_capacity(parts.len());
    for part in parts {
        let mut paths = Vec::new();
        for (k, ranges) in visual_pieces(part).iter().enumerate() {
            let path = format!("mujoco/meshes/{}-{k}.msh", part.name);
            let piece = mesh.visual.extract(ranges);
            match cell {
                Some(c) => write_msh(out, &path, &piece.clustered(&coarse(c)))?,
                None => write_msh(out, &path, &piece)?,
            }
            paths.push(path);
        }
        files.push(paths);
    }
    Ok(files)
}

/// A part's meshes beside its collision: its visual pieces and its services' pieces.
#[derive(Clone, Copy)]
struct PartMeshes<'a> {
    visuals: &'a [String],
    services: &'a [ServiceMesh],
}

/// One piece of a part's services of one material: its asset and geom name, its `.msh`
/// (relative to the world folder) and its material's colour.
struct ServiceMesh {
    name: String,
    file: String,
    colour: [f32; 3],
}

/// Writes each part's services (the world's fixtures whose tile is in the part) baked per
/// material, as `mujoco/meshes/<part>-services-<material>-<k>.msh` in pieces of at most
/// [`VISUAL_PIECE`] triangles (every copy whole): MuJoCo gives a geom one colour, and compiles
/// the pieces on its thread pool as it does the rock's.
fn write_service_meshes(
    out: &mut dyn WorldWriter,
    mesh: &WorldMesh,
    parts: &[Part],
) -> Result<Vec<Vec<ServiceMesh>>, ExportError> {
    let f = &mesh.fixtures;
    if f.is_empty() {
        return Ok(Vec::new());
    }
    let mut part_of = std::collections::BTreeMap::new();
    for (i, p) in parts.iter().enumerate() {
        for &t in &p.tiles {
            part_of.insert(mesh.tiles[t].cell, i);
        }
    }
    let mut copies = vec![Vec::new(); parts.len()];
    for (k, p) in f.placements.iter().enumerate() {
        // A copy serves a tile of some part; the first part takes any other.
        copies[part_of.get(&p.cell).copied().unwrap_or(0)].push(k);
    }
    let mut files = Vec::with_capacity(parts.len());
    for (part, copies) in parts.iter().zip(copies) {
        let mut meshes = Vec::new();
        for (m, list) in crate::services::by_material(f, copies) {
            let Some(material) = mesh.materials.get(usize::from(m)) else {
                continue;
            };
            for (k, run) in crate::services::runs(f, &list, VISUAL_PIECE)
                .into_iter()
                .enumerate()
            {
                let name = format!("{}-services-{}-{k}", part.name, material.name);
                let file = format!("mujoco/meshes/{name}.msh");
                let mut baked = f.bake(list[run].iter().copied());
                // Plain colour, no texture: no coordinates to read.
                baked.uvs.clear();
                write_msh(out, &file, &baked)?;
                meshes.push(ServiceMesh {
                    name,
                    file,
                    colour: material.colour,
                });
            }
        }
        files.push(meshes);
    }
    Ok(files)
}

/// How `visual = "coarse"` simplifies a visual mesh: every vertex snapped to the centre of
/// its `cell`-sized cube (vertices in one cube become one, their normals averaged) and the
/// triangles that collapse dropped ([`Mesh::clustered`]). Snapping to fixed points keeps the
/// seams between pieces and parts closed.
fn coarse(cell: f64) -> Clustering {
    Clustering {
        grid: Grid::CubeCentres { cell: cell as f32 },
        attributes: true,
        distinct: false,
    }
}

/// One mesh as MuJoCo's `.msh`.
fn write_msh(out: &mut dyn WorldWriter, path: &str, m: &Mesh) -> Result<(), ExportError> {
    let nv = m.positions.len();
    let nn = if m.normals.len() == nv { nv } else { 0 };
    let nt = if m.uvs.len() == nv { nv } else { 0 };
    stream_file(out, path, |w| {
        let mut buf: Vec<u8> = Vec::with_capacity(1 << 20);
        for c in [nv, nn, nt, m.triangles.len()] {
            buf.extend_from_slice(&(c as i32).to_le_bytes());
        }
        let flush = |buf: &mut Vec<u8>, w: &mut dyn std::io::Write| {
            if buf.len() >= 1 << 20 {
                w.write_all(buf)?;
                buf.clear();
            }
            Ok::<(), std::io::Error>(())
        };
        for p in &m.positions {
            p.iter()
                .for_each(|v| buf.extend_from_slice(&v.to_le_bytes()));
            flush(&mut buf, w)?;
        }
        for n in &m.normals[..nn] {
            n.iter()
                .for_each(|v| buf.extend_from_slice(&v.to_le_bytes()));
            flush(&mut buf, w)?;
        }
        for t in &m.uvs[..nt] {
            t.iter()
                .for_each(|v| buf.extend_from_slice(&v.to_le_bytes()));
            flush(&mut buf, w)?;
        }
        for t in &m.triangles {
            t.iter()
                .for_each(|&v| buf.extend_from_slice(&(v as i32).to_le_bytes()));
            flush(&mut buf, w)?;
        }
        w.write_all(&buf)
    })?;
    Ok(())
}

/// One height field (`roof` false: the floor) of tile `t`: its asset.
fn field_asset(buf: &mut Vec<u8>, part: &str, t: usize, f: &TileField, roof: bool, base: f64) {
    let z = if roof { &f.roof } else { &f.floor };
    let (lo, hi) = z
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    let range = (hi - lo).max(0.001);
    let n = f.n + 1;
    buf.extend_from_slice(b"    <hfield name=\"");
    push_field_name(buf, part, t, roof);
    buf.extend_from_slice(b"\" nrow=\"");
    push_uint(buf, n as u64);
    buf.extend_from_slice(b"\" ncol=\"");
    push_uint(buf, n as u64);
    buf.extend_from_slice(b"\" size=\"");
    let half = f.half;
    for (k, v) in [half, half, f64::from(range), base].into_iter().enumerate() {
        if k > 0 {
            buf.push(b' ');
        }
        push_fixed(buf, v as f32);
    }
    buf.extend_from_slice(b"\" elevation=\"");
    // MuJoCo reads the first row of `elevation` at +y. The roof is turned upside down about
    // x (y becomes -y), so its first row is the southmost.
    for r in 0..n {
        let row = if roof { r } else { n - 1 - r };
        for c in 0..n {
            if r > 0 || c > 0 {
                buf.push(b' ');
            }
            let v = z[row * n + c];
            let v = if roof { hi - v } else { v - lo };
            push_fixed(buf, v / range);
        }
    }
    buf.extend_from_slice(b"\"/>\n");
}

/// The geom placing a height field: the floor's base at its lowest sample, the roof upside
/// down at its highest.
fn field_geom(
    buf: &mut Vec<u8>,
    part: &str,
    t: usize,
    f: &TileField,
    roof: bool,
    friction: Option<f64>,
) {
    let z = if roof { &f.roof } else { &f.floor };
    let at = if roof {
        z.iter().copied().fold(f32::MIN, f32::max)
    } else {
        z.iter().copied().fold(f32::MAX, f32::min)
    };
    buf.extend_from_slice(b"    <geom type=\"hfield\" hfield=\"");
    push_field_name(buf, part, t, roof);
    buf.extend_from_slice(b"\" pos=\"");
    for (k, v) in [f.centre[0] as f32, f.centre[1] as f32, at]
        .into_iter()
        .enumerate()
    {
        if k > 0 {
            buf.push(b' ');
        }
        push_fixed(buf, v);
    }
    if roof {
        buf.extend_from_slice(b"\" quat=\"0 1 0 0");
    }
    if let Some(mu) = friction {
        // A floor patch (`[hazards]`): MuJoCo's sliding, torsional and rolling friction.
        buf.extend_from_slice(format!("\" friction=\"{mu} 0.005 0.0001").as_bytes());
    }
    buf.extend_from_slice(b"\" group=\"3\" rgba=\"0.5 0.5 0.5 0.4\"/>\n");
}

fn push_field_name(buf: &mut Vec<u8>, part: &str, t: usize, roof: bool) {
    buf.extend_from_slice(part.as_bytes());
    buf.extend_from_slice(if roof { b"-roof-" } else { b"-floor-" });
    push_uint(buf, t as u64);
}

/// A part's collision geometry, ready to write.
enum PartCollision<'a> {
    Slabs(Vec<Piece>),
    /// A floor and a roof field per tile, except the tiles of a ramp between levels
    /// (`world.connections = "ramp"`), whose spiral has several floors over one point (a
    /// height field holds one): those are the part's convex slabs.
    Fields(&'a [TileField], Vec<Piece>),
}

/// Per mesh tile, whether it holds a ramp's spiral: the two cells of each ramp.
fn ramp_tiles(world: &World, mesh: &WorldMesh) -> Vec<bool> {
    if world.resolved.connections != subtgraph_core::config::Connections::Ramp {
        return vec![false; mesh.tiles.len()];
    }
    let cells: std::collections::BTreeSet<_> = world
        .shafts
        .iter()
        .flat_map(|s| [s.up, s.landing])
        .map(|c| (c.level, c.row, c.col))
        .collect();
    mesh.tiles
        .iter()
        .map(|t| cells.contains(&(t.cell.level, t.cell.row, t.cell.col)))
        .collect()
}

/// The artifacts as free bodies (a box each, resting on the floor at its recorded pose): a
/// robot can push them, and `body` names them `artifact-<name>`. A contact margin of 1 cm
/// softens its contact with the height fields.
///
/// Each stands on its pad, `artifact-pad-<name>` ([`Artifact::pad`](subtgraph_core::artifacts::Artifact::pad)).
fn artifact_bodies(s: &mut String, artifacts: &[subtgraph_core::artifacts::Artifact]) {
    if artifacts.is_empty() {
        return;
    }
    s.push_str("  <worldbody>\n");
    for a in artifacts {
        let [x, y, z] = a.position;
        let [qx, qy, qz, qw] = a.quaternion_xyzw();
        let [l, w, h] = a.size;
        let [r, g, b] = a.class.colour();
        let pad = a.pad();
        let _ = std::fmt::Write::write_fmt(
            s,
            format_args!(
                "    <geom name=\"artifact-pad-{n}\" type=\"box\" size=\"{:.4} {:.4} {:.4}\" pos=\"{x:.4} {y:.4} {:.4}\" quat=\"{qw:.6} {qx:.6} {qy:.6} {qz:.6}\" rgba=\"0.35 0.33 0.3 1\"/>\n    <body name=\"artifact-{n}\" pos=\"{x:.4} {y:.4} {z:.4}\" quat=\"{qw:.6} {qx:.6} {qy:.6} {qz:.6}\">\n      <freejoint name=\"artifact-{n}\"/>\n      <geom name=\"artifact-{n}\" type=\"box\" size=\"{:.4} {:.4} {:.4}\" pos=\"0 0 {:.4}\" mass=\"{}\" margin=\"0.01\" rgba=\"{r:.3} {g:.3} {b:.3} 1\"/>\n    </body>\n",
                0.5 * pad.1[0],
                0.5 * pad.1[1],
                0.5 * pad.1[2],
                pad.0[2],
                0.5 * l,
                0.5 * w,
                0.5 * h,
                0.5 * h,
                a.class.mass(),
                n = a.name,
            ),
        );
    }
    s.push_str("  </worldbody>\n");
}

impl Exporter for Mjcf {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let Some(mesh) = world.mesh() else {
            return Err(ExportError::Unsupported(
                "the MJCF exporter needs geometry: add a [tileset] to the pipeline (or drop --no-mesh)".into(),
            ));
        };
        let parts = parts(world, mesh, self.split);
        let (files, services) = if self.visual {
            crate::text::write_textures(out, mesh)?;
            (
                write_visual_meshes(out, mesh, &parts, self.visual_cell)?,
                write_service_meshes(out, mesh, &parts)?,
            )
        } else {
            (Vec::new(), Vec::new())
        };
        // The survey's height fields, found for this step when MuJoCo's writer asks.
        let fields = match self.collision {
            Collision::Heightfields { step } => tile_fields(world, survey, mesh, step),
            Collision::Slabs => Vec::new(),
        };
        let collision = self.part_collisions(world, mesh, &parts, &fields);
        let tiles = Tiles {
            ramp: ramp_tiles(world, mesh),
            friction: floor_friction(mesh, survey.patches().unwrap_or(&[])),
            base: self.pieces.thickness,
        };
        let what = match self.collision {
            Collision::Slabs => "collision slabs (convex, in the rock)",
            Collision::Heightfields { .. } => {
                "collision height fields (a floor and an upside-down roof per tile; convex slabs in a ramp's tiles)"
            }
        };
        let visual = if self.visual {
            "visual geoms in group 1"
        } else {
            "no visual geoms (visual = \"none\")"
        };
        let mut main = format!(
            "<mujoco model=\"subtgraph world, seed {}\">\n  <!-- metres, x east, y north, z up; {visual}, {what} in group 3 -->\n{}",
            world.resolved.seed,
            compiler(mesh)
        );
        for (i, (part, collision)) in parts.iter().zip(&collision).enumerate() {
            let visuals: &[String] = files.get(i).map_or(&[], |f| f.as_slice());
            let services: &[ServiceMesh] = services.get(i).map_or(&[], |f| f.as_slice());
            // The whole world as one part is named `world`: its file must not replace the
            // main file.
            let stem = if part.name == "world" {
                "whole"
            } else {
                &part.name
            };
            main.push_str(&format!("  <include file=\"{}.xml\"/>\n", xml_escape(stem)));
            let path = format!("mujoco/{stem}.xml");
            let meshes = PartMeshes { visuals, services };
            write_part(out, &path, mesh, part, collision, &meshes, &tiles)?;
        }
        artifact_bodies(&mut main, crate::artifacts_of(survey));
        main.push_str("</mujoco>\n");
        write_file(out, "mujoco/world.xml", main.as_bytes())
    }

    fn needs_geometry(&self) -> bool {
        true
    }
}

/// Every file's `<compiler>`: radians, and meshes relative to `mujoco/`'s parent.
const COMPILER: &str = "  <compiler angle=\"radian\" meshdir=\"..\"/>\n";

/// The `<compiler>` of a world with textures: their images relative to `mujoco/`'s parent too.
const COMPILER_TEXTURED: &str = "  <compiler angle=\"radian\" meshdir=\"..\" texturedir=\"..\"/>\n";

fn compiler(mesh: &WorldMesh) -> &'static str {
    if mesh.textures.is_empty() {
        COMPILER
    } else {
        COMPILER_TEXTURED
    }
}

impl Mjcf {
    /// Each part's collision geometry: its convex slabs, or the world's height `fields` and
    /// the slabs of its ramps' tiles. Slabs of every part in parallel; each part's are cut
    /// alone, so the result does not depend on the thread count.
    fn part_collisions<'f>(
        &self,
        world: &World,
        mesh: &WorldMesh,
        parts: &[Part],
        fields: &'f [TileField],
    ) -> Vec<PartCollision<'f>> {
        match self.collision {
            Collision::Slabs => parts
                .par_iter()
                .map(|p| PartCollision::Slabs(convex_pieces(&p.collision(mesh), &self.pieces)))
                .collect(),
            Collision::Heightfields { .. } => {
                let ramps = ramp_tiles(world, mesh);
                parts
                    .par_iter()
                    .map(|p| {
                        let ranges: Vec<_> = p
                            .tiles
                            .iter()
                            .filter(|&&t| ramps[t])
                            .map(|&t| mesh.tiles[t].collision_triangles.clone())
                            .collect();
                        let slabs = if ranges.is_empty() {
                            Vec::new()
                        } else {
                            convex_pieces(&mesh.collision.extract(&ranges), &self.pieces)
                        };
                        PartCollision::Fields(fields, slabs)
                    })
                    .collect()
            }
        }
    }
}

/// What each mesh tile's collision geoms need besides its fields: whether it holds a ramp's
/// spiral, its floor's friction, and how deep a field's base reaches.
struct Tiles {
    ramp: Vec<bool>,
    friction: Vec<Option<f64>>,
    base: f64,
}

/// The floor friction of each mesh tile, from the survey's floor patches (`None`: rock).
fn floor_friction(mesh: &WorldMesh, patches: &[Patch]) -> Vec<Option<f64>> {
    mesh.tiles
        .iter()
        .map(|tile| {
            patches
                .binary_search_by_key(&(tile.cell.level, tile.cell.row, tile.cell.col), |p| {
                    (p.cell.level, p.cell.row, p.cell.col)
                })
                .ok()
                .map(|k| patches[k].friction)
        })
        .collect()
}

/// One part's file: its visual meshes, then its collision geoms, a complete model.
fn write_part(
    out: &mut dyn WorldWriter,
    path: &str,
    mesh: &WorldMesh,
    part: &Part,
    collision: &PartCollision,
    meshes: &PartMeshes,
    tiles: &Tiles,
) -> Result<(), ExportError> {
    let PartMeshes { visuals, services } = *meshes;
    let name = xml_escape(&part.name);
    let colour = part_colour(mesh, part);
    // MuJoCo gives a geom one material: the part's most used one, its albedo repeated by the
    // meshes' texture coordinates.
    let albedo = part_material(mesh, part)
        .and_then(|m| m.texture.as_deref())
        .filter(|_| !visuals.is_empty());
    let Tiles {
        ramp,
        friction,
        base,
    } = tiles;
    // Line k of the assets or geoms: a slab, or a tile's floor (even k) or roof (odd).
    let count = match collision {
        PartCollision::Slabs(p) => p.len(),
        PartCollision::Fields(_, slabs) => 2 * part.tiles.len() + slabs.len(),
    };
    let ramps = format!("{name}-ramp");
    let asset = |b: &mut Vec<u8>, k: usize| match collision {
        PartCollision::Slabs(p) => piece_asset(b, &name, k, &p[k]),
        PartCollision::Fields(_, slabs) if k >= 2 * part.tiles.len() => {
            let i = k - 2 * part.tiles.len();
            piece_asset(b, &ramps, i, &slabs[i]);
        }
        PartCollision::Fields(f, slabs) => {
            let t = part.tiles[k / 2];
            if slabs.is_empty() || !ramp[t] {
                field_asset(b, &name, t, &f[t], k % 2 == 1, *base);
            }
        }
    };
    let geom = |b: &mut Vec<u8>, k: usize| match collision {
        PartCollision::Slabs(p) => piece_geom(b, &name, k, &p[k]),
        PartCollision::Fields(_, slabs) if k >= 2 * part.tiles.len() => {
            let i = k - 2 * part.tiles.len();
            piece_geom(b, &ramps, i, &slabs[i]);
        }
        PartCollision::Fields(f, slabs) => {
            let t = part.tiles[k / 2];
            if !slabs.is_empty() && ramp[t] {
                return;
            }
            let roof = k % 2 == 1;
            field_geom(
                b,
                &name,
                t,
                &f[t],
                roof,
                if roof { None } else { friction[t] },
            );
        }
    };
    stream_file(out, path, |w| {
        let mut head = format!("<mujoco model=\"{name}\">\n{}  <asset>\n", compiler(mesh));
        if let Some(f) = albedo {
            head.push_str(&format!(
                "    <texture name=\"{name}-albedo\" type=\"2d\" file=\"mesh/{}\"/>\n    <material name=\"{name}-surface\" texture=\"{name}-albedo\" texuniform=\"false\" texrepeat=\"1 1\"/>\n",
                xml_escape(f)
            ));
        }
        for (k, file) in visuals.iter().enumerate() {
            head.push_str(&format!(
                "    <mesh name=\"{name}-visual-{k}\" file=\"{}\" inertia=\"shell\"/>\n",
                xml_escape(file)
            ));
        }
        for m in services {
            head.push_str(&format!(
                "    <mesh name=\"{}\" file=\"{}\" inertia=\"shell\"/>\n",
                xml_escape(&m.name),
                xml_escape(&m.file)
            ));
        }
        w.write_all(head.as_bytes())?;
        write_lines(w, count, asset)?;
        let mut mid = Vec::new();
        mid.extend_from_slice(b"  </asset>\n  <worldbody>\n");
        for k in 0..visuals.len() {
            mid.extend_from_slice(
                format!("    <geom name=\"{name}-visual-{k}\" type=\"mesh\" mesh=\"{name}-visual-{k}\" group=\"1\" contype=\"0\" conaffinity=\"0\" ")
                    .as_bytes(),
            );
            if albedo.is_some() {
                mid.extend_from_slice(format!("material=\"{name}-surface\"/>\n").as_bytes());
            } else {
                mid.extend_from_slice(b"rgba=\"");
                push_colour(&mut mid, colour, 1.0);
                mid.extend_from_slice(b"\"/>\n");
            }
        }
        for m in services {
            let n = xml_escape(&m.name);
            mid.extend_from_slice(
                format!("    <geom name=\"{n}\" type=\"mesh\" mesh=\"{n}\" group=\"1\" contype=\"0\" conaffinity=\"0\" rgba=\"").as_bytes(),
            );
            push_colour(&mut mid, m.colour, 1.0);
            mid.extend_from_slice(b"\"/>\n");
        }
        w.write_all(&mid)?;
        write_lines(w, count, geom)?;
        w.write_all(b"  </worldbody>\n</mujoco>\n")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn visual_pieces_keep_every_triangle_in_order_and_none_is_too_big() {
        let ranges = vec![0..10, 20..(20 + VISUAL_PIECE + 5), 200_000..200_001];
        let part = Part {
            name: "level-0".into(),
            level: Some(0),
            tiles: Vec::new(),
            visual_ranges: ranges.clone(),
            collision_ranges: Vec::new(),
        };
        let pieces = visual_pieces(&part);
        assert_eq!(pieces.len(), 2);
        assert!(
            pieces
                .iter()
                .all(|p| p.iter().map(|r| r.len()).sum::<usize>() <= VISUAL_PIECE)
        );
        let flat =
            |rs: &[std::ops::Range<usize>]| rs.iter().flat_map(|r| r.clone()).collect::<Vec<_>>();
        assert_eq!(flat(&pieces.concat()), flat(&ranges));
    }

    #[test]
    fn every_include_names_a_part_file_written_beside_it() {
        let world = crate::test_world_with_mesh();
        let splits = [Split::Whole, Split::Level, Split::Region { tiles: 6 }];
        let collisions = [Collision::Heightfields { step: 1.0 }, Collision::Slabs];
        for (split, collision) in splits.into_iter().zip(collisions.into_iter().cycle()) {
            let mut out = MemoryWriter::default();
            let m = Mjcf {
                split,
                collision,
                ..Mjcf::default()
            };
            m.export(&world, &crate::survey_of(&world), &mut out)
                .unwrap();
            let main = String::from_utf8(out.get("mujoco/world.xml").unwrap().to_vec()).unwrap();
            let includes: Vec<&str> = main
                .split("<include file=\"")
                .skip(1)
                .map(|s| &s[..s.find('"').unwrap()])
                .collect();
            let count = parts(&world, world.mesh().unwrap(), split).len();
            assert_eq!(includes.len(), count, "{split:?}");
            let mut slabs = 0;
            for inc in includes {
                let part = out
                    .get(&format!("mujoco/{inc}"))
                    .expect("included file written");
                let text = String::from_utf8(part.to_vec()).unwrap();
                let visual = text.split("file=\"").nth(1).unwrap();
                let visual = &visual[..visual.find('"').unwrap()];
                assert!(out.contains(visual), "{visual} written");
                // Two height fields per tile, each an asset and a geom.
                slabs += text.matches("-rock-").count() + text.matches("-floor-").count();
            }
            assert!(slabs > 4 * 10, "collision geoms: {slabs}");
        }
    }

    #[test]
    fn coarse_visual_meshes_have_fewer_triangles_on_the_grid_and_stay_close() {
        let world = crate::test_world_with_mesh();
        let full = &world.mesh().unwrap().visual;
        let cell = 0.5_f32;
        let coarse = full.clustered(&super::coarse(f64::from(cell)));
        assert!(
            coarse.triangles.len() * 10 < full.triangles.len() * 9,
            "{} of {} triangles kept",
            coarse.triangles.len(),
            full.triangles.len()
        );
        assert!(
            coarse.triangles.len() * 10 > full.triangles.len(),
            "most of the shape kept"
        );
        // Every vertex is a grid-cube centre within half a cube diagonal of an original vertex.
        for p in &coarse.positions {
            for c in p {
                let k = c / cell - 0.5;
                assert!((k - k.round()).abs() < 1e-3, "{p:?} off the grid");
            }
        }
        for p in &full.positions {
            let q = coarse
                .positions
                .iter()
                .map(|q| (0..3).map(|a| (q[a] - p[a]).powi(2)).sum::<f32>().sqrt());
            let d = q.fold(f32::MAX, f32::min);
            assert!(d <= cell * 3f32.sqrt() / 2.0 + 1e-4, "{p:?} moved {d} m");
        }
        assert!(
            coarse
                .triangles
                .iter()
                .all(|[a, b, c]| a != b && b != c && a != c)
        );
        assert_eq!(coarse.materials.len(), coarse.triangles.len());
        assert_eq!(coarse.normals.len(), coarse.positions.len());
        // Deterministic.
        let again = full.clustered(&super::coarse(f64::from(cell)));
        assert_eq!(again.positions, coarse.positions);
        assert_eq!(again.triangles, coarse.triangles);
    }

    #[test]
    fn bad_lengths_name_the_key() {
        let table = |s: &str| Params::from_table("export[0]", toml::from_str(s).unwrap());
        let m = Mjcf::from_params(&table("tolerance = 0.1\nthickness = 2")).unwrap();
        assert_eq!((m.pieces.tolerance, m.pieces.thickness), (0.1, 2.0));
        for bad in ["tolerance = -1.0", "tolerance = \"big\"", "thickness = 0"] {
            let e = Mjcf::from_params(&table(bad)).unwrap_err();
            let key = bad.split(' ').next().unwrap();
            assert_eq!(e.key, format!("export[0].{key}"), "{bad}");
            assert!(e.message.contains(&format!("{key} = ")), "{}", e.message);
        }
    }
}
