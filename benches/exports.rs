//! Export formatting alone, per registered `[[export]]` format: the cave preset (seed 1) with
//! its mesh, written into a sink that only counts bytes, so the disk plays no part.
//!
//! `cargo bench --bench exports`

use std::io::Write;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use subtgraph::core::export::WorldWriter;
use subtgraph::core::params::ComponentSpec;
use subtgraph::survey::WorldSurvey;

/// Counts what is written and keeps nothing.
#[derive(Default)]
struct Sink {
    bytes: u64,
    files: Vec<String>,
}

struct Counter<'a>(&'a mut u64);

impl Write for Counter<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        *self.0 += buf.len() as u64;
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl WorldWriter for Sink {
    fn write(&mut self, path: &str, bytes: &[u8]) -> std::io::Result<()> {
        self.bytes += bytes.len() as u64;
        self.files.push(path.to_owned());
        Ok(())
    }
    fn stream(
        &mut self,
        path: &str,
        fill: &mut dyn FnMut(&mut dyn Write) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        self.files.push(path.to_owned());
        fill(&mut Counter(&mut self.bytes))
    }
    fn contains(&self, path: &str) -> bool {
        self.files.iter().any(|f| f == path)
    }
}

fn exports(c: &mut Criterion) {
    let registry = subtgraph::registry();
    let mut p = subtgraph::presets::load("cave").unwrap();
    p.world.seed = 1;
    let world = subtgraph::core::generate(&p, &registry).unwrap();
    let mut group = c.benchmark_group("export cave preset");
    group.sample_size(10);
    for name in registry.exporters.names() {
        let exporter = registry
            .exporters
            .build(&ComponentSpec::named(name))
            .unwrap();
        let mut sink = Sink::default();
        let survey = WorldSurvey::new(&world).unwrap();
        exporter.export(&world, &survey, &mut sink).unwrap();
        group.throughput(Throughput::Bytes(sink.bytes));
        // A survey per run: each exporter alone pays for what it asks of it, as it does when
        // a world is exported in that one format.
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut sink = Sink::default();
                let survey = WorldSurvey::new(&world).unwrap();
                exporter.export(&world, &survey, &mut sink).unwrap();
                sink.bytes
            })
        });
    }
    group.finish();
}

criterion_group!(benches, exports);
criterion_main!(benches);
