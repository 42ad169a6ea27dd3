//! `sine`: a full wave per corridor (2 harmonics), as in lava tubes.

use crate::harmonic::FixedHarmonic;

/// `[route] type = "sine"`, optional `amplitude` in cells: a full wave per corridor.
pub type Sine = FixedHarmonic<2>;

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::route::{RouteDescriptor, Segment};

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
