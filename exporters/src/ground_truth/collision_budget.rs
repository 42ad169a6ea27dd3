//! `collision-budget`: how far the visual surface lies from the collision surface, per class of
//! surface (`ground_truth/collision_budget.json`), so a user knows what a simulator's contact
//! and the ground truth (made on the collision surface) may differ by from what the sensors
//! and cameras see (the visual surface).
//!
//! Points are spread over the visual surface (`mesh/world.obj`; a mine's services, which no
//! robot touches, are not part of it) by area: [`SAMPLES`] of them, placed by the additive
//! recurrence of the plastic number (Roberts' R3 sequence: evenly spread without a random
//! generator, so the file is the same on any machine and thread count). Each point's distance
//! is the one to the nearest point of the collision surface (the survey's hierarchy), and each
//! point is classed by the normal of the visual triangle it lies on (as wound, into the
//! passage): a floor within 45 degrees of up, a roof within 45 degrees of down, walls
//! between; a floor within 1 m of a graph edge's polyline (3D) is one a robot drives on
//! (`floor_by_routes`), and `elsewhere` is every point but those. Per class the file gives the
//! median, 90th and 99th percentile (numpy's linear interpolation) and the largest distance.
//!
//! It is one-sided, as the budget is defined (the visual surface's points, their distance to
//! the collision surface): a procedural tile set's collision vertices lie on the visual surface
//! exactly (`subtgraph_tilesets::collision`), so the other way round adds nothing there.
//! `tests/readers/collision_budget_check.py` measures the same with trimesh, apart from this
//! code. Without a mesh there is nothing to measure: `ground-truth` then leaves the file out
//! and `collision-budget` refuses.

use std::collections::HashMap;

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter};
use subtgraph_core::mesh::{BuildFastHash, Mesh};
use subtgraph_core::raycast::RayCaster;
use subtgraph_core::survey::Survey;
use subtgraph_core::vec3::{V3, cross, dot, sub};
use subtgraph_schema::{Classes, Distances};

/// Points drawn on the visual surface.
pub const SAMPLES: usize = 200_000;
/// Metres within which the nearest collision point is looked for first.
const NEAR: f64 = 0.5;
/// Metres from a route's polyline within which a floor is driven on.
const REACH: f64 = 1.0;
/// The z of a unit normal beyond which a triangle faces up (a floor) or down (a roof).
const FACING: f64 = std::f64::consts::FRAC_1_SQRT_2;

type Document = subtgraph_schema::CollisionBudget<&'static str>;

/// Writes `ground_truth/collision_budget.json`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CollisionBudget;

impl Exporter for CollisionBudget {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let Some(mesh) = world.mesh().filter(|m| has_surfaces(m)) else {
            return Err(ExportError::Unsupported(
                "collision-budget: the world has no mesh (--no-mesh, or no [tileset]), or no \
                 visual or no collision triangles: there are not two surfaces to compare; \
                 leave the format out or make the mesh"
                    .into(),
            ));
        };
        let own = match survey.ray_caster() {
            Some(_) => None,
            None => Some(RayCaster::new(&mesh.collision)),
        };
        let caster = survey
            .ray_caster()
            .or(own.as_ref())
            .expect("one or the other");
        let doc = measure(&mesh.visual, caster, survey, world.resolved.seed);
        crate::write_json(out, "ground_truth/collision_budget.json", &doc)
    }
}

/// Whether a world's mesh has both surfaces to compare (what `ground-truth` asks before
/// writing the budget).
pub(crate) fn has_surfaces(mesh: &subtgraph_core::assembly::WorldMesh) -> bool {
    !mesh.visual.triangles.is_empty() && !mesh.collision.triangles.is_empty()
}

