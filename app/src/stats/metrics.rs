//! The paper's variability metrics on occupancy matrices ("Topological Analysis").
//!
//! - IoU (eq. 19): the paper prints `sum(M1 M2) / sum(M1 + M2)`, which divides by the sum of
//!   the two areas, not their union, so two identical worlds score 0.5. We report the true
//!   IoU `|A and B| / |A or B|` everywhere, and the printed formula beside it, labelled as such.
//! - Mirror asymmetry (eqs. 20-22): the IoU of a level with its horizontal mirror (columns
//!   reversed), its vertical mirror (rows reversed), and the mean over its 90, 180 and 270
//!   degree rotations. A rotation of a non-square level is taken on the square of side
//!   max(rows, cols) holding it at the top-left (empty cells added to neither set).

/// A binary level: `rows x cols` cells, row-major, `true` occupied.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Cells, row-major.
    pub cells: Vec<bool>,
}

impl Mask {
    /// A mask from its cells. Panics when the length is not `rows * cols`.
    pub fn new(rows: usize, cols: usize, cells: Vec<bool>) -> Mask {
        assert_eq!(cells.len(), rows * cols, "mask size");
        Mask { rows, cols, cells }
    }

    /// Occupied or not; `false` outside the mask.
    pub fn at(&self, r: usize, c: usize) -> bool {
        r < self.rows && c < self.cols && self.cells[r * self.cols + c]
    }

    /// Number of occupied cells.
    pub fn count(&self) -> usize {
        self.cells.iter().filter(|&&v| v).count()
    }

    fn map(&self, rows: usize, cols: usize, f: impl Fn(usize, usize) -> bool) -> Mask {
        let cells = (0..rows)
            .flat_map(|r| (0..cols).map(move |c| (r, c)))
            .map(|(r, c)| f(r, c))
            .collect();
        Mask { rows, cols, cells }
    }

    /// `H(M)(i, j) = M(i, W - j + 1)`: columns reversed (eq. 20).
    pub fn mirror_horizontal(&self) -> Mask {
        self.map(self.rows, self.cols, |r, c| self.at(r, self.cols - 1 - c))
    }

    /// `V(M)(i, j) = M(H - i + 1, j)`: rows reversed (eq. 21).
    pub fn mirror_vertical(&self) -> Mask {
        self.map(self.rows, self.cols, |r, c| self.at(self.rows - 1 - r, c))
    }

    /// The mask on the square of side max(rows, cols), turned by `quarter_turns` x 90 degrees
    /// counter-clockwise.
    pub fn rotated(&self, quarter_turns: u8) -> Mask {
        let n = self.rows.max(self.cols);
        self.map(n, n, |r, c| match quarter_turns % 4 {
            0 => self.at(r, c),
            1 => self.at(c, n - 1 - r),
            2 => self.at(n - 1 - r, n - 1 - c),
            _ => self.at(n - 1 - c, r),
        })
    }

    /// The top-left `rows x cols` corner (cells outside the mask empty).
    pub fn crop(&self, rows: usize, cols: usize) -> Mask {
        self.map(rows, cols, |r, c| self.at(r, c))
    }
}

/// `(|A and B|, |A|, |B|, |A or B|)` over the cells of the larger extent (cells outside a mask
/// are empty).
fn overlap(a: &Mask, b: &Mask) -> (usize, usize, usize, usize) {
    let (rows, cols) = (a.rows.max(b.rows), a.cols.max(b.cols));
    let (mut both, mut na, mut nb, mut either) = (0, 0, 0, 0);
    for r in 0..rows {
        for c in 0..cols {
            let (x, y) = (a.at(r, c), b.at(r, c));
            both += usize::from(x && y);
            na += usize::from(x);
            nb += usize::from(y);
            either += usize::from(x || y);
        }
    }
    (both, na, nb, either)
}

/// True IoU, `|A and B| / |A or B|`; `None` when both are empty.
pub fn iou(a: &Mask, b: &Mask) -> Option<f64> {
    let (both, _, _, either) = overlap(a, b);
    (either > 0).then(|| both as f64 / either as f64)
}

/// The paper's eq. 19 as printed, `sum(A B) / sum(A + B)` (at most 0.5); `None` when both are
/// empty.
pub fn iou_eq19_as_printed(a: &Mask, b: &Mask) -> Option<f64> {
    let (both, na, nb, _) = overlap(a, b);
    (na + nb > 0).then(|| both as f64 / (na + nb) as f64)
}

/// The mirror asymmetry of one level (eqs. 20-22), each a true IoU.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// With the horizontal mirror.
    pub horizontal: f64,
    /// With the vertical mirror.
    pub vertical: f64,
    /// Mean over the 90, 180 and 270 degree rotations.
    pub rotational: f64,
}

/// Eqs. 20-22 on one level; `None` for an empty level.
pub fn mirror(m: &Mask) -> Option<Mirror> {
    let horizontal = iou(m, &m.mirror_horizontal())?;
    let vertical = iou(m, &m.mirror_vertical())?;
    let square = m.rotated(0);
    let rotational = (1..=3)
        .map(|q| iou(&square, &square.rotated(q)).unwrap_or(0.0))
        .sum::<f64>()
        / 3.0;
    Some(Mirror {
        horizontal,
        vertical,
        rotational,
    })
}

