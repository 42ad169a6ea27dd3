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

criterion_group!(benches, presets, largest_lava_tube);
criterion_main!(benches);
