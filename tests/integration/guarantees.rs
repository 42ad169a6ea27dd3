//! The three guarantees, checked over many seeds and configurations:
//! one connected world, the requested topology on the final grid, and determinism.

use proptest::prelude::*;
use subtgraph::core::export::MemoryWriter;
use subtgraph::core::graph::EdgeKind;
use subtgraph::core::grid::Direction;
use subtgraph::core::tile::TileKind;
use subtgraph::core::world::fused_blocks;
use subtgraph::core::{Error, Pipeline, World, layout};

/// The layout of a pipeline as a world without geometry (what the exporters take).
fn generate(p: &Pipeline, r: &subtgraph::core::Registry) -> Result<World, Error> {
    layout(p, r).map(World::from)
}

#[allow(clippy::too_many_arguments)]
fn pipeline(
    seed: u64,
    levels: u32,
    side: u32,
    loops: u32,
    t: u32,
    x: u32,
    exact: bool,
    route: &str,
) -> Pipeline {
    let text = format!(
        "[world]\nseed = {seed}\nlevels = {levels}\nrows = {side}\ncols = {side}\n\
         [topology]\nloops = {loops}\nt_junctions = {t}\nintersections = {x}\nexact = {exact}\n\
         [route]\ntype = \"{route}\"\n"
    );
    Pipeline::parse(&text, "property.toml").unwrap()
}

/// Every guarantee a generated world must keep.
fn check_world(w: &World) {
    let levels = w.resolved.levels;
    assert_eq!(w.occupancy.levels(), levels, "exactly the requested levels");
    assert_eq!(w.levels.len(), levels);

    // One connected world.
    assert_eq!(
        w.reachable_from_start(),
        w.occupancy.occupied_count(),
        "every occupied cell is reachable from the start"
    );

    // No corridors fused side by side.
    assert!(fused_blocks(&w.occupancy).is_empty(), "no 2 x 2 blocks");

    // The requested topology, per level.
    for l in &w.levels {
        assert_eq!(l.components, 1, "level {} is one piece", l.level);
        let want = l.expected.expect("generated levels have expectations");
        let got = l.achieved;
        let req = |name: &str| l.requested.get(name).copied().unwrap_or(0);
        assert!(got.t_junctions >= req("t-junction"));
        assert!(got.intersections >= req("intersection"));
        assert!(got.loops >= req("loop"));
        if w.resolved.exact {
            assert_eq!(got.t_junctions, want.t_junctions, "level {}", l.level);
            assert_eq!(got.intersections, want.intersections, "level {}", l.level);
            assert_eq!(got.loops, want.loops, "level {}", l.level);
        } else {
            assert!(got.t_junctions >= want.t_junctions);
            assert!(got.intersections >= want.intersections);
            assert!(got.loops >= want.loops);
        }
    }

    // Shafts join consecutive levels, stacked, between dead ends.
    assert_eq!(w.shafts.len(), levels - 1);
    for (k, s) in w.shafts.iter().enumerate() {
        assert_eq!((s.up.level, s.landing.level), (k, k + 1));
        assert_eq!((s.up.row, s.up.col), (s.landing.row, s.landing.col));
        let up = w.tiles.get(s.up).unwrap();
        let landing = w.tiles.get(s.landing).unwrap();
        assert_eq!(up.kind, TileKind::ShaftUp);
        assert_eq!(landing.kind, TileKind::ShaftLanding);
        assert_eq!(up.openings.count_ones(), 1);
        assert_eq!(landing.openings.count_ones(), 1);
    }

    // Every occupied cell has a tile and the graph covers every corridor step once.
    let mut steps = 0;
    for c in w.occupancy.cells() {
        assert_eq!(w.tiles.get(c).is_some(), *w.occupancy.get(c));
        if let Some(t) = w.tiles.get(c) {
            steps += (t.openings & (Direction::East.bit() | Direction::South.bit())).count_ones()
                as usize;
        }
    }
    let corridor_steps: usize = w
        .graph
        .edges
        .iter()
        .filter(|e| e.kind == EdgeKind::Corridor)
        .map(|e| e.length_cells)
        .sum();
    assert_eq!(corridor_steps, steps, "graph edges cover each step once");
}

