//! `parabolic`: one wide bend per corridor, half a sine wave (1 harmonic), as in natural caves.

use crate::harmonic::FixedHarmonic;

/// `[route] type = "parabolic"`, optional `amplitude` in cells: half a sine wave per corridor.
pub type Parabolic = FixedHarmonic<1>;

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::route::{RouteDescriptor, Segment};

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
