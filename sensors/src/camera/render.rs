//! Rendering a frame: every pixel's first hit in the scene's hierarchy, the point it meets
//! lit by each lamp unless something stands between (a shadow ray cast from the point to the
//! lamp), shaded by its material, turned into the electrons a second its pixel
//! collects; its depth, class and instance beside.
//!
//! **First hits rasterised where the lens allows.** A pinhole camera (radial-tangential
//! distortion) with a global shutter and no motion blur draws the triangles of its view into
//! an undistorted grid of samples ([`super::raster`]) and tests each pixel's ray against the
//! triangles that grid says it can meet: the same hit as a cast through the hierarchy, found
//! with a few triangle tests instead of a traversal. A fisheye (no pinhole grid holds 180
//! degrees), a rolling shutter (a pose per row) and motion blur (five poses a pixel) keep a
//! ray through every pixel. Shadows are rays in every case: drawing each lamp's view the same
//! way (tried: every pixel's own shadow from two lamp rasters) cost more CPU than the shared
//! shadow rays below (cave, stereo, 3 s: about 19 against 16 CPU seconds). Measured in
//! `docs/src/cameras.md`.
//!
//! **Time.** A frame is stamped at the middle of its exposure. With a global shutter every row
//! is seen from the pose at the stamp; with a rolling shutter row `r` of `h` is seen from the
//! pose at `stamp + r readout / h`, as the LiDAR's points are from their own instants.
//! **Motion blur** (on request) averages five instants spread over the exposure; depth, class
//! and instance are the middle instant's, the stamp's.
//!
//! Rows are rendered in parallel; everything drawn at random is hashed from the seed, frame,
//! camera and pixel, so a frame is the same on any number of threads.

use std::sync::Mutex;

use rayon::prelude::*;
use subtgraph_core::raycast::Tracer;
use subtgraph_core::vec3::{V3, dot};

use super::haze::Air;
use super::lens::Distortion;
use super::light::{PlacedLamp, Rig};
use super::raster::{Grid, Raster};
use super::scene::CameraScene;
use super::sensor::{electrons_per_nit_second, vignetting};
use super::shade::{self, Surface};
use super::texture::Map;
use super::{CameraModel, Shutter};
use crate::conditions::Active;
use crate::frames::{Pose, mul};
use crate::trajectory::Trajectory;

/// Farthest a camera's ray looks, metres.
const FAR: f64 = 500.0;
/// How far off a surface a shadow ray starts, metres.
const SHADOW_OFFSET: f64 = 1e-3;
/// Instants a motion-blurred pixel averages.
const BLUR_SAMPLES: usize = 5;
/// Rows a task renders.
const ROWS_PER_TASK: usize = 4;

/// What a camera's pixels look along, worked out once.
pub struct Pixels {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// Each pixel's unit ray in the optical frame; zero outside a fisheye's circle.
    pub rays: Vec<[f32; 3]>,
    /// Electrons a second per candela per square metre at each pixel (vignetting included).
    pub response: Vec<f32>,
    /// Radians a pixel spans at the image's centre.
    pub pixel_angle: f64,
    /// For a pinhole lens with a global shutter: the undistorted grid its first hits are
    /// rasterised into, and each pixel's first sample there ([`Grid::around`]).
    pub grid: Option<(Grid, Vec<u32>)>,
}

