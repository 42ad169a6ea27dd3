//! Matching detected nodes to graph nodes within a radius, closest pairs first, each once
//! (issue 37, item 10), without keeping every pair: a map whose every pixel is a detection,
//! scored with a radius that covers the level, made millions of detections times the level's
//! nodes of pairs (an abort under 3 GB).
//!
//! Why keeping few pairs gives the same matches: the pairs are taken in the order of their
//! distance (then detection, then node). When graph node `j` is matched to detection `i`,
//! every detection before `i` in `j`'s own order was already taken, each by another graph
//! node: at most `t - 1` of them for `t` graph nodes. So `i` is among the `t` first detections
//! of `j`'s order, and the pairs outside those lists are never taken: leaving them out changes
//! no match. The lists hold at most `t` pairs per graph node, and no more than the pairs
//! within the radius; they are refused past the memory budget, with the radius to change.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::Error;

/// A candidate `(distance, detection)`, ordered by distance, then detection.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Candidate(f64, usize);

impl Eq for Candidate {}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0).then(self.1.cmp(&other.1))
    }
}

/// Bytes one kept candidate takes (in its heap, then in the sorted list).
const CANDIDATE_BYTES: u64 = 40;

/// Matches detections `found` to graph nodes `truth` within `radius`, closest pairs first,
/// each once: the matched `(detection, node, distance)`, in the order they were matched. The
/// candidates kept may take at most `budget` bytes.
pub fn matches(
    found: &[[f64; 2]],
    truth: &[[f64; 2]],
    radius: f64,
    budget: u64,
) -> Result<Vec<(usize, usize, f64)>, Error> {
    let t = truth.len();
    let mut near: Vec<BinaryHeap<Candidate>> = vec![BinaryHeap::new(); t];
    let mut kept: u64 = 0;
    for (i, a) in found.iter().enumerate() {
        for (j, b) in truth.iter().enumerate() {
            let d = (a[0] - b[0]).hypot(a[1] - b[1]);
            if d > radius {
                continue;
            }
            let c = Candidate(d, i);
            let heap = &mut near[j];
            if heap.len() < t {
                heap.push(c);
                kept += 1;
                if kept.saturating_mul(CANDIDATE_BYTES) > budget {
                    return Err(Error::TooLarge(format!(
                        "matching {} detected nodes to the level's {t} graph nodes within --node-radius {radius} m keeps more than {} of candidate pairs, more than this machine's memory allows (--max-memory's default); give a smaller --node-radius (the default is half the tile pitch), or a segmentation with fewer node regions",
                        found.len(),
                        subtgraph_core::budget::Bytes(budget)
                    )));
                }
            } else if heap.peek().is_some_and(|worst| c < *worst) {
                heap.pop();
                heap.push(c);
            }
        }
    }
    let mut pairs: Vec<(usize, usize, f64)> = near
        .into_iter()
        .enumerate()
        .flat_map(|(j, heap)| heap.into_iter().map(move |Candidate(d, i)| (i, j, d)))
        .collect();
    pairs.sort_by(|a, b| a.2.total_cmp(&b.2).then((a.0, a.1).cmp(&(b.0, b.1))));
    let (mut used_a, mut used_b) = (vec![false; found.len()], vec![false; t]);
    Ok(pairs
        .into_iter()
        .filter(|&(i, j, _)| {
            let free = !used_a[i] && !used_b[j];
            if free {
                used_a[i] = true;
                used_b[j] = true;
            }
            free
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pair, sorted, taken greedily: the definition.
    fn every_pair(found: &[[f64; 2]], truth: &[[f64; 2]], radius: f64) -> Vec<(usize, usize, f64)> {
        let mut pairs = Vec::new();
        for (i, a) in found.iter().enumerate() {
            for (j, b) in truth.iter().enumerate() {
                let d = (a[0] - b[0]).hypot(a[1] - b[1]);
                if d <= radius {
                    pairs.push((i, j, d));
                }
            }
        }
        pairs.sort_by(|a, b| a.2.total_cmp(&b.2).then((a.0, a.1).cmp(&(b.0, b.1))));
        let (mut ua, mut ub) = (vec![false; found.len()], vec![false; truth.len()]);
        pairs.retain(|&(i, j, _)| {
            let free = !ua[i] && !ub[j];
            if free {
                ua[i] = true;
                ub[j] = true;
            }
            free
        });
        pairs
    }

    #[test]
    fn the_kept_candidates_match_as_every_pair_does() {
        // splitmix64 points on a small integer lattice, so that many distances tie.
        let mut s = 7u64;
        let mut next = || {
            s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) % 12) as f64
        };
        for case in 0..300 {
            let (d, t) = (case % 17, case % 7);
            let found: Vec<[f64; 2]> = (0..d).map(|_| [next(), next()]).collect();
            let truth: Vec<[f64; 2]> = (0..t).map(|_| [next(), next()]).collect();
            for radius in [0.0, 1.5, 4.0, 100.0] {
                assert_eq!(
                    matches(&found, &truth, radius, u64::MAX).unwrap(),
                    every_pair(&found, &truth, radius),
                    "case {case}, radius {radius}"
                );
            }
        }
        let e = matches(&[[0.0; 2]; 100], &[[0.0; 2]; 100], 1.0, 1000).unwrap_err();
        assert!(e.to_string().contains("--node-radius"), "{e}");
    }
}
