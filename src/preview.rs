//! `subtgraph preview`: a shaded perspective picture of a world's mesh, drawn on the CPU (no
//! GPU, no display): from above and to the south-west (the whole world, or a close-up of the
//! tiles around a node), or from inside a passage, where a robot's camera would be.
//!
//! Triangles are kept only when they face the camera from the passage side, so from outside
//! the ceilings nearest the camera drop out and the picture shows the floors and far walls of
//! every passage: a cutaway of the network at a glance. From inside, triangles are clipped at
//! the camera, so walls right beside it are drawn too.
//!
//! Two lights ([`Light`]). The sun, fixed and high, lights a face by its angle alone and suits
//! the outside views: a lamp at a camera many tiles away lights every face nearly alike, as a
//! flash photograph does. The lamp, a point light just above the camera that falls off with
//! distance, is how a robot sees a passage: faces turned to it bright, grazing ones dark, near
//! rock brighter than far rock, so relief, slopes and chambers read from the shading.
//!
//! Each pixel keeps its nearest triangle (depth as 1/z, interpolated on screen) and is shaded
//! once afterwards, in one thread and in a fixed order: the same world and options give the
//! same PNG bytes.

use std::path::Path;

use anyhow::{Context, Result, bail};

use subtgraph_core::vec3::{V3, cross, dot, sub};

/// A parsed `mesh/world.obj`: positions, triangles and their colours.
struct Scene {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    colours: Vec<[f32; 3]>,
}

fn read_scene(world: &Path) -> Result<Scene> {
    let obj_path = world.join("mesh/world.obj");
    let text = std::fs::read_to_string(&obj_path).with_context(|| {
        format!(
            "reading {}: is {} a world generated with a [tileset] (not `generate --no-mesh`), with its mesh as OBJ (the default, or `obj` among `generate --format`)?",
            obj_path.display(),
            world.display()
        )
    })?;
    let mtl = std::fs::read_to_string(world.join("mesh/world.mtl")).unwrap_or_default();
    let mut palette = std::collections::HashMap::new();
    let mut current = String::new();
    for line in mtl.lines() {
        if let Some(name) = line.strip_prefix("newmtl ") {
            current = name.trim().to_owned();
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
    };
    let mut colour = [0.6, 0.6, 0.6];
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("v ") {
            let mut it = rest.split_whitespace().map(|x| x.parse::<f32>());
            match (it.next(), it.next(), it.next()) {
                (Some(Ok(x)), Some(Ok(y)), Some(Ok(z))) => scene.positions.push([x, y, z]),
                _ => bail!(
                    "{}: bad vertex line '{}'",
                    obj_path.display(),
                    subtgraph_core::error::excerpt(line)
                ),
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
            }
        } else if let Some(name) = line.strip_prefix("usemtl ") {
            colour = palette.get(name.trim()).copied().unwrap_or([0.6, 0.6, 0.6]);
        }
    }
    if scene.triangles.is_empty() {
        bail!("{} has no triangles", obj_path.display());
    }
    let n = scene.positions.len() as u32;
    if scene.triangles.iter().flatten().any(|&i| i >= n) {
        bail!(
            "{}: a face refers to a vertex that does not exist",
            obj_path.display()
        );
    }
    Ok(scene)
}

/// `a` scaled to length 1 (a zero vector stays zero: degenerate triangles shade black).
fn norm(a: V3) -> V3 {
    let l = dot(a, a).sqrt().max(1e-12);
    [a[0] / l, a[1] / l, a[2] / l]
}

/// Keeps only the triangles within `radius` metres (horizontally) of `centre` and within
/// `below`/`above` metres of its height.
fn crop(scene: Scene, centre: [f64; 3], radius: f64, below: f64, above: f64) -> Scene {
    let keep = |p: [f32; 3]| {
        let d = [
            f64::from(p[0]) - centre[0],
            f64::from(p[1]) - centre[1],
            f64::from(p[2]) - centre[2],
        ];
        d[0].abs() <= radius && d[1].abs() <= radius && d[2] >= -below && d[2] <= above
    };
    let (triangles, colours) = scene
        .triangles
        .iter()
        .zip(&scene.colours)
        .filter(|(t, _)| t.iter().all(|&i| keep(scene.positions[i as usize])))
        .map(|(t, c)| (*t, *c))
        .unzip();
    Scene {
        positions: scene.positions,
        triangles,
        colours,
    }
}