impl Pixels {
    /// The table of camera `c` of `model`.
    pub fn of(model: &CameraModel, c: usize) -> Pixels {
        let lens = &model.cameras[c].intrinsics;
        let (w, h) = (lens.width as usize, lens.height as usize);
        let k = electrons_per_nit_second(model);
        let mut rays = Vec::with_capacity(w * h);
        let mut response = Vec::with_capacity(w * h);
        for j in 0..h {
            for i in 0..w {
                let ray = lens
                    .in_circle(i as f64, j as f64)
                    .then(|| lens.ray(i as f64, j as f64))
                    .flatten();
                match ray {
                    Some(r) => {
                        let n = dot(r, r).sqrt();
                        let u = r.map(|x| x / n);
                        rays.push(u.map(|x| x as f32));
                        let theta = u[2].clamp(-1.0, 1.0).acos();
                        response.push((k * vignetting(&lens.distortion, theta)) as f32);
                    }
                    None => {
                        rays.push([0.0; 3]);
                        response.push(0.0);
                    }
                }
            }
        }
        let pinhole = matches!(lens.distortion, Distortion::RadTan { .. })
            && model.shutter == Shutter::Global;
        let grid = pinhole
            .then(|| {
                let step = [1.0 / lens.focal[0], 1.0 / lens.focal[1]];
                let anchor = [-lens.centre[0] * step[0], -lens.centre[1] * step[1]];
                Grid::around(&rays, step, anchor)
            })
            .flatten();
        Pixels {
            width: w,
            height: h,
            rays,
            response,
            pixel_angle: 1.0 / lens.focal[0].max(lens.focal[1]),
            grid,
        }
    }
}

/// One camera's frame before exposure.
#[derive(Clone, Debug, Default)]
pub struct Shot {
    /// Electrons a second per pixel and channel (negative outside a fisheye's circle).
    pub signal: Vec<[f32; 3]>,
    /// Depth along the optical axis, metres (0: nothing seen).
    pub depth: Vec<f32>,
    /// Semantic class ids.
    pub class: Vec<u16>,
    /// Instance ids.
    pub instance: Vec<u32>,
    /// Each pixel's hit: distance along its unit ray (0: none), triangle, normal.
    hits: Vec<PixelHit>,
    /// Each sampled pixel's shadows: bit `2k` set when lamp `k` was tested, bit `2k + 1`
    /// when its light is blocked.
    shadows: Vec<u8>,
}

impl Shot {
    /// The triangle pixel `k` (`y * width + x`) sees first (the scene's index, as
    /// [`CameraScene::class`] counts them), with its distance along the pixel's unit ray,
    /// metres; `None` when it sees nothing.
    pub fn first_hit(&self, k: usize) -> Option<(u32, f32)> {
        let h = self.hits.get(k)?;
        (h.t > 0.0).then_some((h.triangle, h.t))
    }
}

/// A pixel's first hit.
#[derive(Clone, Copy, Debug, Default)]
struct PixelHit {
    t: f32,
    triangle: u32,
    normal: [f32; 3],
}

/// Where a camera is and its lamps are when a row is seen.
struct View {
    camera: Pose,
    lamps: Vec<PlacedLamp>,
}

/// Renders frames of a rig moving through a scene.
pub struct Renderer<'a> {
    /// The scene.
    pub scene: &'a CameraScene,
    /// The platform's motion.
    pub trajectory: &'a Trajectory,
    /// Cameras and lamps on the platform.
    pub rig: &'a Rig,
    /// The camera model.
    pub model: &'a CameraModel,
    /// Each camera's pixels.
    pub pixels: Vec<Pixels>,
    /// Average instants over the exposure.
    pub motion_blur: bool,
    /// Dust, fog or mist to look through (`sense --conditions`; see [`super::haze`]).
    pub air: Option<&'a Active<'a>>,
    /// The rasteriser's buffers, one set for every camera: a frame's cameras render one after
    /// another, and the buffers are scratch (each camera's first hits are read out of them
    /// into its [`Shot`] before the next draws).
    raster: Mutex<Raster>,
}

