//! A block of the world lattice, what the marching tetrahedra mesh ([`crate::marching`]) and
//! the small pieces they drop are found in ([`crate::islands`]): a leaf, so neither of the two
//! names the other for it.

/// A block of the world lattice: `cubes` cubes from integer lattice point `origin`, spacing
/// `h` metres.
#[derive(Clone, Copy, Debug)]
pub struct Block {
    /// Lattice index of the block's lowest corner.
    pub origin: [i64; 3],
    /// Cubes along x, y, z.
    pub cubes: [usize; 3],
    /// Lattice spacing in metres.
    pub h: f64,
}
