//! `subtgraph preview`: a shaded perspective picture of a world's mesh, drawn on the CPU (no
//! GPU, no display), from above and to the south-west.
//!
//! Triangles are kept only when they face the camera from the passage side, so the ceilings
//! nearest the camera drop out and the picture shows the floors and far walls of every
//! passage: a cutaway of the whole network at a glance.

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

/// The start tile's position and the pitch and level height, from `topology.json`.
fn start_of(world: &Path) -> Result<([f64; 3], f64, f64)> {
    let path = world.join("topology.json");
    let doc: serde_json::Value = serde_json::from_slice(
        &std::fs::read(&path).with_context(|| format!("reading {}", path.display()))?,
    )
    .with_context(|| format!("parsing {}", path.display()))?;
    let start = doc["start"]
        .as_u64()
        .context("topology.json has no start node")? as usize;
    let p = &doc["nodes"][start]["position"];
    let pos = [0, 1, 2].map(|i| p[i].as_f64().unwrap_or(0.0));
    Ok((
        pos,
        doc["tile_pitch_m"].as_f64().unwrap_or(25.0),
        doc["level_height_m"].as_f64().unwrap_or(20.0),
    ))
}

/// Renders `world/mesh/world.obj` to a PNG of `width x height` pixels: the whole world, or
/// with `close_up` the few tiles around the start.
pub fn render(
    world: &Path,
    out: &Path,
    width: usize,
    height: usize,
    close_up: bool,
) -> Result<usize> {
    let mut scene = read_scene(world)?;
    if close_up {
        let (start, pitch, level) = start_of(world)?;
        scene = crop(scene, start, 3.5 * pitch, 0.3 * level, 0.9 * level);
        if scene.triangles.is_empty() {
            bail!("nothing to draw around the start tile");
        }
    }
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
    let centre = [
        0.5 * (lo[0] + hi[0]),
        0.5 * (lo[1] + hi[1]),
        0.5 * (lo[2] + hi[2]),
    ];
    let radius = 0.5 * dot(sub(hi, lo), sub(hi, lo)).sqrt();
    // From the south-west, above the horizon.
    let (az, el) = (
        225f64.to_radians(),
        if close_up { 40f64 } else { 50f64 }.to_radians(),
    );
    let dir = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
    let dist = 2.5 * radius;
    let eye = [
        centre[0] + dir[0] * dist,
        centre[1] + dir[1] * dist,
        centre[2] + dir[2] * dist,
    ];
    let forward = norm(sub(centre, eye));
    let right = norm(cross(forward, [0.0, 0.0, 1.0]));
    let up = cross(right, forward);
    // Project with unit focal length, then scale and centre the picture on what is there.
    let raw: Vec<V3> = scene
        .positions
        .iter()
        .map(|p| {
            let d = sub(p.map(f64::from), eye);
            let z = dot(d, forward);
            [dot(d, right) / z, -dot(d, up) / z, z]
        })
        .collect();
    let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in raw.iter().zip(&used).filter(|(_, u)| **u).map(|(p, _)| p) {
        for d in 0..2 {
            min[d] = min[d].min(p[d]);
            max[d] = max[d].max(p[d]);
        }
    }
    let f = 0.94
        * (width as f64 / (max[0] - min[0]).max(1e-9))
            .min(height as f64 / (max[1] - min[1]).max(1e-9));
    let (cx, cy) = (0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1]));
    let screen: Vec<V3> = raw
        .iter()
        .map(|p| {
            [
                0.5 * width as f64 + f * (p[0] - cx),
                0.5 * height as f64 + f * (p[1] - cy),
                p[2],
            ]
        })
        .collect();
    let mut depth = vec![f64::INFINITY; width * height];
    let mut image = vec![[18u8, 18, 22]; width * height];
    let light = norm([0.3, -0.4, 1.0]);
    let mut drawn = 0;
    for (t, colour) in scene.triangles.iter().zip(&scene.colours) {
        let [a, b, c] = t.map(|i| screen[i as usize]);
        if a[2] <= 0.0 || b[2] <= 0.0 || c[2] <= 0.0 {
            continue;
        }
        // Counter-clockwise on screen (y down) means seen from the passage side.
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area >= 0.0 {
            continue;
        }
        let [pa, pb, pc] = t.map(|i| scene.positions[i as usize].map(f64::from));
        let n = norm(cross(sub(pb, pa), sub(pc, pa)));
        let shade = 0.25 + 0.75 * dot(n, light).abs();
        let rgb = colour.map(|c| ((f64::from(c) * shade).sqrt().min(1.0) * 255.0) as u8);
        let x0 = a[0].min(b[0]).min(c[0]).floor().max(0.0) as usize;
        let x1 = (a[0].max(b[0]).max(c[0]).ceil() as usize).min(width - 1);
        let y0 = a[1].min(b[1]).min(c[1]).floor().max(0.0) as usize;
        let y1 = (a[1].max(b[1]).max(c[1]).ceil() as usize).min(height - 1);
        if x0 > x1 || y0 > y1 {
            continue;
        }
        drawn += 1;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
                let w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let z = w0 * a[2] + w1 * b[2] + w2 * c[2];
                let i = y * width + x;
                if z < depth[i] {
                    depth[i] = z;
                    image[i] = rgb;
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
