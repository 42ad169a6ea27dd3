//! `harmonic`: `A sin(h pi t)` with any whole number of half-waves `h` (paper eq. 11).

use serde::Deserialize;
use subtgraph_core::error::ConfigError;
use subtgraph_core::params::Params;
use subtgraph_core::route::{RouteDescriptor, Segment, default_amplitude, harmonic_offset};

/// `[route] type = "harmonic"`, `harmonics = 3`, optional `amplitude` in cells.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Harmonic {
    /// Half-waves per corridor (0 = straight).
    pub harmonics: u32,
    /// Peak sideways offset in cells; default `min(rows, cols) / 20`.
    #[serde(default)]
    pub amplitude: Option<f64>,
}

impl Harmonic {
    /// Reads `harmonics` (required, 0 to 64) and `amplitude` (optional, cells, >= 0).
    pub fn from_params(p: &Params) -> Result<Self, ConfigError> {
        let h: Harmonic = p.deserialize()?;
        if h.harmonics > 64 {
            return Err(p.error("harmonics", "must be at most 64 half-waves per corridor"));
        }
        check_amplitude(p, h.amplitude)?;
        Ok(h)
    }
}

/// Refuses a negative or non-finite amplitude.
pub(crate) fn check_amplitude(p: &Params, amplitude: Option<f64>) -> Result<(), ConfigError> {
    match amplitude {
        Some(a) if !(a.is_finite() && a >= 0.0) => Err(p.error(
            "amplitude",
            "must be a number of cells >= 0 (the side of the bend is drawn per corridor)",
        )),
        _ => Ok(()),
    }
}

/// A harmonic descriptor with a fixed number of half-waves `H` and an optional `amplitude`:
/// what `parabolic` (`H = 1`) and `sine` (`H = 2`) are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixedHarmonic<const H: u32> {
    /// Peak sideways offset in cells; default `min(rows, cols) / 20`.
    #[serde(default)]
    pub amplitude: Option<f64>,
}

impl<const H: u32> FixedHarmonic<H> {
    /// Reads the optional `amplitude`.
    pub fn from_params(p: &Params) -> Result<Self, ConfigError> {
        let d: Self = p.deserialize()?;
        check_amplitude(p, d.amplitude)?;
        Ok(d)
    }
}

impl<const H: u32> RouteDescriptor for FixedHarmonic<H> {
    fn offset(&self, t: f64, segment: &Segment) -> f64 {
        Harmonic {
            harmonics: H,
            amplitude: self.amplitude,
        }
        .offset(t, segment)
    }
}

impl RouteDescriptor for Harmonic {
    fn offset(&self, t: f64, segment: &Segment) -> f64 {
        let a = self.amplitude.unwrap_or_else(|| default_amplitude(segment));
        segment.side * harmonic_offset(a, self.harmonics, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg() -> Segment {
        Segment {
            start: [20.0, 2.0],
            end: [20.0, 38.0],
            rows: 40,
            cols: 40,
            side: 1.0,
        }
    }

    #[test]
    fn three_harmonics_cross_the_line_twice_inside() {
        let h = Harmonic {
            harmonics: 3,
            amplitude: Some(4.0),
        };
        let s = seg();
        let signs: Vec<bool> = (1..30)
            .map(|i| h.offset(i as f64 / 30.0, &s) > 0.0)
            .collect();
        let changes = signs.windows(2).filter(|w| w[0] != w[1]).count();
        assert_eq!(changes, 2);
        assert!((h.offset(1.0 / 6.0, &s) - 4.0).abs() < 1e-9);
    }

    #[test]
    fn parameters_are_checked() {
        let mut t = toml::Table::new();
        t.insert("harmonics".into(), toml::Value::Integer(2));
        t.insert("amplitude".into(), toml::Value::Float(-1.0));
        let e = Harmonic::from_params(&Params::from_table("route", t)).unwrap_err();
        assert_eq!(e.key, "route.amplitude");
        let e =
            Harmonic::from_params(&Params::from_table("route", toml::Table::new())).unwrap_err();
        assert!(e.message.contains("harmonics"), "{e}");
    }
}
