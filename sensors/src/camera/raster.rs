//! First hits by rasterising: which triangle each pixel sees, found by drawing the triangles in
//! the view (the hierarchy's leaves inside its frustum) into a grid of samples with a depth
//! test, then settled by the pixel's own ray against the few triangles the samples around it
//! hold.
//!
//! **Why.** Casting a ray through every pixel is most of a frame's time (perf: 36 % ray
//! casting, 25 % shading); a view's pixels are coherent, which a rasteriser uses and a ray
//! cast does not. The rasteriser only proposes: each pixel's hit is the watertight ray test
//! of the core's caster against the triangles of the two by two samples around the pixel's
//! direction ([`RayCaster::hit_slots`]), so its distance, triangle and normal are the numbers
//! a cast gives when it meets that triangle, and a ray that meets none of them (a pixel on an
//! edge the samples straddle) is cast in full.
//!
//! **Slivers.** A triangle narrower than a sample's spacing can cross a pixel's ray and cover
//! none of the four samples around it (the cave's surface has many long thin ones); tested
//! only against the samples' triangles, that pixel would see through it to the surface
//! behind (84 pixels of 1.2 million on four cave views, up to 24 m too deep, before this
//! pass). So a second pass records, for every cell between four samples, the nearest two
//! triangles reaching into it that are nearest at none of its samples (its **threats**),
//! with a bound on how near each can be there (the largest `1/z` its plane takes at the
//! cell's corners). A pixel tests the nearest threat with the samples' triangles and keeps
//! the hit only when it is nearer than the second threat's bound; otherwise it is cast in
//! full. So the first hit is the cast's: the same triangle at the same distance for every
//! pixel (`tests/integration/camera_raster.rs`), the rasteriser deciding only which
//! triangles to test.
//!
//! **Distortion.** A pinhole rasteriser draws straight lines; a lens with radial-tangential
//! distortion bends them. So the grid is the undistorted one (sample `(i, j)` looks along
//! `(x0 + i sx, y0 + j sy, 1)` in the view's frame, one sample a pixel at the image's centre,
//! wider than the image where barrel distortion pulls its corners in), and each pixel looks
//! up the samples around its own undistorted direction. Without distortion the samples are
//! the pixels' centres. A fisheye (beyond 90 degrees no pinhole grid holds it), a rolling
//! shutter (a pose per row) and motion blur (five poses a pixel) keep the ray cast.
//!
//! The depth test orders samples by `1/z` and then by slot, so the result does not depend on
//! the order triangles are drawn in or on the thread count.

use rayon::prelude::*;
use subtgraph_core::raycast::{Plane, RayCaster};
use subtgraph_core::vec3::V3;

use crate::frames::{Pose, mul, mul_t};

/// Rows of samples a task draws.
const BAND: usize = 8;
/// The nearest a drawn point may be, metres along the view's axis (triangles are clipped
/// there).
const NEAR: f64 = 1e-3;
/// An empty sample's key: no triangle.
const EMPTY: u64 = u64::MAX;

/// A pinhole view's samples: sample `(i, j)` looks along `(x0 + i sx, y0 + j sy, 1)` in the
/// view's frame (x right, y down, z forward).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Normalised coordinates of sample `(0, 0)`.
    pub origin: [f64; 2],
    /// Normalised spacing of samples across and down.
    pub step: [f64; 2],
    /// Samples across.
    pub width: usize,
    /// Samples down.
    pub height: usize,
}

