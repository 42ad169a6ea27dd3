//! Building the hierarchy: a binary tree by the binned surface area heuristic, then collapsed
//! into a four-wide tree whose nodes hold their children's boxes axis by axis, so one node's
//! four box tests are a handful of vector instructions.

use rayon::prelude::*;

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
pub(super) struct Node {
    pub(super) lo: [f32; 3],
    /// Interior: the first of the two children; leaf: the first triangle.
    pub(super) index: u32,
    pub(super) hi: [f32; 3],
    /// Leaf: how many triangles (at least one); interior: 0.
    pub(super) count: u32,
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
pub(super) struct Aabb {
    pub(super) lo: [f32; 3],
    pub(super) hi: [f32; 3],
}

impl Aabb {
    pub(super) const EMPTY: Aabb = Aabb {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    // Plain compares rather than `f32::min`/`max`, whose NaN rules cost instructions on
    // every item of every level: no coordinate is NaN.
    pub(super) fn grow(&mut self, p: [f32; 3]) {
        for (k, &v) in p.iter().enumerate() {
            self.lo[k] = if v < self.lo[k] { v } else { self.lo[k] };
            self.hi[k] = if v > self.hi[k] { v } else { self.hi[k] };
        }
    }

    pub(super) fn merge(&mut self, b: &Aabb) {
        for k in 0..3 {
            self.lo[k] = if b.lo[k] < self.lo[k] {
                b.lo[k]
            } else {
                self.lo[k]
            };
            self.hi[k] = if b.hi[k] > self.hi[k] {
                b.hi[k]
            } else {
                self.hi[k]
            };
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

/// Items at and above which a node's two subtrees are built on two threads (the right one
/// into nodes of its own, moved in after the left one's): the same tree as one thread
/// builds, node for node.
const PARALLEL_MIN: usize = 1 << 15;

/// The four-wide tree over `mesh` and the order its triangles are stored in (mesh indices).
pub(super) fn tree(mesh: &Mesh) -> (Vec<Node4>, Vec<u32>) {
    tree_with(mesh, PARALLEL_MIN)
}

/// Every triangle of `mesh` as the builders see it, in mesh order.
fn items_of(mesh: &Mesh) -> Vec<Item> {
    mesh.triangles
        .par_iter()
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
        .collect()
}

/// [`tree`], with subtrees of at least `parallel_min` items built on two threads.
pub(super) fn tree_with(mesh: &Mesh, parallel_min: usize) -> (Vec<Node4>, Vec<u32>) {
    let mut items = items_of(mesh);
    if items.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let builder = Builder { parallel_min };
    let nodes = builder.subtree(&mut items, 0, 0, None);
    let order = items.iter().map(|it| it.id).collect();
    (widen(&nodes), order)
}

/// The four-wide tree of binary tree `nodes` (its root first).
pub(super) fn widen(nodes: &[Node]) -> Vec<Node4> {
    let mut wide = Vec::with_capacity(nodes.len() / 3 + 1);
    wide.push(Node4::EMPTY);
    if nodes[0].count > 0 {
        // A tree of one leaf: a root with that one child.
        wide[0].set(0, &nodes[0], nodes[0].index, nodes[0].count);
    } else {
        collapse(nodes, 0, &mut wide, 0);
    }
    wide
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

/// A node's box and the box of its triangles' centres.
type Boxes = (Aabb, Aabb);

/// How the binary tree is built.
struct Builder {
    parallel_min: usize,
}

pub(super) const EMPTY_NODE: Node = Node {
    lo: [0.0; 3],
    index: 0,
    hi: [0.0; 3],
    count: 0,
};

impl Builder {
    /// The binary tree over `items` (the triangles `offset..` of the whole order) as nodes of
    /// its own, its root first; `boxes` when the caller knows them.
    fn subtree(
        &self,
        items: &mut [Item],
        offset: usize,
        depth: usize,
        boxes: Option<Boxes>,
    ) -> Vec<Node> {
        let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1);
        nodes.push(EMPTY_NODE);
        self.build(&mut nodes, 0, items, offset, depth, boxes);
        nodes
    }

    /// Builds node `at` (at `depth`) over `items` (the triangles `offset..` of the whole
    /// order), appending its descendants to `nodes`.
    fn build(
        &self,
        nodes: &mut Vec<Node>,
        at: usize,
        items: &mut [Item],
        offset: usize,
        depth: usize,
        boxes: Option<Boxes>,
    ) {
        let (bounds, centres) = boxes.unwrap_or_else(|| boxes_of(items));
        let count = items.len();
        let leaf = |nodes: &mut Vec<Node>| {
            nodes[at] = Node {
                lo: bounds.lo,
                index: offset as u32,
                hi: bounds.hi,
                count: count as u32,
            };
        };
        if count <= LEAF_SIZE {
            return leaf(nodes);
        }
        let split = if depth < MEDIAN_DEPTH {
            best_split(items, &centres, bounds.half_area(), count)
        } else {
            None
        };
        let Some(split) = split else {
            // No split beats a leaf of a few triangles; or the centres are all one point, or
            // the tree is deep (a sliver of many triangles): halves along the longest axis of
            // the centres, which bounds the depth by MEDIAN_DEPTH + log2(triangles).
            if count <= 4 * LEAF_SIZE && depth < MEDIAN_DEPTH {
                return leaf(nodes);
            }
            let axis = (0..3)
                .max_by(|&a, &b| {
                    (centres.hi[a] - centres.lo[a]).total_cmp(&(centres.hi[b] - centres.lo[b]))
                })
                .unwrap_or(0);
            let mid = count / 2;
            items.select_nth_unstable_by(mid, |p, q| {
                p.centre[axis]
                    .total_cmp(&q.centre[axis])
                    .then(p.id.cmp(&q.id))
            });
            return self.children(nodes, at, bounds, items, offset, mid, depth, [None, None]);
        };
        let (lo, extent) = (
            centres.lo[split.axis],
            centres.hi[split.axis] - centres.lo[split.axis],
        );
        let scale = BINS as f32 / extent;
        // Partitioned in one pass that also finds the two sides' boxes.
        let mut mid = 0;
        let mut sides = [(Aabb::EMPTY, Aabb::EMPTY); 2];
        for i in 0..count {
            let it = items[i];
            let left = bin_of(it.centre[split.axis], lo, scale) < split.bin;
            let side = &mut sides[usize::from(!left)];
            side.0.merge(&it.bounds);
            side.1.grow(it.centre);
            if left {
                items.swap(i, mid);
                mid += 1;
            }
        }
        let known = if mid == 0 || mid == count {
            mid = count / 2;
            [None, None]
        } else {
            sides.map(Some)
        };
        self.children(nodes, at, bounds, items, offset, mid, depth, known);
    }

    /// Makes node `at` an interior node over `items` split at `mid`, and builds its two
    /// children (on two threads when there are enough items).
    #[allow(clippy::too_many_arguments)]
    fn children(
        &self,
        nodes: &mut Vec<Node>,
        at: usize,
        bounds: Aabb,
        items: &mut [Item],
        offset: usize,
        mid: usize,
        depth: usize,
        known: [Option<Boxes>; 2],
    ) {
        let first = nodes.len();
        nodes.push(EMPTY_NODE);
        nodes.push(EMPTY_NODE);
        nodes[at] = Node {
            lo: bounds.lo,
            index: first as u32,
            hi: bounds.hi,
            count: 0,
        };
        let count = items.len();
        let (left, right) = items.split_at_mut(mid);
        if count >= self.parallel_min {
            // The left subtree goes straight into `nodes`, as on one thread; the right one
            // into nodes of its own, moved in after it.
            let ((), b) = rayon::join(
                || self.build(nodes, first, left, offset, depth + 1, known[0]),
                || self.subtree(right, offset + mid, depth + 1, known[1]),
            );
            graft(nodes, first + 1, &b);
        } else {
            self.build(nodes, first, left, offset, depth + 1, known[0]);
            self.build(nodes, first + 1, right, offset + mid, depth + 1, known[1]);
        }
    }
}

/// Puts a subtree built apart (`b`, its root first) in as the child at `at`, its other
/// nodes appended: the nodes one thread would have made, in the same order.
fn graft(nodes: &mut Vec<Node>, at: usize, b: &[Node]) {
    let base = nodes.len();
    let moved = |n: &Node| {
        if n.count > 0 {
            return *n;
        }
        // Its root becomes `at`, its other nodes follow the ones already there.
        let index = match n.index {
            0 => at,
            i => base + i as usize - 1,
        };
        Node {
            index: index as u32,
            ..*n
        }
    };
    let root = moved(&b[0]);
    nodes[at] = root;
    nodes.extend(b[1..].iter().map(moved));
}

/// The box of `items` and the box of their centres.
fn boxes_of(items: &[Item]) -> Boxes {
    let mut bounds = Aabb::EMPTY;
    let mut centres = Aabb::EMPTY;
    for it in items {
        bounds.merge(&it.bounds);
        centres.grow(it.centre);
    }
    (bounds, centres)
}

fn bin_of(c: f32, lo: f32, scale: f32) -> usize {
    (((c - lo) * scale) as usize).min(BINS - 1)
}

/// A split by the surface area heuristic: items whose centre falls in a bin below `bin`
/// along `axis` go left.
struct Split {
    axis: usize,
    bin: usize,
}

/// One axis's bins: each bin's box and its count.
#[derive(Clone, Copy)]
struct Bins {
    boxes: [Aabb; BINS],
    counts: [usize; BINS],
}

/// The split with the least surface area heuristic cost, if it is cheaper than a leaf. The
/// items are binned along the three axes in one pass.
fn best_split(items: &[Item], centres: &Aabb, area: f32, count: usize) -> Option<Split> {
    let empty = Bins {
        boxes: [Aabb::EMPTY; BINS],
        counts: [0; BINS],
    };
    let mut bins = [empty; 3];
    // Zero or NaN extent: nothing to split along that axis.
    let extent = [0, 1, 2].map(|k| centres.hi[k] - centres.lo[k]);
    let live = extent.map(|e| !e.is_nan() && e > 0.0);
    let scale = extent.map(|e| BINS as f32 / e);
    for it in items {
        for axis in 0..3 {
            if live[axis] {
                let b = bin_of(it.centre[axis], centres.lo[axis], scale[axis]);
                let bins = &mut bins[axis];
                bins.boxes[b].merge(&it.bounds);
                bins.counts[b] += 1;
            }
        }
    }
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if !live[axis] {
            continue;
        }
        let Bins { boxes, counts, .. } = &bins[axis];
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
    let (cost, axis, bin) = best?;
    // Relative to a leaf: NODE_COST for the extra visit, triangles weighted by area share.
    let split_cost = NODE_COST + cost / area.max(f32::MIN_POSITIVE);
    (split_cost < count as f32 || count > 4 * LEAF_SIZE).then_some(())?;
    Some(Split { axis, bin })
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
