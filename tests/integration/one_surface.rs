//! A world is one surface (issue 21 item 15): over 30 seeds of each preset, the visual and the
//! collision mesh are each one connected piece. A lava tube of seed 11 had a second closed
//! surface, 24 triangles round a single lattice point 0.7 m across, floating in the passage.
//!
//! The pieces are counted here, independently of the tile sets' code: vertices are welded by
//! their exact coordinates (bit for bit, as the OBJ writes them), and triangles sharing a
//! vertex are joined by a union-find.

use std::collections::HashMap;

use subtgraph::core::mesh::Mesh;

/// One connected piece of a mesh: its triangles and bounding box.
#[derive(Debug)]
struct Piece {
    triangles: usize,
    lo: [f32; 3],
    hi: [f32; 3],
}

fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let up = parent[parent[i as usize] as usize];
        parent[i as usize] = up;
        i = up;
    }
    i
}

/// The connected pieces of `mesh`, largest first.
fn pieces(mesh: &Mesh) -> Vec<Piece> {
    // Welded vertex ids by exact position: the vertices sorted by their coordinates' bits,
    // equal runs one id (a sort, not a hash map: a lava tube has millions of vertices).
    let keys: Vec<[u32; 3]> = mesh.positions.iter().map(|p| p.map(f32::to_bits)).collect();
    let mut order: Vec<u32> = (0..keys.len() as u32).collect();
    order.sort_unstable_by_key(|&i| keys[i as usize]);
    let mut welded = vec![0u32; keys.len()];
    let mut ids = 0u32;
    for (k, &i) in order.iter().enumerate() {
        if k == 0 || keys[i as usize] != keys[order[k - 1] as usize] {
            ids += 1;
        }
        welded[i as usize] = ids - 1;
    }
    let mut parent: Vec<u32> = (0..ids).collect();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| welded[v as usize]);
        for (x, y) in [(a, b), (b, c)] {
            let (rx, ry) = (find(&mut parent, x), find(&mut parent, y));
            if rx != ry {
                parent[rx.max(ry) as usize] = rx.min(ry);
            }
        }
    }
    let mut by_root: HashMap<u32, Piece> = HashMap::new();
    for t in &mesh.triangles {
        let root = find(&mut parent, welded[t[0] as usize]);
        let piece = by_root.entry(root).or_insert(Piece {
            triangles: 0,
            lo: [f32::MAX; 3],
            hi: [f32::MIN; 3],
        });
        piece.triangles += 1;
        for &v in t {
            let p = mesh.positions[v as usize];
            for (k, x) in p.into_iter().enumerate() {
                piece.lo[k] = piece.lo[k].min(x);
                piece.hi[k] = piece.hi[k].max(x);
            }
        }
    }
    let mut out: Vec<Piece> = by_root.into_values().collect();
    out.sort_by_key(|p| std::cmp::Reverse(p.triangles));
    out
}

/// Generates `preset` with meshes on seeds `1..=30` and lists every mesh that is not one
/// piece, with its extra pieces. Without textures: they change no geometry (`textures::`
/// checks that byte for byte) and are an eighth of a cave's time.
fn extra_pieces(preset: &str) -> Vec<String> {
    let registry = subtgraph::registry();
    let mut found = Vec::new();
    for seed in 1..=30 {
        let mut p = subtgraph::presets::load(preset).unwrap();
        p.world.seed = seed;
        p.tileset
            .as_mut()
            .expect("the presets have a tile set")
            .params
            .set("textures", toml::Value::String("none".into()));
        let world = subtgraph::core::generate(&p, &registry).unwrap();
        let mesh = world.mesh().expect("the presets have a tile set");
        for (name, m) in [("visual", &mesh.visual), ("collision", &mesh.collision)] {
            let all = pieces(m);
            assert!(!all.is_empty(), "{preset} seed {seed}: empty {name} mesh");
            if all.len() > 1 {
                found.push(format!(
                    "{preset} seed {seed} {name}: {} pieces besides one of {} triangles: {:?}",
                    all.len() - 1,
                    all[0].triangles,
                    &all[1..]
                ));
            }
        }
    }
    found
}

#[test]
fn union_find_counts_pieces() {
    // Two tetrahedra apart, one of them written with its vertices duplicated per triangle
    // (as tiles bring their own copies): two pieces.
    let tet = |o: f32| -> Vec<[f32; 3]> {
        vec![
            [o, 0.0, 0.0],
            [o + 1.0, 0.0, 0.0],
            [o, 1.0, 0.0],
            [o, 0.0, 1.0],
        ]
    };
    let mut m = Mesh::default();
    m.positions.extend(tet(0.0));
    m.triangles
        .extend([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
    let faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    for f in faces {
        let base = m.positions.len() as u32;
        let t = tet(5.0);
        m.positions.extend(f.map(|i| t[i as usize]));
        m.triangles.push([base, base + 1, base + 2]);
    }
    let p = pieces(&m);
    assert_eq!(p.len(), 2, "{p:?}");
    assert_eq!((p[0].triangles, p[1].triangles), (4, 4));
}

#[test]
fn every_cave_is_one_surface() {
    let found = extra_pieces("cave");
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn every_mine_is_one_surface() {
    let found = extra_pieces("mine");
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn every_lava_tube_is_one_surface() {
    let found = extra_pieces("lava-tube");
    assert!(found.is_empty(), "{found:#?}");
}
