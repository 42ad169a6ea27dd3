use super::*;
use crate::vec3::{dot, sub};

/// A closed sphere of radius `r` about `c`, wound so normals point inwards (a passage seen from
/// inside): subdivided icosahedron, vertices shared.
fn sphere(c: [f64; 3], r: f64, subdivisions: usize) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<[f64; 3]> = vec![
        [-1., t, 0.],
        [1., t, 0.],
        [-1., -t, 0.],
        [1., -t, 0.],
        [0., -1., t],
        [0., 1., t],
        [0., -1., -t],
        [0., 1., -t],
        [t, 0., -1.],
        [t, 0., 1.],
        [-t, 0., -1.],
        [-t, 0., 1.],
    ];
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mids = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, p: &mut Vec<[f64; 3]>| {
            *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (x, y) = (p[a as usize], p[b as usize]);
                p.push([0, 1, 2].map(|k| (x[k] + y[k]) / 2.0));
                p.len() as u32 - 1
            })
        };
        let mut next = Vec::new();
        for [a, b, c] in f {
            let (ab, bc, ca) = (mid(a, b, &mut p), mid(b, c, &mut p), mid(c, a, &mut p));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    Mesh {
        positions: p
            .iter()
            .map(|v| {
                let l = dot(*v, *v).sqrt();
                [0, 1, 2].map(|k| (c[k] + r * v[k] / l) as f32)
            })
            .collect(),
        // Inward: reverse the outward winding.
        triangles: f.into_iter().map(|[a, b, c]| [a, c, b]).collect(),
        ..Mesh::default()
    }
}

/// A small deterministic generator (no dependency for tests).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn dir(&mut self) -> [f64; 3] {
        loop {
            let v = [0, 1, 2].map(|_| 2.0 * self.next() - 1.0);
            let l = dot(v, v).sqrt();
            if l > 0.1 && l <= 1.0 {
                return v.map(|x| x / l);
            }
        }
    }
}

/// A brute-force caster over every triangle with the same watertight test.
fn brute(mesh: &Mesh, o: [f64; 3], d: [f64; 3], max: f64) -> Option<f32> {
    let ray = Prepared::new(o, d)?;
    let mut best = max as f32;
    let mut hit = None;
    for t in &mesh.triangles {
        let tri = t.map(|v| mesh.positions[v as usize]);
        if let Some(t) = ray.triangle(&tri, best) {
            best = t;
            hit = Some(t);
        }
    }
    hit
}

#[test]
fn no_ray_escapes_a_closed_sphere_even_through_its_vertices_and_edges() {
    let centre = [1234.5, -876.25, 40.0];
    let m = sphere(centre, 7.0, 4);
    assert!(m.edge_report().is_closed());
    // Aimed exactly at every vertex and every edge's midpoint, from the centre and from
    // points off it: the rays most likely to slip between two triangles.
    let mut rng = Lcg(7);
    let mut origins = vec![centre];
    for _ in 0..4 {
        let d = rng.dir();
        origins.push([0, 1, 2].map(|k| centre[k] + 3.0 * d[k]));
    }
    let mut targets: Vec<[f64; 3]> = m.positions.iter().map(|p| p.map(f64::from)).collect();
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (
                m.positions[t[k] as usize],
                m.positions[t[(k + 1) % 3] as usize],
            );
            targets.push([0, 1, 2].map(|i| (f64::from(a[i]) + f64::from(b[i])) / 2.0));
        }
    }
    // The heuristic's tree and the quick one (in Morton order).
    for caster in [RayCaster::new(&m), RayCaster::quick(&m)] {
        let mut cast = 0;
        for o in &origins {
            for t in &targets {
                let d = sub(*t, *o);
                let hit = caster.cast(*o, d, 10.0);
                assert!(hit.is_some(), "ray from {o:?} towards {t:?} escaped");
                let h = hit.unwrap();
                // It stops at the target (a vertex or an edge of the surface), within f32
                // rounding at 1.2 km from the frame's origin.
                assert!((h.t - 1.0).abs() * dot(d, d).sqrt() < 2e-3, "{}", h.t);
                cast += 1;
            }
        }
        assert!(cast > 20_000);
    }
}

