//! `ground_truth/collision_budget.json`: how far the visual surface (`mesh/world.obj`, what
//! sensors and cameras see) lies from the collision surface (`mesh/collision.obj`, what physics
//! and the rest of the ground truth use), per class of surface, written by the exporters'
//! `CollisionBudget`.
//!
//! `S` is the type of the fixed texts: `&'static str` where the writer fills them in,
//! `String` (the default) where a file is read.

use serde::{Deserialize, Serialize};

use crate::{Document, SchemaError, finite};

/// `ground_truth/collision_budget.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CollisionBudget<S = String> {
    /// [`CollisionBudget::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The world's seed.
    pub seed: u64,
    /// Units, in words.
    pub units: S,
    /// How the distances were measured, in words.
    pub method: S,
    /// How the points are classed, in words.
    pub classes_note: S,
    /// Points drawn on the visual surface.
    pub samples: usize,
    /// The visual surface's area, square metres.
    pub visual_area_m2: f64,
    /// Triangles of the visual surface.
    pub visual_triangles: usize,
    /// Triangles of the collision surface.
    pub collision_triangles: usize,
    /// Per class: the points in it and their distances.
    pub classes: Classes,
}

/// The classes of [`CollisionBudget`], each the distances of its points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Classes {
    /// Floors within 1 m of a graph edge's polyline: what a robot drives on.
    pub floor_by_routes: Distances,
    /// Every floor (facing within 45 degrees of up).
    pub floor: Distances,
    /// Facing neither up nor down.
    pub walls: Distances,
    /// Facing within 45 degrees of down.
    pub roof: Distances,
    /// Every point but `floor_by_routes`.
    pub elsewhere: Distances,
}

/// The distances of one class's points to the collision surface, metres (all `0` for a class
/// with no point).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Distances {
    /// Points in the class.
    pub count: usize,
    /// The median.
    pub median_m: f64,
    /// The 90th percentile.
    pub p90_m: f64,
    /// The 99th percentile.
    pub p99_m: f64,
    /// The largest.
    pub max_m: f64,
}

impl Classes {
    /// The classes with their names, in file order.
    pub fn named(&self) -> [(&'static str, &Distances); 5] {
        [
            ("floor_by_routes", &self.floor_by_routes),
            ("floor", &self.floor),
            ("walls", &self.walls),
            ("roof", &self.roof),
            ("elsewhere", &self.elsewhere),
        ]
    }
}

impl Document for CollisionBudget {
    const PATH: &'static str = "ground_truth/collision_budget.json";
    const FORMAT: &'static str = "subtgraph-collision-budget/1";

    fn format(&self) -> &str {
        &self.format
    }

    fn check(&self) -> Result<(), SchemaError> {
        finite::<Self>(|| "visual_area_m2".into(), &[self.visual_area_m2])?;
        for (name, d) in self.classes.named() {
            let v = [d.median_m, d.p90_m, d.p99_m, d.max_m];
            finite::<Self>(|| format!("classes.{name}"), &v)?;
            if v.iter().any(|&x| x < 0.0) || v.windows(2).any(|w| w[0] > w[1]) {
                return Err(SchemaError::invalid::<Self>(format!(
                    "classes.{name}: distances {v:?} must be at least 0 and rise from the \
                     median to the largest"
                )));
            }
        }
        Ok(())
    }
}
