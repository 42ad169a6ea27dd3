//! The ray caster (`core::raycast`) on the presets' collision surfaces: building the hierarchy,
//! and OS1-32-like scans (32 beams over 45 degrees, 1,024 columns: 32,768 rays) cast from the
//! passage axis of the ground-truth graph, 0.6 m above its floor, on all threads and on one.
//! Run with `cargo bench --bench raycast`; the throughput is in rays per second.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use subtgraph::core::raycast::{Ray, RayCaster};
use subtgraph::core::survey::Survey;
use subtgraph::core::{World, generate};
use subtgraph::survey::WorldSurvey;

/// Scan origins: every 25th point of the survey's edge centrelines (the ground truth's
/// polylines), 0.6 m above the floor.
fn origins(world: &World) -> Vec<[f64; 3]> {
    let survey = WorldSurvey::new(world).expect("survey");
    survey
        .edges()
        .iter()
        .flat_map(|edge| edge.points.iter().step_by(25))
        .map(|p| [p[0], p[1], p[2] + 0.6])
        .collect()
}

/// The rays of an OS1-32-like scan from `o`.
fn scan(o: [f64; 3]) -> Vec<Ray> {
    let mut rays = Vec::with_capacity(32 * 1024);
    for c in 0..1024 {
        let az = c as f64 / 1024.0 * std::f64::consts::TAU;
        for b in 0..32 {
            let el = (-22.5 + 45.0 * b as f64 / 31.0).to_radians();
            rays.push(Ray {
                origin: o,
                dir: [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()],
            });
        }
    }
    rays
}

fn presets(c: &mut Criterion) {
    let registry = subtgraph::registry();
    for name in ["cave", "mine", "lava-tube"] {
        let p = subtgraph::presets::load(name).expect("preset");
        let world = generate(&p, &registry).expect("world");
        let mesh = &world.mesh().expect("mesh").collision;
        let mut group = c.benchmark_group("raycast-build");
        group.sample_size(10);
        group.throughput(Throughput::Elements(mesh.triangle_count() as u64));
        group.bench_function(name, |b| b.iter(|| RayCaster::new(black_box(mesh))));
        group.finish();

        let caster = RayCaster::new(mesh);
        let starts = origins(&world);
        let scans: Vec<Vec<Ray>> = starts
            .iter()
            .step_by(starts.len() / 8 + 1)
            .map(|&o| scan(o))
            .collect();
        let rays: usize = scans.iter().map(Vec::len).sum();
        let mut group = c.benchmark_group("raycast-os1-32");
        group.sample_size(10);
        group.throughput(Throughput::Elements(rays as u64));
        group.bench_function(format!("{name}/all-threads"), |b| {
            b.iter(|| {
                for s in &scans {
                    black_box(caster.cast_all(s, 120.0));
                }
            })
        });
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool");
        group.bench_function(format!("{name}/one-thread"), |b| {
            b.iter(|| {
                one.install(|| {
                    for s in &scans {
                        black_box(caster.cast_all(s, 120.0));
                    }
                })
            })
        });
        group.finish();
    }
}

criterion_group!(benches, presets);
criterion_main!(benches);
