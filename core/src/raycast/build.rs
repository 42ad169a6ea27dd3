//! Building the hierarchy: a binary tree by the binned surface area heuristic, then collapsed
//! into a four-wide tree whose nodes hold their children's boxes axis by axis, so one node's
//! four box tests are a handful of vector instructions.

use super::{LEAF_SIZE, Node4};
use crate::mesh::Mesh;

/// Depth from which nodes are split in halves rather than by the heuristic, so the binary tree
/// is at most `MEDIAN_DEPTH` + 32 deep and a traversal's stack cannot overflow.
pub(super) const MEDIAN_DEPTH: usize = 64;
/// Bins per axis of the surface area heuristic.
const BINS: usize = 16;
/// What visiting a node costs against testing one triangle, in the heuristic.
const NODE_COST: f32 = 1.0;

/// A node of the binary tree: a box and either two children (stored side by side at `index`)
/// or triangles.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: [f32; 3],
    /// Interior: the first of the two children; leaf: the first triangle.
    index: u32,
    hi: [f32; 3],
    /// Leaf: how many triangles (at least one); interior: 0.
    count: u32,
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
pub(super) struct Aabb {
    lo: [f32; 3],
    hi: [f32; 3],
}

impl Aabb {
    pub(super) const EMPTY: Aabb = Aabb {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    pub(super) fn grow(&mut self, p: [f32; 3]) {
        for (k, &v) in p.iter().enumerate() {
            self.lo[k] = self.lo[k].min(v);
            self.hi[k] = self.hi[k].max(v);
        }
    }

    fn merge(&mut self, b: &Aabb) {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(b.lo[k]);
            self.hi[k] = self.hi[k].max(b.hi[k]);
        }
    }

    fn half_area(&self) -> f32 {
        let d = [
            self.hi[0] - self.lo[0],
            self.hi[1] - self.lo[1],
            self.hi[2] - self.lo[2],
        ];
        if d[0] < 0.0 {
            return 0.0;
        }
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }
}

/// What the builder knows of one triangle.
#[derive(Clone, Copy)]
struct Item {
    bounds: Aabb,
    centre: [f32; 3],
    id: u32,
}

/// The four-wide tree over `mesh` and the order its triangles are stored in (mesh indices).
pub(super) fn tree(mesh: &Mesh) -> (Vec<Node4>, Vec<u32>) {
    let mut items: Vec<Item> = mesh
        .triangles
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let mut bounds = Aabb::EMPTY;
            for &v in t {
                bounds.grow(mesh.positions[v as usize]);
            }
            let centre = [0, 1, 2].map(|k| 0.5 * (bounds.lo[k] + bounds.hi[k]));
            Item {
                bounds,
                centre,
                id: i as u32,
            }
        })
        .collect();
    if items.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let empty = Node {
        lo: [0.0; 3],
        index: 0,
        hi: [0.0; 3],
        count: 0,
    };
    let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1);
    nodes.push(empty);
    let n = items.len();
    build(&mut nodes, 0, &mut items, 0, n, 0);
    let order = items.iter().map(|it| it.id).collect();
    let mut wide = Vec::with_capacity(nodes.len() / 3 + 1);
    wide.push(Node4::EMPTY);
    if nodes[0].count > 0 {
        // A tree of one leaf: a root with that one child.
        wide[0].set(0, &nodes[0], nodes[0].index, nodes[0].count);
    } else {
        collapse(&nodes, 0, &mut wide, 0);
    }
    (wide, order)
}

/// Fills four-wide node `at` from binary node `node` (an interior one): its children, each
/// replaced by its own two children when it has them, children kept in order.
fn collapse(nodes: &[Node], node: usize, wide: &mut Vec<Node4>, at: usize) {
    let n = nodes[node];
    let mut kids: Vec<usize> = Vec::with_capacity(4);
    for c in [n.index as usize, n.index as usize + 1] {
        if nodes[c].count > 0 {
            kids.push(c);
        } else {
            kids.extend([nodes[c].index as usize, nodes[c].index as usize + 1]);
        }
    }
    for (slot, &c) in kids.iter().enumerate() {
        let child = nodes[c];
        if child.count > 0 {
            wide[at].set(slot, &child, child.index, child.count);
        } else {
            let index = wide.len();
            wide.push(Node4::EMPTY);
            wide[at].set(slot, &child, index as u32, 0);
            collapse(nodes, c, wide, index);
        }
    }
}

