//! The ray caster (`core::raycast`) on the presets' collision surfaces: building the hierarchy,
//! and OS1-32-like scans (32 beams over 45 degrees, 1,024 columns: 32,768 rays) cast from the
//! passage axis of the ground-truth graph, 0.6 m above its floor, on all threads and on one.
//! Run with `cargo bench --bench raycast`; the throughput is in rays per second.
//!
//! The scans are timed twice: by the wall clock (`raycast-os1-32`) and by the CPU time of the
//! process's threads (`raycast-os1-32-cpu`: "rays/s" there are rays per CPU second). On a
//! machine other programs load, a thread gets a share of a core and the wall clock counts the
//! time it waits; the CPU time does not, so it is the steadier number, and rays per CPU second
//! times the cores is what the machine does when nothing else runs.

use std::hint::black_box;
use std::sync::OnceLock;
use std::time::Duration;

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use subtgraph::core::mesh::Mesh;
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

/// A preset's collision surface and eight scans from along its graph.
struct Preset {
    name: &'static str,
    mesh: Mesh,
    scans: Vec<Vec<Ray>>,
}

/// The three presets, generated once for both measurements.
fn presets() -> &'static [Preset] {
    static PRESETS: OnceLock<Vec<Preset>> = OnceLock::new();
    PRESETS.get_or_init(|| {
        let registry = subtgraph::registry();
        ["cave", "mine", "lava-tube"]
            .into_iter()
            .map(|name| {
                let p = subtgraph::presets::load(name).expect("preset");
                let world = generate(&p, &registry).expect("world");
                let mesh = world.mesh().expect("mesh").collision.clone();
                let starts = origins(&world);
                let scans = starts
                    .iter()
                    .step_by(starts.len() / 8 + 1)
                    .map(|&o| scan(o))
                    .collect();
                Preset { name, mesh, scans }
            })
            .collect()
    })
}

fn build(c: &mut Criterion) {
    for p in presets() {
        let mut group = c.benchmark_group("raycast-build");
        group.sample_size(10);
        group.throughput(Throughput::Elements(p.mesh.triangle_count() as u64));
        group.bench_function(p.name, |b| b.iter(|| RayCaster::new(black_box(&p.mesh))));
        // In Morton order, as the mine's bolt rings use it on the visual surface.
        group.bench_function(format!("{}/quick", p.name), |b| {
            b.iter(|| RayCaster::quick(black_box(&p.mesh)))
        });
        group.finish();
    }
}

/// The presets' scans on all threads and on one, in group `name`, timed by `M`.
fn scans<M: Measurement>(c: &mut Criterion<M>, name: &str) {
    for p in presets() {
        let caster = RayCaster::new(&p.mesh);
        let rays: usize = p.scans.iter().map(Vec::len).sum();
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        group.throughput(Throughput::Elements(rays as u64));
        group.bench_function(format!("{}/all-threads", p.name), |b| {
            b.iter(|| {
                for s in &p.scans {
                    black_box(caster.cast_all(s, 120.0));
                }
            })
        });
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool");
        group.bench_function(format!("{}/one-thread", p.name), |b| {
            b.iter(|| {
                one.install(|| {
                    for s in &p.scans {
                        black_box(caster.cast_all(s, 120.0));
                    }
                })
            })
        });
        group.finish();
    }
}

fn wall(c: &mut Criterion) {
    scans(c, "raycast-os1-32");
}

fn cpu(c: &mut Criterion<CpuTime>) {
    scans(c, "raycast-os1-32-cpu");
}

/// CPU time of all the process's threads (Linux: the first field of each thread's
/// `/proc/self/task/*/schedstat`, nanoseconds on a CPU), read at the start and end of a
/// sample. Threads that end during a sample (none here: rayon's pools outlive their samples)
/// would take their time with them.
struct CpuTime;

/// Nanoseconds the process's threads have run.
fn cpu_ns() -> u64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0;
    };
    tasks
        .flatten()
        .filter_map(|t| std::fs::read_to_string(t.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum()
}

impl Measurement for CpuTime {
    type Intermediate = u64;
    type Value = Duration;

    fn start(&self) -> u64 {
        cpu_ns()
    }
    fn end(&self, start: u64) -> Duration {
        Duration::from_nanos(cpu_ns().saturating_sub(start))
    }
    fn add(&self, a: &Duration, b: &Duration) -> Duration {
        *a + *b
    }
    fn zero(&self) -> Duration {
        Duration::ZERO
    }
    fn to_f64(&self, v: &Duration) -> f64 {
        v.as_nanos() as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &CpuFormatter
    }
}

/// CPU nanoseconds shown as CPU milliseconds, throughputs per CPU second.
struct CpuFormatter;

impl ValueFormatter for CpuFormatter {
    fn scale_values(&self, _typical: f64, values: &mut [f64]) -> &'static str {
        for v in values {
            *v *= 1e-6;
        }
        "ms CPU"
    }
    fn scale_throughputs(&self, _typical: f64, t: &Throughput, values: &mut [f64]) -> &'static str {
        let n = match *t {
            Throughput::Elements(n) | Throughput::ElementsAndBytes { elements: n, .. } => n,
            Throughput::Bytes(n) | Throughput::BytesDecimal(n) => n,
            Throughput::Bits(n) => n,
        } as f64;
        for v in values {
            *v = n * 1e9 / *v * 1e-6;
        }
        "M/CPU s"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

criterion_group!(benches, build, wall);
criterion_group! {
    name = per_cpu;
    config = Criterion::default().with_measurement(CpuTime);
    targets = cpu
}
criterion_main!(benches, per_cpu);
