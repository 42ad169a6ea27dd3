//! Inside the passages, column by column: where a vertical line crosses the closed collision
//! surface, and so which stretches of it are passage (free) and which are rock.
//!
//! The collision surface is closed, so along any vertical line its crossings alternate between
//! entering and leaving the passages (ray parity); where a surface is not (the DARPA tiles'
//! overlap themselves and each other), the triangles' facing tells floors from ceilings
//! (`stretches`). Each triangle is rasterised to the columns
//! of a regular grid whose centres it covers, so a whole grid costs O(triangles + columns),
//! bands of rows run in parallel, and the result does not depend on the thread count.
//!
//! The test "does this column's line cross this triangle" is exact: x and y are rounded to a
//! 1/65536 m integer lattice (vertices and column centres alike, 15 µm, far below the mesh's
//! own precision), orientations are computed in integers, and a line through an edge or a
//! vertex counts as moved by (ε, ε²) (simulation of simplicity). Triangles sharing an edge then
//! agree on which of them the line passes through, so a closed surface is always crossed an
//! even number of times, even along lines through its vertices.
//!
//! Without geometry, the passages are the grid's own: each occupied cell's whole square, from
//! its floor up to half the level height (the other half is the rock between levels); the foot
//! of a shaft reaches up into the landing above.
//!
//! A world's passages are made once, by its survey ([`crate::WorldSurvey`]), and shared by
//! everything that looks at them: artifact placement, passage axes, the height fields, and
//! the exporters' maps and free-space grids (through `Survey::visit_rows`).

use std::ops::Range;

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::mesh::Mesh;
pub(crate) use subtgraph_core::survey::{Columns, Raster, Source, Span, grid_clear_height};
use subtgraph_core::tile::TileKind;

/// Lattice steps per metre for the exact plane tests.
const LATTICE: f64 = 65536.0;

/// Rows per parallel band of a raster.
const BAND: usize = 16;

fn snap(v: f64) -> i64 {
    (v * LATTICE).round() as i64
}

/// Twice the signed area of `(a, b, p)`, exact.
fn orient(a: [i64; 2], b: [i64; 2], p: [i64; 2]) -> i128 {
    i128::from(b[0] - a[0]) * i128::from(p[1] - a[1])
        - i128::from(b[1] - a[1]) * i128::from(p[0] - a[0])
}

/// The side of edge `a -> b` that `p + (ε, ε²)` lies on: never zero for a proper edge.
fn side(a: [i64; 2], b: [i64; 2], exact: i128) -> i128 {
    if exact != 0 {
        return exact.signum();
    }
    // d/dx of the orientation is -(b.y - a.y), d/dy is (b.x - a.x).
    let dx = a[1] - b[1];
    if dx != 0 {
        i128::from(dx.signum())
    } else {
        i128::from((b[0] - a[0]).signum())
    }
}

/// The height at which the vertical line through `p` crosses the triangle `(a, b, c)` with
/// heights `z`, if it does.
fn crossing(a: [i64; 2], b: [i64; 2], c: [i64; 2], z: [f32; 3], p: [i64; 2]) -> Option<f64> {
    let area = orient(a, b, c);
    if area == 0 {
        return None; // a wall seen edge-on: the perturbed line never meets it
    }
    let s = area.signum();
    let wa = orient(b, c, p);
    if side(b, c, wa) != s {
        return None;
    }
    let wb = orient(c, a, p);
    if side(c, a, wb) != s {
        return None;
    }
    let wc = orient(a, b, p);
    if side(a, b, wc) != s {
        return None;
    }
    let area = area as f64;
    Some(
        (wa as f64 * f64::from(z[0]) + wb as f64 * f64::from(z[1]) + wc as f64 * f64::from(z[2]))
            / area,
    )
}

