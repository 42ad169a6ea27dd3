//! Template plugin: one route descriptor, `wiggle`. Replace it with yours; keep the
//! `declare_plugin!` line at the end.
//!
//! Other kinds register the same way (`r.constraint_shape`, `r.tileset`, `r.exporter`; see
//! docs/plugins.md and plugins/examples). An exporter (plugin API 6) formats the world and what
//! its survey found, and computes nothing of its own:
//!
//! ```ignore
//! impl Exporter for Mine {
//!     fn export(&self, world: &World, survey: &dyn Survey, out: &mut dyn WorldWriter)
//!         -> Result<(), ExportError> {
//!         let artifacts = survey.artifacts().map_or(0, |a| a.artifacts.len());
//!         write_file(out, "mine.txt", format!("{artifacts}").as_bytes())
//!     }
//! }
//! ```

use subtgraph_core::route::{RouteDescriptor, Segment};

/// Bends every corridor into a small S.
struct Wiggle {
    amplitude: f64,
}

impl RouteDescriptor for Wiggle {
    fn offset(&self, t: f64, segment: &Segment) -> f64 {
        segment.side * self.amplitude * (2.0 * std::f64::consts::PI * t).sin()
    }
}

fn register(r: &mut subtgraph_plugins::Registrar<'_>) {
    r.route_descriptor("wiggle", "a small S per corridor", |params| {
        let amplitude = match params.raw("amplitude") {
            None => 1.5,
            Some(v) => v
                .as_float()
                .or_else(|| v.as_integer().map(|i| i as f64))
                .ok_or_else(|| params.error("amplitude", "must be a number of cells"))?,
        };
        params.expect_known(&["amplitude"])?;
        Ok(Box::new(Wiggle { amplitude }))
    });
}

subtgraph_plugins::declare_plugin!("template", register);