impl<'a> Renderer<'a> {
    /// A renderer of `model` on `rig` along `trajectory` through `scene`.
    pub fn new(
        scene: &'a CameraScene,
        trajectory: &'a Trajectory,
        rig: &'a Rig,
        model: &'a CameraModel,
        motion_blur: bool,
    ) -> Renderer<'a> {
        let pixels = (0..model.cameras.len())
            .into_par_iter()
            .map(|c| Pixels::of(model, c))
            .collect();
        Renderer {
            scene,
            trajectory,
            rig,
            model,
            pixels,
            motion_blur,
            air: None,
            raster: Mutex::default(),
        }
    }

    /// This renderer looking through the media of `air` (none: clear air).
    pub fn with_air(mut self, air: Option<&'a Active<'a>>) -> Renderer<'a> {
        self.air = air;
        self
    }

    /// When row `row` of camera `c`'s frame stamped `stamp` is seen.
    pub fn row_time(&self, c: usize, stamp: f64, row: usize) -> f64 {
        match self.model.shutter {
            Shutter::Global => stamp,
            Shutter::Rolling { readout_s } => {
                let h = self.model.cameras[c].intrinsics.height as f64;
                stamp + readout_s * row as f64 / h
            }
        }
    }

    /// Camera `c`'s optical frame in the world at time `t`.
    pub fn camera_pose(&self, c: usize, t: f64) -> Pose {
        self.trajectory.pose(t).then(&self.rig.cameras[c])
    }

    /// Camera `c` and the lamps at time `t`.
    fn view(&self, c: usize, t: f64) -> View {
        let body = self.trajectory.pose(t);
        View {
            camera: body.then(&self.rig.cameras[c]),
            lamps: self.rig.lamps.iter().map(|l| l.placed(&body)).collect(),
        }
    }

    /// Renders camera `c`'s frame stamped `stamp`, exposed `exposure_s` (for motion blur),
    /// into `out`.
    ///
    /// Three passes over the rows: every pixel's first hit (rasterised where the camera has
    /// a grid, [`Pixels::grid`]); the shadow rays of every other pixel of every other row;
    /// then each pixel shaded, its shadows those of the sampled pixels around it where they
    /// agree and lie at its depth, else its own rays. A shadow narrower than two pixels that
    /// falls between samples that all see the lamp is missed; every other pixel's light is
    /// what its own shadow ray would give. With motion blur each instant's pixel casts its
    /// own.
    pub fn render(&self, c: usize, stamp: f64, exposure_s: f64, out: &mut Shot) {
        let px = &self.pixels[c];
        let n = px.width * px.height;
        out.signal.resize(n, [0.0; 3]);
        out.depth.resize(n, 0.0);
        out.class.resize(n, 0);
        out.instance.resize(n, 0);
        out.hits.resize(n, PixelHit::default());
        out.shadows.resize(n, 0);
        if self.motion_blur {
            self.render_blurred(c, stamp, exposure_s, out);
            return;
        }
        let w = px.width;
        let chunk = ROWS_PER_TASK * w;
        // First hits.
        self.first_hits(c, stamp, out);
        self.sampled_shadows(c, stamp, out);
        // Shading.
        let (hits, shadows, depth) = (&out.hits, &out.shadows, &out.depth);
        out.signal
            .par_chunks_mut(chunk)
            .enumerate()
            .for_each(|(task, signal)| {
                let mut tracer = self.scene.caster.tracer();
                for (r, row) in signal.chunks_mut(w).enumerate() {
                    let y = task * ROWS_PER_TASK + r;
                    let t = self.row_time(c, stamp, y);
                    let view = self.view(c, t);
                    let mut air = self.air.map(|a| Air::at(a, t, view.camera.translation));
                    for (x, s) in row.iter_mut().enumerate() {
                        let k = y * w + x;
                        if px.rays[k] == [0.0; 3] {
                            *s = [-1.0; 3];
                            continue;
                        }
                        let hit = hits[k];
                        if hit.t <= 0.0 {
                            *s = [0.0; 3];
                            continue;
                        }
                        let shared = Shared {
                            hits,
                            shadows,
                            depth,
                            width: w,
                            height: px.height,
                            x,
                            y,
                        };
                        let (l, ambient) =
                            self.light(px, k, &view, hit, Some(&shared), &mut tracer);
                        let l = match &mut air {
                            Some(air) => self.through(air, px, k, &view, hit, l, ambient),
                            None => l,
                        };
                        let scale = f64::from(px.response[k]);
                        *s = l.map(|v| (v * scale) as f32);
                    }
                }
            });
    }

    /// Every pixel's first hit, depth, class and instance: rasterised where the camera has a
    /// grid ([`Pixels::grid`]), a ray through each pixel otherwise.
    fn first_hits(&self, c: usize, stamp: f64, out: &mut Shot) {
        let px = &self.pixels[c];
        let w = px.width;
        let chunk = ROWS_PER_TASK * w;
        let caster = &*self.scene.caster;
        let mut raster = self.raster.lock().unwrap_or_else(|e| e.into_inner());
        let drawn = px.grid.as_ref().map(|(grid, base)| {
            raster.draw(caster, grid, &self.camera_pose(c, stamp), FAR);
            (&*raster, base)
        });
        out.hits
            .par_chunks_mut(chunk)
            .zip(out.depth.par_chunks_mut(chunk))
            .zip(out.class.par_chunks_mut(chunk))
            .zip(out.instance.par_chunks_mut(chunk))
            .enumerate()
            .for_each(|(task, (((hits, depth), class), instance))| {
                let mut tracer = caster.tracer();
                for (r, hits) in hits.chunks_mut(w).enumerate() {
                    let y = task * ROWS_PER_TASK + r;
                    let camera = self.camera_pose(c, self.row_time(c, stamp, y));
                    for (i, h) in hits.iter_mut().enumerate() {
                        let k = y * w + i;
                        let ray = px.rays[k].map(f64::from);
                        let at = r * w + i;
                        let hit = if ray == [0.0; 3] {
                            None
                        } else {
                            let (o, d) = (camera.translation, mul(&camera.rotation, ray));
                            match drawn {
                                Some((raster, base)) => {
                                    // The candidates' nearest hit, when no other triangle can
                                    // be nearer; else the whole cast.
                                    let near = raster.candidates(base[k]);
                                    if near.count == 0 {
                                        None
                                    } else {
                                        caster
                                            .hit_slots(o, d, near.slots(), FAR)
                                            .filter(|h| near.settles(h.t * ray[2]))
                                            .or_else(|| tracer.cast(o, d, FAR))
                                    }
                                }
                                None => tracer.cast(o, d, FAR),
                            }
                        };
                        match hit {
                            Some(hit) => {
                                *h = PixelHit {
                                    t: hit.t as f32,
                                    triangle: hit.triangle,
                                    normal: hit.normal,
                                };
                                depth[at] = (hit.t * ray[2]) as f32;
                                class[at] = self.scene.class[hit.triangle as usize];
                                instance[at] = self.scene.instance[hit.triangle as usize];
                            }
                            None => {
                                *h = PixelHit::default();
                                depth[at] = 0.0;
                                class[at] = 0;
                                instance[at] = 0;
                            }
                        }
                    }
                }
            });
    }

    /// The shadow rays of every other pixel of every other row, for the shading pass to share
    /// ([`Shared`]).
    fn sampled_shadows(&self, c: usize, stamp: f64, out: &mut Shot) {
        let px = &self.pixels[c];
        let w = px.width;
        let chunk = ROWS_PER_TASK * w;
        let hits = &out.hits;
        out.shadows
            .par_chunks_mut(chunk)
            .enumerate()
            .for_each(|(task, shadows)| {
                let mut tracer = self.scene.caster.tracer();
                for (r, row) in shadows.chunks_mut(w).enumerate() {
                    let y = task * ROWS_PER_TASK + r;
                    row.fill(0);
                    if y % 2 != 0 {
                        continue;
                    }
                    let view = self.view(c, self.row_time(c, stamp, y));
                    for x in (0..w).step_by(2) {
                        let k = y * w + x;
                        row[x] = self.shadow_bits(px, k, &view, hits[k], &mut tracer);
                    }
                }
            });
    }

    /// [`render`](Self::render) with motion blur: five instants a pixel, each with its own
    /// rays; depth, class and instance the middle instant's.
    fn render_blurred(&self, c: usize, stamp: f64, exposure_s: f64, out: &mut Shot) {
        let px = &self.pixels[c];
        let w = px.width;
        let chunk = ROWS_PER_TASK * w;
        out.signal
            .par_chunks_mut(chunk)
            .zip(out.depth.par_chunks_mut(chunk))
            .zip(out.class.par_chunks_mut(chunk))
            .zip(out.instance.par_chunks_mut(chunk))
            .enumerate()
            .for_each(|(task, (((signal, depth), class), instance))| {
                let mut tracer = self.scene.caster.tracer();
                for (r, row) in signal.chunks_mut(w).enumerate() {
                    let y = task * ROWS_PER_TASK + r;
                    let t = self.row_time(c, stamp, y);
                    let views: Vec<View> = (0..BLUR_SAMPLES)
                        .map(|s| {
                            let f = s as f64 / (BLUR_SAMPLES - 1) as f64 - 0.5;
                            self.view(c, t + exposure_s * f)
                        })
                        .collect();
                    let mut airs: Vec<Air> = match self.air {
                        Some(a) => (0..BLUR_SAMPLES)
                            .map(|s| {
                                let f = s as f64 / (BLUR_SAMPLES - 1) as f64 - 0.5;
                                Air::at(a, t + exposure_s * f, views[s].camera.translation)
                            })
                            .collect(),
                        None => Vec::new(),
                    };
                    for (x, s) in row.iter_mut().enumerate() {
                        let k = y * w + x;
                        let at = r * w + x;
                        let ray = px.rays[k].map(f64::from);
                        if ray == [0.0; 3] {
                            *s = [-1.0; 3];
                            depth[at] = 0.0;
                            class[at] = 0;
                            instance[at] = 0;
                            continue;
                        }
                        let mut sum = [0.0f64; 3];
                        for (v, view) in views.iter().enumerate() {
                            let cam = &view.camera;
                            let hit = tracer.cast(cam.translation, mul(&cam.rotation, ray), FAR);
                            if v == BLUR_SAMPLES / 2 {
                                depth[at] = hit.map_or(0.0, |h| (h.t * ray[2]) as f32);
                                class[at] =
                                    hit.map_or(0, |h| self.scene.class[h.triangle as usize]);
                                instance[at] =
                                    hit.map_or(0, |h| self.scene.instance[h.triangle as usize]);
                            }
                            if let Some(h) = hit {
                                let hit = PixelHit {
                                    t: h.t as f32,
                                    triangle: h.triangle,
                                    normal: h.normal,
                                };
                                let (l, ambient) = self.light(px, k, view, hit, None, &mut tracer);
                                let l = match airs.get_mut(v) {
                                    Some(air) => self.through(air, px, k, view, hit, l, ambient),
                                    None => l,
                                };
                                for ch in 0..3 {
                                    sum[ch] += l[ch];
                                }
                            }
                        }
                        let scale = f64::from(px.response[k]) / BLUR_SAMPLES as f64;
                        *s = sum.map(|v| (v * scale) as f32);
                    }
                }
            });
    }

    /// The point pixel `k`'s hit is at, its unit ray in the world, and its normal turned to
    /// face the camera.
    fn point(&self, px: &Pixels, k: usize, view: &View, hit: PixelHit) -> (V3, V3, V3) {
        let cam = &view.camera;
        let dir = mul(&cam.rotation, px.rays[k].map(f64::from));
        let t = f64::from(hit.t);
        let p = [0, 1, 2].map(|i| cam.translation[i] + t * dir[i]);
        let mut n = hit.normal.map(f64::from);
        if dot(n, dir) > 0.0 {
            n = n.map(|x| -x);
        }
        (p, dir, n)
    }

    /// A sampled pixel's shadow bits: for each lamp that lights its point, whether a shadow
    /// ray reaches the lamp.
    fn shadow_bits(
        &self,
        px: &Pixels,
        k: usize,
        view: &View,
        hit: PixelHit,
        tracer: &mut Tracer<'_>,
    ) -> u8 {
        if hit.t <= 0.0 {
            return 0;
        }
        let (p, _, n) = self.point(px, k, view, hit);
        let mut bits = 0u8;
        for (li, lamp) in view.lamps.iter().enumerate().take(4) {
            let (lux, l, dist) = lamp.at(p);
            if lux < 1e-6 || dot(n, l) <= 0.0 {
                continue;
            }
            bits |= 1 << (2 * li);
            if blocked(tracer, p, n, l, dist) {
                bits |= 2 << (2 * li);
            }
        }
        bits
    }

    /// Pixel `k`'s light `l` (`ambient` of it from the ambient light) as it reaches the
    /// camera through `air`.
    #[allow(clippy::too_many_arguments)]
    fn through(
        &self,
        air: &mut Air<'_, '_>,
        px: &Pixels,
        k: usize,
        view: &View,
        hit: PixelHit,
        l: [f64; 3],
        ambient: [f64; 3],
    ) -> [f64; 3] {
        let cam = &view.camera;
        let dir = mul(&cam.rotation, px.rays[k].map(f64::from));
        air.seen(
            cam.translation,
            dir,
            f64::from(hit.t),
            l,
            ambient,
            &view.lamps,
        )
    }

    /// The light leaving pixel `k`'s point towards the camera, candela per square metre per
    /// channel: its material's answer to each lamp whose light reaches it (the sampled
    /// pixels' shadows in `shared` where they settle it, else a shadow ray) and to the
    /// ambient light; and the ambient light's part of it.
    fn light(
        &self,
        px: &Pixels,
        k: usize,
        view: &View,
        hit: PixelHit,
        shared: Option<&Shared<'_>>,
        tracer: &mut Tracer<'_>,
    ) -> ([f64; 3], [f64; 3]) {
        let scene = self.scene;
        let tri = hit.triangle;
        let (p, dir, n) = self.point(px, k, view, hit);
        let corners = scene.corners(tri);
        let ids = scene.mesh.triangles[tri as usize];
        let w = barycentric(corners, p);
        let uvs = ids.map(|i| scene.mesh.uvs[i as usize].map(f64::from));
        let uv = [
            w[0] * uvs[0][0] + w[1] * uvs[1][0] + w[2] * uvs[2][0],
            w[0] * uvs[0][1] + w[1] * uvs[1][1] + w[2] * uvs[2][1],
        ];
        let mut shading = n;
        let vn = &scene.vertex_normals;
        if ids.iter().all(|&i| (i as usize) < vn.len()) {
            let m = ids.map(|i| vn[i as usize].map(f64::from));
            let s = [0, 1, 2].map(|k| w[0] * m[0][k] + w[1] * m[1][k] + w[2] * m[2][k]);
            let len = dot(s, s).sqrt();
            if len > 1e-9 {
                shading = s.map(|x| x / len);
                if dot(shading, n) < 0.0 {
                    shading = shading.map(|x| -x);
                }
            }
        }
        let look = &scene.looks[usize::from(scene.mesh.materials[tri as usize])];
        let mut surface = Surface {
            albedo: look.colour,
            roughness: look.roughness,
            retro: look.retro,
        };
        let textured =
            look.albedo.is_some() || look.normal.is_some() || look.roughness_map.is_some();
        if textured || look.stack.is_some() {
            let frame = shade::tangent_frame(corners, uvs);
            // The pixel's footprint on the surface, in texels of the first level: which level
            // to read so a texel is about a pixel.
            let cos = dot(n, dir).abs().max(0.2);
            let metres = f64::from(hit.t) * px.pixel_angle / cos;
            let metres_per_unit = frame.map_or(1.0, |f| 0.5 * (f.2 + f.3));
            let level = |texels: f64| level_of(metres / metres_per_unit.max(1e-9) * texels);
            if let Some(st) = &look.stack {
                let sample = st.sample(uv[0], uv[1], level(st.texels_per_repeat()));
                surface.albedo = sample.albedo;
                surface.roughness = sample.roughness;
                if let Some((tu, tv, ..)) = frame {
                    shading = shade::bend(shading, tu, tv, sample.normal);
                }
            }
            if let Some(t) = &look.albedo {
                surface.albedo =
                    t.bilinear(uv[0], uv[1], level(t.texels_per_repeat()), Map::Albedo);
            }
            if let Some(t) = &look.roughness_map {
                surface.roughness =
                    t.bilinear(uv[0], uv[1], level(t.texels_per_repeat()), Map::Roughness)[0];
            }
            if let (Some(t), Some((tu, tv, ..))) = (&look.normal, frame) {
                let m = t.bilinear(uv[0], uv[1], level(t.texels_per_repeat()), Map::Normal);
                shading = shade::bend(shading, tu, tv, m);
            }
        }
        let v = dir.map(|x| -x);
        let mut out = shade::ambient(&surface, self.rig.ambient_lux);
        let ambient = out;
        for (li, lamp) in view.lamps.iter().enumerate() {
            let (lux, l, dist) = lamp.at(p);
            if lux < 1e-6 || dot(n, l) <= 0.0 {
                continue;
            }
            let settled = shared.and_then(|s| s.blocked(li));
            if settled.unwrap_or_else(|| blocked(tracer, p, n, l, dist)) {
                continue;
            }
            let r = shade::reflected(&surface, shading, v, l, lux);
            for k in 0..3 {
                out[k] += r[k];
            }
        }
        (out, ambient)
    }
}

