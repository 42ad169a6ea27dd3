//! The quick hierarchy: triangles ordered along a Morton curve and split where their keys'
//! highest differing bit changes (a linear BVH), for a tree asked a few rays per thousand
//! triangles (a mine's bolt rings on its visual surface).
//!
//! Why not the surface area heuristic's builder with its splits replaced by medians: that
//! partitions every level's items again (`select_nth` over 40-byte items, twenty levels
//! deep for the mine's 2.5 M visual triangles) and it cost a tenth of the mine's whole
//! `generate`. Here the order is one radix sort of 30-bit keys, and the tree is the sorted
//! order split by its keys' bits, each node's box merged from its children's: linear after
//! the sort. Casting into it is slower than into the heuristic's tree, which a few thousand
//! rays do not notice. Its depth is at most the keys' 30 bits and the halvings of the
//! largest run of one key, well inside the traversal's stack.

use rayon::prelude::*;

use super::RayCaster;
use super::build::{Aabb, EMPTY_NODE, Node, widen};
use crate::mesh::Mesh;

/// Cells of the Morton grid along each axis (10 bits an axis: a metre's resolution over a
/// kilometre, enough for an order that only needs to keep neighbours together).
const CELLS: u32 = 1 << 10;

/// Triangles a leaf holds at most: four times the heuristic tree's. A few rays test a few
/// more triangles each, and the tree has a quarter of the nodes: over the mine's 2.5 M visual
/// triangles, leaves of four made 150 MB of nodes, more than the triangles themselves.
const LEAF: usize = 4 * super::LEAF_SIZE;

/// The quick hierarchy over every triangle of `mesh`, its triangles' normals left to the
/// hits. The same hierarchy on any number of threads.
pub(super) fn quick(mesh: &Mesh) -> RayCaster {
    let corners = |t: &[u32; 3]| t.map(|v| mesh.positions[v as usize]);
    let centres: Vec<[f32; 3]> = mesh
        .triangles
        .par_iter()
        .map(|t| {
            let mut b = Aabb::EMPTY;
            for p in corners(t) {
                b.grow(p);
            }
            [0, 1, 2].map(|k| 0.5 * (b.lo[k] + b.hi[k]))
        })
        .collect();
    let mut all = Aabb::EMPTY;
    for &c in &centres {
        all.grow(c);
    }
    // Each step's inputs are dropped as soon as it is done: over the mine's 2.5 M visual
    // triangles they are tens of megabytes each.
    let keys: Vec<u32> = centres.par_iter().map(|&c| key(c, &all)).collect();
    drop(centres);
    let ids = radix_order(&keys);
    let sorted: Vec<u32> = ids.iter().map(|&i| keys[i as usize]).collect();
    drop(keys);
    let vertices: Vec<[[f32; 3]; 3]> = ids
        .par_iter()
        .map(|&i| corners(&mesh.triangles[i as usize]))
        .collect();
    // Exactly as many nodes as the tree has: a growing vector would double (and copy) tens
    // of megabytes once it outgrew a guess.
    let mut nodes = Vec::with_capacity(if sorted.is_empty() { 0 } else { count(&sorted) });
    if !vertices.is_empty() {
        nodes.push(EMPTY_NODE);
        split(&mut nodes, 0, &vertices, &sorted, 0);
    }
    drop(sorted);
    RayCaster {
        nodes: if nodes.is_empty() {
            Vec::new()
        } else {
            widen(&nodes)
        },
        vertices,
        ids,
        normals: Vec::new(),
    }
}

/// The Morton key of `p`: its cell in a `CELLS`³ grid over `bounds`, the bits of the three
/// cell coordinates interleaved.
fn key(p: [f32; 3], bounds: &Aabb) -> u32 {
    let mut k = 0;
    for (axis, &x) in p.iter().enumerate() {
        let extent = bounds.hi[axis] - bounds.lo[axis];
        let cell = if extent > 0.0 {
            let c = (x - bounds.lo[axis]) / extent * CELLS as f32;
            // Saturating: the top edge and any rounding past it go in the last cell.
            (c as u32).min(CELLS - 1)
        } else {
            0
        };
        k |= spread(cell) << axis;
    }
    k
}

/// The ten low bits of `x` moved to every third bit.
fn spread(x: u32) -> u32 {
    let mut x = x & 0x3ff;
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    (x | (x << 2)) & 0x0924_9249
}