/// The passages of a world.
pub(crate) enum Passages<'a> {
    /// Inside the closed collision surface.
    Mesh {
        /// The surface.
        mesh: &'a Mesh,
        /// Vertices on the exact lattice.
        xy: Vec<[i64; 2]>,
        /// Each tile's triangles and their bounding box `[x0, y0, x1, y1]`.
        tiles: Vec<([f64; 4], Range<usize>)>,
    },
    /// The grid's cells.
    Grid(&'a World),
}

impl<'a> Passages<'a> {
    /// The world's collision surface when it has one, else its grid.
    pub fn of(world: &'a World) -> Self {
        let Some(m) = world.mesh() else {
            return Passages::Grid(world);
        };
        let mesh = &m.collision;
        let tiles = m
            .tiles
            .iter()
            .map(|t| {
                let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
                for tri in &mesh.triangles[t.collision_triangles.clone()] {
                    for &v in tri {
                        let p = mesh.positions[v as usize];
                        b = [
                            b[0].min(f64::from(p[0])),
                            b[1].min(f64::from(p[1])),
                            b[2].max(f64::from(p[0])),
                            b[3].max(f64::from(p[1])),
                        ];
                    }
                }
                (b, t.collision_triangles.clone())
            })
            .collect();
        Passages::Mesh {
            mesh,
            xy: Self::lattice(mesh),
            tiles,
        }
    }

    pub(crate) fn lattice(mesh: &Mesh) -> Vec<[i64; 2]> {
        mesh.positions
            .iter()
            .map(|p| [snap(f64::from(p[0])), snap(f64::from(p[1]))])
            .collect()
    }

    /// What the passages were found from.
    pub fn source(&self) -> Source {
        match self {
            Passages::Mesh { .. } => Source::CollisionMesh,
            Passages::Grid(_) => Source::Grid,
        }
    }

    /// The free stretches along the vertical line through `(x, y)`, bottom up.
    pub fn column(&self, x: f64, y: f64) -> Vec<[f64; 2]> {
        let cols = Columns {
            x0: x - 0.5,
            y0: y - 0.5,
            step: 1.0,
            nx: 1,
            ny: 1,
        };
        let r = self.raster_within(&cols, [x, y, x, y], |_, spans, _| {
            spans.iter().map(|s| [s.z0, s.z1]).collect::<Vec<_>>()
        });
        r.rows.into_iter().next().unwrap_or_default()
    }

