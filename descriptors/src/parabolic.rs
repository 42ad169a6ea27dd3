//! `parabolic`: one wide bend per corridor, half a sine wave (1 harmonic), as in natural caves.

use serde::Deserialize;
use subtgraph_core::error::ConfigError;
use subtgraph_core::params::Params;
use subtgraph_core::route::{RouteDescriptor, Segment, default_amplitude, harmonic_offset};

use crate::harmonic::check_amplitude;

/// `[route] type = "parabolic"`, optional `amplitude` in cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Parabolic {
    /// Peak sideways offset in cells; default `min(rows, cols) / 20`.
    #[serde(default)]
    pub amplitude: Option<f64>,
}

impl Parabolic {
    /// Reads the optional `amplitude`.
    pub fn from_params(p: &Params) -> Result<Self, ConfigError> {
        let d: Parabolic = p.deserialize()?;
        check_amplitude(p, d.amplitude)?;
        Ok(d)
    }
}

impl RouteDescriptor for Parabolic {
    fn offset(&self, t: f64, segment: &Segment) -> f64 {
        let a = self.amplitude.unwrap_or_else(|| default_amplitude(segment));
        segment.side * harmonic_offset(a, 1, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bends_one_way_with_the_peak_in_the_middle() {
        let s = Segment {
            start: [20.0, 0.0],
            end: [20.0, 39.0],
            rows: 40,
            cols: 40,
            side: 1.0,
        };
        let d = Parabolic::default();
        assert!((d.offset(0.5, &s) - 2.0).abs() < 1e-9, "n / 20 = 2 cells");
        assert!((1..20).all(|i| d.offset(i as f64 / 20.0, &s) > 0.0));
        let flipped = Segment { side: -1.0, ..s };
        assert!(d.offset(0.5, &flipped) < 0.0);
    }
}