/// Where the light comes from (`--light`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Light {
    /// A point light just above the camera whose light falls off with distance, as a robot's
    /// lamp shows a passage: each face lit by how squarely it faces the lamp (Lambert, faces
    /// turned away stay dark), near surfaces brighter than far ones, so relief, slopes and
    /// chambers read from their shading; a little ambient light keeps nothing pure black.
    Lamp,
    /// A fixed light from high in the south-east, the same at every distance (the pictures
    /// before lamps): every face lit by the angle it makes with that light, either side.
    Sun,
}

impl std::str::FromStr for Light {
    type Err = anyhow::Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "lamp" => Ok(Light::Lamp),
            "sun" => Ok(Light::Sun),
            other => bail!(
                "--light must be lamp (a light at the camera that falls off with distance, the default) or sun (a fixed light from above, the same everywhere), not '{}'",
                subtgraph_core::error::excerpt(other)
            ),
        }
    }
}

/// What the camera looks at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The whole world from above and to the south-west.
    Whole,
    /// The tiles within 3.5 tile pitches of a node (the start unless `at`), from above and to
    /// the south-west.
    CloseUp,
    /// From inside the passage at a node (the start unless `at`), 1.5 m above its floor, looking
    /// along its first passage: what a robot's camera sees there.
    Inside,
}

/// How `render` draws.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Picture width in pixels.
    pub width: usize,
    /// Picture height in pixels.
    pub height: usize,
    /// What the camera looks at.
    pub view: View,
    /// Where the light comes from.
    pub light: Light,
    /// The graph node a close-up or inside view is taken at (`None`: the start).
    pub at: Option<usize>,
}

/// Light that reaches every face whatever its facing or distance, as a share of full light.
const AMBIENT: f64 = 0.12;
/// The lamp's reach `d0` as a share of the tile pitch: its light falls off as
/// `1 / (1 + (d / d0)^2)` at `d` metres, half at `d0`. Pictures are exposed for the nearest
/// lit surface (full light there, if it faces the lamp squarely).
const LAMP_REACH: f64 = 0.5;
/// The inside view's camera height above the floor, metres (a ground robot's mast camera).
const EYE_HEIGHT: f64 = 1.5;
/// How far above the camera the lamp sits, metres (inside view).
const LAMP_ABOVE: f64 = 0.3;

fn read_json(path: &Path) -> Result<serde_json::Value> {
    serde_json::from_slice(
        &std::fs::read(path).with_context(|| format!("reading {}", path.display()))?,
    )
    .with_context(|| format!("parsing {}", path.display()))
}

fn triple(v: &serde_json::Value) -> Option<V3> {
    let a = v.as_array()?;
    Some([
        a.first()?.as_f64()?,
        a.get(1)?.as_f64()?,
        a.get(2)?.as_f64()?,
    ])
}

/// A graph node's place in the world.
struct Place {
    /// Its cell's centre at the level's nominal floor height (`topology.json`).
    cell_centre: V3,
    /// On its passage's floor (`ground_truth/graph.json`), when the world has it.
    floor: Option<V3>,
    /// The horizontal direction of its first passage (lowest edge id), if it has one.
    along: Option<V3>,
    pitch: f64,
    level: f64,
}

/// The tile pitch of a world (`topology.json`; the default without it).
fn pitch_of(world: &Path) -> f64 {
    read_json(&world.join("topology.json"))
        .ok()
        .and_then(|t| t["tile_pitch_m"].as_f64())
        .unwrap_or(25.0)
}

