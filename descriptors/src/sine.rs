//! `sine`: a full wave per corridor (2 harmonics), as in lava tubes.

use serde::Deserialize;
use subtgraph_core::error::ConfigError;
use subtgraph_core::params::Params;
use subtgraph_core::route::{RouteDescriptor, Segment, default_amplitude, harmonic_offset};

use crate::harmonic::check_amplitude;

/// `[route] type = "sine"`, optional `amplitude` in cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sine {
    /// Peak sideways offset in cells; default `min(rows, cols) / 20`.
    #[serde(default)]
    pub amplitude: Option<f64>,
}

impl Sine {
    /// Reads the optional `amplitude`.
    pub fn from_params(p: &Params) -> Result<Self, ConfigError> {
        let d: Sine = p.deserialize()?;
        check_amplitude(p, d.amplitude)?;
        Ok(d)
    }
}

impl RouteDescriptor for Sine {
    fn offset(&self, t: f64, segment: &Segment) -> f64 {
        let a = self.amplitude.unwrap_or_else(|| default_amplitude(segment));
        segment.side * harmonic_offset(a, 2, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swings_to_both_sides() {
        let s = Segment {
            start: [30.0, 0.0],
            end: [30.0, 59.0],
            rows: 60,
            cols: 60,
            side: 1.0,
        };
        let d = Sine {
            amplitude: Some(5.0),
        };
        assert!((d.offset(0.25, &s) - 5.0).abs() < 1e-9);
        assert!((d.offset(0.75, &s) + 5.0).abs() < 1e-9);
        let guide = d.guide(&s);
        assert!(guide.iter().any(|c| c[0] == 25) && guide.iter().any(|c| c[0] == 35));
    }
}