impl Grid {
    /// The grid over the directions `rays` (unit, in the view's frame; zero for none) with
    /// one sample per `step` and samples at `(x, y) = anchor + whole steps`, with a sample to
    /// spare on every side; and each ray's first sample of the two by two around it (the
    /// others are the next across, the next down and the one across from that), `u32::MAX`
    /// for a zero ray. `None` if a ray looks sideways or back (no pinhole grid holds it).
    pub fn around(rays: &[[f32; 3]], step: [f64; 2], anchor: [f64; 2]) -> Option<(Grid, Vec<u32>)> {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for r in rays.iter().filter(|r| **r != [0.0; 3]) {
            if r[2] < 0.05 {
                return None;
            }
            let q = [
                f64::from(r[0]) / f64::from(r[2]),
                f64::from(r[1]) / f64::from(r[2]),
            ];
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        if lo[0] > hi[0] {
            return None;
        }
        let first = [0, 1].map(|k| ((lo[k] - anchor[k]) / step[k]).floor() - 1.0);
        let origin = [0, 1].map(|k| anchor[k] + first[k] * step[k]);
        let size = [0, 1].map(|k| ((hi[k] - origin[k]) / step[k]).ceil() as usize + 2);
        let grid = Grid {
            origin,
            step,
            width: size[0],
            height: size[1],
        };
        let base = rays
            .iter()
            .map(|r| {
                if *r == [0.0; 3] {
                    return u32::MAX;
                }
                let q = [
                    f64::from(r[0]) / f64::from(r[2]),
                    f64::from(r[1]) / f64::from(r[2]),
                ];
                let [i, j] = [0, 1].map(|k| ((q[k] - origin[k]) / step[k]).floor() as usize);
                let i = i.min(grid.width - 2);
                let j = j.min(grid.height - 2);
                (j * grid.width + i) as u32
            })
            .collect();
        Some((grid, base))
    }

    /// The half-spaces of the view from `pose` (world from view): its four sides through the
    /// samples at its edges, and its near and far ends.
    fn planes(&self, pose: &Pose, far: f64) -> [Plane; 6] {
        let x1 = self.origin[0] + (self.width - 1) as f64 * self.step[0];
        let y1 = self.origin[1] + (self.height - 1) as f64 * self.step[1];
        let local: [(V3, f64); 6] = [
            ([1.0, 0.0, -self.origin[0]], 0.0),
            ([-1.0, 0.0, x1], 0.0),
            ([0.0, 1.0, -self.origin[1]], 0.0),
            ([0.0, -1.0, y1], 0.0),
            ([0.0, 0.0, 1.0], -NEAR),
            ([0.0, 0.0, -1.0], far),
        ];
        local.map(|(n, d)| {
            let w = mul(&pose.rotation, n);
            let o = pose.translation;
            [
                w[0],
                w[1],
                w[2],
                d - (w[0] * o[0] + w[1] * o[1] + w[2] * o[2]),
            ]
        })
    }
}

/// A triangle drawn into the grid: its slot, its corners as sample coordinates and `1/z`,
/// and the rows of cells (a cell: the square between four samples, named by its first) it
/// reaches into.
#[derive(Clone, Copy, Debug)]
struct Drawn {
    slot: u32,
    corners: [[f64; 3]; 3],
    rows: [usize; 2],
}

/// A pixel's candidates ([`Raster::candidates`]).
#[derive(Clone, Copy, Debug)]
pub struct Candidates {
    /// The distinct triangles (slots) to test, in increasing order: the nearest at each of the
    /// four samples around the pixel, and the nearest other triangle reaching into their cell.
    pub slots: [u32; 5],
    /// How many of `slots` there are.
    pub count: usize,
    /// The largest `1/z` any triangle not in `slots` can have in the cell (0: none reaches in):
    /// a hit among `slots` nearer than that is the first hit.
    pub beyond: f64,
}

impl Candidates {
    /// The slots to test.
    #[inline]
    pub fn slots(&self) -> &[u32] {
        &self.slots[..self.count]
    }

