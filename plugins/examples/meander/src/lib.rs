//! A route descriptor plugin: corridors that meander with a wavelength given in cells.
//!
//! ```toml
//! [plugins]
//! paths = ["target/release/libsubtgraph_plugin_meander.so"]
//! [route]
//! type = "meander"
//! wavelength = 6
//! ```

use serde::Deserialize;
use subtgraph_core::error::ConfigError;
use subtgraph_core::params::Params;
use subtgraph_core::route::{RouteDescriptor, Segment};

/// `wavelength` cells per full swing, `amplitude` cells to each side.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Meander {
    wavelength: f64,
    #[serde(default = "two")]
    amplitude: f64,
    /// For tests of the host's panic handling: panic when asked for an offset past this `t`.
    #[serde(default)]
    panic_after: Option<f64>,
}

fn two() -> f64 {
    2.0
}

impl RouteDescriptor for Meander {
    fn offset(&self, t: f64, segment: &Segment) -> f64 {
        if self.panic_after.is_some_and(|p| t > p) {
            panic!(
                "meander was asked to panic after t = {:?}",
                self.panic_after
            );
        }
        let waves = segment.length() / self.wavelength;
        // Whole waves only, so the route still ends on its objective.
        let waves = waves.round().max(1.0);
        segment.side * self.amplitude * (2.0 * std::f64::consts::PI * waves * t).sin()
    }
}

fn register(r: &mut subtgraph_plugins::Registrar<'_>) {
    r.route_descriptor(
        "meander",
        "corridors that swing side to side every `wavelength` cells",
        |p: &Params| {
            let m: Meander = p.deserialize()?;
            if !(m.wavelength.is_finite() && m.wavelength >= 2.0) {
                return Err::<_, ConfigError>(p.error("wavelength", "must be at least 2 cells"));
            }
            Ok(Box::new(m))
        },
    );
}

subtgraph_plugins::declare_plugin!("meander", register);