fn world_bytes(w: &World) -> Vec<(String, Vec<u8>)> {
    let mut out = MemoryWriter::default();
    let survey = subtgraph::survey::WorldSurvey::new(w).unwrap();
    subtgraph::exporters::write_world_folder(w, &survey, &mut out).unwrap();
    out.files
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn generated_worlds_keep_their_guarantees(
        seed in 0u64..1_000_000,
        levels in 1u32..=4,
        side in 28u32..=64,
        loops in 0u32..=2,
        t in 0u32..=3,
        x in 0u32..=2,
        exact in any::<bool>(),
        route in prop::sample::select(vec!["linear", "parabolic", "sine"]),
    ) {
        prop_assume!(loops + t + x > 0);
        let p = pipeline(seed, levels, side, loops, t, x, exact, route);
        let w = generate(&p, &subtgraph::registry()).unwrap();
        check_world(&w);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn the_same_seed_gives_the_same_bytes(seed in 0u64..1_000_000, exact in any::<bool>()) {
        let p = pipeline(seed, 2, 40, 1, 2, 1, exact, "sine");
        let r = subtgraph::registry();
        let a = world_bytes(&generate(&p, &r).unwrap());
        let b = world_bytes(&generate(&p, &r).unwrap());
        prop_assert_eq!(a, b);
    }
}

#[test]
fn presets_keep_their_guarantees_over_many_seeds() {
    let r = subtgraph::registry();
    for (name, levels) in [("mine", 3), ("cave", 1), ("lava-tube", 5)] {
        let mut p = subtgraph::presets::load(name).unwrap();
        for seed in 0..100 {
            p.world.seed = seed;
            let w = generate(&p, &r).unwrap_or_else(|e| panic!("{name} seed {seed}: {e}"));
            assert_eq!(w.resolved.levels, levels, "{name}");
            check_world(&w);
        }
    }
}

/// Issue 15 item 9: the presets and the paper's dataset configurations give exactly the
/// topology asked for (Table 1's counts, no extra junction or loop), as does a pipeline that
/// does not say; `exact = false` keeps the original's behaviour (at least what was asked).
#[test]
fn presets_and_paper_datasets_give_exactly_the_topology_asked_for() {
    let r = subtgraph::registry();
    let mut sources: Vec<(String, Pipeline)> = ["mine", "cave", "lava-tube"]
        .iter()
        .map(|n| (n.to_string(), subtgraph::presets::load(n).unwrap()))
        .collect();
    for n in ["mine", "cave", "lava-tube"] {
        let path = format!(
            "{}/examples/datasets/paper-{n}.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(&path).unwrap();
        sources.push((path.clone(), Pipeline::parse(&text, &path).unwrap()));
    }
    let unsaid = Pipeline::parse("[world]\nrows = 30\ncols = 30\n", "unsaid.toml").unwrap();
    sources.push(("no exact key".into(), unsaid));
    for (name, mut p) in sources {
        assert!(p.topology.exact, "{name} is exact");
        for seed in 0..50 {
            p.world.seed = seed;
            let w = generate(&p, &r).unwrap_or_else(|e| panic!("{name} seed {seed}: {e}"));
            assert!(w.resolved.exact);
            for l in &w.levels {
                let want = l.expected.unwrap();
                let req = |k: &str| l.requested.get(k).copied().unwrap_or(0);
                assert_eq!(l.achieved.loops, req("loop"), "{name} seed {seed}");
                assert_eq!(
                    l.achieved.intersections,
                    req("intersection"),
                    "{name} {seed}"
                );
                assert_eq!(
                    l.achieved.t_junctions,
                    req("t-junction") + 4 * req("loop"),
                    "{name} seed {seed}: the T-junctions asked for and those of the loops"
                );
                let key = |c: subtgraph::core::topology::Counts| {
                    (c.t_junctions, c.intersections, c.loops)
                };
                assert_eq!(key(l.achieved), key(want), "{name} seed {seed}");
            }
        }
    }
    // The original's behaviour stays available: some cave levels get more than asked.
    let mut p = subtgraph::presets::load("cave").unwrap();
    p.topology.exact = false;
    let extra = (0..50)
        .filter(|&seed| {
            p.world.seed = seed;
            let w = generate(&p, &r).unwrap();
            w.levels.iter().any(|l| {
                let (a, e) = (l.achieved, l.expected.unwrap());
                (a.t_junctions, a.intersections, a.loops)
                    != (e.t_junctions, e.intersections, e.loops)
            })
        })
        .count();
    assert!(
        extra > 0,
        "exact = false lets arms join corridors, as the original"
    );
}

/// Issue 15 item 2: mines' linear routes run straight and meet at right angles, so their tile
/// mix is the original's published mines' (corners under 5 %, against 29.5 % when a linear
/// route was laid as a staircase), and most corridors between two nodes turn at most once
/// (more only where a detour round another corridor needs it). Curved routes keep theirs.
#[test]
fn mine_drifts_run_straight_and_turn_at_right_angles() {
    let r = subtgraph::registry();
    let share = |name: &str| {
        let mut p = subtgraph::presets::load(name).unwrap();
        let (mut corners, mut tiles, mut edges, mut straightish) = (0, 0, 0, 0);
        for seed in 0..40 {
            p.world.seed = seed;
            let w = generate(&p, &r).unwrap();
            let is_corner = |c| w.tiles.get(c).is_some_and(|t| t.kind == TileKind::Corner);
            for c in w.occupancy.cells().filter(|&c| *w.occupancy.get(c)) {
                tiles += 1;
                corners += usize::from(is_corner(c));
            }
            for e in w
                .graph
                .edges
                .iter()
                .filter(|e| e.kind == EdgeKind::Corridor)
            {
                edges += 1;
                straightish += usize::from(e.cells.iter().filter(|&&c| is_corner(c)).count() <= 1);
            }
        }
        (
            corners as f64 / tiles as f64,
            straightish as f64 / edges as f64,
        )
    };
    let (mine, mine_straight) = share("mine");
    assert!(mine < 0.05, "mine corner share {:.1} %", 100.0 * mine);
    assert!(
        mine_straight > 0.75,
        "only {:.0} % of mine corridors turn at most once",
        100.0 * mine_straight
    );
    let (cave, _) = share("cave");
    assert!(
        cave > 0.2,
        "caves still wind: corner share {:.1} %",
        100.0 * cave
    );
}

#[test]
fn different_seeds_give_different_worlds() {
    let r = subtgraph::registry();
    let mut p = subtgraph::presets::load("cave").unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for seed in 0..20 {
        p.world.seed = seed;
        seen.insert(generate(&p, &r).unwrap().spatial_codes());
    }
    assert_eq!(seen.len(), 20);
}

#[test]
fn thread_count_does_not_change_the_world() {
    let r = subtgraph::registry();
    let p = subtgraph::presets::load("lava-tube").unwrap();
    let alone = world_bytes(&generate(&p, &r).unwrap());
    let together: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..4)
            .map(|_| s.spawn(|| world_bytes(&generate(&p, &subtgraph::registry()).unwrap())))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for t in together {
        assert_eq!(t, alone);
    }
}

#[test]
fn a_resolved_pipeline_regenerates_the_same_world() {
    let r = subtgraph::registry();
    for name in ["mine", "cave", "lava-tube"] {
        let p = subtgraph::presets::load(name).unwrap();
        let w = generate(&p, &r).unwrap();
        let text = w.pipeline.to_toml();
        let again = generate(&Pipeline::parse(&text, "world.toml").unwrap(), &r).unwrap();
        assert_eq!(w.spatial_codes(), again.spatial_codes(), "{name}");
    }
}

#[test]
fn an_impossible_request_fails_with_what_to_change() {
    let p = pipeline(3, 1, 10, 2, 3, 3, true, "linear");
    let started = std::time::Instant::now();
    let err = generate(&p, &subtgraph::registry()).unwrap_err();
    assert!(
        matches!(err, Error::Unsatisfiable { level: 0, .. }),
        "{err}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("larger grid") && msg.contains("fewer structures"),
        "{msg}"
    );
    // Bounded: 64 attempts on a tiny grid, far from an endless loop.
    assert!(started.elapsed().as_secs() < 30);
}
