//! Issue 15 items 5 and 6: chambers and squeezes keep `min_clearance` on the collision surface,
//! graph edges report their least width and height as an independent measurement finds them,
//! chamber tiles are rooms, and bad values are refused naming the key.

use subtgraph::core::Pipeline;
use subtgraph::core::export::{Exporter, MemoryWriter};
use subtgraph::core::mesh::Mesh;
use subtgraph::core::params::{ComponentSpec, Params};

/// Our own ray test on the collision triangles (independent of the exporter's): the triangles
/// in square buckets of the plane, every bucket a ray's box touches tested by brute force.
struct Rays<'a> {
    mesh: &'a Mesh,
    buckets: std::collections::HashMap<(i64, i64), Vec<usize>>,
    size: f64,
}

impl<'a> Rays<'a> {
    fn new(mesh: &'a Mesh, size: f64) -> Self {
        let mut buckets: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = tri.map(|v| mesh.positions[v as usize]);
            let b = |k: usize, f: fn(f64, f64) -> f64, init: f64| {
                (p.iter().map(|q| f64::from(q[k])).fold(init, f) / size).floor() as i64
            };
            for bx in b(0, f64::min, f64::MAX)..=b(0, f64::max, f64::MIN) {
                for by in b(1, f64::min, f64::MAX)..=b(1, f64::max, f64::MIN) {
                    buckets.entry((bx, by)).or_default().push(t);
                }
            }
        }
        Rays {
            mesh,
            buckets,
            size,
        }
    }

    /// Distance from `o` along unit `d` to the nearest triangle within `reach` (else `reach`),
    /// by the plane-then-inside test on each candidate triangle.
    fn cast(&self, o: [f64; 3], d: [f64; 3], reach: f64) -> f64 {
        let e = [o[0] + reach * d[0], o[1] + reach * d[1]];
        let key = |v: f64| (v / self.size).floor() as i64;
        let mut best = reach;
        let mut seen = std::collections::HashSet::new();
        for bx in key(o[0].min(e[0]))..=key(o[0].max(e[0])) {
            for by in key(o[1].min(e[1]))..=key(o[1].max(e[1])) {
                for &t in self
                    .buckets
                    .get(&(bx, by))
                    .map(Vec::as_slice)
                    .unwrap_or(&[])
                {
                    if !seen.insert(t) {
                        continue;
                    }
                    let p = self.mesh.triangles[t]
                        .map(|v| self.mesh.positions[v as usize].map(f64::from));
                    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                    let cross = |a: [f64; 3], b: [f64; 3]| {
                        [
                            a[1] * b[2] - a[2] * b[1],
                            a[2] * b[0] - a[0] * b[2],
                            a[0] * b[1] - a[1] * b[0],
                        ]
                    };
                    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
                    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
                    let den = dot(n, d);
                    if den.abs() < 1e-12 {
                        continue;
                    }
                    let s = dot(n, sub(p[0], o)) / den;
                    if s <= 1e-9 || s >= best {
                        continue;
                    }
                    let x = [o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2]];
                    let inside = (0..3)
                        .all(|k| dot(cross(sub(p[(k + 1) % 3], p[k]), sub(x, p[k])), n) >= -1e-12);
                    if inside {
                        best = s;
                    }
                }
            }
        }
        best
    }

    /// The floor under a centreline point and the free height over it.
    fn floor_and_height(&self, p: [f64; 3], reach: f64) -> (f64, f64) {
        let o = [p[0], p[1], p[2] + 0.5];
        let down = self.cast(o, [0.0, 0.0, -1.0], reach);
        let up = self.cast(o, [0.0, 0.0, 1.0], reach);
        (o[2] - down, up + down)
    }

    /// Free span through `(x, y, z)` along the horizontal unit `n`, both ways.
    fn span(&self, p: [f64; 3], n: [f64; 2], reach: f64) -> f64 {
        self.cast(p, [n[0], n[1], 0.0], reach) + self.cast(p, [-n[0], -n[1], 0.0], reach)
    }
}