/// The sampled pixels' shadows, for a pixel at (`x`, `y`) to take where they settle its own.
struct Shared<'s> {
    hits: &'s [PixelHit],
    shadows: &'s [u8],
    depth: &'s [f32],
    width: usize,
    height: usize,
    x: usize,
    y: usize,
}

impl Shared<'_> {
    /// Whether lamp `li`'s light is blocked at this pixel, when the sampled pixels settle it:
    /// the pixel itself if sampled, else the two or four sampled neighbours around it, when
    /// each tested the lamp, all agree, and each lies within 3 % of this pixel's depth.
    fn blocked(&self, li: usize) -> Option<bool> {
        if li >= 4 {
            return None;
        }
        let (x, y, w) = (self.x, self.y, self.width);
        let tested = 1u8 << (2 * li);
        let block = 2u8 << (2 * li);
        if x % 2 == 0 && y % 2 == 0 {
            let b = self.shadows[y * w + x];
            return (b & tested != 0).then_some(b & block != 0);
        }
        let xs = if x % 2 == 0 {
            [x, x]
        } else {
            [x.wrapping_sub(1), x + 1]
        };
        let ys = if y % 2 == 0 {
            [y, y]
        } else {
            [y.wrapping_sub(1), y + 1]
        };
        let z = self.depth[y * w + x];
        let mut answer = None;
        for ny in ys {
            for nx in xs {
                if nx >= w || ny >= self.height {
                    return None;
                }
                let k = ny * w + nx;
                let b = self.shadows[k];
                if b & tested == 0 || self.hits[k].t <= 0.0 || (self.depth[k] - z).abs() > 0.03 * z
                {
                    return None;
                }
                let here = b & block != 0;
                if answer.is_some_and(|a| a != here) {
                    return None;
                }
                answer = Some(here);
            }
        }
        answer
    }
}

