//! Drawing a level's problems from its seeded streams: single-agent start/goal pairs and
//! multi-agent instances, each pair inside one connected group of free cells.

use rayon::prelude::*;
use subtgraph_core::rng::WorldRng;

use super::octile::{Groups, Octile, Search};

/// One start/goal pair and its optimal length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Problem {
    /// Start cell index (row-major, row 0 north).
    pub start: u32,
    /// Goal cell index.
    pub goal: u32,
    /// Optimal octile length, cells.
    pub length: f64,
}

impl Problem {
    /// MovingAI's bucket: the optimal length over 4, rounded down.
    pub fn bucket(&self) -> u64 {
        (self.length / 4.0).floor() as u64
    }
}

/// Tries for a start and goal an agent has not taken before the instance stops short.
const TRIES: usize = 1000;

/// A level's cells that have somewhere to go: free, in a group of two or more.
pub struct Places<'a> {
    map: &'a Octile,
    groups: &'a Groups,
    /// Cells of groups of two or more, row-major.
    starts: Vec<u32>,
}

impl<'a> Places<'a> {
    /// The places of `map`.
    pub fn new(map: &'a Octile, groups: &'a Groups) -> Self {
        let starts = (0..map.free.len() as u32)
            .filter(|&c| {
                let g = groups.of[c as usize];
                g != u32::MAX && groups.cells[g as usize].len() >= 2
            })
            .collect();
        Self {
            map,
            groups,
            starts,
        }
    }

    /// A start uniform over the places and a goal uniform over the rest of its group, neither
    /// among the cells `taken` refuses; `None` after [`TRIES`] draws.
    fn pair(&self, rng: &mut WorldRng, taken: impl Fn(u32, u32) -> bool) -> Option<(u32, u32)> {
        if self.starts.is_empty() {
            return None;
        }
        for _ in 0..TRIES {
            let s = self.starts[rng.below(self.starts.len() as u64) as usize];
            let group = &self.groups.cells[self.groups.of[s as usize] as usize];
            let g = group[rng.below(group.len() as u64) as usize];
            if g != s && !taken(s, g) {
                return Some((s, g));
            }
        }
        None
    }

    /// `count` single-agent problems, sorted by bucket (draw order within one).
    pub fn problems(&self, rng: &mut WorldRng, count: u32) -> Vec<Problem> {
        let pairs: Vec<(u32, u32)> = (0..count)
            .map_while(|_| self.pair(rng, |_, _| false))
            .collect();
        let mut out = self.solve_all(&pairs);
        out.sort_by_key(Problem::bucket);
        out
    }

    /// The optimal length of every pair, in order: on every thread (a length does not depend
    /// on which thread finds it, so the files do not either).
    fn solve_all(&self, pairs: &[(u32, u32)]) -> Vec<Problem> {
        // A chunk per thread: each search's scratch is a whole map's worth of costs.
        let chunk = pairs.len().div_ceil(rayon::current_num_threads()).max(1);
        let solved: Vec<Vec<Problem>> = pairs
            .par_chunks(chunk)
            .map(|part| {
                let mut search = Search::new(self.map);
                part.iter()
                    .map(|&(s, g)| solve(&mut search, s, g))
                    .collect()
            })
            .collect();
        solved.concat()
    }

    /// One multi-agent instance: up to `agents` agents, no two sharing a start or a goal,
    /// in draw order (planners take the first n).
    pub fn instance(&self, rng: &mut WorldRng, agents: u32) -> Vec<Problem> {
        let mut start_taken = vec![false; self.map.free.len()];
        let mut goal_taken = vec![false; self.map.free.len()];
        let mut pairs = Vec::new();
        for _ in 0..agents {
            let Some((s, g)) = self.pair(rng, |s, g| {
                start_taken[s as usize] || goal_taken[g as usize]
            }) else {
                break;
            };
            start_taken[s as usize] = true;
            goal_taken[g as usize] = true;
            pairs.push((s, g));
        }
        self.solve_all(&pairs)
    }
}

fn solve(search: &mut Search<'_>, start: u32, goal: u32) -> Problem {
    let length = search
        .length(start, goal)
        .expect("a start and goal in one group are joined");
    Problem {
        start,
        goal,
        length,
    }
}
