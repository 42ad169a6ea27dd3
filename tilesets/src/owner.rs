//! The field at a lattice point outside a tile's block, as the tile whose block owns the
//! point computes it: what [`crate::islands`] reads to follow a small piece across a face.
//!
//! Each tile evaluates the world's field with its own [`LocalField`] (its cell's 3 x 3
//! neighbourhood on three levels), which is exact inside its block. A point a few lattice
//! steps beyond it is computed here with the owning tile's field, built the way that tile
//! builds it, so the two tiles agree bit for bit on every point either reads. A point no
//! block owns (beyond an unoccupied cell) is meshed by no tile; the asking tile's own field
//! answers for it.

use std::cell::RefCell;
use std::collections::HashMap;

use subtgraph_core::Layout;
use subtgraph_core::grid::Cell;

use crate::field::LocalField;
use crate::marching::Block;
use crate::passage::{Levels, Passage, Profile};

/// The owners of lattice points around one tile, and their fields, built when first read.
pub struct Owners<'a> {
    world: &'a Layout,
    passage: &'a Passage,
    profile: &'a dyn Profile,
    levels: Levels,
    /// The visual lattice's spacing, which every tile builds its field with.
    fine: f64,
    /// The block of a cell on this lattice.
    block: &'a dyn Fn(Cell) -> Block,
    /// The asking tile's own field.
    own: &'a LocalField<'a>,
    fields: RefCell<HashMap<Cell, LocalField<'a>>>,
}

impl<'a> Owners<'a> {
    /// Owners on the lattice whose blocks `block` gives, for the tile whose field is `own`.
    pub fn new(
        world: &'a Layout,
        passage: &'a Passage,
        profile: &'a dyn Profile,
        levels: Levels,
        fine: f64,
        block: &'a dyn Fn(Cell) -> Block,
        own: &'a LocalField<'a>,
    ) -> Self {
        Self {
            world,
            passage,
            profile,
            levels,
            fine,
            block,
            own,
            fields: RefCell::new(HashMap::new()),
        }
    }

    /// The occupied cell whose block holds lattice point `p` (the first in raster order of
    /// the candidates, when `p` lies on a face two blocks share: they compute it alike).
    fn owner(&self, p: [i64; 3], h: f64) -> Option<Cell> {
        let occ = &self.world.occupancy;
        let n = (self.world.resolved.tile_pitch / h).round() as i64;
        let holds = |b: Block| {
            (0..3).all(|d| p[d] >= b.origin[d] && p[d] <= b.origin[d] + b.cubes[d] as i64)
        };
        for level in 0..occ.levels() {
            let (lo, hi) = (
                self.levels.block_z(level).0,
                self.levels.block_z(level + 1).0,
            );
            let z = p[2] as f64 * h;
            if z < lo - h || z > hi + h {
                continue;
            }
            let off = self.world.level_offsets[level];
            let col = (p[0] + n / 2).div_euclid(n) - off[1];
            let row = occ.rows() as i64 - 1 - (p[1] + n / 2).div_euclid(n) - off[0];
            for r in row - 1..=row + 1 {
                for c in col - 1..=col + 1 {
                    if r < 0 || c < 0 || r as usize >= occ.rows() || c as usize >= occ.cols() {
                        continue;
                    }
                    let cell = Cell::new(level, r as usize, c as usize);
                    if self.world.tiles.get(cell).is_some() && holds((self.block)(cell)) {
                        return Some(cell);
                    }
                }
            }
        }
        None
    }

    /// The field at global lattice point `p` (spacing `h`), as its owner computes it.
    pub fn value(&self, p: [i64; 3], h: f64) -> f64 {
        let q = p.map(|i| i as f64 * h);
        let v = match self.owner(p, h) {
            Some(cell) => {
                let mut fields = self.fields.borrow_mut();
                let f = fields.entry(cell).or_insert_with(|| {
                    LocalField::around(
                        self.world,
                        cell,
                        self.passage,
                        self.profile,
                        self.levels,
                        self.fine,
                    )
                });
                f.at_column(q, &f.column(q[0], q[1])).0
            }
            None => self.own.at_column(q, &self.own.column(q[0], q[1])).0,
        };
        // As the marching does: exactly on the surface counts as solid.
        if v == 0.0 { 1e-12 } else { v }
    }
}