/// Where node `at` (the start when `None`) is: from `topology.json`, and from
/// `ground_truth/graph.json` (each node and passage on its own floor) when the world has it.
fn place_of(world: &Path, at: Option<usize>) -> Result<Place> {
    let topo = read_json(&world.join("topology.json"))?;
    let nodes = topo["nodes"].as_array().map_or(&[][..], Vec::as_slice);
    let node = match at {
        Some(n) => n,
        None => topo["start"]
            .as_u64()
            .context("topology.json has no start node")? as usize,
    };
    let Some(entry) = nodes.iter().find(|n| n["id"].as_u64() == Some(node as u64)) else {
        bail!(
            "--at {node}: {} has nodes 0 to {} (their ids are in topology.json)",
            world.display(),
            nodes.len().saturating_sub(1)
        );
    };
    let cell_centre =
        triple(&entry["position"]).context("topology.json: a node has no position")?;
    let (pitch, level) = (
        topo["tile_pitch_m"].as_f64().unwrap_or(25.0),
        topo["level_height_m"].as_f64().unwrap_or(20.0),
    );
    let horizontal = |d: V3| {
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        (l > 1e-9).then(|| [d[0] / l, d[1] / l, 0.0])
    };
    let id_is = |v: &serde_json::Value| v.as_u64() == Some(node as u64);
    let graph_path = world.join("ground_truth/graph.json");
    if graph_path.is_file() {
        let g = read_json(&graph_path)?;
        let gnode = g["nodes"]
            .as_array()
            .and_then(|ns| ns.iter().find(|n| id_is(&n["id"])));
        if let Some(floor) = gnode.and_then(|n| triple(&n["position"])) {
            let along = g["edges"].as_array().and_then(|es| {
                es.iter().find_map(|e| {
                    let mut line: Vec<V3> = e["polyline"]
                        .as_array()?
                        .iter()
                        .filter_map(triple)
                        .collect();
                    if id_is(&e["to"]) && !id_is(&e["from"]) {
                        line.reverse();
                    } else if !id_is(&e["from"]) {
                        return None;
                    }
                    // Look at the passage a quarter of a tile on, not at its first wiggle.
                    let far = line
                        .iter()
                        .find(|p| {
                            horizontal(sub(**p, floor)).is_some() && {
                                let d = sub(**p, floor);
                                d[0] * d[0] + d[1] * d[1] >= (0.25 * pitch).powi(2)
                            }
                        })
                        .or(line.last())?;
                    horizontal(sub(*far, floor))
                })
            });
            return Ok(Place {
                cell_centre,
                floor: Some(floor),
                along,
                pitch,
                level,
            });
        }
    }
    let cell = &entry["cell"];
    let along = topo["edges"].as_array().and_then(|es| {
        es.iter().find_map(|e| {
            let cells = e["cells"].as_array()?;
            let next = if id_is(&e["from"]) {
                cells.get(1)?
            } else if id_is(&e["to"]) {
                cells.get(cells.len().checked_sub(2)?)?
            } else {
                return None;
            };
            let d = |k: &str| next[k].as_f64().unwrap_or(0.0) - cell[k].as_f64().unwrap_or(0.0);
            // Columns run east (+x), rows south (-y).
            horizontal([d("col"), -d("row"), 0.0])
        })
    });
    Ok(Place {
        cell_centre,
        floor: None,
        along,
        pitch,
        level,
    })
}

