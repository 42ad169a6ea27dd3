//! Occupancy, tile classification and topological graph per preset (one core), and the world
//! folder's files. Run with `cargo bench --bench occupancy`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use subtgraph::core::export::MemoryWriter;
use subtgraph::core::layout as generate;

fn presets(c: &mut Criterion) {
    let registry = subtgraph::registry();
    for name in ["cave", "mine", "lava-tube"] {
        let pipeline = subtgraph::presets::load(name).expect("preset");
        c.bench_function(&format!("generate/{name}"), |b| {
            b.iter(|| generate(black_box(&pipeline), &registry).expect("generates"))
        });
        let world =
            subtgraph::core::World::from(generate(&pipeline, &registry).expect("generates"));
        c.bench_function(&format!("world-folder/{name}"), |b| {
            b.iter(|| {
                let mut out = MemoryWriter::default();
                let survey =
                    subtgraph::survey::WorldSurvey::new(black_box(&world)).expect("surveys");
                subtgraph::exporters::write_world_folder(&world, &survey, &mut out)
                    .expect("writes");
                out
            })
        });
    }
}

/// The largest lava tube the preset draws: 5 levels of 70 x 70 cells.
fn largest_lava_tube(c: &mut Criterion) {
    let registry = subtgraph::registry();
    let mut pipeline = subtgraph::presets::load("lava-tube").expect("preset");
    pipeline.world.min_length = None;
    pipeline.world.rows = Some(70);
    pipeline.world.cols = Some(70);
    c.bench_function("generate/lava-tube-70x70x5", |b| {
        b.iter(|| generate(black_box(&pipeline), &registry).expect("generates"))
    });
}

/// A room-and-pillar panel of 300 x 300 pillars (360,000 cells of drifts and crosscuts) on a
/// 640 x 640 level: the cost that grew with the square of the block (issue 21 item 8).
fn large_room_and_pillar(c: &mut Criterion) {
    let registry = subtgraph::registry();
    let pipeline = subtgraph::core::Pipeline::parse(
        "[world]\nseed = 1\nrows = 640\ncols = 640\n\n\
         [topology]\nloops = 0\nt_junctions = 0\nintersections = 0\n\n\
         [[topology.structure]]\ntype = \"room-and-pillar\"\ncount = 1\npillars = [300, 300]\n",
        "room-and-pillar bench",
    )
    .expect("parses");
    let mut group = c.benchmark_group("generate");
    group.sample_size(10);
    group.bench_function("room-and-pillar-300x300", |b| {
        b.iter(|| generate(black_box(&pipeline), &registry).expect("generates"))
    });
    group.finish();
}

criterion_group!(benches, presets, largest_lava_tube, large_room_and_pillar);
criterion_main!(benches);
