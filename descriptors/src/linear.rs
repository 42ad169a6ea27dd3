//! `linear`: no bend; corridors follow the straight segment (0 harmonics), as in operational
//! mines.

use subtgraph_core::error::ConfigError;
use subtgraph_core::params::Params;
use subtgraph_core::route::{RouteDescriptor, Segment};

/// `[route] type = "linear"`. Takes no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Linear;

impl Linear {
    /// Refuses any parameter: a straight line has nothing to set.
    pub fn from_params(p: &Params) -> Result<Self, ConfigError> {
        p.expect_none()?;
        Ok(Linear)
    }
}

impl RouteDescriptor for Linear {
    fn offset(&self, _t: f64, _segment: &Segment) -> f64 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guides_run_straight_and_parameters_are_refused() {
        let s = Segment {
            start: [5.0, 5.0],
            end: [25.0, 5.0],
            rows: 30,
            cols: 30,
            side: -1.0,
        };
        assert!(Linear.guide(&s).iter().all(|c| c[1] == 5));
        let mut t = toml::Table::new();
        t.insert("amplitude".into(), toml::Value::Float(1.0));
        let e = Linear::from_params(&Params::from_table("route", t)).unwrap_err();
        assert_eq!(e.key, "route.amplitude");
    }
}