    /// Whether a hit at `z` along the view's axis is nearer than every triangle not in
    /// [`slots`](Self::slots) can be (with a margin for rounding).
    #[inline]
    pub fn settles(&self, z: f64) -> bool {
        z > 0.0 && (1.0 / z) * (1.0 - 1e-5) > self.beyond
    }
}

/// One view drawn: the nearest triangle at each sample. Buffers are kept from view to view.
#[derive(Clone, Debug, Default)]
pub struct Raster {
    /// Per sample, `(u32::MAX - bits of 1/z) << 32 | slot`: the smallest is the nearest.
    keys: Vec<u64>,
    /// Per cell, the two largest `(bits of the bound on 1/z) << 32 | slot` of the triangles
    /// reaching into it that are nearest at none of its four samples.
    threats: Vec<[u64; 2]>,
    width: usize,
    slots: Vec<u32>,
    drawn: Vec<Drawn>,
    bins: Vec<Vec<u32>>,
}

impl Raster {
    /// Draws what the view from `pose` (world from view) sees of `caster`'s triangles within
    /// `far` metres into `grid`'s samples.
    pub fn draw(&mut self, caster: &RayCaster, grid: &Grid, pose: &Pose, far: f64) {
        self.slots.clear();
        caster.slots_within(&grid.planes(pose, far), &mut self.slots);
        let (g, pose_c) = (*grid, *pose);
        self.drawn = self
            .slots
            .par_chunks(4096)
            .flat_map_iter(|chunk| {
                let mut out = Vec::with_capacity(chunk.len());
                for &s in chunk {
                    project(&g, &pose_c, s, caster.slot_corners(s), &mut out);
                }
                out
            })
            .collect();
        let bands = g.height.div_ceil(BAND);
        self.bins.resize_with(bands, Vec::new);
        for b in &mut self.bins {
            b.clear();
        }
        for (k, d) in self.drawn.iter().enumerate() {
            for b in d.rows[0] / BAND..=d.rows[1] / BAND {
                self.bins[b].push(k as u32);
            }
        }
        self.width = g.width;
        self.keys.clear();
        self.keys.resize(g.width * g.height, EMPTY);
        let (drawn, bins) = (&self.drawn, &self.bins);
        self.keys
            .par_chunks_mut(BAND * g.width)
            .enumerate()
            .for_each(|(b, keys)| {
                let rows = [b * BAND, (b * BAND + BAND).min(g.height) - 1];
                for &k in &bins[b] {
                    fill(&drawn[k as usize], rows, g.width, keys);
                }
            });
        // Then every cell's threats: what reaches into it between its samples.
        self.threats.clear();
        self.threats.resize(g.width * g.height, [0; 2]);
        let keys = &self.keys;
        self.threats
            .par_chunks_mut(BAND * g.width)
            .enumerate()
            .for_each(|(b, threats)| {
                let rows = [b * BAND, (b * BAND + BAND).min(g.height) - 1];
                for &k in &bins[b] {
                    threaten(&drawn[k as usize], rows, &g, keys, threats);
                }
            });
    }

    /// What pixel `base` ([`Grid::around`]) may see: the distinct triangles nearest at the
    /// two by two samples from `base` and the nearest other triangle reaching into their
    /// cell, and how near any further one can be.
    #[inline]
    pub fn candidates(&self, base: u32) -> Candidates {
        let b = base as usize;
        let mut out = Candidates {
            slots: [0; 5],
            count: 0,
            beyond: 0.0,
        };
        let add = |s: u32, out: &mut Candidates| {
            if !out.slots[..out.count].contains(&s) {
                out.slots[out.count] = s;
                out.count += 1;
            }
        };
        for k in [b, b + 1, b + self.width, b + self.width + 1] {
            let key = self.keys[k];
            if key != EMPTY {
                add(key as u32, &mut out);
            }
        }
        // The nearest threat is tested; no other one is nearer than the second (which may
        // be another piece of the same triangle, a bound all the same).
        let [first, second] = self.threats[b];
        if first != 0 {
            add(first as u32, &mut out);
            out.beyond = f64::from(f32::from_bits((second >> 32) as u32));
        }
        out.slots[..out.count].sort_unstable();
        out
    }
}

/// Appends the triangle in `slot` with world corners `c`, clipped to the view's near end and
/// put in sample coordinates, to `out` (nothing when it covers no sample's rows).
fn project(g: &Grid, pose: &Pose, slot: u32, c: [[f32; 3]; 3], out: &mut Vec<Drawn>) {
    let local = c.map(|p| {
        let d = [0, 1, 2].map(|k| f64::from(p[k]) - pose.translation[k]);
        mul_t(&pose.rotation, d)
    });
    // Clip to z >= NEAR (Sutherland-Hodgman against one plane: at most four corners).
    let mut poly = [[0.0f64; 3]; 4];
    let mut n = 0;
    for k in 0..3 {
        let (a, b) = (local[k], local[(k + 1) % 3]);
        let (ina, inb) = (a[2] >= NEAR, b[2] >= NEAR);
        if ina {
            poly[n] = a;
            n += 1;
        }
        if ina != inb {
            let t = (NEAR - a[2]) / (b[2] - a[2]);
            poly[n] = [0, 1, 2].map(|i| a[i] + t * (b[i] - a[i]));
            poly[n][2] = NEAR;
            n += 1;
        }
    }
    if n < 3 {
        return;
    }
    let screen = |p: V3| {
        [
            (p[0] / p[2] - g.origin[0]) / g.step[0],
            (p[1] / p[2] - g.origin[1]) / g.step[1],
            1.0 / p[2],
        ]
    };
    let s: Vec<[f64; 3]> = poly[..n].iter().map(|&p| screen(p)).collect();
    for k in 1..n - 1 {
        let corners = [s[0], s[k], s[k + 1]];
        let lo = corners.iter().map(|c| c[1]).fold(f64::INFINITY, f64::min);
        let hi = corners
            .iter()
            .map(|c| c[1])
            .fold(f64::NEG_INFINITY, f64::max);
        if !(hi >= 0.0 && lo <= (g.height - 1) as f64) {
            continue;
        }
        out.push(Drawn {
            slot,
            corners,
            rows: [
                lo.floor().max(0.0) as usize,
                (hi.floor() as usize).min(g.height - 1),
            ],
        });
    }
}

/// Draws one triangle into the samples of rows `rows` (`keys` starts at row `rows[0]`).
fn fill(d: &Drawn, rows: [usize; 2], width: usize, keys: &mut [u64]) {
    let [a, b, c] = d.corners;
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let inv = 1.0 / area;
    let left = a[0].min(b[0]).min(c[0]).ceil().max(0.0);
    let right = a[0].max(b[0]).max(c[0]).floor().min((width - 1) as f64);
    if left > right {
        return;
    }
    let (i0, i1) = (left as usize, right as usize);
    let top = a[1].min(b[1]).min(c[1]).ceil().max(0.0) as usize;
    let j0 = top.max(rows[0]);
    let j1 = d.rows[1].min(rows[1]);
    // Edge functions: e_a is zero on edge bc (so a's weight is e_a / area), and so on.
    let edge = |p: [f64; 3], q: [f64; 3], x: f64, y: f64| {
        (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0])
    };
    let slot = u64::from(d.slot);
    for j in j0..=j1 {
        let y = j as f64;
        let row = &mut keys[(j - rows[0]) * width..(j - rows[0] + 1) * width];
        for (i, key) in row.iter_mut().enumerate().take(i1 + 1).skip(i0) {
            let x = i as f64;
            let wa = edge(b, c, x, y) * inv;
            let wb = edge(c, a, x, y) * inv;
            let wc = edge(a, b, x, y) * inv;
            if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                continue;
            }
            let w = (wa * a[2] + wb * b[2] + wc * c[2]) as f32;
            if w <= 0.0 {
                continue;
            }
            let k = (u64::from(u32::MAX - w.to_bits()) << 32) | slot;
            if k < *key {
                *key = k;
            }
        }
    }
}

