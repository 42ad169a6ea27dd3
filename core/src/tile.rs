//! Tiles: what each occupied cell becomes, classified from its four neighbours.
//!
//! Each kind has a base orientation (the DARPA SubT tiles' own): a dead end opens east, a
//! straight east and west, a corner east and south, a T-junction east, north and south, an
//! intersection every way. A tile's rotation is the number of quarter turns counter-clockwise
//! (seen from above) that take the base orientation to the cell's openings.

use serde::{Deserialize, Serialize};

use crate::grid::{Cell, Direction, Occupancy, Openings, rotate_openings};

/// What a tile is, in the paper's and the robotics user's words.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TileKind {
    /// One opening.
    DeadEnd,
    /// Two opposite openings.
    Straight,
    /// Two adjacent openings.
    Corner,
    /// Three openings.
    TJunction,
    /// Four openings.
    Intersection,
    /// A dead end whose closed top leads up a shaft to the level above.
    ShaftUp,
    /// A dead end where the shaft from the level below arrives.
    ShaftLanding,
}

impl TileKind {
    /// All kinds, in the order of their spatial codes.
    pub const ALL: [TileKind; 7] = [
        TileKind::DeadEnd,
        TileKind::Straight,
        TileKind::Corner,
        TileKind::TJunction,
        TileKind::Intersection,
        TileKind::ShaftUp,
        TileKind::ShaftLanding,
    ];

    /// The original SubTGraph's spatial code (0 is reserved for empty cells).
    pub const fn spatial_code(self) -> u8 {
        match self {
            TileKind::DeadEnd => 1,
            TileKind::Straight => 2,
            TileKind::Corner => 3,
            TileKind::TJunction => 4,
            TileKind::Intersection => 5,
            TileKind::ShaftUp => 11,
            TileKind::ShaftLanding => 111,
        }
    }

    /// The kind with this spatial code, if any.
    pub fn from_spatial_code(code: u8) -> Option<TileKind> {
        TileKind::ALL.into_iter().find(|k| k.spatial_code() == code)
    }

    /// The openings of the base orientation (rotation 0).
    pub const fn base_openings(self) -> Openings {
        use Direction::*;
        match self {
            TileKind::DeadEnd | TileKind::ShaftUp | TileKind::ShaftLanding => East.bit(),
            TileKind::Straight => East.bit() | West.bit(),
            TileKind::Corner => East.bit() | South.bit(),
            TileKind::TJunction => East.bit() | North.bit() | South.bit(),
            TileKind::Intersection => 0b1111,
        }
    }

    /// The kebab-case name used in files (`dead-end`, `t-junction`, ...).
    pub const fn name(self) -> &'static str {
        match self {
            TileKind::DeadEnd => "dead-end",
            TileKind::Straight => "straight",
            TileKind::Corner => "corner",
            TileKind::TJunction => "t-junction",
            TileKind::Intersection => "intersection",
            TileKind::ShaftUp => "shaft-up",
            TileKind::ShaftLanding => "shaft-landing",
        }
    }

    /// Whether this kind is a node of the topological graph (anything but a corridor piece).
    pub const fn is_node(self) -> bool {
        !matches!(self, TileKind::Straight | TileKind::Corner)
    }
}

/// A classified tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tile {
    /// What the tile is.
    pub kind: TileKind,
    /// Quarter turns counter-clockwise from the kind's base orientation.
    pub rotation: u8,
    /// The directions the tile opens to (see [`Direction::bit`]).
    pub openings: Openings,
}

/// The kind and rotation of a cell with these openings, or `None` for an isolated cell (no
/// openings), which has no tile shape.
pub fn classify_openings(openings: Openings) -> Option<Tile> {
    let kind = match openings.count_ones() {
        1 => TileKind::DeadEnd,
        2 if openings == 0b0101 || openings == 0b1010 => TileKind::Straight,
        2 => TileKind::Corner,
        3 => TileKind::TJunction,
        4 => TileKind::Intersection,
        _ => return None,
    };
    let rotation = (0..4)
        .find(|&q| rotate_openings(kind.base_openings(), q) == openings)
        .expect("every non-empty mask is a rotation of its kind's base");
    Some(Tile {
        kind,
        rotation,
        openings,
    })
}

/// Classifies one occupied cell from its neighbours. An occupied cell with no neighbour (a lone
/// cell) is reported as a dead end facing east so that every occupied cell gets a tile.
pub fn classify_cell(occupancy: &Occupancy, cell: Cell) -> Tile {
    classify_openings(occupancy.openings(cell)).unwrap_or(Tile {
        kind: TileKind::DeadEnd,
        rotation: 0,
        openings: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mask_classifies_to_its_base_rotated() {
        for mask in 1u8..16 {
            let t = classify_openings(mask).unwrap();
            assert_eq!(rotate_openings(t.kind.base_openings(), t.rotation), mask);
        }
        assert!(classify_openings(0).is_none());
    }

    #[test]
    fn kinds_follow_the_paper() {
        use Direction::*;
        let k = |m| classify_openings(m).unwrap().kind;
        assert_eq!(k(North.bit()), TileKind::DeadEnd);
        assert_eq!(k(North.bit() | South.bit()), TileKind::Straight);
        assert_eq!(k(North.bit() | East.bit()), TileKind::Corner);
        assert_eq!(k(0b0111), TileKind::TJunction);
        assert_eq!(k(0b1111), TileKind::Intersection);
        // A straight running north-south is the base turned a quarter.
        assert_eq!(classify_openings(0b1010).unwrap().rotation, 1);
    }

    #[test]
    fn spatial_codes_round_trip() {
        for k in TileKind::ALL {
            assert_eq!(TileKind::from_spatial_code(k.spatial_code()), Some(k));
        }
        assert_eq!(TileKind::from_spatial_code(0), None);
        assert_eq!(TileKind::from_spatial_code(6), None);
    }
}