/// A pair's IoU (true and as printed), the bit-packed way: pairwise IoU over a dataset is
/// N^2 / 2 pairs, so each level is kept as rows of 64-bit words.
#[derive(Clone, Debug)]
pub struct Packed {
    rows: usize,
    cols: usize,
    words: usize,
    bits: Vec<u64>,
}

impl Packed {
    /// Packs a mask.
    pub fn new(m: &Mask) -> Packed {
        let words = m.cols.div_ceil(64).max(1);
        let mut bits = vec![0u64; m.rows * words];
        for r in 0..m.rows {
            for c in 0..m.cols {
                if m.at(r, c) {
                    bits[r * words + c / 64] |= 1 << (c % 64);
                }
            }
        }
        Packed {
            rows: m.rows,
            cols: m.cols,
            words,
            bits,
        }
    }

    /// `(true IoU, eq. 19 as printed)` of two levels, either on the rows and columns both
    /// have (`common`, the top-left crop) or over both whole (empty cells added to the
    /// smaller). `None` when both are empty there.
    pub fn iou(&self, other: &Packed, common: bool) -> Option<(f64, f64)> {
        let (rows, cols) = if common {
            (self.rows.min(other.rows), self.cols.min(other.cols))
        } else {
            (self.rows.max(other.rows), self.cols.max(other.cols))
        };
        let words = cols.div_ceil(64);
        let (mut both, mut na, mut nb, mut either) = (0u64, 0u64, 0u64, 0u64);
        for r in 0..rows {
            for w in 0..words {
                let keep = if (w + 1) * 64 <= cols {
                    u64::MAX
                } else {
                    (1u64 << (cols % 64)) - 1
                };
                let word = |p: &Packed| {
                    if r < p.rows && w < p.words {
                        p.bits[r * p.words + w] & keep
                    } else {
                        0
                    }
                };
                let (x, y) = (word(self), word(other));
                both += u64::from((x & y).count_ones());
                na += u64::from(x.count_ones());
                nb += u64::from(y.count_ones());
                either += u64::from((x | y).count_ones());
            }
        }
        (either > 0).then(|| (both as f64 / either as f64, both as f64 / (na + nb) as f64))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask(rows: &[&str]) -> Mask {
        let cells = rows
            .iter()
            .flat_map(|r| r.chars().map(|c| c == '#'))
            .collect();
        Mask::new(rows.len(), rows[0].len(), cells)
    }

    #[test]
    fn iou_of_identical_disjoint_and_overlapping() {
        let a = mask(&["##..", "##..", "....", "...."]);
        let b = mask(&["....", "....", "..##", "..##"]);
        let c = mask(&[".#..", ".##.", "....", "...."]);
        assert_eq!(iou(&a, &a), Some(1.0));
        assert_eq!(iou_eq19_as_printed(&a, &a), Some(0.5));
        assert_eq!(iou(&a, &b), Some(0.0));
        // a and c share 2 cells; together they cover 5.
        assert_eq!(iou(&a, &c), Some(2.0 / 5.0));
        assert_eq!(iou_eq19_as_printed(&a, &c), Some(2.0 / 7.0));
        assert_eq!(
            Packed::new(&a).iou(&Packed::new(&c), true),
            Some((0.4, 2.0 / 7.0))
        );
        assert_eq!(iou(&mask(&[".."]), &mask(&[".."])), None);
    }

    #[test]
    fn mirrors_and_rotations_of_known_patterns() {
        let plus = mask(&["...", "###", "..."]);
        let m = mirror(&plus).unwrap();
        assert_eq!((m.horizontal, m.vertical), (1.0, 1.0));
        // Turned a quarter, the bar is a column: it shares only the centre of 5 cells.
        assert!((m.rotational - (0.2 + 1.0 + 0.2) / 3.0).abs() < 1e-12);
        let l = mask(&["#..", "#..", "###"]);
        let m = mirror(&l).unwrap();
        // Mirrored left-right the L shares its bottom row (3) of 7 cells covered.
        assert!((m.horizontal - 3.0 / 7.0).abs() < 1e-12);
        assert!((m.vertical - 3.0 / 7.0).abs() < 1e-12);
    }

    #[test]
    fn packing_crops_and_pads_wide_grids() {
        let mut cells = vec![false; 2 * 70];
        cells[69] = true;
        cells[70 + 3] = true;
        let wide = Mask::new(2, 70, cells);
        let small = wide.crop(2, 10);
        let (pw, ps) = (Packed::new(&wide), Packed::new(&small));
        assert_eq!(pw.iou(&ps, true), Some((1.0, 0.5)));
        assert_eq!(pw.iou(&ps, false), Some((0.5, 1.0 / 3.0)));
        assert_eq!(pw.iou(&pw, false), Some((1.0, 0.5)));
    }
}