/// The height of the floor under `p`: the upward-facing surface (a floor, seen from its
/// passage) crossing the vertical line through `p` nearest to `p`'s height, within `below`
/// and `above` metres of it.
fn floor_under(scene: &Scene, p: V3, below: f64, above: f64) -> Option<f64> {
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

/// A pinhole camera: world points to camera coordinates (x right, y up, z forward) and to
/// pixels.
struct Camera {
    eye: V3,
    right: V3,
    up: V3,
    forward: V3,
    /// Pixels per unit of x/z.
    focal: f64,
    /// The x/z and -y/z drawn at the picture's centre.
    centre: [f64; 2],
    half: [f64; 2],
}

impl Camera {
    fn looking(forward: V3) -> (V3, V3, V3) {
        let forward = norm(forward);
        let right = norm(cross(forward, [0.0, 0.0, 1.0]));
        (forward, right, cross(right, forward))
    }

    fn to_camera(&self, p: V3) -> V3 {
        let d = sub(p, self.eye);
        [dot(d, self.right), dot(d, self.up), dot(d, self.forward)]
    }

    /// Pixel coordinates and depth of a camera-frame point in front of the camera.
    fn to_screen(&self, c: V3) -> V3 {
        [
            self.half[0] + self.focal * (c[0] / c[2] - self.centre[0]),
            self.half[1] + self.focal * (-c[1] / c[2] - self.centre[1]),
            c[2],
        ]
    }

    /// The world point at depth `z` seen through pixel (`px`, `py`).
    fn at_pixel(&self, px: f64, py: f64, z: f64) -> V3 {
        let u = (px - self.half[0]) / self.focal + self.centre[0];
        let v = -((py - self.half[1]) / self.focal + self.centre[1]);
        [0, 1, 2].map(|k| self.eye[k] + z * (u * self.right[k] + v * self.up[k] + self.forward[k]))
    }
}

/// The part of a camera-frame triangle in front of the plane `z = near` (none, a triangle or
/// a quadrilateral), in order.
fn clip_near(c: [V3; 3], near: f64) -> Vec<V3> {
    let mut out = Vec::with_capacity(4);
    for k in 0..3 {
        let (p, q) = (c[k], c[(k + 1) % 3]);
        if p[2] > near {
            out.push(p);
        }
        if (p[2] > near) != (q[2] > near) {
            let s = (near - p[2]) / (q[2] - p[2]);
            out.push([0, 1, 2].map(|i| p[i] + s * (q[i] - p[i])));
        }
    }
    out
}

/// Renders `world/mesh/world.obj` to a PNG as `options` say; returns the number of triangles
/// drawn.
pub fn render(world: &Path, out: &Path, options: &Options) -> Result<usize> {
    let Options {
        width,
        height,
        view,
        light,
        at,
    } = *options;
    if view == View::Whole && at.is_some() {
        bail!("--at NODE picks where a --close-up or --inside picture is taken; add one of them");
    }
    // The node first: a wrong --at is refused before the mesh is read.
    let place = match view {
        View::Whole => None,
        View::CloseUp | View::Inside => Some(place_of(world, at)?),
    };
    let mut scene = read_scene(world)?;
    let mut pitch = pitch_of(world);
    let mut inside_eye = None;
    match view {
        View::Whole => {}
        View::CloseUp => {
            let place = place
                .as_ref()
                .context("a close-up or inside view has its node")?;
            pitch = place.pitch;
            scene = crop(
                scene,
                place.cell_centre,
                3.5 * place.pitch,
                0.3 * place.level,
                0.9 * place.level,
            );
            if scene.triangles.is_empty() {
                bail!("nothing to draw around the tile");
            }
        }
        View::Inside => {
            let place = place
                .as_ref()
                .context("a close-up or inside view has its node")?;
            pitch = place.pitch;
            let level = place.level;
            let floor = match place.floor {
                Some(f) => f,
                None => {
                    let c = place.cell_centre;
                    let z = floor_under(&scene, c, 0.5 * level, 0.9 * level).with_context(|| {
                        format!(
                            "no floor under the centre of node {}'s tile; make the world with ground truth (`subtgraph generate --format obj,ground-truth`), whose graph gives each node's floor",
                            at.map_or("start".to_owned(), |n| n.to_string())
                        )
                    })?;
                    [c[0], c[1], z]
                }
            };
            let along = place.along.unwrap_or([1.0, 0.0, 0.0]);
            // A little downward, as a robot's camera is tilted to see the ground ahead.
            let tilt = 8f64.to_radians();
            let forward = [along[0] * tilt.cos(), along[1] * tilt.cos(), -tilt.sin()];
            inside_eye = Some(([floor[0], floor[1], floor[2] + EYE_HEIGHT], forward));
        }
    }
    let camera = if let Some((eye, forward)) = inside_eye {
        let (forward, right, up) = Camera::looking(forward);
        // 90 degrees across.
        Camera {
            eye,
            right,
            up,
            forward,
            focal: 0.5 * width as f64,
            centre: [0.0, 0.0],
            half: [0.5 * width as f64, 0.5 * height as f64],
        }
    } else {
        outside_camera(&scene, view, width, height)
    };
    // The lamp: just above the camera (inside: a robot's lamp; outside: a lamp carried with
    // the viewer, a tenth of the way to the picture's centre above it, so faces turned a
    // little up read lighter than walls).
    let lamp = if inside_eye.is_some() {
        [camera.eye[0], camera.eye[1], camera.eye[2] + LAMP_ABOVE]
    } else {
        let lift = 0.1 * dot(sub(camera.eye, scene_centre(&scene)), camera.forward).abs();
        [0, 1, 2].map(|k| camera.eye[k] + lift * camera.up[k])
    };
    let near = if inside_eye.is_some() { 0.05 } else { 1e-6 };

    // Rasterise: each pixel keeps its nearest triangle and depth; shading comes after, once
    // per pixel.
    const NONE: u32 = u32::MAX;
    let mut depth = vec![f64::INFINITY; width * height];
    let mut nearest = vec![NONE; width * height];
    let mut drawn = 0;
    for (ti, t) in scene.triangles.iter().enumerate() {
        let p = t.map(|i| scene.positions[i as usize].map(f64::from));
        // Seen from the side the normal points to: the passage side.
        if dot(
            cross(sub(p[1], p[0]), sub(p[2], p[0])),
            sub(camera.eye, p[0]),
        ) <= 0.0
        {
            continue;
        }
        let c = p.map(|q| camera.to_camera(q));
        let poly = if c.iter().all(|q| q[2] > near) {
            c.to_vec()
        } else {
            clip_near(c, near)
        };
        if poly.len() < 3 {
            continue;
        }
        let s: Vec<V3> = poly.iter().map(|&q| camera.to_screen(q)).collect();
        let (lo, hi) = s
            .iter()
            .fold(([f64::MAX; 2], [f64::MIN; 2]), |(lo, hi), q| {
                (
                    [lo[0].min(q[0]), lo[1].min(q[1])],
                    [hi[0].max(q[0]), hi[1].max(q[1])],
                )
            });
        if hi[0] < 0.0 || hi[1] < 0.0 || lo[0] > (width - 1) as f64 || lo[1] > (height - 1) as f64 {
            continue;
        }
        drawn += 1;
        for k in 1..s.len() - 1 {
            fill(
                [s[0], s[k], s[k + 1]],
                ti as u32,
                width,
                height,
                &mut depth,
                &mut nearest,
            );
        }
    }

    let normal = |ti: u32| {
        let [a, b, c] =
            scene.triangles[ti as usize].map(|i| scene.positions[i as usize].map(f64::from));
        norm(cross(sub(b, a), sub(c, a)))
    };
    // Shade.
    let mut image = vec![[18u8, 18, 22]; width * height];
    match light {
        Light::Sun => {
            let sun = norm([0.3, -0.4, 1.0]);
            for (i, &ti) in nearest.iter().enumerate() {
                if ti != NONE {
                    let shade = 0.25 + 0.75 * dot(normal(ti), sun).abs();
                    image[i] = colour(scene.colours[ti as usize], shade);
                }
            }
        }
        Light::Lamp => {
            // Distance to the lamp and the cosine of each pixel's face with it; the picture is
            // exposed for the nearest lit surface.
            let mut lit = vec![(0.0, 0.0); width * height];
            let mut closest = f64::INFINITY;
            for (i, &ti) in nearest.iter().enumerate() {
                if ti == NONE {
                    continue;
                }
                let (x, y) = ((i % width) as f64 + 0.5, (i / width) as f64 + 0.5);
                let to_lamp = sub(lamp, camera.at_pixel(x, y, depth[i]));
                let d = dot(to_lamp, to_lamp).sqrt().max(1e-9);
                lit[i] = (d, (dot(normal(ti), to_lamp) / d).max(0.0));
                closest = closest.min(d);
            }
            let d0 = LAMP_REACH * pitch.max(1e-3);
            let falloff = |d: f64| 1.0 / (1.0 + (d / d0) * (d / d0));
            let exposure = 1.0 / falloff(closest.min(1e12));
            for (i, &ti) in nearest.iter().enumerate() {
                if ti != NONE {
                    let (d, cos) = lit[i];
                    let shade = AMBIENT + (1.0 - AMBIENT) * (cos * falloff(d) * exposure).min(1.0);
                    image[i] = colour(scene.colours[ti as usize], shade);
                }
            }
        }
    }
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, width as u32, height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.add_text_chunk("Software".into(), SOFTWARE.into())?;
        let mut w = enc.write_header()?;
        w.write_image_data(image.as_flattened())?;
    }
    write_picture(out, &bytes)?;
    Ok(drawn)
}