    /// The free stretches along the vertical lines through a few `points` close together, as
    /// [`column`](Self::column) gives them one at a time, with the triangles near them gathered
    /// once: read from the triangles' facing where the crossings do not alternate (a surface
    /// that overlaps itself, as the DARPA tiles' collision copy does: two coincident floors
    /// under one ceiling left such a line with no free stretch, though `column` and the
    /// collision mesh have one).
    pub fn columns_at(&self, points: &[[f64; 2]]) -> Vec<Vec<[f64; 2]>> {
        match self {
            Passages::Grid(world) => points
                .iter()
                .map(|p| grid_column(world, p[0], p[1]))
                .collect(),
            Passages::Mesh { mesh, xy, tiles } => {
                let lattice: Vec<[i64; 2]> =
                    points.iter().map(|p| [snap(p[0]), snap(p[1])]).collect();
                let (mut lo, mut hi) = ([i64::MAX; 2], [i64::MIN; 2]);
                for p in &lattice {
                    for k in 0..2 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
                let f = |v: i64| v as f64 / LATTICE;
                let near: Vec<usize> = tiles
                    .iter()
                    .filter(|(b, _)| {
                        b[0] <= f(hi[0]) + 1e-3
                            && b[2] >= f(lo[0]) - 1e-3
                            && b[1] <= f(hi[1]) + 1e-3
                            && b[3] >= f(lo[1]) - 1e-3
                    })
                    .flat_map(|(_, r)| r.clone())
                    .filter(|&t| {
                        let [a, b, c] = mesh.triangles[t].map(|v| xy[v as usize]);
                        (0..2).all(|k| {
                            a[k].min(b[k]).min(c[k]) <= hi[k] && a[k].max(b[k]).max(c[k]) >= lo[k]
                        })
                    })
                    .collect();
                lattice
                    .iter()
                    .map(|&p| {
                        let mut hits: Vec<Hit> = near
                            .iter()
                            .filter_map(|&t| {
                                let idx = mesh.triangles[t];
                                let [a, b, c] = idx.map(|v| xy[v as usize]);
                                let z = idx.map(|v| mesh.positions[v as usize][2]);
                                crossing(a, b, c, z, p).map(|z| Hit {
                                    j: 0,
                                    i: 0,
                                    z,
                                    up: orient(a, b, c) > 0,
                                })
                            })
                            .collect();
                        hits.sort_unstable_by(|p, q| p.z.total_cmp(&q.z).then(p.up.cmp(&q.up)));
                        let mut spans = Vec::new();
                        stretches(&hits, |z0, z1| spans.push([z0, z1]));
                        spans
                    })
                    .collect()
            }
        }
    }

    /// Every line of `cols`: `row(j, spans, open)` for each row `j`, south to north, spans
    /// sorted by line then height; `open` lists the lines of the row that crossed the surface an
    /// odd number of times (an open surface: their spans are unreliable).
    #[cfg(test)]
    pub fn raster<T: Send>(
        &self,
        cols: &Columns,
        row: impl Fn(usize, &[Span], &[u32]) -> T + Sync,
    ) -> Raster<T> {
        let all = [f64::MIN, f64::MIN, f64::MAX, f64::MAX];
        self.raster_within(cols, all, row)
    }

    /// [`raster`](Self::raster), using only the tiles whose box meets `bounds`
    /// (`[x0, y0, x1, y1]`), which must hold every line of `cols`.
    pub fn raster_within<T: Send>(
        &self,
        cols: &Columns,
        bounds: [f64; 4],
        row: impl Fn(usize, &[Span], &[u32]) -> T + Sync,
    ) -> Raster<T> {
        match self {
            Passages::Grid(world) => {
                let rows = (0..cols.ny)
                    .into_par_iter()
                    .map(|j| {
                        let y = cols.y(j);
                        let mut spans = Vec::new();
                        for i in 0..cols.nx {
                            for [z0, z1] in grid_column(world, cols.x(i), y) {
                                spans.push(Span {
                                    i: i as u32,
                                    z0,
                                    z1,
                                });
                            }
                        }
                        row(j, &spans, &[])
                    })
                    .collect();
                Raster {
                    rows,
                    open_lines: 0,
                }
            }
            Passages::Mesh { mesh, xy, tiles } => {
                let ranges: Vec<Range<usize>> = tiles
                    .iter()
                    .filter(|(b, _)| {
                        b[0] <= bounds[2]
                            && b[2] >= bounds[0]
                            && b[1] <= bounds[3]
                            && b[3] >= bounds[1]
                    })
                    .map(|(_, r)| r.clone())
                    .collect();
                mesh_raster(mesh, xy, &ranges, cols, row)
            }
        }
    }

    /// The floor under `(x, y)` for a level whose nominal floor is at `nominal` metres: the
    /// bottom of the free stretch holding `nominal + probe` (a downward cast from that height).
    #[cfg(test)]
    pub fn floor(&self, x: f64, y: f64, nominal: f64, probe: f64) -> Option<f64> {
        subtgraph_core::survey::floor_in(&self.column(x, y), nominal + probe)
    }
}

/// The free stretches of a grid world along the line through `(x, y)`.
fn grid_column(world: &World, x: f64, y: f64) -> Vec<[f64; 2]> {
    let lh = world.resolved.level_height;
    let clear = grid_clear_height(world);
    let mut out: Vec<[f64; 2]> = Vec::new();
    for level in 0..world.occupancy.levels() {
        let Some(c) = world.cell_at(level, x, y) else {
            continue;
        };
        let Some(t) = world.tiles.get(c) else {
            continue;
        };
        let floor = level as f64 * lh;
        let top = floor + clear + if t.kind == TileKind::ShaftUp { lh } else { 0.0 };
        match out.last_mut() {
            Some(last) if last[1] >= floor => last[1] = last[1].max(top),
            _ => out.push([floor, top]),
        }
    }
    out
}

/// Rasterises the triangles in `ranges` to the lines of `cols`, band by band in parallel.
fn mesh_raster<T: Send>(
    mesh: &Mesh,
    xy: &[[i64; 2]],
    ranges: &[Range<usize>],
    cols: &Columns,
    row: impl Fn(usize, &[Span], &[u32]) -> T + Sync,
) -> Raster<T> {
    let results: Vec<(Vec<T>, usize)> = band_hits(mesh, xy, ranges, cols, |first, last, hits| {
        let mut open = 0;
        let mut out = Vec::with_capacity(last - first);
        let mut k = 0;
        let mut spans = Vec::new();
        let mut open_here = Vec::new();
        for j in first..last {
            spans.clear();
            open_here.clear();
            while k < hits.len() && hits[k].j as usize == j {
                let i = hits[k].i;
                let n = hits[k..].partition_point(|h| h.j as usize == j && h.i == i);
                let line = &hits[k..k + n];
                if n % 2 == 1 {
                    open += 1;
                    open_here.push(i);
                }
                stretches(line, |z0, z1| spans.push(Span { i, z0, z1 }));
                k += n;
            }
            out.push(row(j, &spans, &open_here));
        }
        (out, open)
    });
    let mut rows = Vec::with_capacity(cols.ny);
    let mut open_lines = 0;
    for (r, o) in results {
        rows.extend(r);
        open_lines += o;
    }
    Raster { rows, open_lines }
}

/// The free stretches along one line, from its crossings sorted bottom up: `push(z0, z1)` for
/// each. On a closed surface the crossings alternate between a floor and a ceiling, whatever
/// the winding, and the stretches are the pairs (ray parity). Where they do not alternate, the
/// surface overlaps itself or is open (the DARPA tiles' collision meshes hold a flat plate
/// under the rock's own floor, so a line through a mound crosses two floors and one ceiling):
/// parity would then call rock what is passage and the other way round, so the facing decides,
/// with the convention every tile set follows (normals point into the passage; a floor faces
/// up). A stretch starts at the highest floor of a run of floors (below it lies rock: the
/// space between two floors is under one) and ends at the lowest ceiling of a run of ceilings.
fn stretches(line: &[Hit], mut push: impl FnMut(f64, f64)) {
    let alternating = line.len() % 2 == 0 && line.windows(2).all(|w| w[0].up != w[1].up);
    if alternating {
        for pair in line.chunks_exact(2) {
            push(pair[0].z, pair[1].z);
        }
        return;
    }
    let mut floor: Option<f64> = None;
    for h in line {
        if h.up {
            floor = Some(h.z);
        } else if let Some(z0) = floor.take() {
            push(z0, h.z);
        }
    }
}

/// Where a vertical line crosses a triangle: row `j`, line `i`, height `z`, and whether the
/// triangle is wound counter-clockwise seen from above (its normal points up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Hit {
    pub j: u32,
    pub i: u32,
    pub z: f64,
    pub up: bool,
}

