//! Drawing a frame: every triangle facing the camera rasterised into a depth buffer that keeps
//! each pixel's nearest triangle, then each pixel shaded once, by the sun or the lamp, and the
//! image encoded as PNG. One thread, a fixed order: the same scene gives the same bytes.

use subtgraph_core::vec3::{V3, cross, dot, sub};

use super::camera::{Camera, clip_near, norm};
use super::scene::Scene;
use super::{AMBIENT, LAMP_REACH, Light, SOFTWARE};

/// A pixel no triangle covers.
const NONE: u32 = u32::MAX;

/// The depth buffer: per pixel, the nearest triangle's camera depth and index.
pub(super) struct Frame {
    pub width: usize,
    pub height: usize,
    depth: Vec<f64>,
    nearest: Vec<u32>,
    /// Triangles drawn (facing the camera and at least partly in the picture).
    pub drawn: usize,
}

/// Rasterises the triangles of `scene` that face `camera` from their passage side, clipped at
/// `near` metres before it.
pub(super) fn rasterise(
    scene: &Scene,
    camera: &Camera,
    near: f64,
    width: usize,
    height: usize,
) -> Frame {
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

    Frame {
        width,
        height,
        depth,
        nearest,
        drawn,
    }
}

/// The RGB image of a frame: each covered pixel its triangle's colour under `light` (the lamp
/// at `lamp`, reaching as far as the tile `pitch` says), the rest the background.
pub(super) fn shade(
    scene: &Scene,
    frame: &Frame,
    camera: &Camera,
    light: Light,
    lamp: V3,
    pitch: f64,
) -> Vec<[u8; 3]> {
    let Frame {
        width,
        height,
        ref depth,
        ref nearest,
        ..
    } = *frame;
    let normal = |ti: u32| {
        let [a, b, c] =
            scene.triangles[ti as usize].map(|i| scene.positions[i as usize].map(f64::from));
        norm(cross(sub(b, a), sub(c, a)))
    };
    // A pixel's surface colour: its triangle's, or its albedo image's at the pixel's
    // texture coordinates (barycentric in the triangle, from the pixel's point on it).
    let surface = |i: usize, ti: u32| -> [f32; 3] {
        let t = ti as usize;
        let Some(img) = scene.images.get(usize::from(scene.textures[t])) else {
            return scene.colours[t];
        };
        let (x, y) = ((i % width) as f64 + 0.5, (i / width) as f64 + 0.5);
        let p = camera.at_pixel(x, y, depth[i]);
        let [a, b, c] = scene.triangles[t].map(|k| scene.positions[k as usize].map(f64::from));
        let n = cross(sub(b, a), sub(c, a));
        let nn = dot(n, n).max(1e-300);
        let wb = dot(cross(sub(p, a), sub(c, a)), n) / nn;
        let wc = dot(cross(sub(b, a), sub(p, a)), n) / nn;
        let wa = 1.0 - wb - wc;
        let [ua, ub, uc] = scene.triangles[t].map(|k| scene.uvs[k as usize].map(f64::from));
        img.at(
            wa * ua[0] + wb * ub[0] + wc * uc[0],
            wa * ua[1] + wb * ub[1] + wc * uc[1],
        )
    };
    let mut image = vec![[18u8, 18, 22]; width * height];
    match light {
        Light::Sun => {
            let sun = norm([0.3, -0.4, 1.0]);
            for (i, &ti) in nearest.iter().enumerate() {
                if ti != NONE {
                    let shade = 0.25 + 0.75 * dot(normal(ti), sun).abs();
                    image[i] = colour(surface(i, ti), shade);
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
                    image[i] = colour(surface(i, ti), shade);
                }
            }
        }
    }
    image
}

/// The image as a PNG carrying [`SOFTWARE`], by which `preview` knows a picture it drew.
pub(super) fn encode(
    image: &[[u8; 3]],
    width: usize,
    height: usize,
) -> Result<Vec<u8>, png::EncodingError> {
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, width as u32, height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.add_text_chunk("Software".into(), SOFTWARE.into())?;
        let mut w = enc.write_header()?;
        w.write_image_data(image.as_flattened())?;
    }
    Ok(bytes)
}

/// A material colour under `shade` (0 to 1 of full light), with a square-root gamma.
#[inline]
fn colour(c: [f32; 3], shade: f64) -> [u8; 3] {
    c.map(|c| ((f64::from(c) * shade).max(0.0).sqrt().min(1.0) * 255.0) as u8)
}

/// Draws one screen triangle (pixel x, pixel y, camera depth) into the depth buffer, keeping
/// triangle `id` where it is nearest. Depth is interpolated as 1/z, which is linear on screen.
#[inline]
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
