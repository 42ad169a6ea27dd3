//! The ground-truth exporters through the command line, checked by the readers their users
//! have (numpy, PIL, yaml, networkx, csv, json) against the grid and against an independent
//! ray parity on the collision surface: `tests/readers/ground_truth_check.py`.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{arg, fails, folder_bytes, ok, read_with_python, small_cave_pipeline};

const READERS: &[&str] = &["numpy", "PIL", "yaml", "networkx", "trimesh"];

/// The small two-level cave.
fn pipeline(dir: &Path, extra: &str) -> PathBuf {
    small_cave_pipeline(dir, 2, extra)
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("subtgraph-gt-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn ground_truth_agrees_with_the_grid_and_the_collision_surface() {
    let dir = temp("mesh");
    let p = pipeline(&dir, "[[export]]\ntype = \"ground-truth\"\n");
    let out = dir.join("world");
    ok(&["generate", arg(&p), "--out", arg(&out)]);
    for f in [
        "graph.json",
        "graph.graphml",
        "maps/level-0.pgm",
        "maps/level-1.yaml",
        "free_space.npy",
        "free_space.json",
        "semantic_labels.json",
        "semantic_labels.csv",
        "spawn_poses.json",
    ] {
        assert!(out.join("ground_truth").join(f).is_file(), "{f}");
    }
    let meta = std::fs::read_to_string(out.join("ground_truth/free_space.json")).unwrap();
    assert!(meta.contains("\"source\": \"collision-mesh\""), "{meta}");
    if let Some(said) = read_with_python(READERS, "ground_truth_check.py", &[arg(&out), "mesh"]) {
        eprintln!("{said}");
        assert!(said.contains("spawn poses: 4 robots"), "{said}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_a_mesh_ground_truth_falls_back_to_the_grid_and_says_so() {
    let dir = temp("grid");
    let p = pipeline(&dir, "");
    let out = dir.join("world");
    ok(&[
        "generate",
        arg(&p),
        "--no-mesh",
        "--format",
        "ground-truth",
        "--out",
        arg(&out),
    ]);
    assert!(!out.join("mesh").exists());
    for f in ["free_space.json", "spawn_poses.json"] {
        let text = std::fs::read_to_string(out.join("ground_truth").join(f)).unwrap();
        assert!(text.contains("\"source\": \"grid\""), "{f}: {text}");
    }
    let yaml = std::fs::read_to_string(out.join("ground_truth/maps/level-1.yaml")).unwrap();
    assert!(yaml.contains("computed from: grid"), "{yaml}");
    if let Some(said) = read_with_python(READERS, "ground_truth_check.py", &[arg(&out), "grid"]) {
        assert!(
            said.contains("agrees with every voxel against the cells"),
            "{said}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_ground_truth_keys_are_refused_naming_the_key() {
    let dir = temp("bad");
    let cases = [
        (
            "ground-truth",
            "resolutin = 0.5",
            "export[0].resolutin",
            "this component takes: resolution, height, voxel",
        ),
        (
            "ros-map",
            "resolution = 0",
            "export[0].resolution",
            "positive number of metres per pixel, e.g. resolution = 0.25",
        ),
        (
            "ros-map",
            "voxel = 1.0",
            "export[0].voxel",
            "this component takes: resolution, height",
        ),
        (
            "free-space",
            "voxel = -0.5",
            "export[0].voxel",
            "e.g. voxel = 0.5",
        ),
        (
            "spawn-poses",
            "robots = 0",
            "export[0].robots",
            "e.g. robots = 4",
        ),
        (
            "spawn-poses",
            "clearance = \"wide\"",
            "export[0].clearance",
            "invalid type",
        ),
        (
            "graph",
            "height = 1.0",
            "export[0].height",
            "this component takes no parameters",
        ),
    ];
    for (kind, line, key, says) in cases {
        let p = pipeline(&dir, &format!("[[export]]\ntype = \"{kind}\"\n{line}\n"));
        let err = fails(&["generate", arg(&p), "--out", arg(&dir.join("never"))]);
        assert!(err.contains(key), "{kind} {line}: {err}");
        assert!(err.contains(says), "{kind} {line}: {err}");
        assert!(!dir.join("never").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ground_truth_is_byte_identical_on_one_and_three_threads() {
    let dir = temp("threads");
    let p = pipeline(&dir, "[[export]]\ntype = \"ground-truth\"\n");
    let run = |threads: &str| {
        let out = dir.join(format!("world-{threads}"));
        let status = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
            .args(["generate", arg(&p), "--out", arg(&out)])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{}",
            String::from_utf8_lossy(&status.stderr)
        );
        folder_bytes(&out.join("ground_truth"))
    };
    let (one, three) = (run("1"), run("3"));
    assert_eq!(
        one.len(),
        12,
        "{:?}",
        one.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((a, x), (b, y)) in one.iter().zip(&three) {
        assert_eq!(a, b);
        assert!(x == y, "{a} differs between 1 and 3 threads");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The floor under `p` by our own vertical ray test on a triangle soup (independent of the
/// exporter's exact raster): the highest crossing at most `reach` below `p.z + 0.5`, if its
/// triangle faces up (a floor, seen from the passage) and nothing else crosses the line within
/// a metre above it (room for a robot's body). Works on open surfaces (the DARPA tiles').
struct Soup<'a> {
    mesh: &'a subtgraph::core::mesh::Mesh,
    buckets: std::collections::HashMap<(i64, i64), Vec<usize>>,
    size: f64,
}

impl<'a> Soup<'a> {
    fn new(mesh: &'a subtgraph::core::mesh::Mesh, size: f64) -> Self {
        let mut buckets: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = tri.map(|v| mesh.positions[v as usize]);
            let lo = |k: usize| {
                (p.iter().map(|q| f64::from(q[k])).fold(f64::MAX, f64::min) / size).floor() as i64
            };
            let hi = |k: usize| {
                (p.iter().map(|q| f64::from(q[k])).fold(f64::MIN, f64::max) / size).floor() as i64
            };
            for bx in lo(0)..=hi(0) {
                for by in lo(1)..=hi(1) {
                    buckets.entry((bx, by)).or_default().push(t);
                }
            }
        }
        Soup {
            mesh,
            buckets,
            size,
        }
    }

    /// `(height, faces up)` of every crossing of the vertical line through `(x, y)`, sorted.
    fn crossings(&self, x: f64, y: f64) -> Vec<(f64, bool)> {
        let (x, y) = (x + 3.1e-6, y + 1.7e-6); // off shared edges
        let key = (
            (x / self.size).floor() as i64,
            (y / self.size).floor() as i64,
        );
        let mut out = Vec::new();
        for &t in self.buckets.get(&key).map(Vec::as_slice).unwrap_or(&[]) {
            let p = self.mesh.triangles[t].map(|v| self.mesh.positions[v as usize].map(f64::from));
            let o =
                |a: [f64; 3], b: [f64; 3]| (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
            let area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
            if area == 0.0 {
                continue;
            }
            let (wa, wb, wc) = (o(p[1], p[2]), o(p[2], p[0]), o(p[0], p[1]));
            if (wa >= 0.0 && wb >= 0.0 && wc >= 0.0) || (wa <= 0.0 && wb <= 0.0 && wc <= 0.0) {
                out.push((
                    (wa * p[0][2] + wb * p[1][2] + wc * p[2][2]) / area,
                    area > 0.0,
                ));
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }

    /// Whether the straight segment from `a` to `b` crosses no triangle (Möller-Trumbore).
    fn segment_is_free(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        let sub = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
        let cross = |u: [f64; 3], v: [f64; 3]| {
            [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ]
        };
        let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        let d = sub(b, a);
        let cell = |v: f64| (v / self.size).floor() as i64;
        for bx in cell(a[0].min(b[0]))..=cell(a[0].max(b[0])) {
            for by in cell(a[1].min(b[1]))..=cell(a[1].max(b[1])) {
                for &t in self
                    .buckets
                    .get(&(bx, by))
                    .map(Vec::as_slice)
                    .unwrap_or(&[])
                {
                    let p = self.mesh.triangles[t]
                        .map(|v| self.mesh.positions[v as usize].map(f64::from));
                    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
                    let h = cross(d, e2);
                    let det = dot(e1, h);
                    if det.abs() < 1e-12 {
                        continue;
                    }
                    let s = sub(a, p[0]);
                    let u = dot(s, h) / det;
                    let q = cross(s, e1);
                    let v = dot(d, q) / det;
                    let along = dot(e2, q) / det;
                    if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && (0.0..=1.0).contains(&along) {
                        return false;
                    }
                }
            }
        }
        true
    }

    fn stands_on_a_floor(&self, p: [f64; 3]) -> bool {
        let hits = self.crossings(p[0], p[1]);
        let probe = p[2] + 0.5;
        let Some(k) = hits.iter().rposition(|h| h.0 <= probe) else {
            return false;
        };
        // Tiles may overlap in coincident triangles (a cap's floor on a corridor's): any of
        // those at the floor's height facing up makes it a floor.
        let floor = hits[k].0;
        let up = hits.iter().any(|h| (h.0 - floor).abs() < 1e-6 && h.1);
        let above = hits.iter().find(|h| h.0 > floor + 1e-6);
        up && probe - floor <= 1.0 && above.is_none_or(|h| h.0 >= floor + 1.0)
    }
}

/// Issue 15 items 6 and 7: every node and every point of every corridor's polyline in
/// `graph.json` stands in free space on a floor, over many seeds per preset and on the DARPA
/// tiles (whose passages miss their tile centres).
fn graph_points_stand_on_floors(p: &subtgraph::core::Pipeline, what: &str) -> usize {
    let world = subtgraph::core::generate(p, &subtgraph::registry())
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    world_points_stand_on_floors(&world, what)
}

fn world_points_stand_on_floors(world: &subtgraph::core::World, what: &str) -> usize {
    let mesh = &world.mesh().expect("a mesh").collision;
    let soup = Soup::new(mesh, world.resolved.tile_pitch / 4.0);
    let doc = crate::common::graph_json(world);
    let point = crate::common::json_point;
    let mut checked = 0;
    // A vertical shaft's landing node stands over the shaft's hole (its collar, issue 24): in
    // free space, not on a floor.
    let mut collars = Vec::new();
    for n in doc["nodes"].as_array().unwrap() {
        let p = point(&n["position"]);
        if n["kind"] == "shaft-landing" {
            assert!(
                soup.segment_is_free([p[0], p[1], p[2] + 0.5], [p[0], p[1], p[2] + 1.5]),
                "{what}: landing {} at {p:?} not in free space",
                n["id"]
            );
            collars.push(p);
            continue;
        }
        assert!(
            soup.stands_on_a_floor(p),
            "{what}: node {} at {p:?}",
            n["id"]
        );
        checked += 1;
    }
    for e in doc["edges"].as_array().unwrap() {
        if e["kind"] != "corridor" {
            continue;
        }
        for v in e["polyline"].as_array().unwrap() {
            let p = point(v);
            if collars.contains(&p) {
                continue;
            }
            // A seam point lies on a tile border: the floor is the one just beside it.
            let near = [
                [0.0, 0.0],
                [0.05, 0.0],
                [-0.05, 0.0],
                [0.0, 0.05],
                [0.0, -0.05],
            ];
            assert!(
                near.iter()
                    .any(|d| soup.stands_on_a_floor([p[0] + d[0], p[1] + d[1], p[2]])),
                "{what}: edge {} point {p:?}",
                e["id"]
            );
            checked += 1;
        }
    }
    checked
}

#[test]
fn graph_nodes_and_centrelines_stand_on_floors_over_many_seeds() {
    for (preset, seeds) in [("cave", 0..6), ("mine", 0..3), ("lava-tube", 0..2)] {
        let mut p = subtgraph::presets::load(preset).unwrap();
        for seed in seeds {
            p.world.seed = seed;
            let n = graph_points_stand_on_floors(&p, &format!("{preset} seed {seed}"));
            assert!(n > 100);
        }
    }
}

#[test]
fn graph_nodes_and_centrelines_stand_on_floors_of_the_darpa_tiles() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if !root.join("../shared/darpa-subt-tiles/cave-type-b").is_dir() {
        eprintln!(
            "skipping: ../shared/darpa-subt-tiles is absent (the DARPA tiles live in ../shared)"
        );
        return;
    }
    let file = root.join("examples/darpa-cave.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    let p = subtgraph::core::Pipeline::parse(&text, file.to_str().unwrap()).unwrap();
    let n = graph_points_stand_on_floors(&p, "examples/darpa-cave.toml");
    eprintln!("{n} node and polyline points on the DARPA tiles' floors");
}

/// What keeps a robot from going between a shaft's foot or landing and its corridors on the
/// collision surface, for every shaft of `p`'s world, and the shafts' relative turns (landing
/// to foot, quarter turns): the shaft edge's ends are the foot's and the landing's nodes, so
/// 1 m above them the vertical segment from the foot's node up to the landing's height, and
/// from there the segment across to the landing's node, must be free; and so must the
/// segments between the points of each corridor's polyline (1 m above them) leaving the foot
/// or the landing, within its tile.
fn shaft_connections(world: &subtgraph::core::World, what: &str) -> (Vec<String>, Vec<u8>) {
    let mesh = &world.mesh().expect("a mesh").collision;
    let pitch = world.resolved.tile_pitch;
    let soup = Soup::new(mesh, pitch / 4.0);
    let doc = crate::common::graph_json(world);
    let point = crate::common::json_point;
    let nodes = doc["nodes"].as_array().unwrap();
    let node = |id: &serde_json::Value| nodes.iter().find(|n| n["id"] == *id).unwrap();
    let cell = |n: &serde_json::Value| {
        let u = |k: &str| n[k].as_u64().unwrap() as usize;
        subtgraph::core::grid::Cell::new(u("level"), u("row"), u("col"))
    };
    let up = |p: [f64; 3]| [p[0], p[1], p[2] + 1.0];
    let (mut problems, mut turns) = (Vec::new(), Vec::new());
    let edges = doc["edges"].as_array().unwrap();
    for shaft in edges.iter().filter(|e| e["kind"] == "shaft") {
        let (foot, landing) = (node(&shaft["from"]), node(&shaft["to"]));
        assert_eq!(
            (&foot["kind"], &landing["kind"]),
            (&"shaft-up".into(), &"shaft-landing".into())
        );
        let rotation = |n| world.tiles.get(cell(n)).unwrap().rotation;
        turns.push((rotation(foot) + 4 - rotation(landing)) % 4);
        let (f, l) = (point(&foot["position"]), point(&landing["position"]));
        let top = [f[0], f[1], l[2] + 1.0];
        if !soup.segment_is_free(up(f), top) {
            problems.push(format!(
                "{what}: rock over the foot {f:?} below the landing's height {}",
                l[2]
            ));
        }
        if !soup.segment_is_free(top, up(l)) {
            problems.push(format!(
                "{what}: rock between the shaft's top {top:?} and the landing {l:?}"
            ));
        }
        for end in [foot, landing] {
            let centre = world.cell_position(cell(end));
            let inside = |p: &[f64; 3]| {
                (p[0] - centre[0]).abs() <= 0.5 * pitch && (p[1] - centre[1]).abs() <= 0.5 * pitch
            };
            let mut corridors = 0;
            for e in edges.iter().filter(|e| e["kind"] == "corridor") {
                let mut line: Vec<[f64; 3]> = e["polyline"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(point)
                    .collect();
                if e["to"] == end["id"] {
                    line.reverse();
                } else if e["from"] != end["id"] {
                    continue;
                }
                corridors += 1;
                for w in line
                    .windows(2)
                    .take_while(|w| inside(&w[0]) && inside(&w[1]))
                {
                    if !soup.segment_is_free(up(w[0]), up(w[1])) {
                        problems.push(format!(
                            "{what}: corridor {} blocked between {:?} and {:?} in the {} tile",
                            e["id"], w[0], w[1], end["kind"]
                        ));
                    }
                }
            }
            assert_eq!(corridors, 1, "{what}: a shaft end is a dead end");
        }
    }
    (problems, turns)
}

/// Issue 15 item 7: on two levels of DARPA tiles (`examples/darpa-cave-levels.toml`, and the
/// same with seeds whose landings' corridors leave the shaft every other way relative to
/// their feet's), the shaft tile's foot faces the foot's corridor and its top the landing's:
/// the shaft edge and both corridors join through free space, and every node and polyline
/// point stands on a floor. The manifest's old shaft fails the same check.
#[test]
fn the_darpa_shaft_joins_its_foot_and_landing_corridors() {
    let Some(tiles) = common::darpa_tiles() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let parse = |file: &Path| {
        let text = std::fs::read_to_string(file).unwrap();
        subtgraph::core::Pipeline::parse(&text, file.to_str().unwrap()).unwrap()
    };
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/darpa-cave-levels.toml");
    let mut worlds = vec![(
        parse(&example),
        "examples/darpa-cave-levels.toml".to_string(),
    )];
    // Landings turned 0, 2 and 3 quarter turns from their feet (the example's: 1).
    for seed in [8, 14, 10] {
        let file = common::darpa_levels(dir.path(), &tiles, seed, false);
        worlds.push((parse(&file), format!("darpa-cave-levels, seed {seed}")));
    }
    let (mut seen, mut shafts) = (std::collections::BTreeSet::new(), 0);
    for (p, what) in &worlds {
        let world = subtgraph::core::generate(p, &subtgraph::registry())
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        let (problems, turns) = shaft_connections(&world, what);
        assert!(problems.is_empty(), "{problems:#?}");
        shafts += turns.len();
        seen.extend(turns);
        world_points_stand_on_floors(&world, what);
    }
    eprintln!("{shafts} DARPA shafts joined, landings turned {seen:?} from their feet");
    assert_eq!(
        seen.len(),
        4,
        "the landings turn every way from their feet: {seen:?}"
    );
    let old = parse(&common::darpa_levels(dir.path(), &tiles, 15, true));
    let world = subtgraph::core::generate(&old, &subtgraph::registry()).unwrap();
    let (problems, _) = shaft_connections(&world, "the old shaft");
    assert!(!problems.is_empty(), "the old shaft passes the check");
}

/// The comms table (`--format comms`): every pair of tiles within range listed once, its
/// distance and line of sight what trimesh's own ray test says on the collision surface (a
/// sample of 400 pairs, both kinds), the same bytes on 1 and 3 threads; the grid answers
/// without a mesh and says so; a bad range is refused naming the key.
#[test]
fn the_comms_table_is_what_trimesh_sees_between_the_tiles() {
    let dir = tempfile::tempdir().unwrap();
    let p = pipeline(
        dir.path(),
        "[[export]]\ntype = \"comms\"\nrange = 60\n\n[[export]]\ntype = \"semantic-labels\"\n",
    );
    let folders = common::assert_same_on_one_and_three_threads(dir.path(), &p, "graph");
    let w = &folders[0];
    let meta: serde_json::Value =
        serde_json::from_slice(&std::fs::read(w.join("ground_truth/comms.json")).unwrap()).unwrap();
    assert_eq!(meta["source"], "collision-mesh");
    assert_eq!(meta["range_m"], 60.0);
    let pairs = meta["pairs"].as_u64().unwrap();
    let seen = meta["in_sight"].as_u64().unwrap();
    assert!(pairs > 50 && seen > 10 && seen < pairs, "{meta}");
    if let Some(said) =
        read_with_python(&["numpy", "trimesh", "rtree"], "comms_check.py", &[arg(w)])
    {
        eprintln!("{said}");
        assert!(said.contains("all listed"), "{said}");
    }
    let grid = dir.path().join("grid");
    ok(&["generate", arg(&p), "--no-mesh", "--out", arg(&grid)]);
    let meta: serde_json::Value =
        serde_json::from_slice(&std::fs::read(grid.join("ground_truth/comms.json")).unwrap())
            .unwrap();
    assert_eq!(meta["source"], "grid");
    // The DARPA tiles (when ../shared holds them): their own collision surface, visual OBJ
    // left out (360 MB nobody reads here).
    if common::darpa_tiles().is_some() {
        let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
        let text = std::fs::read_to_string(examples.join("darpa-cave.toml"))
            .unwrap()
            .replace("\"../", &format!("\"{}/../", examples.display()));
        let darpa = dir.path().join("darpa.toml");
        std::fs::write(
            &darpa,
            format!("{text}\n[[export]]\ntype = \"obj\"\nvisual = \"none\"\n\n[[export]]\ntype = \"comms\"\n\n[[export]]\ntype = \"semantic-labels\"\n"),
        )
        .unwrap();
        let w = dir.path().join("darpa");
        ok(&["generate", arg(&darpa), "--seed", "1", "--out", arg(&w)]);
        if let Some(said) = read_with_python(
            &["numpy", "trimesh", "rtree"],
            "comms_check.py",
            &[arg(&w), "200"],
        ) {
            eprintln!("{said}");
        }
    }
    let bad = pipeline(dir.path(), "[[export]]\ntype = \"comms\"\nrange = -5\n");
    let e = fails(&["generate", arg(&bad), "--out", arg(&dir.path().join("bad"))]);
    assert!(e.contains("range") && e.contains("range = 100"), "{e}");
}