/// A material colour under `shade` (0 to 1 of full light), with a square-root gamma.
fn colour(c: [f32; 3], shade: f64) -> [u8; 3] {
    c.map(|c| ((f64::from(c) * shade).max(0.0).sqrt().min(1.0) * 255.0) as u8)
}

/// Draws one screen triangle (pixel x, pixel y, camera depth) into the depth buffer, keeping
/// triangle `id` where it is nearest. Depth is interpolated as 1/z, which is linear on screen.
fn fill(
    [a, b, c]: [V3; 3],
    id: u32,
    width: usize,
    height: usize,
    depth: &mut [f64],
    nearest: &mut [u32],
) {
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if area.abs() < 1e-12 {
        return;
    }
    let x0 = a[0].min(b[0]).min(c[0]).floor().max(0.0) as usize;
    let x1 = (a[0].max(b[0]).max(c[0]).ceil().max(0.0) as usize).min(width - 1);
    let y0 = a[1].min(b[1]).min(c[1]).floor().max(0.0) as usize;
    let y1 = (a[1].max(b[1]).max(c[1]).ceil().max(0.0) as usize).min(height - 1);
    let inv = [1.0 / a[2], 1.0 / b[2], 1.0 / c[2]];
    for y in y0..=y1 {
        let py = y as f64 + 0.5;
        for x in x0..=x1 {
            let px = x as f64 + 0.5;
            let w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
            let w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
            let w2 = 1.0 - w0 - w1;
            if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                continue;
            }
            let z = 1.0 / (w0 * inv[0] + w1 * inv[1] + w2 * inv[2]);
            let i = y * width + x;
            if z < depth[i] {
                depth[i] = z;
                nearest[i] = id;
            }
        }
    }
}