/// Whether something lies between the point `p` (normal `n`) and a lamp `dist` metres away
/// along the unit `l`: a shadow ray from just off the surface.
#[inline]
fn blocked(tracer: &mut Tracer<'_>, p: V3, n: V3, l: V3, dist: f64) -> bool {
    let from = [0, 1, 2].map(|k| p[k] + SHADOW_OFFSET * n[k]);
    tracer.cast(from, l, dist - 2.0 * SHADOW_OFFSET).is_some()
}

/// The mip level whose texels are about `texels_per_pixel` of the first level's: the nearest
/// whole `log2`, from the float's exponent (no logarithm).
#[inline]
fn level_of(texels_per_pixel: f64) -> usize {
    if texels_per_pixel.is_nan() || texels_per_pixel <= 1.0 {
        return 0;
    }
    let x = (texels_per_pixel * std::f64::consts::SQRT_2).min(1e300);
    (((x.to_bits() >> 52) & 0x7ff) as usize).saturating_sub(1023)
}

/// Barycentric weights of `p` in the triangle `c` (by areas in the triangle's plane).
#[inline]
fn barycentric(c: [V3; 3], p: V3) -> [f64; 3] {
    use subtgraph_core::vec3::{cross, sub};
    let n = cross(sub(c[1], c[0]), sub(c[2], c[0]));
    let nn = dot(n, n).max(1e-300);
    let wb = dot(cross(sub(p, c[0]), sub(c[2], c[0])), n) / nn;
    let wc = dot(cross(sub(c[1], c[0]), sub(p, c[0])), n) / nn;
    [1.0 - wb - wc, wb, wc]
}