#[test]
fn hits_lie_on_the_surface_and_normals_face_the_inside() {
    let centre = [10.0, 20.0, 30.0];
    let r = 5.0;
    let m = sphere(centre, r, 3);
    let caster = RayCaster::new(&m);
    let mut rng = Lcg(1);
    for _ in 0..2000 {
        let d = rng.dir();
        let h = caster
            .cast(centre, d, 100.0)
            .expect("inside a closed sphere");
        // The facets lie within the sagitta of a 3-times subdivided icosphere of the sphere.
        assert!(h.t <= r + 1e-4 && h.t > r * 0.98, "{}", h.t);
        let n = h.normal.map(f64::from);
        assert!(dot(n, d) < 0.0, "the normal faces the ray's origin");
        assert!((dot(n, n) - 1.0).abs() < 1e-5);
        // The barycentric coordinates rebuild the hit point from the triangle's vertices, as
        // the mesh lists them (what a camera interpolates texture coordinates with).
        let [u, v] = h.barycentric.map(f64::from);
        assert!(u >= 0.0 && v >= 0.0 && u + v <= 1.0 + 1e-6, "{u} {v}");
        let [a, b, c] =
            m.triangles[h.triangle as usize].map(|i| m.positions[i as usize].map(f64::from));
        let at = [0, 1, 2].map(|k| (1.0 - u - v) * a[k] + u * b[k] + v * c[k]);
        let hit = [0, 1, 2].map(|k| centre[k] + h.t * d[k]);
        let miss = sub(at, hit);
        assert!(dot(miss, miss).sqrt() < 1e-4, "{at:?} against {hit:?}");
    }
    // From outside, looking away: nothing.
    assert_eq!(caster.cast([30.0, 20.0, 30.0], [1.0, 0.0, 0.0], 1e3), None);
    // Limited by max.
    assert_eq!(caster.cast(centre, [1.0, 0.0, 0.0], 4.0), None);
    assert!(caster.cast(centre, [1.0, 0.0, 0.0], 5.1).is_some());
}

#[test]
fn the_hierarchy_finds_what_testing_every_triangle_finds() {
    // A soup of random triangles, many overlapping: the hardest case for the heuristic.
    let mut rng = Lcg(3);
    let mut m = Mesh::default();
    for i in 0..3000u32 {
        let c = [0, 1, 2].map(|_| 40.0 * rng.next());
        for _ in 0..3 {
            let d = rng.dir();
            let s = 0.2 + 3.0 * rng.next();
            m.positions
                .push([0, 1, 2].map(|k| (c[k] + s * d[k]) as f32));
        }
        m.triangles.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    // The heuristic's tree and the quick one (in Morton order).
    for caster in [RayCaster::new(&m), RayCaster::quick(&m)] {
        assert_eq!(caster.triangle_count(), 3000);
        let mut hits = 0;
        for _ in 0..3000 {
            let o = [0, 1, 2].map(|_| 50.0 * rng.next() - 5.0);
            let d = rng.dir();
            let got = caster.cast(o, d, 30.0);
            let want = brute(&m, o, d, 30.0);
            assert_eq!(got.map(|h| h.t as f32), want, "from {o:?} along {d:?}");
            if let Some(h) = got {
                // The reported triangle is hit at that distance.
                let tri = m.triangles[h.triangle as usize].map(|v| m.positions[v as usize]);
                let ray = Prepared::new(o, d).unwrap();
                assert_eq!(ray.triangle(&tri, 31.0), Some(h.t as f32));
                hits += 1;
            }
        }
        assert!(hits > 500, "{hits}");
    }
}

#[test]
fn nearest_points_match_testing_every_triangle() {
    let m = sphere([0.0, 0.0, 0.0], 3.0, 2);
    let caster = RayCaster::new(&m);
    let mut rng = Lcg(11);
    for _ in 0..500 {
        let p = [0, 1, 2].map(|_| 10.0 * rng.next() - 5.0);
        let got = caster.nearest(p, 100.0).expect("within 100 m");
        let want = m
            .triangles
            .iter()
            .map(|t| {
                let q = closest_on_triangle(p, t.map(|v| m.positions[v as usize].map(f64::from)));
                dot(sub(q, p), sub(q, p)).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            (got.distance - want).abs() < 1e-9,
            "{} {want}",
            got.distance
        );
        assert!((dot(sub(got.point, p), sub(got.point, p)).sqrt() - want).abs() < 1e-9);
        // Within a radius that excludes it: nothing.
        assert_eq!(caster.nearest(p, want * 0.99), None);
    }
}

#[test]
fn casting_in_parallel_gives_the_same_hits_on_one_and_three_threads() {
    let m = sphere([5.0, 5.0, 5.0], 4.0, 4);
    let caster = RayCaster::new(&m);
    let mut rng = Lcg(5);
    let rays: Vec<Ray> = (0..20_000)
        .map(|_| Ray {
            origin: [0, 1, 2].map(|_| 5.0 + 2.0 * rng.next() - 1.0),
            dir: rng.dir(),
        })
        .collect();
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| caster.cast_all(&rays, 20.0))
    };
    let one = run(1);
    assert!(one.iter().all(Option::is_some));
    assert_eq!(one, run(3));
}