/// The bounds of the vertices the scene's triangles use.
fn used_bounds(scene: &Scene) -> (V3, V3) {
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

fn scene_centre(scene: &Scene) -> V3 {
    let (lo, hi) = used_bounds(scene);
    [0, 1, 2].map(|d| 0.5 * (lo[d] + hi[d]))
}

/// A camera above and to the south-west of the scene, framing all of it.
fn outside_camera(scene: &Scene, view: View, width: usize, height: usize) -> Camera {
    let (lo, hi) = used_bounds(scene);
    let centre = [0, 1, 2].map(|d| 0.5 * (lo[d] + hi[d]));
    let radius = 0.5 * dot(sub(hi, lo), sub(hi, lo)).sqrt();
    let (az, el) = (
        225f64.to_radians(),
        if view == View::CloseUp { 40f64 } else { 50f64 }.to_radians(),
    );
    let dir = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
    let dist = 2.5 * radius;
    let eye = [0, 1, 2].map(|k| centre[k] + dir[k] * dist);
    let (forward, right, up) = Camera::looking(sub(centre, eye));
    let mut camera = Camera {
        eye,
        right,
        up,
        forward,
        focal: 1.0,
        centre: [0.0, 0.0],
        half: [0.5 * width as f64, 0.5 * height as f64],
    };
    // Scale and centre the picture on what is there.
    let mut used = vec![false; scene.positions.len()];
    for t in &scene.triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in scene
        .positions
        .iter()
        .zip(&used)
        .filter(|(_, u)| **u)
        .map(|(p, _)| p)
    {
        let c = camera.to_camera(p.map(f64::from));
        let q = [c[0] / c[2], -c[1] / c[2]];
        for d in 0..2 {
            min[d] = min[d].min(q[d]);
            max[d] = max[d].max(q[d]);
        }
    }
    camera.focal = 0.94
        * (width as f64 / (max[0] - min[0]).max(1e-9))
            .min(height as f64 / (max[1] - min[1]).max(1e-9));
    camera.centre = [0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1])];
    camera
}