/// The indices of `keys` in ascending order of key, equal keys in index order (a stable
/// radix sort, three passes of ten bits).
fn radix_order(keys: &[u32]) -> Vec<u32> {
    const BITS: u32 = 10;
    let mut order: Vec<u32> = (0..keys.len() as u32).collect();
    let mut next = vec![0u32; keys.len()];
    for pass in 0..3 {
        let digit = |i: u32| ((keys[i as usize] >> (pass * BITS)) & ((1 << BITS) - 1)) as usize;
        let mut start = vec![0usize; (1 << BITS) + 1];
        for &i in &order {
            start[digit(i) + 1] += 1;
        }
        for d in 0..1 << BITS {
            start[d + 1] += start[d];
        }
        for &i in &order {
            let d = digit(i);
            next[start[d]] = i;
            start[d] += 1;
        }
        std::mem::swap(&mut order, &mut next);
    }
    order
}

/// Builds binary node `at` over triangles `tris` (the triangles `offset..` of the whole
/// order, `keys` theirs), appending its descendants to `nodes`; returns its box.
///
/// A node splits where its keys' highest differing bit changes (Karras's split), so its
/// children are the two halves of an octree cell and their boxes barely overlap; triangles
/// of one key are split in halves of their count.
fn split(
    nodes: &mut Vec<Node>,
    at: usize,
    tris: &[[[f32; 3]; 3]],
    keys: &[u32],
    offset: usize,
) -> Aabb {
    let (bounds, index, count) = if tris.len() <= LEAF {
        let mut b = Aabb::EMPTY;
        for p in tris.iter().flatten() {
            b.grow(*p);
        }
        (b, offset, tris.len())
    } else {
        let mid = mid_of(keys);
        let child = nodes.len();
        nodes.push(EMPTY_NODE);
        nodes.push(EMPTY_NODE);
        let mut b = split(nodes, child, &tris[..mid], &keys[..mid], offset);
        b.merge(&split(
            nodes,
            child + 1,
            &tris[mid..],
            &keys[mid..],
            offset + mid,
        ));
        (b, child, 0)
    };
    nodes[at] = Node {
        lo: bounds.lo,
        index: index as u32,
        hi: bounds.hi,
        count: count as u32,
    };
    bounds
}

/// Where a node over `keys` (more than a leaf's) splits: the first key with the highest bit
/// in which the range differs set; in halves when they are all one key, or few enough that
/// a split by bit would leave slivers of leaves.
fn mid_of(keys: &[u32]) -> usize {
    let (first, last) = (keys[0], keys[keys.len() - 1]);
    if first == last || keys.len() <= 2 * LEAF {
        keys.len() / 2
    } else {
        let bit = 31 - (first ^ last).leading_zeros();
        keys.partition_point(|&k| (k >> bit) & 1 == 0)
    }
}

/// How many binary nodes [`split`] makes over `keys` (at least one).
fn count(keys: &[u32]) -> usize {
    if keys.len() <= LEAF {
        return 1;
    }
    let mid = mid_of(keys);
    1 + count(&keys[..mid]) + count(&keys[mid..])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_interleave_the_cells_bits() {
        assert_eq!(spread(0b1), 0b1);
        assert_eq!(spread(0b11), 0b1001);
        assert_eq!(spread(0x3ff), 0x0924_9249);
        let b = Aabb {
            lo: [0.0; 3],
            hi: [1024.0; 3],
        };
        // Cell (1, 0, 0) is bit 0, (0, 1, 0) bit 1, (0, 0, 1) bit 2.
        assert_eq!(key([1.5, 0.5, 0.5], &b), 0b001);
        assert_eq!(key([0.5, 1.5, 0.5], &b), 0b010);
        assert_eq!(key([0.5, 0.5, 1.5], &b), 0b100);
        assert_eq!(key([1024.0, 1024.0, 1024.0], &b), (1 << 30) - 1);
    }

    #[test]
    fn the_radix_order_is_a_stable_sort() {
        let mut x = 12345u64;
        let keys: Vec<u32> = (0..5000)
            .map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((x >> 33) as u32) & ((1 << 30) - 1) & 0x3f0f_00ff
            })
            .collect();
        let mut expected: Vec<u32> = (0..keys.len() as u32).collect();
        expected.sort_by_key(|&i| (keys[i as usize], i));
        assert_eq!(radix_order(&keys), expected);
    }
}