/// The budget of `visual` against the surface `caster` holds.
fn measure(visual: &Mesh, caster: &RayCaster, survey: &dyn Survey, seed: u64) -> Document {
    let (points, area) = spread(visual, SAMPLES);
    let routes = Routes::new(survey);
    let measured: Vec<(f64, Class)> = points
        .par_iter()
        .map(|&(p, t)| {
            // Most points are centimetres from the collision surface: a tight first bound
            // prunes the search to a few boxes; the rest are searched again without one.
            let d = caster
                .nearest(p, NEAR)
                .or_else(|| caster.nearest(p, f64::INFINITY))
                .map_or(0.0, |n| n.distance);
            (d, class_of(visual, t, p, &routes))
        })
        .collect();
    let of = |keep: &dyn Fn(Class) -> bool| {
        let mut d: Vec<f64> = measured
            .iter()
            .filter(|(_, c)| keep(*c))
            .map(|&(d, _)| d)
            .collect();
        distances(&mut d)
    };
    Document {
        format: "subtgraph-collision-budget/1",
        seed,
        units: "metres",
        method: "points spread by area over the visual surface (mesh/world.obj, without a \
                 mine's services) by Roberts' R3 sequence; each one's distance to the nearest \
                 point of the collision surface (mesh/collision.obj)",
        classes_note: "by the normal of the visual triangle a point lies on: floor within 45 \
                       degrees of up, roof within 45 degrees of down, walls between; \
                       floor_by_routes: floor points within 1 m (3D) of a graph edge's \
                       polyline; elsewhere: every point but those",
        samples: points.len(),
        visual_area_m2: area,
        visual_triangles: visual.triangles.len(),
        collision_triangles: caster.triangle_count(),
        classes: Classes {
            floor_by_routes: of(&|c| c == Class::FloorByRoutes),
            floor: of(&|c| matches!(c, Class::Floor | Class::FloorByRoutes)),
            walls: of(&|c| c == Class::Walls),
            roof: of(&|c| c == Class::Roof),
            elsewhere: of(&|c| c != Class::FloorByRoutes),
        },
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    FloorByRoutes,
    Floor,
    Walls,
    Roof,
}

fn class_of(visual: &Mesh, t: u32, p: V3, routes: &Routes) -> Class {
    let [a, b, c] =
        visual.triangles[t as usize].map(|v| visual.positions[v as usize].map(f64::from));
    let n = cross(sub(b, a), sub(c, a));
    let z = n[2] / dot(n, n).sqrt().max(1e-30);
    if z >= FACING {
        if routes.near(p) {
            Class::FloorByRoutes
        } else {
            Class::Floor
        }
    } else if z <= -FACING {
        Class::Roof
    } else {
        Class::Walls
    }
}

/// `count` points spread over `mesh` by area, each with its triangle, and the total area.
fn spread(mesh: &Mesh, count: usize) -> (Vec<(V3, u32)>, f64) {
    let corners = |t: &[u32; 3]| t.map(|v| mesh.positions[v as usize].map(f64::from));
    let mut cumulative = Vec::with_capacity(mesh.triangles.len());
    let mut total = 0.0;
    for t in &mesh.triangles {
        let [a, b, c] = corners(t);
        let n = cross(sub(b, a), sub(c, a));
        total += 0.5 * dot(n, n).sqrt();
        cumulative.push(total);
    }
    if total <= 0.0 {
        return (Vec::new(), 0.0);
    }
    // Roberts' R3: the plastic number's powers' inverses as the three steps.
    let g = 1.220_744_084_605_759_5_f64;
    let step = [1.0 / g, 1.0 / (g * g), 1.0 / (g * g * g)];
    let points = (0..count)
        .map(|i| {
            let x = step.map(|s| (0.5 + s * i as f64).fract());
            let at = x[0] * total;
            let t = cumulative
                .partition_point(|&c| c <= at)
                .min(cumulative.len() - 1);
            let (mut r1, mut r2) = (x[1], x[2]);
            if r1 + r2 > 1.0 {
                (r1, r2) = (1.0 - r1, 1.0 - r2);
            }
            let [a, b, c] = corners(&mesh.triangles[t]);
            let p = [0, 1, 2].map(|k| a[k] + r1 * (b[k] - a[k]) + r2 * (c[k] - a[k]));
            (p, t as u32)
        })
        .collect();
    (points, total)
}

/// The graph's polylines' segments, found by the 1 m cells they come within [`REACH`] of.
struct Routes {
    segments: Vec<[V3; 2]>,
    cells: HashMap<[i64; 3], Vec<u32>, BuildFastHash>,
}

impl Routes {
    fn new(survey: &dyn Survey) -> Routes {
        let mut segments = Vec::new();
        for e in survey.edges() {
            for w in e.points.windows(2) {
                segments.push([w[0], w[1]]);
            }
            if let [p] = e.points[..] {
                segments.push([p, p]);
            }
        }
        let mut cells: HashMap<[i64; 3], Vec<u32>, BuildFastHash> = HashMap::default();
        for (i, s) in segments.iter().enumerate() {
            let lo = [0, 1, 2].map(|k| (s[0][k].min(s[1][k]) - REACH).floor() as i64);
            let hi = [0, 1, 2].map(|k| (s[0][k].max(s[1][k]) + REACH).floor() as i64);
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        cells.entry([x, y, z]).or_default().push(i as u32);
                    }
                }
            }
        }
        Routes { segments, cells }
    }

    /// Whether `p` is within [`REACH`] of a segment.
    fn near(&self, p: V3) -> bool {
        let cell = p.map(|x| x.floor() as i64);
        self.cells.get(&cell).is_some_and(|list| {
            list.iter().any(|&i| {
                let [a, b] = self.segments[i as usize];
                let ab = sub(b, a);
                let len2 = dot(ab, ab);
                let t = if len2 > 0.0 {
                    (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = sub(p, [0, 1, 2].map(|k| a[k] + t * ab[k]));
                dot(d, d) <= REACH * REACH
            })
        })
    }
}

/// The median, 90th and 99th percentiles (numpy's linear interpolation) and the largest of
/// `d` (sorted here).
fn distances(d: &mut [f64]) -> Distances {
    if d.is_empty() {
        return Distances::default();
    }
    d.sort_unstable_by(f64::total_cmp);
    let q = |f: f64| {
        let h = (d.len() - 1) as f64 * f;
        let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
        d[lo] + (h - lo as f64) * (d[hi] - d[lo])
    };
    Distances {
        count: d.len(),
        median_m: q(0.5),
        p90_m: q(0.9),
        p99_m: q(0.99),
        max_m: d[d.len() - 1],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_numpys() {
        // numpy.quantile([0, 1, ..., 9], [0.5, 0.9, 0.99]) = 4.5, 8.1, 8.91
        let mut d: Vec<f64> = (0..10).rev().map(f64::from).collect();
        let q = distances(&mut d);
        assert_eq!(q.count, 10);
        assert!((q.median_m - 4.5).abs() < 1e-12);
        assert!((q.p90_m - 8.1).abs() < 1e-12);
        assert!((q.p99_m - 8.91).abs() < 1e-12);
        assert_eq!(q.max_m, 9.0);
        assert_eq!(distances(&mut []), Distances::default());
    }

    #[test]
    fn points_spread_by_area() {
        // Two squares, one four times the other's area: about four times its points.
        let mesh = Mesh {
            positions: vec![
                [0., 0., 0.],
                [1., 0., 0.],
                [1., 1., 0.],
                [0., 1., 0.],
                [5., 0., 0.],
                [7., 0., 0.],
                [7., 2., 0.],
                [5., 2., 0.],
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
            ..Mesh::default()
        };
        let (points, area) = spread(&mesh, 10_000);
        assert!((area - 5.0).abs() < 1e-12);
        let big = points.iter().filter(|(p, _)| p[0] >= 5.0).count();
        assert!((7950..=8050).contains(&big), "{big}");
        for (p, t) in &points {
            let inside = if *t < 2 {
                (0.0..=1.0).contains(&p[0]) && (0.0..=1.0).contains(&p[1])
            } else {
                (5.0..=7.0).contains(&p[0]) && (0.0..=2.0).contains(&p[1])
            };
            assert!(inside, "{p:?} on triangle {t}");
        }
    }
}