/// The PNG `Software` text our pictures carry: how `preview` knows a file is one it drew.
const SOFTWARE: &str = "subtgraph preview";

/// Writes the picture through a temporary file and a rename, replacing only a picture
/// `preview` drew before: any other file at `out` is the user's and is refused.
fn write_picture(out: &Path, bytes: &[u8]) -> Result<()> {
    if out.exists() {
        let ours = std::fs::File::open(out)
            .ok()
            .and_then(|f| {
                png::Decoder::new(std::io::BufReader::new(f))
                    .read_info()
                    .ok()
            })
            .is_some_and(|r| {
                r.info()
                    .uncompressed_latin1_text
                    .iter()
                    .any(|t| t.keyword == "Software" && t.text == SOFTWARE)
            });
        if !ours {
            bail!(
                "{} exists and is not a picture subtgraph preview drew; choose another --out (it is never overwritten)",
                out.display()
            );
        }
    }
    let name = out
        .file_name()
        .ok_or_else(|| anyhow::anyhow!("--out must name a file, like cave.png"))?
        .to_string_lossy();
    let tmp = out.with_file_name(format!(".{name}.partial-{}", std::process::id()));
    std::fs::write(&tmp, bytes)
        .and_then(|()| std::fs::rename(&tmp, out))
        .map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            anyhow::anyhow!(
                "writing {}: {e}{}",
                out.display(),
                subtgraph_core::export::io_hint(&e)
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle crossing the near plane keeps the part in front of it: one vertex behind
    /// gives a quadrilateral, two behind a smaller triangle, every corner on or before the
    /// plane, and the crossing points on the triangle's edges.
    #[test]
    fn clipping_at_the_camera_keeps_the_part_in_front() {
        let near = 0.05;
        let quad = clip_near([[0.0, 0.0, -1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]], near);
        assert_eq!(quad.len(), 4);
        assert!(quad.iter().all(|p| p[2] >= near - 1e-12));
        // The edge from (0,0,-1) to (1,0,1) crosses z = near at x = (near + 1) / 2.
        assert!(
            quad.iter()
                .any(|p| (p[0] - (near + 1.0) / 2.0).abs() < 1e-12 && p[1] == 0.0)
        );
        let tri = clip_near([[0.0, 0.0, 2.0], [1.0, 0.0, -1.0], [0.0, 1.0, -1.0]], near);
        assert_eq!(tri.len(), 3);
        assert!(tri.iter().all(|p| p[2] >= near - 1e-12));
        assert!(clip_near([[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [0.0, 1.0, 0.0]], near).is_empty());
    }

    /// The light names `--light` takes, and a refusal that names both.
    #[test]
    fn lights_by_name() {
        assert_eq!("lamp".parse::<Light>().unwrap(), Light::Lamp);
        assert_eq!("sun".parse::<Light>().unwrap(), Light::Sun);
        let e = "Lamp".parse::<Light>().unwrap_err().to_string();
        assert!(
            e.contains("lamp") && e.contains("sun") && e.contains("'Lamp'"),
            "{e}"
        );
    }
}
