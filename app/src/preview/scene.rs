//! The mesh a preview draws: `mesh/world.obj` with its materials' colours (`world.mtl`),
//! and what the views ask of it (bounds, a crop around a tile, the floor under a point).

use std::path::Path;

use subtgraph_core::vec3::{V3, cross, dot, sub};

use subtgraph_sensors::camera::texture::{Texture, linear};

use crate::Error;

/// A parsed `mesh/world.obj`: positions, triangles and their colours, and where the
/// materials have an albedo image (`map_Kd`), the texture coordinates and the images.
pub(super) struct Scene {
    pub positions: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
    pub colours: Vec<[f32; 3]>,
    /// Per vertex, when the OBJ has them (`vt`, indexed as the positions).
    pub uvs: Vec<[f32; 2]>,
    /// Per triangle, its albedo in `images` ([`NO_IMAGE`] for a plain colour).
    pub textures: Vec<u16>,
    pub images: Vec<Albedo>,
}

/// A triangle without an albedo image.
pub(super) const NO_IMAGE: u16 = u16::MAX;

/// An albedo image: the sensors' texture (one reader of a world's images for the preview and
/// the cameras), sampled at the nearest texel.
pub(super) struct Albedo(Texture);

impl Albedo {
    /// The colour at texture coordinates `(u, v)`, repeating (nearest pixel), linear RGB.
    pub fn at(&self, u: f64, v: f64) -> [f32; 3] {
        self.0.nearest(u, v).map(linear)
    }

    fn read(path: &Path) -> Result<Albedo, Error> {
        let bad = |why: String| {
            Error::Input(format!(
                "{}: the albedo image `map_Kd` names cannot be read ({why}); regenerate the world or fix world.mtl",
                path.display()
            ))
        };
        let bytes = std::fs::read(path).map_err(|e| bad(e.to_string()))?;
        Texture::decode(&bytes).map(Albedo).map_err(bad)
    }
}

pub(super) fn read_scene(world: &Path) -> Result<Scene, Error> {
    let obj_path = world.join("mesh/world.obj");
    if !obj_path.exists() {
        return Err(Error::Input(format!(
            "{} has no mesh/world.obj: is it a world generated with a [tileset] (not `generate --no-mesh`), with its mesh as OBJ (the default, or `obj` among `generate --format`)?",
            world.display()
        )));
    }
    let text = crate::input::read_text(&obj_path)?;
    let mtl = std::fs::read_to_string(world.join("mesh/world.mtl")).unwrap_or_default();
    let mut palette = std::collections::HashMap::new();
    let mut albedo: std::collections::HashMap<String, u16> = std::collections::HashMap::new();
    let mut images = Vec::new();
    let mut current = String::new();
    for line in mtl.lines() {
        if let Some(name) = line.strip_prefix("newmtl ") {
            current = name.trim().to_owned();
        } else if let Some(file) = line.strip_prefix("map_Kd ") {
            if images.len() < usize::from(NO_IMAGE) {
                images.push(Albedo::read(&world.join("mesh").join(file.trim()))?);
                albedo.insert(current.clone(), (images.len() - 1) as u16);
            }
        } else if let Some(kd) = line.strip_prefix("Kd ") {
            let v: Vec<f32> = kd
                .split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect();
            if v.len() == 3 {
                palette.insert(current.clone(), [v[0], v[1], v[2]]);
            }
        }
    }
    let mut scene = Scene {
        positions: Vec::new(),
        triangles: Vec::new(),
        colours: Vec::new(),
        uvs: Vec::new(),
        textures: Vec::new(),
        images,
    };
    let mut colour = [0.6, 0.6, 0.6];
    let mut texture = NO_IMAGE;
    for line in text.lines() {
        if !scene.images.is_empty() {
            if let Some(rest) = line.strip_prefix("vt ") {
                let mut it = rest
                    .split_whitespace()
                    .map(|x| x.parse::<f32>().unwrap_or(0.0));
                scene
                    .uvs
                    .push([it.next().unwrap_or(0.0), it.next().unwrap_or(0.0)]);
                continue;
            }
        }
        if let Some(rest) = line.strip_prefix("v ") {
            let mut it = rest.split_whitespace().map(|x| x.parse::<f32>());
            match (it.next(), it.next(), it.next()) {
                (Some(Ok(x)), Some(Ok(y)), Some(Ok(z))) => scene.positions.push([x, y, z]),
                _ => {
                    return Err(Error::Input(format!(
                        "{}: bad vertex line '{}'",
                        obj_path.display(),
                        subtgraph_core::error::excerpt(line)
                    )));
                }
            }
        } else if let Some(rest) = line.strip_prefix("f ") {
            // OBJ indices are 1-based; 0 (or a negative, relative one) is refused below
            // with the other out-of-range indices, not subtracted into a panic.
            let idx: Vec<u32> = rest
                .split_whitespace()
                .filter_map(|t| t.split('/').next()?.parse::<u32>().ok())
                .map(|i| i.checked_sub(1).unwrap_or(u32::MAX))
                .collect();
            for k in 1..idx.len().saturating_sub(1) {
                scene.triangles.push([idx[0], idx[k], idx[k + 1]]);
                scene.colours.push(colour);
                scene.textures.push(texture);
            }
        } else if let Some(name) = line.strip_prefix("usemtl ") {
            colour = palette.get(name.trim()).copied().unwrap_or([0.6, 0.6, 0.6]);
            texture = albedo.get(name.trim()).copied().unwrap_or(NO_IMAGE);
        }
    }
    if scene.triangles.is_empty() {
        return Err(Error::Input(format!(
            "{} has no triangles",
            obj_path.display()
        )));
    }
    if scene.uvs.len() != scene.positions.len() {
        // Coordinates missing or not one per vertex: plain colours.
        scene.uvs.clear();
        scene.textures.fill(NO_IMAGE);
    }
    let n = scene.positions.len() as u32;
    if scene.triangles.iter().flatten().any(|&i| i >= n) {
        return Err(Error::Input(format!(
            "{}: a face refers to a vertex that does not exist",
            obj_path.display()
        )));
    }
    Ok(scene)
}