/// A preset's pipeline with one level and `table`'s keys over its `[tileset]`: chambers and
/// squeezes are drawn tile by tile, so the mine's and the lava tube's further levels would
/// only repeat the checks at their cost.
fn with_tileset(preset: &str, seed: u64, table: &str) -> Pipeline {
    let mut p = subtgraph::presets::load(preset).unwrap();
    p.world.seed = seed;
    p.world.levels = subtgraph::core::range::IntRange::Fixed(1);
    let spec = p.tileset.as_mut().unwrap();
    let mut t = spec.params.to_table();
    for (k, v) in toml::from_str::<toml::Table>(table).unwrap() {
        t.insert(k, v);
    }
    spec.params = Params::from_table("tileset", t);
    p
}

struct Seen {
    points: usize,
    chambers: usize,
    squeezes: usize,
    tightest: f64,
}

/// Generates one world and checks it; returns what it saw.
fn check_world(p: &Pipeline, clearance: [f64; 2], what: &str) -> Seen {
    let world = subtgraph::core::generate(p, &subtgraph::registry())
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    let pitch = world.resolved.tile_pitch;
    let mesh = &world.mesh().expect("a mesh").collision;
    let rays = Rays::new(mesh, pitch / 6.0);
    let mut out = MemoryWriter::default();
    let survey = subtgraph::survey::WorldSurvey::new(&world).unwrap();
    subtgraph::exporters::GraphFiles
        .export(&world, &survey, &mut out)
        .unwrap();
    subtgraph::exporters::SemanticLabels
        .export(&world, &survey, &mut out)
        .unwrap();
    let json = |f: &str| -> serde_json::Value {
        serde_json::from_slice(out.get(&format!("ground_truth/{f}")).unwrap()).unwrap()
    };
    let graph = json("graph.json");
    let labels = json("semantic_labels.json");
    let point = crate::common::json_point;
    let [cw, ch] = clearance;
    let mut seen = Seen {
        points: 0,
        chambers: 0,
        squeezes: 0,
        tightest: f64::MAX,
    };
    for e in graph["edges"].as_array().unwrap() {
        if e["kind"] != "corridor" {
            continue;
        }
        let line: Vec<[f64; 3]> = e["polyline"]
            .as_array()
            .unwrap()
            .iter()
            .map(point)
            .collect();
        let (mut least_w, mut least_h) = (f64::MAX, f64::MAX);
        for i in 0..line.len() {
            let a = line[i.saturating_sub(1)];
            let b = line[(i + 1).min(line.len() - 1)];
            let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            if len < 1e-6 {
                continue;
            }
            let n = [-(b[1] - a[1]) / len, (b[0] - a[0]) / len];
            let p = line[i];
            let (floor, height) = rays.floor_and_height(p, pitch);
            // A box `clearance` wide and high fits across the passage at the point: free
            // height over it, and the span across at every height up to the box's top.
            assert!(
                height >= ch,
                "{what}: edge {} point {p:?}: {height:.2} m high, under min_clearance {ch}",
                e["id"]
            );
            for k in 1..=8 {
                let z = floor + 0.25f64.max(ch * f64::from(k) / 8.0 - 0.01);
                let w = rays.span([p[0], p[1], z], n, pitch);
                assert!(
                    w >= cw,
                    "{what}: edge {} point {p:?}: {w:.2} m wide at {:.2} m, under min_clearance {cw}",
                    e["id"],
                    z - floor
                );
            }
            // The exporter's definition, measured independently.
            let w = rays.span([p[0], p[1], floor + 1.0f64.min(0.5 * height)], n, pitch);
            least_w = least_w.min(w);
            least_h = least_h.min(height);
            seen.points += 1;
        }
        let (rw, rh) = (
            e["min_width_m"].as_f64().unwrap(),
            e["min_height_m"].as_f64().unwrap(),
        );
        assert!(
            (rw - least_w).abs() < 0.02 && (rh - least_h).abs() < 0.02,
            "{what}: edge {} reports {rw} x {rh} m, measured {least_w:.3} x {least_h:.3} m",
            e["id"]
        );
        seen.tightest = seen.tightest.min(rw.min(rh));
    }
    for t in labels["tiles"].as_array().unwrap() {
        let features = t.get("features").map(|f| f.to_string()).unwrap_or_default();
        seen.squeezes += usize::from(features.contains("\"squeeze\""));
        seen.chambers += usize::from(features.contains("\"chamber\""));
    }
    seen
}

