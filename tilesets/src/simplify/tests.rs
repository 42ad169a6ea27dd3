use super::*;

/// A closed icosphere of radius `r` (wound inwards), subdivided `n` times, with its vertices
/// moved by `shape` (a floor, bumps).
fn blob(r: f64, n: usize, shape: impl Fn([f64; 3]) -> [f64; 3]) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<V3> = vec![
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
    for _ in 0..n {
        let mut mids = std::collections::HashMap::new();
        let mut next = Vec::new();
        for [a, b, c] in f {
            let mut mid = |x: u32, y: u32| {
                *mids.entry((x.min(y), x.max(y))).or_insert_with(|| {
                    let (q, s) = (p[x as usize], p[y as usize]);
                    p.push([0, 1, 2].map(|k| (q[k] + s[k]) / 2.0));
                    p.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    Mesh {
        positions: p
            .iter()
            .map(|&q| {
                let l = dot(q, q).sqrt();
                shape(q.map(|x| x / l * r)).map(|x| x as f32)
            })
            .collect(),
        // Outward as listed: reversed to face the inside.
        triangles: f.into_iter().map(|[a, b, c]| [a, c, b]).collect(),
        ..Mesh::default()
    }
}

/// A room: a sphere of radius 5 with a flat floor 2 m below its centre and bumps on its walls.
fn room() -> Mesh {
    blob(5.0, 5, |[x, y, z]| {
        let bump = 1.0 + 0.03 * (1.3 * x).sin() * (1.7 * y).cos() * (0.9 * z + 0.4).sin();
        [x * bump, y * bump, (z * bump).max(-2.0)]
    })
}

/// The largest distance from a vertex of `a` to the surface `b` (every triangle tried).
fn farthest(a: &Mesh, b: &Mesh) -> Vec<f64> {
    a.positions
        .iter()
        .map(|p| {
            let p = p.map(f64::from);
            b.triangles
                .iter()
                .map(|t| {
                    let c = t.map(|v| b.positions[v as usize].map(f64::from));
                    let d = sub(closest_on_triangle(p, c), p);
                    dot(d, d).sqrt()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

#[test]
fn a_room_stays_closed_and_within_each_vertex_tolerance_with_far_fewer_triangles() {
    let m = room();
    assert!(m.edge_report().is_closed());
    // Tight on the floor, looser on the walls and roof.
    let tol: Vec<f32> = m
        .positions
        .iter()
        .map(|p| if p[2] < -1.99 { 0.01 } else { 0.08 })
        .collect();
    let s = simplify(&m, &[], &tol);
    let report = s.mesh.edge_report();
    assert!(report.is_closed(), "{report:?}");
    assert!(
        s.mesh.triangles.len() * 4 < m.triangles.len(),
        "{} of {} triangles",
        s.mesh.triangles.len(),
        m.triangles.len()
    );
    for (v, d) in farthest(&m, &s.mesh).into_iter().enumerate() {
        assert!(d <= f64::from(tol[v]) + 1e-6, "vertex {v}: {d} m");
    }
    // Every kept vertex is an original one, exactly.
    for (v, &k) in s.kept.iter().enumerate() {
        if k != u32::MAX {
            assert_eq!(s.mesh.positions[k as usize], m.positions[v]);
        }
    }
    // The flat floor goes to a handful of triangles; the bumpy walls keep more.
    let floor = s
        .mesh
        .triangles
        .iter()
        .filter(|t| t.iter().all(|&v| s.mesh.positions[v as usize][2] < -1.99))
        .count();
    assert!(floor < 200, "{floor} floor triangles");
}

#[test]
fn a_tolerance_of_zero_keeps_the_surface_as_it_is() {
    let m = room();
    let s = simplify(&m, &[], &vec![0.0; m.positions.len()]);
    assert_eq!(s.mesh.positions, m.positions);
    assert_eq!(s.mesh.triangles, m.triangles);
}

#[test]
fn locked_vertices_and_the_open_rim_stay_so_pieces_still_weld() {
    // A closed room cut in two along x = 0: each half is open along the cut, its rim
    // vertices listed as locked; both halves simplified apart weld into one closed surface.
    let m = room();
    let halves: Vec<Mesh> = [true, false]
        .into_iter()
        .map(|east| {
            let keep: Vec<usize> = (0..m.triangles.len())
                .filter(|&t| {
                    let cx: f32 = m.triangles[t]
                        .iter()
                        .map(|&v| m.positions[v as usize][0])
                        .sum();
                    (cx >= 0.0) == east
                })
                .collect();
            let ranges: Vec<_> = keep.iter().map(|&t| t..t + 1).collect();
            m.extract(&ranges)
        })
        .collect();
    let mut whole = Mesh::default();
    for h in &halves {
        let mut fans = vec![Vec::new(); h.positions.len()];
        for (t, tri) in h.triangles.iter().enumerate() {
            for &v in tri {
                fans[v as usize].push(t as u32);
            }
        }
        let rim = open_edge_vertices(&h.triangles, &fans);
        assert!(!rim.is_empty());
        let s = simplify(h, &[], &vec![0.08; h.positions.len()]);
        for &v in &rim {
            assert_ne!(s.kept[v as usize], u32::MAX, "rim vertex {v} removed");
        }
        assert!(s.mesh.triangles.len() * 2 < h.triangles.len());
        // No new edge between two rim vertices: the other half could make the same one from
        // its side, and four triangles would share it once welded.
        let edges = |m: &Mesh, map: &dyn Fn(u32) -> u32| {
            let mut e = std::collections::BTreeSet::new();
            for t in &m.triangles {
                for k in 0..3 {
                    let (a, b) = (map(t[k]), map(t[(k + 1) % 3]));
                    e.insert((a.min(b), a.max(b)));
                }
            }
            e
        };
        let before = edges(h, &|v| v);
        let original: Vec<u32> = {
            let mut o = vec![u32::MAX; s.mesh.positions.len()];
            for (v, &k) in s.kept.iter().enumerate() {
                if k != u32::MAX {
                    o[k as usize] = v as u32;
                }
            }
            o
        };
        let on_rim = |v: u32| rim.contains(&v);
        for (a, b) in edges(&s.mesh, &|k| original[k as usize]) {
            if on_rim(a) && on_rim(b) {
                assert!(
                    before.contains(&(a, b)),
                    "a new edge {a}-{b} across the rim"
                );
            }
        }
        whole.append(&s.mesh);
    }
    whole.weld();
    let report = whole.edge_report();
    assert!(report.is_closed(), "{report:?}");
}

#[test]
fn the_same_surface_simplifies_the_same_way_every_time() {
    let m = room();
    let tol = vec![0.05; m.positions.len()];
    let a = simplify(&m, &[], &tol);
    let b = simplify(&m, &[], &tol);
    assert_eq!(a.mesh, b.mesh);
}