/// Keeps only the triangles within `radius` metres (horizontally) of `centre` and within
/// `below`/`above` metres of its height.
pub(super) fn crop(scene: Scene, centre: [f64; 3], radius: f64, below: f64, above: f64) -> Scene {
    let keep = |p: [f32; 3]| {
        let d = [
            f64::from(p[0]) - centre[0],
            f64::from(p[1]) - centre[1],
            f64::from(p[2]) - centre[2],
        ];
        d[0].abs() <= radius && d[1].abs() <= radius && d[2] >= -below && d[2] <= above
    };
    let kept: Vec<usize> = (0..scene.triangles.len())
        .filter(|&t| {
            scene.triangles[t]
                .iter()
                .all(|&i| keep(scene.positions[i as usize]))
        })
        .collect();
    Scene {
        triangles: kept.iter().map(|&t| scene.triangles[t]).collect(),
        colours: kept.iter().map(|&t| scene.colours[t]).collect(),
        textures: kept.iter().map(|&t| scene.textures[t]).collect(),
        positions: scene.positions,
        uvs: scene.uvs,
        images: scene.images,
    }
}

/// The height of the floor under `p`: the upward-facing surface (a floor, seen from its
/// passage) crossing the vertical line through `p` nearest to `p`'s height, within `below`
/// and `above` metres of it.
pub(super) fn floor_under(scene: &Scene, p: V3, below: f64, above: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for t in &scene.triangles {
        let [a, b, c] = t.map(|i| scene.positions[i as usize].map(f64::from));
        let n = cross(sub(b, a), sub(c, a));
        if n[2] <= 0.5 * dot(n, n).sqrt() {
            continue;
        }
        // Barycentric coordinates of p in the triangle's shadow on the ground.
        let det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if det.abs() < 1e-12 {
            continue;
        }
        let u = ((p[0] - a[0]) * (c[1] - a[1]) - (p[1] - a[1]) * (c[0] - a[0])) / det;
        let v = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / det;
        if u < 0.0 || v < 0.0 || u + v > 1.0 {
            continue;
        }
        let z = a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]);
        if z < p[2] - below || z > p[2] + above {
            continue;
        }
        if best.is_none_or(|bz| (z - p[2]).abs() < (bz - p[2]).abs()) {
            best = Some(z);
        }
    }
    best
}

/// The bounds of the vertices the scene's triangles use.
pub(super) fn used_bounds(scene: &Scene) -> (V3, V3) {
    let mut used = vec![false; scene.positions.len()];
    for t in &scene.triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for p in scene
        .positions
        .iter()
        .zip(&used)
        .filter(|(_, u)| **u)
        .map(|(p, _)| p)
    {
        for d in 0..3 {
            lo[d] = lo[d].min(f64::from(p[d]));
            hi[d] = hi[d].max(f64::from(p[d]));
        }
    }
    (lo, hi)
}

pub(super) fn scene_centre(scene: &Scene) -> V3 {
    let (lo, hi) = used_bounds(scene);
    [0, 1, 2].map(|d| 0.5 * (lo[d] + hi[d]))
}