/// Free distance from a tile's centre, 2 m over its floor (above the lava tube's benches),
/// along the four diagonals (where no corridor of the grid runs), capped at half a pitch:
/// their mean. `c`'s height must be near the floor there: floors slope, so the level's nominal
/// floor may be inside the rock under a lifted passage (the tile's node height serves).
fn diagonal_room(rays: &Rays, c: [f64; 3], pitch: f64) -> f64 {
    let (floor, _) = rays.floor_and_height(c, pitch);
    let o = [c[0], c[1], floor + 2.0];
    let s = std::f64::consts::FRAC_1_SQRT_2;
    [[s, s], [-s, s], [-s, -s], [s, -s]]
        .iter()
        .map(|d| rays.cast(o, [d[0], d[1], 0.0], 0.5 * pitch))
        .sum::<f64>()
        / 4.0
}

/// Chamber tiles are measurably roomier than the same tiles of the same world without
/// chambers, and no other tile changes (a chamber stays in its cell).
fn chambers_are_rooms(p: &Pipeline, what: &str) -> usize {
    let r = subtgraph::registry();
    let with = subtgraph::core::generate(p, &r).unwrap();
    let mut plain = p.clone();
    let spec = plain.tileset.as_mut().unwrap();
    let mut t = spec.params.to_table();
    t.insert("chambers".into(), toml::from_str("rate = 0.0").unwrap());
    spec.params = Params::from_table("tileset", t);
    let without = subtgraph::core::generate(&plain, &r).unwrap();
    let pitch = with.resolved.tile_pitch;
    let (mw, mo) = (with.mesh().unwrap(), without.mesh().unwrap());
    let (rw, ro) = (
        Rays::new(&mw.collision, pitch / 6.0),
        Rays::new(&mo.collision, pitch / 6.0),
    );
    let width = p_width(&with);
    // Each tile's node height (on its passage's floor), from the ground truth.
    let mut out = MemoryWriter::default();
    subtgraph::exporters::SemanticLabels
        .export(
            &with,
            &subtgraph::survey::WorldSurvey::new(&with).unwrap(),
            &mut out,
        )
        .unwrap();
    let labels: serde_json::Value =
        serde_json::from_slice(out.get("ground_truth/semantic_labels.json").unwrap()).unwrap();
    let node_z: std::collections::HashMap<(u64, u64, u64), f64> = labels["tiles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            let at = |k: &str| t[k].as_u64().unwrap();
            (
                (at("level"), at("row"), at("col")),
                t["position"][2].as_f64().unwrap(),
            )
        })
        .collect();
    let mut chambers = 0;
    for t in &mw.tiles {
        let mut c = with.cell_position(t.cell);
        c[2] = node_z[&(t.cell.level as u64, t.cell.row as u64, t.cell.col as u64)];
        let (a, b) = (diagonal_room(&rw, c, pitch), diagonal_room(&ro, c, pitch));
        if t.labels.contains(&"chamber") {
            chambers += 1;
            assert!(
                a >= b + 0.15 * width && 2.0 * a >= 1.4 * width,
                "{what}: chamber at {:?}: {a:.1} m to the walls diagonally, {b:.1} m without it \
                 (passage {width:.1} m)",
                t.cell
            );
        } else {
            assert!(
                (a - b).abs() < 1e-6,
                "{what}: {:?} changed by a chamber elsewhere: {a} m, {b} m",
                t.cell
            );
        }
    }
    chambers
}

/// The passage width the procedural tile sets use by default: their style's share of the pitch.
fn p_width(world: &subtgraph::core::World) -> f64 {
    let share = match world.pipeline.tileset.as_ref().unwrap().type_name.as_str() {
        "cave" => 0.34,
        "lava-tube" => 0.38,
        _ => 0.32,
    };
    (share * world.resolved.tile_pitch).min(world.resolved.max_width)
}