#[test]
fn empty_meshes_and_degenerate_rays_hit_nothing() {
    let empty = RayCaster::new(&Mesh::default());
    assert_eq!(empty.cast([0.0; 3], [1.0, 0.0, 0.0], 10.0), None);
    assert_eq!(empty.nearest([0.0; 3], 10.0), None);
    let caster = RayCaster::new(&sphere([0.0; 3], 1.0, 1));
    assert_eq!(caster.cast([0.0; 3], [0.0; 3], 10.0), None);
    assert_eq!(caster.cast([0.0; 3], [f64::NAN, 0.0, 1.0], 10.0), None);
    assert_eq!(caster.cast([0.0; 3], [0.0, 0.0, 1.0], 0.0), None);
    // Axis-aligned directions (zero components) work.
    for d in [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]] {
        assert!(caster.cast([0.0; 3], d, 10.0).is_some());
    }
}

#[test]
fn the_hierarchy_is_the_same_built_on_one_thread_or_many() {
    // Spheres far apart and overlapping, so the tree has subtrees of every size.
    let mut mesh = sphere([0.0, 0.0, 0.0], 5.0, 4);
    for (k, c) in [[30.0, 0.0, 0.0], [2.0, 1.0, 0.5], [0.0, -40.0, 7.0]]
        .into_iter()
        .enumerate()
    {
        let s = sphere(c, 3.0 + k as f64, 3);
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(&s.positions);
        mesh.triangles
            .extend(s.triangles.iter().map(|t| t.map(|v| v + base)));
    }
    let one = build::tree_with(&mesh, usize::MAX);
    for parallel_min in [1, 16, 1000] {
        let many = build::tree_with(&mesh, parallel_min);
        assert_eq!(
            one.1, many.1,
            "triangle order, parallel from {parallel_min}"
        );
        assert_eq!(
            format!("{:?}", one.0),
            format!("{:?}", many.0),
            "nodes, parallel from {parallel_min}"
        );
    }
}

