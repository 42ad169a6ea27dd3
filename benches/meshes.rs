//! The mesh stage: assembling every tile of a world (procedural tile sets on each preset, and
//! the DARPA tiles on the original's largest worlds when ../shared is present).
//! Run with `cargo bench --bench meshes`.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use subtgraph::core::assembly::assemble;
use subtgraph::core::{Pipeline, layout};

fn bench(c: &mut Criterion, name: &str, pipeline: &Pipeline) {
    let registry = subtgraph::registry();
    let world = layout(pipeline, &registry).expect("layout");
    let tileset = registry
        .tilesets
        .build(pipeline.tileset.as_ref().expect("a [tileset]"))
        .expect("tile set");
    let triangles = assemble(&world, tileset.as_ref())
        .expect("mesh")
        .visual
        .triangle_count();
    let mut group = c.benchmark_group("mesh");
    group.sample_size(10);
    group.throughput(criterion::Throughput::Elements(triangles as u64));
    group.bench_function(name, |b| {
        b.iter(|| assemble(black_box(&world), tileset.as_ref()).expect("mesh"))
    });
    group.finish();
    // What assembly adds to check the memory budget before the first tile: the estimate.
    let mut group = c.benchmark_group("estimate");
    group.bench_function(name, |b| {
        b.iter(|| {
            let w = black_box(&world);
            w.mesh_estimate(|k| tileset.estimate(w, k))
        })
    });
    group.finish();
}

fn presets(c: &mut Criterion) {
    for name in ["cave", "mine", "lava-tube"] {
        let p = subtgraph::presets::load(name).expect("preset");
        bench(c, name, &p);
    }
}

fn darpa(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if !root.join("../shared/darpa-subt-tiles").is_dir() {
        eprintln!("skipping the DARPA benchmarks: ../shared/darpa-subt-tiles is absent");
        return;
    }
    for name in ["cave-darpa", "lava-tube-darpa"] {
        let file = root.join(format!("benches/pipelines/{name}.toml"));
        let text = std::fs::read_to_string(&file).expect("pipeline");
        let mut p = Pipeline::parse(&text, &file.display().to_string()).expect("valid");
        p.anchor_paths(file.parent().expect("folder"));
        bench(c, name, &p);
    }
}

criterion_group!(benches, presets, darpa);
criterion_main!(benches);