#[test]
fn squeezes_keep_min_clearance_and_edges_report_their_narrowest_over_many_seeds() {
    let mut total = Seen {
        points: 0,
        chambers: 0,
        squeezes: 0,
        tightest: f64::MAX,
    };
    let robot = [1.2, 1.5];
    for (preset, seeds, table) in [
        ("cave", 0..5, "min_clearance = [1.2, 1.5]"),
        (
            "cave",
            5..7,
            "min_clearance = [1.2, 1.5]\nsqueezes = { rate = 0.6, factor = [0.2, 0.4] }\n\
             chambers = { rate = 0.8 }",
        ),
        (
            "mine",
            0..3,
            "min_clearance = [1.2, 1.5]\nsqueezes = { rate = 0.4 }\nchambers = { rate = 0.6 }",
        ),
        ("lava-tube", 0..1, "min_clearance = [1.2, 1.5]"),
    ] {
        for seed in seeds {
            let p = with_tileset(preset, seed, table);
            let s = check_world(&p, robot, &format!("{preset} seed {seed} {table:?}"));
            eprintln!(
                "{preset} seed {seed}: {} points, {} chambers, {} squeezes, tightest edge {:.2} m",
                s.points, s.chambers, s.squeezes, s.tightest
            );
            total.points += s.points;
            total.chambers += s.chambers;
            total.squeezes += s.squeezes;
            total.tightest = total.tightest.min(s.tightest);
        }
    }
    assert!(total.points > 1000 && total.chambers > 5 && total.squeezes > 20);
    let mut chambers = 0;
    for (preset, seed, table) in [
        ("cave", 0, ""),
        ("cave", 1, "chambers = { rate = 1.0 }"),
        ("mine", 0, "chambers = { rate = 0.6 }"),
        ("lava-tube", 2, ""),
    ] {
        chambers += chambers_are_rooms(
            &with_tileset(preset, seed, table),
            &format!("{preset} seed {seed} {table:?}"),
        );
    }
    assert!(chambers > 10, "{chambers} chambers");
    // Squeezes do squeeze: some edge is well under the nominal passage (cave 8.5 x 7.5 m).
    assert!(total.tightest < 4.0, "tightest edge {}", total.tightest);
}

#[test]
fn bad_chamber_and_squeeze_values_are_refused_naming_the_key() {
    let r = subtgraph::registry();
    for (table, key) in [
        ("chambers = { rate = 1.5 }", "tileset.chambers.rate"),
        ("chambers = { size = [3.0, 2.0] }", "tileset.chambers.size"),
        ("chambers = { size = [0.5, 2.0] }", "tileset.chambers.size"),
        ("squeezes = { rate = -0.1 }", "tileset.squeezes.rate"),
        (
            "squeezes = { length = [-1.0, 2.0] }",
            "tileset.squeezes.length",
        ),
        (
            "squeezes = { factor = [0.0, 0.5] }",
            "tileset.squeezes.factor",
        ),
        (
            "squeezes = { factor = [0.5, 1.5] }",
            "tileset.squeezes.factor",
        ),
        ("min_clearance = [0.0, 1.0]", "tileset.min_clearance"),
    ] {
        let spec = ComponentSpec {
            type_name: "cave".into(),
            params: Params::from_table("tileset", toml::from_str(table).unwrap()),
        };
        let err = match r.tilesets.build(&spec) {
            Err(e) => e,
            Ok(_) => panic!("{table} accepted"),
        };
        assert_eq!(err.key, key, "{err}");
    }
    // A robot larger than the passage itself: refused before any tile is made, naming the key.
    let p = with_tileset("cave", 1, "min_clearance = [8.0, 2.0]");
    let Err(err) = subtgraph::core::generate(&p, &r) else {
        panic!("min_clearance = [8.0, 2.0] accepted");
    };
    let text = err.to_string();
    assert!(text.contains("min_clearance = [8, 2]"), "{text}");
}