/// A closed cube `[0, n]^3` of unit squares (two triangles each, vertices shared), wound so
/// normals point inwards: the axis-aligned, integer-cornered walls a mine's tiles make, where
/// rays meet edges and vertices exactly.
fn gridded_cube(n: u32) -> Mesh {
    let mut m = Mesh::default();
    let mut index = std::collections::HashMap::new();
    let mut vertex = |p: [u32; 3], m: &mut Mesh| {
        *index.entry(p).or_insert_with(|| {
            m.positions.push(p.map(|x| x as f32));
            m.positions.len() as u32 - 1
        })
    };
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: u32, dj: u32| {
                        let mut p = [0; 3];
                        p[axis] = side;
                        p[u] = i + di;
                        p[v] = j + dj;
                        p
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
                        .map(|p| vertex(p, &mut m));
                    // Counter-clockwise seen from inside: (u, v, axis) is right-handed, so the
                    // low side is seen from +axis as wound, the high side reversed.
                    if side == 0 {
                        m.triangles.push([q[0], q[1], q[2]]);
                        m.triangles.push([q[0], q[2], q[3]]);
                    } else {
                        m.triangles.push([q[0], q[2], q[1]]);
                        m.triangles.push([q[0], q[3], q[2]]);
                    }
                }
            }
        }
    }
    m
}

#[test]
fn rays_at_the_edges_and_corners_of_axis_aligned_walls_hit_what_every_triangle_gives() {
    let m = gridded_cube(6);
    assert!(m.edge_report().is_closed());
    let caster = RayCaster::new(&m);
    assert_eq!(caster.triangle_count(), 6 * 6 * 6 * 2);
    // Every grid vertex and every edge midpoint of the walls, from points inside on and off
    // the grid: rays through vertices and edges, along axes and diagonals.
    let mut targets = Vec::new();
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (
                m.positions[t[k] as usize],
                m.positions[t[(k + 1) % 3] as usize],
            );
            targets.push(a.map(f64::from));
            targets.push([0, 1, 2].map(|i| (f64::from(a[i]) + f64::from(b[i])) / 2.0));
        }
    }
    let origins = [
        [3.0, 3.0, 3.0],
        [1.0, 2.0, 5.0],
        [0.5, 5.5, 2.25],
        [4.0, 1.0, 1.0],
    ];
    let mut cast = 0;
    for o in origins {
        for t in &targets {
            let d = sub(*t, o);
            if dot(d, d) == 0.0 {
                continue;
            }
            let got = caster.cast(o, d, 10.0);
            let h = got.unwrap_or_else(|| panic!("ray from {o:?} towards {t:?} escaped"));
            assert_eq!(
                Some(h.t as f32),
                brute(&m, o, d, 10.0),
                "from {o:?} towards {t:?}"
            );
            assert!((h.t - 1.0).abs() < 1e-5, "{}", h.t);
            // The triangle reported is hit there, and its normal is its own.
            let tri = m.triangles[h.triangle as usize].map(|v| m.positions[v as usize]);
            let ray = Prepared::new(o, d).unwrap();
            assert_eq!(ray.triangle(&tri, 11.0), Some(h.t as f32));
            let [a, b, c] = tri.map(|p| p.map(f64::from));
            let n = crate::vec3::cross(sub(b, a), sub(c, a));
            let n = n.map(|x| x / dot(n, n).sqrt());
            for (got, want) in h.normal.iter().zip(n) {
                assert!((f64::from(*got) - want).abs() < 1e-6);
            }
            cast += 1;
        }
    }
    assert!(cast > 5_000, "{cast}");
}

#[test]
fn rays_grazing_a_wall_along_its_plane_still_stop_at_the_next_wall() {
    let m = gridded_cube(4);
    let caster = RayCaster::new(&m);
    let mut rng = Lcg(17);
    for _ in 0..2000 {
        // From a point on the floor (z = 0) or on a wall (x = 0), along it.
        let (p, q) = (0.2 + 3.6 * rng.next(), 0.2 + 3.6 * rng.next());
        let a = std::f64::consts::TAU * rng.next();
        for (o, d) in [
            ([p, q, 0.0], [a.cos(), a.sin(), 0.0]),
            ([0.0, p, q], [0.0, a.cos(), a.sin()]),
        ] {
            let h = caster.cast(o, d, 10.0);
            let want = brute(&m, o, d, 10.0);
            assert!(want.is_some(), "every triangle: from {o:?} along {d:?}");
            assert_eq!(h.map(|h| h.t as f32), want, "from {o:?} along {d:?}");
        }
    }
}