/// Records the triangle `d` as a threat in each cell of rows `rows` (`threats` starts at row
/// `rows[0]`) it reaches into where none of the cell's four samples has it as the nearest:
/// a ray through the cell may meet it though no sample did (a sliver between samples, an
/// edge). Its bound is the largest `1/z` its plane takes at the cell's corners, and no more
/// than at its own corners: nothing of it in the cell is nearer.
fn threaten(d: &Drawn, rows: [usize; 2], g: &Grid, keys: &[u64], threats: &mut [[u64; 2]]) {
    let [a, b, c] = d.corners;
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let nearest = a[2].max(b[2]).max(c[2]);
    let plane = (area != 0.0 && area.is_finite()).then(|| 1.0 / area);
    let edge = |p: [f64; 3], q: [f64; 3], x: f64, y: f64| {
        (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0])
    };
    let w_at = |x: f64, y: f64| match plane {
        Some(inv) => {
            (edge(b, c, x, y) * a[2] + edge(c, a, x, y) * b[2] + edge(a, b, x, y) * c[2]) * inv
        }
        None => nearest,
    };
    let slot = d.slot;
    let (w, h) = (g.width, g.height);
    // A hair of a sample around each cell, so rounding never leaves one out.
    const HAIR: f64 = 1e-3;
    let j0 = d.rows[0].max(rows[0]);
    let j1 = d.rows[1].min(rows[1]).min(h.saturating_sub(2));
    if h < 2 || w < 2 {
        return;
    }
    for j in j0..=j1 {
        // The triangle's extent across within the strip of rows j to j + 1.
        let (y0, y1) = (j as f64 - HAIR, j as f64 + 1.0 + HAIR);
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for (p, q) in [(a, b), (b, c), (c, a)] {
            if (y0..=y1).contains(&p[1]) {
                lo = lo.min(p[0]);
                hi = hi.max(p[0]);
            }
            for y in [y0, y1] {
                if (p[1] - y) * (q[1] - y) < 0.0 {
                    let x = p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]);
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
            }
        }
        if lo > hi || hi < 0.0 || lo > (w - 1) as f64 {
            continue;
        }
        let i0 = (lo - HAIR).floor().max(0.0) as usize;
        let i1 = ((hi + HAIR).floor() as usize).min(w.saturating_sub(2));
        let row = &mut threats[(j - rows[0]) * w..(j - rows[0] + 1) * w];
        for (i, t) in row.iter_mut().enumerate().take(i1 + 1).skip(i0) {
            let k = j * w + i;
            let held = [k, k + 1, k + w, k + w + 1]
                .iter()
                .any(|&s| keys[s] != EMPTY && keys[s] as u32 == slot);
            if held {
                continue;
            }
            let (x, y) = (i as f64, j as f64);
            let corners = [
                w_at(x, y),
                w_at(x + 1.0, y),
                w_at(x, y + 1.0),
                w_at(x + 1.0, y + 1.0),
            ];
            let bound = corners
                .iter()
                .fold(f64::NEG_INFINITY, |m, &v| m.max(v))
                .min(nearest);
            if bound.is_nan() || bound <= 0.0 {
                continue;
            }
            let key = (u64::from((bound as f32).to_bits()) << 32) | u64::from(slot);
            if key > t[0] {
                t[1] = t[0];
                t[0] = key;
            } else if key > t[1] && key != t[0] {
                t[1] = key;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::mesh::Mesh;

    /// Two squares facing the view along +z: a near one (z = 2, x and y in [-0.5, 0.5]) in
    /// front of a far wall (z = 5, x and y in [-5, 5]).
    fn scene() -> Mesh {
        let mut m = Mesh::default();
        for (z, h) in [(2.0f32, 0.5f32), (5.0, 5.0)] {
            let base = m.positions.len() as u32;
            for [x, y] in [[-h, -h], [h, -h], [h, h], [-h, h]] {
                m.positions.push([x, y, z]);
            }
            m.triangles.push([base, base + 1, base + 2]);
            m.triangles.push([base, base + 2, base + 3]);
        }
        m.materials = vec![0; 4];
        m
    }

    #[test]
    fn the_nearest_triangle_wins_each_sample_and_pixels_find_the_cast_hit_among_candidates() {
        let mesh = scene();
        let caster = RayCaster::new(&mesh);
        // A 41 x 41 pinhole image, 20 pixels a unit of x / z.
        let (w, f) = (41usize, 20.0);
        let rays: Vec<[f32; 3]> = (0..w * w)
            .map(|k| {
                let (i, j) = ((k % w) as f64, (k / w) as f64);
                let r = [(i - 20.0) / f, (j - 20.0) / f, 1.0];
                let n = (r[0] * r[0] + r[1] * r[1] + 1.0f64).sqrt();
                r.map(|x| (x / n) as f32)
            })
            .collect();
        let (grid, base) = Grid::around(&rays, [1.0 / f, 1.0 / f], [-1.0, -1.0]).unwrap();
        let mut raster = Raster::default();
        raster.draw(&caster, &grid, &Pose::IDENTITY, 100.0);
        let mut agree = 0;
        for (k, r) in rays.iter().enumerate() {
            let d = r.map(f64::from);
            let cast = caster.cast([0.0; 3], d, 100.0);
            let c = raster.candidates(base[k]);
            assert!(c.count > 0, "pixel {k} has no candidate");
            let hit = caster.hit_slots([0.0; 3], d, c.slots(), 100.0);
            if hit == cast {
                agree += 1;
            } else {
                // Only a pixel on the near square's edge may differ, and only by which of two
                // triangles sharing an edge it reports.
                let h = hit.unwrap();
                let c = cast.unwrap();
                assert!((h.t - c.t).abs() < 1e-5, "pixel {k}: {h:?} {c:?}");
            }
        }
        assert!(agree > rays.len() * 95 / 100, "{agree}");
        // The centre pixel sees the near square at z = 2; a corner the far wall.
        let centre = raster.candidates(base[20 * w + 20]);
        let near = caster.slot_triangle(centre.slots()[0]);
        assert!(near < 2, "{near}");
        let corner = raster.candidates(base[0]);
        assert!(caster.slot_triangle(corner.slots()[0]) >= 2);
    }
}
