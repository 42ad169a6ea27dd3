//! Route descriptors: the shape tendency that bends every corridor (paper eqs. 7-13).
//!
//! A route between a start and an end cell begins as a straight segment. The descriptor offsets
//! each point of it sideways (along the unit perpendicular) by [`RouteDescriptor::offset`]; the
//! offset points, rounded to cells, become the cheap cells of the guiding cost matrix that the
//! shortest-path search follows. The search may leave the guide where it is blocked, at a
//! higher cost, so a bent route can still reach its end.

/// The straight segment a route descriptor bends, in cell coordinates (row, column).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Start, `[row, col]`.
    pub start: [f64; 2],
    /// End, `[row, col]`.
    pub end: [f64; 2],
    /// Rows of the level.
    pub rows: usize,
    /// Columns of the level.
    pub cols: usize,
    /// Which side the route bends to: `1.0` or `-1.0`, drawn per route by the generator.
    pub side: f64,
}

impl Segment {
    /// Euclidean length in cells.
    pub fn length(&self) -> f64 {
        let dr = self.end[0] - self.start[0];
        let dc = self.end[1] - self.start[1];
        libm::sqrt(dr * dr + dc * dc)
    }

    /// The point at `t` in `[0, 1]` moved `offset` cells along the unit perpendicular
    /// (paper eqs. 10, 12, 13).
    pub fn point(&self, t: f64, offset: f64) -> [f64; 2] {
        let dr = self.end[0] - self.start[0];
        let dc = self.end[1] - self.start[1];
        let len = self.length();
        let (pr, pc) = if len > 0.0 {
            (-dc / len, dr / len)
        } else {
            (0.0, 0.0)
        };
        [
            self.start[0] + dr * t + offset * pr,
            self.start[1] + dc * t + offset * pc,
        ]
    }
}

/// Bends routes between constraint and objective nodes.
///
/// Only [`offset`](RouteDescriptor::offset) is required; the sampling of guide points follows
/// the original (four samples per cell of segment length) unless overridden.
///
/// # Example
///
/// A descriptor that bends every route into a zig-zag of amplitude two cells:
///
/// ```
/// use subtgraph_core::route::{RouteDescriptor, Segment};
///
/// struct ZigZag;
///
/// impl RouteDescriptor for ZigZag {
///     fn offset(&self, t: f64, segment: &Segment) -> f64 {
///         let phase = (t * 4.0).fract();
///         segment.side * 2.0 * (1.0 - 4.0 * (phase - 0.5).abs())
///     }
/// }
///
/// let seg = Segment { start: [5.0, 5.0], end: [5.0, 25.0], rows: 30, cols: 30, side: 1.0 };
/// let guide = ZigZag.guide(&seg);
/// assert_eq!(guide.first(), Some(&[5, 5]));
/// assert_eq!(guide.last(), Some(&[5, 25]));
/// ```
pub trait RouteDescriptor: Send + Sync {
    /// Sideways offset in cells at `t` in `[0, 1]` (positive to the left of start -> end).
    /// Should be 0 at `t = 0` and `t = 1` so routes meet their nodes.
    fn offset(&self, t: f64, segment: &Segment) -> f64;

    /// Extra cost of a right-angle turn for the shortest-path search that lays the route along
    /// the guide (a step costs 1 on the guide, more off it). `0`, the default, lets a route turn
    /// anywhere at no cost, so a detour or a diagonal run becomes a staircase of corners, as
    /// in the original. A positive cost makes routes run straight and turn only where they
    /// must: the `linear` descriptor's mine drifts.
    fn turn_cost(&self) -> u32 {
        0
    }

    /// Number of points sampled along a segment (paper eq. 8, factor 4 as in the original).
    fn samples(&self, segment: &Segment) -> usize {
        (4.0 * segment.length()).floor().max(1.0) as usize
    }

    /// The guide cells `[row, col]`, clamped to the level, in order from start to end, without
    /// consecutive repeats. The first is the start cell and the last the end cell.
    fn guide(&self, segment: &Segment) -> Vec<[i32; 2]> {
        let n = self.samples(segment);
        let max_r = segment.rows.saturating_sub(1) as f64;
        let max_c = segment.cols.saturating_sub(1) as f64;
        let mut cells: Vec<[i32; 2]> = Vec::with_capacity(n + 1);
        for i in 0..=n {
            let t = i as f64 / n as f64;
            let off = if i == 0 || i == n {
                0.0
            } else {
                self.offset(t, segment)
            };
            let p = segment.point(t, off);
            let cell = [
                libm::round(p[0]).clamp(0.0, max_r) as i32,
                libm::round(p[1]).clamp(0.0, max_c) as i32,
            ];
            if cells.last() != Some(&cell) {
                cells.push(cell);
            }
        }
        cells
    }
}

/// The paper's amplitude for a level: the original uses `min(rows, cols) / 20` cells.
pub fn default_amplitude(segment: &Segment) -> f64 {
    segment.rows.min(segment.cols) as f64 / 20.0
}

/// `A sin(h pi t)`: the harmonic family of paper eq. 11, shared by the built-in descriptors.
pub fn harmonic_offset(amplitude: f64, harmonics: u32, t: f64) -> f64 {
    amplitude * libm::sin(f64::from(harmonics) * core::f64::consts::PI * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Flat;
    impl RouteDescriptor for Flat {
        fn offset(&self, _t: f64, _s: &Segment) -> f64 {
            0.0
        }
    }

    #[test]
    fn a_flat_guide_is_the_straight_line_between_its_ends() {
        let seg = Segment {
            start: [3.0, 2.0],
            end: [3.0, 12.0],
            rows: 20,
            cols: 20,
            side: 1.0,
        };
        let g = Flat.guide(&seg);
        assert_eq!(g.len(), 11);
        assert!(g.iter().all(|c| c[0] == 3));
    }

    #[test]
    fn perpendicular_points_left_of_the_direction() {
        // Heading east (+col), left is north (-row).
        let seg = Segment {
            start: [10.0, 0.0],
            end: [10.0, 10.0],
            rows: 20,
            cols: 20,
            side: 1.0,
        };
        let p = seg.point(0.5, 2.0);
        assert_eq!(p, [8.0, 5.0]);
    }

    #[test]
    fn guides_are_clamped_to_the_level() {
        let seg = Segment {
            start: [0.0, 0.0],
            end: [0.0, 10.0],
            rows: 5,
            cols: 11,
            side: 1.0,
        };
        struct Big;
        impl RouteDescriptor for Big {
            fn offset(&self, _t: f64, _s: &Segment) -> f64 {
                50.0
            }
        }
        for c in Big.guide(&seg) {
            assert!((0..5).contains(&c[0]) && (0..11).contains(&c[1]));
        }
    }
}