impl Passages<'_> {
    /// Every crossing of the lines of `cols` with the surface, row by row: `row(j, hits)` with
    /// the row's hits sorted by line then height. Unlike [`raster`](Self::raster) this does not
    /// rely on the surface being closed (a mesh whose tiles leave gaps or overlap, like the
    /// DARPA tiles): callers read floors from the triangles' facing. `None` without a mesh.
    pub fn crossings_within<T: Send>(
        &self,
        cols: &Columns,
        bounds: [f64; 4],
        row: impl Fn(usize, &[Hit]) -> T + Sync,
    ) -> Option<Vec<T>> {
        let Passages::Mesh { mesh, xy, tiles } = self else {
            return None;
        };
        let ranges: Vec<Range<usize>> = tiles
            .iter()
            .filter(|(b, _)| {
                b[0] <= bounds[2] && b[2] >= bounds[0] && b[1] <= bounds[3] && b[3] >= bounds[1]
            })
            .map(|(_, r)| r.clone())
            .collect();
        let bands = band_hits(mesh, xy, &ranges, cols, |first, last, hits| {
            let mut out = Vec::with_capacity(last - first);
            let mut k = 0;
            for j in first..last {
                let n = hits[k..].partition_point(|h| h.j as usize == j);
                out.push(row(j, &hits[k..k + n]));
                k += n;
            }
            out
        });
        Some(bands.into_iter().flatten().collect())
    }
}