/// Builds node `at` (at `depth`) over `items[start..end]`, appending its descendants to
/// `nodes`.
fn build(
    nodes: &mut Vec<Node>,
    at: usize,
    items: &mut [Item],
    start: usize,
    end: usize,
    depth: usize,
) {
    let mut bounds = Aabb::EMPTY;
    let mut centres = Aabb::EMPTY;
    for it in &items[start..end] {
        bounds.merge(&it.bounds);
        centres.grow(it.centre);
    }
    let count = end - start;
    let leaf = |nodes: &mut Vec<Node>| {
        nodes[at] = Node {
            lo: bounds.lo,
            index: start as u32,
            hi: bounds.hi,
            count: count as u32,
        };
    };
    if count <= LEAF_SIZE {
        return leaf(nodes);
    }
    let split = if depth < MEDIAN_DEPTH {
        best_split(&items[start..end], &centres, bounds.half_area(), count)
    } else {
        None
    };
    let Some((axis, split)) = split else {
        // No split beats a leaf of a few triangles; or the centres are all one point, or the
        // tree is deep (a sliver of many triangles): halves along the longest axis of the
        // centres, which bounds the depth by MEDIAN_DEPTH + log2(triangles).
        if count <= 4 * LEAF_SIZE && depth < MEDIAN_DEPTH {
            return leaf(nodes);
        }
        let axis = (0..3)
            .max_by(|&a, &b| {
                (centres.hi[a] - centres.lo[a]).total_cmp(&(centres.hi[b] - centres.lo[b]))
            })
            .unwrap_or(0);
        let mid = count / 2;
        items[start..end].select_nth_unstable_by(mid, |p, q| {
            p.centre[axis]
                .total_cmp(&q.centre[axis])
                .then(p.id.cmp(&q.id))
        });
        return children(nodes, at, bounds, items, start, start + mid, end, depth);
    };
    let (lo, extent) = (centres.lo[axis], centres.hi[axis] - centres.lo[axis]);
    let scale = BINS as f32 / extent;
    let mut mid = start;
    for i in start..end {
        if bin_of(items[i].centre[axis], lo, scale) < split {
            items.swap(i, mid);
            mid += 1;
        }
    }
    if mid == start || mid == end {
        mid = start + count / 2;
    }
    children(nodes, at, bounds, items, start, mid, end, depth);
}

#[allow(clippy::too_many_arguments)]
fn children(
    nodes: &mut Vec<Node>,
    at: usize,
    bounds: Aabb,
    items: &mut [Item],
    start: usize,
    mid: usize,
    end: usize,
    depth: usize,
) {
    let first = nodes.len();
    let empty = Node {
        lo: [0.0; 3],
        index: 0,
        hi: [0.0; 3],
        count: 0,
    };
    nodes.push(empty);
    nodes.push(empty);
    nodes[at] = Node {
        lo: bounds.lo,
        index: first as u32,
        hi: bounds.hi,
        count: 0,
    };
    build(nodes, first, items, start, mid, depth + 1);
    build(nodes, first + 1, items, mid, end, depth + 1);
}

fn bin_of(c: f32, lo: f32, scale: f32) -> usize {
    (((c - lo) * scale) as usize).min(BINS - 1)
}

/// The axis and the bin boundary (items in bins below it go left) with the least surface area
/// heuristic cost, if it is cheaper than a leaf.
fn best_split(items: &[Item], centres: &Aabb, area: f32, count: usize) -> Option<(usize, usize)> {
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        let extent = centres.hi[axis] - centres.lo[axis];
        // Zero or NaN: nothing to split along this axis.
        if extent.is_nan() || extent <= 0.0 {
            continue;
        }
        let scale = BINS as f32 / extent;
        let mut boxes = [Aabb::EMPTY; BINS];
        let mut counts = [0usize; BINS];
        for it in items {
            let b = bin_of(it.centre[axis], centres.lo[axis], scale);
            boxes[b].merge(&it.bounds);
            counts[b] += 1;
        }
        // Costs of every split from the right, then swept from the left.
        let mut right_area = [0f32; BINS];
        let mut right_count = [0usize; BINS];
        let mut acc = Aabb::EMPTY;
        let mut n = 0;
        for b in (1..BINS).rev() {
            acc.merge(&boxes[b]);
            n += counts[b];
            right_area[b] = acc.half_area();
            right_count[b] = n;
        }
        let mut acc = Aabb::EMPTY;
        let mut n = 0;
        for b in 1..BINS {
            acc.merge(&boxes[b - 1]);
            n += counts[b - 1];
            if n == 0 || right_count[b] == 0 {
                continue;
            }
            let cost = acc.half_area() * n as f32 + right_area[b] * right_count[b] as f32;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, b));
            }
        }
    }
    let (cost, axis, split) = best?;
    // Relative to a leaf: NODE_COST for the extra visit, triangles weighted by area share.
    let split_cost = NODE_COST + cost / area.max(f32::MIN_POSITIVE);
    (split_cost < count as f32 || count > 4 * LEAF_SIZE).then_some((axis, split))
}

/// What has a box a four-wide node can hold.
pub(super) trait Boxed {
    /// Low and high corners.
    fn corners(&self) -> ([f32; 3], [f32; 3]);
}

impl Boxed for Node {
    fn corners(&self) -> ([f32; 3], [f32; 3]) {
        (self.lo, self.hi)
    }
}