/// The crossings of the triangles in `ranges` with the lines of `cols`, band by band in
/// parallel: `band(first_row, end_row, hits)` per band, hits sorted by row, line, height.
fn band_hits<B: Send>(
    mesh: &Mesh,
    xy: &[[i64; 2]],
    ranges: &[Range<usize>],
    cols: &Columns,
    band: impl Fn(usize, usize, &[Hit]) -> B + Sync,
) -> Vec<B> {
    let bands = cols.ny.div_ceil(BAND);
    let lx: Vec<i64> = (0..cols.nx).map(|i| snap(cols.x(i))).collect();
    let ly: Vec<i64> = (0..cols.ny).map(|j| snap(cols.y(j))).collect();
    // The lines whose lattice coordinate lies in [lo, hi]: a superset from floats, trimmed
    // exactly.
    let span_of = |lo: i64, hi: i64, lines: &[i64], origin: f64| -> Range<usize> {
        let f = |v: i64| (v as f64 / LATTICE - origin) / cols.step - 0.5;
        let a = (f(lo).floor().max(0.0) as usize).min(lines.len());
        let b = ((f(hi).ceil() + 1.0).max(0.0) as usize).min(lines.len());
        let a = a + lines[a..b].partition_point(|&v| v < lo);
        let b = a + lines[a..b].partition_point(|&v| v <= hi);
        a..b
    };
    // Triangles per band.
    let mut per_band: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for r in ranges {
        for t in r.clone() {
            let [a, b, c] = mesh.triangles[t].map(|v| xy[v as usize]);
            let rows = span_of(
                a[1].min(b[1]).min(c[1]),
                a[1].max(b[1]).max(c[1]),
                &ly,
                cols.y0,
            );
            if rows.is_empty() {
                continue;
            }
            for band in per_band[rows.start / BAND..=(rows.end - 1) / BAND].iter_mut() {
                band.push(t as u32);
            }
        }
    }
    per_band
        .par_iter()
        .enumerate()
        .map(|(b, tris)| {
            let first = b * BAND;
            let last = (first + BAND).min(cols.ny);
            let mut hits: Vec<Hit> = Vec::new();
            for &t in tris {
                let idx = mesh.triangles[t as usize];
                let [a, b, c] = idx.map(|v| xy[v as usize]);
                let z = idx.map(|v| mesh.positions[v as usize][2]);
                let up = orient(a, b, c) > 0;
                let rows = span_of(
                    a[1].min(b[1]).min(c[1]),
                    a[1].max(b[1]).max(c[1]),
                    &ly,
                    cols.y0,
                );
                let xs = span_of(
                    a[0].min(b[0]).min(c[0]),
                    a[0].max(b[0]).max(c[0]),
                    &lx,
                    cols.x0,
                );
                let js = rows.start.max(first)..rows.end.min(last);
                for (j, &y) in ly.iter().enumerate().take(js.end).skip(js.start) {
                    for (i, &x) in lx.iter().enumerate().take(xs.end).skip(xs.start) {
                        if let Some(h) = crossing(a, b, c, z, [x, y]) {
                            hits.push(Hit {
                                j: j as u32,
                                i: i as u32,
                                z: h,
                                up,
                            });
                        }
                    }
                }
            }
            hits.sort_unstable_by(|p, q| {
                (p.j, p.i)
                    .cmp(&(q.j, q.i))
                    .then(p.z.total_cmp(&q.z))
                    .then(p.up.cmp(&q.up))
            });
            band(first, last, &hits)
        })
        .collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A closed box from `lo` to `hi`, triangles wound CCW seen from inside, with its top split
    /// along a diagonal and vertices on lattice points of the test grids.
    pub(crate) fn box_mesh(lo: [f32; 3], hi: [f32; 3]) -> Mesh {
        let mut m = Mesh::default();
        for k in 0..8 {
            m.positions.push([
                if k & 1 == 0 { lo[0] } else { hi[0] },
                if k & 2 == 0 { lo[1] } else { hi[1] },
                if k & 4 == 0 { lo[2] } else { hi[2] },
            ]);
        }
        // Outward-facing quads (corner indices), then reversed to face inward.
        let quads = [
            [0, 2, 3, 1], // bottom (-z)
            [4, 5, 7, 6], // top (+z)
            [0, 1, 5, 4], // south
            [2, 6, 7, 3], // north
            [0, 4, 6, 2], // west
            [1, 3, 7, 5], // east
        ];
        for q in quads {
            m.triangles.push([q[0], q[2], q[1]]);
            m.triangles.push([q[0], q[3], q[2]]);
        }
        m
    }

    fn passages(mesh: &Mesh) -> Passages<'_> {
        Passages::Mesh {
            mesh,
            xy: Passages::lattice(mesh),
            tiles: vec![(
                [f64::MIN, f64::MIN, f64::MAX, f64::MAX],
                0..mesh.triangles.len(),
            )],
        }
    }

    #[test]
    fn a_box_is_free_exactly_inside_even_through_its_edges_and_vertices() {
        let mesh = box_mesh([1.0, 1.0, 0.5], [3.0, 2.0, 2.5]);
        let p = passages(&mesh);
        // Lines every 0.5 m from 0.25: some pass through the box's vertical edges and corners
        // (x = 1, 3; y = 1, 2) and along the top's diagonal.
        let cols = Columns {
            x0: -0.25,
            y0: -0.25,
            step: 0.25,
            nx: 20,
            ny: 12,
        };
        let r = p.raster(&cols, |_, s, _| s.to_vec());
        assert_eq!(
            r.open_lines, 0,
            "a closed box is crossed an even number of times"
        );
        for (j, spans) in r.rows.iter().enumerate() {
            for i in 0..cols.nx {
                let (x, y) = (cols.x(i), cols.y(j));
                let line: Vec<&Span> = spans.iter().filter(|s| s.i as usize == i).collect();
                let strictly_inside = x > 1.0 && x < 3.0 && y > 1.0 && y < 2.0;
                let strictly_outside = !(1.0..=3.0).contains(&x) || !(1.0..=2.0).contains(&y);
                if strictly_inside {
                    assert_eq!(line.len(), 1, "({x}, {y})");
                    assert!((line[0].z0 - 0.5).abs() < 1e-9 && (line[0].z1 - 2.5).abs() < 1e-9);
                } else if strictly_outside {
                    assert!(line.is_empty(), "({x}, {y}) is outside the box");
                } else {
                    // On a side face: counted on one side or the other, never half.
                    assert!(line.len() <= 1, "({x}, {y})");
                }
            }
        }
        // The point query agrees with the raster.
        assert_eq!(p.column(2.0, 1.5), vec![[0.5, 2.5]]);
        assert!(p.column(0.5, 1.5).is_empty());
        assert_eq!(p.floor(2.0, 1.5, 0.5, 1.0), Some(0.5));
    }

    #[test]
    fn lines_through_a_hole_in_the_surface_are_reported_open() {
        let mut mesh = box_mesh([0.0, 0.0, 0.0], [2.0, 2.0, 1.0]);
        mesh.triangles.remove(2); // half of the top
        let p = passages(&mesh);
        let cols = Columns {
            x0: 0.0,
            y0: 0.0,
            step: 0.5,
            nx: 4,
            ny: 4,
        };
        let r = p.raster(&cols, |_, _, open| open.to_vec());
        let open: usize = r.rows.iter().map(Vec::len).sum();
        assert_eq!(r.open_lines, open);
        // The missing triangle covers the lines south-east of the top's diagonal; those on the
        // diagonal go to one side or the other.
        for (j, row) in r.rows.iter().enumerate() {
            for i in 0..4u32 {
                match (i as usize).cmp(&j) {
                    std::cmp::Ordering::Greater => assert!(row.contains(&i), "{:?}", r.rows),
                    std::cmp::Ordering::Less => assert!(!row.contains(&i), "{:?}", r.rows),
                    std::cmp::Ordering::Equal => {}
                }
            }
        }
        assert!((6..=10).contains(&open));
    }

    #[test]
    fn overlapping_floors_are_read_by_their_facing() {
        // A box (floor at 0, ceiling at 2) with its floor repeated (two coplanar floors, as
        // vertex snapping leaves them) and a plate facing up at 0.5 over its western half (the
        // top of a mound whose sides snapped away): three floors and one ceiling on a line.
        let mut mesh = box_mesh([0.0, 0.0, 0.0], [2.0, 2.0, 2.0]);
        let (first, second) = (mesh.triangles[0], mesh.triangles[1]);
        mesh.triangles.push(first);
        mesh.triangles.push(second);
        let base = mesh.positions.len() as u32;
        for p in [
            [0.0, 0.0, 0.5],
            [1.0, 0.0, 0.5],
            [1.0, 2.0, 0.5],
            [0.0, 2.0, 0.5],
        ] {
            mesh.positions.push(p);
        }
        mesh.triangles.push([base, base + 1, base + 2]); // CCW from above: faces up
        mesh.triangles.push([base, base + 2, base + 3]);
        let p = passages(&mesh);
        // Parity would pair the two floors (a stretch of no height) and leave the ceiling alone.
        assert_eq!(p.column(1.5, 1.3), vec![[0.0, 2.0]]);
        // Under the plate is rock: the passage starts on it.
        assert_eq!(p.column(0.5, 1.3), vec![[0.5, 2.0]]);
    }

    #[test]
    fn lines_through_shared_vertices_of_a_fan_cross_once() {
        // A box whose top and bottom are fans around a centre vertex at (2, 1.5): the line
        // through it touches six triangles of each face and must cross each face once.
        let mut mesh = box_mesh([1.0, 1.0, 0.0], [3.0, 2.0, 1.0]);
        let centre_bottom = mesh.positions.len() as u32;
        mesh.positions.push([2.0, 1.5, 0.0]);
        mesh.positions.push([2.0, 1.5, 1.0]);
        // Replace bottom and top (the first four triangles) by fans.
        let bottom = [0u32, 1, 3, 2];
        let top = [4u32, 5, 7, 6];
        let mut tris: Vec<[u32; 3]> = Vec::new();
        for k in 0..4 {
            let (a, b) = (bottom[k], bottom[(k + 1) % 4]);
            tris.push([centre_bottom, a, b]); // CCW from above: the normal points up, inside
            let (a, b) = (top[k], top[(k + 1) % 4]);
            tris.push([centre_bottom + 1, b, a]);
        }
        tris.extend_from_slice(&mesh.triangles[4..]);
        mesh.triangles = tris;
        let p = passages(&mesh);
        assert_eq!(p.column(2.0, 1.5), vec![[0.0, 1.0]]);
        assert_eq!(p.column(1.5, 1.5), vec![[0.0, 1.0]]);
        assert_eq!(p.column(1.5, 1.25), vec![[0.0, 1.0]], "on a fan edge");
    }
}
