//! Voxel sets as bits in 64-bit words, one run of words per `(z, y)` row: growing a set by a
//! radius is a few shifts and ORs per word ([`super::coverage`] measures with them, and the
//! world's free space is one, [`super::world`]).

/// Voxels as bits, one row of `words` 64-bit words per `(z, y)`; bit `i % 64` of word `i / 64`
/// is voxel `i` along x.
#[derive(Clone, Debug, PartialEq)]
pub struct Bits {
    /// Voxels along x, y, z.
    pub n: [usize; 3],
    /// Words per row.
    pub words: usize,
    /// Rows of words, z-major.
    pub data: Vec<u64>,
}

impl Bits {
    /// All clear.
    pub fn empty(n: [usize; 3]) -> Bits {
        let words = n[0].div_ceil(64);
        Bits {
            n,
            words,
            data: vec![0; words * n[1] * n[2]],
        }
    }

    /// From `free_space.npy`'s packed bytes (`np.packbits` along x: the first voxel is the
    /// high bit of its byte).
    pub fn from_packed(n: [usize; 3], packed: &[u8]) -> Bits {
        let mut b = Bits::empty(n);
        let row_bytes = n[0].div_ceil(8);
        for r in 0..n[1] * n[2] {
            let src = &packed[r * row_bytes..(r + 1) * row_bytes];
            let dst = &mut b.data[r * b.words..(r + 1) * b.words];
            for (m, &byte) in src.iter().enumerate() {
                dst[m / 8] |= u64::from(byte.reverse_bits()) << (8 * (m % 8));
            }
        }
        b.mask();
        b
    }

    fn mask(&mut self) {
        let tail = self.n[0] % 64;
        if tail != 0 {
            let keep = (1u64 << tail) - 1;
            for r in 0..self.n[1] * self.n[2] {
                self.data[r * self.words + self.words - 1] &= keep;
            }
        }
    }

    /// Sets voxel `[x, y, z]`; returns whether it was clear.
    pub fn set(&mut self, v: [usize; 3]) -> bool {
        let w = &mut self.data[(v[2] * self.n[1] + v[1]) * self.words + v[0] / 64];
        let bit = 1u64 << (v[0] % 64);
        let was = *w & bit == 0;
        *w |= bit;
        was
    }

    /// Whether voxel `[x, y, z]` is set.
    pub fn get(&self, v: [usize; 3]) -> bool {
        self.data[(v[2] * self.n[1] + v[1]) * self.words + v[0] / 64] >> (v[0] % 64) & 1 == 1
    }

    /// Every voxel not set (within the grid).
    pub fn not(&self) -> Bits {
        let mut b = self.clone();
        for w in &mut b.data {
            *w = !*w;
        }
        b.mask();
        b
    }

    /// Grown by `r` voxels along each axis (a cube). A set grown by `d` and then by `s` (at most
    /// `2d + 1`) is grown by `d + s`, so the growth is passes of 1, 2, 4, ... voxels (about
    /// log2 r of them, each a shift and an OR per word or row) instead of `r` passes of one;
    /// and a set grown by its axis's length covers that axis wherever it has a voxel, so `r`
    /// is cut to it. A radius of 1e300 metres costs what one of the world's size does.
    pub fn dilate(&self, r: usize) -> Bits {
        let [nx, ny, nz] = self.n;
        let mut out = self.grown_along_x(r.min(nx));
        for (stride, len) in [(1, ny), (ny, nz)] {
            let r = r.min(len);
            out = if r <= WINDOW {
                out.grown_within_rows(r, stride, len)
            } else {
                steps(r)
                    .into_iter()
                    .fold(out, |b, s| b.grown_along_rows(s, stride, len))
            };
        }
        out
    }

    /// Grown by `r` along x: directly for a few voxels, by doubling passes beyond.
    fn grown_along_x(&self, r: usize) -> Bits {
        if r <= WINDOW {
            return self.grown_within_x(r);
        }
        steps(r)
            .into_iter()
            .fold(self.clone(), |b, s| b.grown_by_pass_x(s))
    }

    /// Grown by `r` (at most [`WINDOW`]) along x: `r` steps of one voxel over each row, in
    /// place, carrying across words.
    fn grown_within_x(&self, r: usize) -> Bits {
        let words = self.words;
        let mut out = self.clone();
        for row in out.data.chunks_exact_mut(words) {
            for _ in 0..r {
                // Bit 63 of the word before, as it was before this step.
                let mut carry = 0u64;
                for k in 0..words {
                    let v = row[k];
                    let next_low = if k + 1 < words { row[k + 1] & 1 } else { 0 };
                    row[k] = v | (v << 1) | carry | (v >> 1) | (next_low << 63);
                    carry = v >> 63;
                }
            }
        }
        out.mask();
        out
    }

    /// Each row grown by `r` (at most [`WINDOW`]) along the axis whose index steps by `stride`
    /// rows and runs to `len`: the OR of the rows within `r`, in one pass.
    fn grown_within_rows(&self, r: usize, stride: usize, len: usize) -> Bits {
        if r == 0 {
            return self.clone();
        }
        let w = self.words;
        let mut out = Bits::empty(self.n);
        let rows = self.n[1] * self.n[2];
        for block in (0..rows).step_by(stride * len) {
            for idx in 0..len {
                for off in 0..stride {
                    let r0 = block + idx * stride + off;
                    let dst = &mut out.data[r0 * w..(r0 + 1) * w];
                    for t in idx.saturating_sub(r)..=(idx + r).min(len - 1) {
                        let src = block + t * stride + off;
                        or_into(dst, &self.data[src * w..(src + 1) * w]);
                    }
                }
            }
        }
        out
    }

    /// Each voxel ORed with those `s` away along x (one doubling pass).
    fn grown_by_pass_x(&self, s: usize) -> Bits {
        let words = self.words;
        let (q, b) = (s / 64, (s % 64) as u32);
        let mut out = self.clone();
        for (dst, src) in out
            .data
            .chunks_exact_mut(words)
            .zip(self.data.chunks_exact(words))
        {
            if q == 0 {
                // Within a word and into its neighbours: the common case, a few voxels.
                let mut lower = 0u64;
                for (k, (d, &w)) in dst.iter_mut().zip(src).enumerate() {
                    let higher = src.get(k + 1).copied().unwrap_or(0);
                    *d |= (w << b) | (lower >> (64 - b)) | (w >> b) | (higher << (64 - b));
                    lower = w;
                }
                continue;
            }
            let at = |k: usize| src.get(k).copied().unwrap_or(0);
            for (k, w) in dst.iter_mut().enumerate() {
                // From `s` below (k - q words, b bits) and from `s` above.
                let below = k.checked_sub(q).map_or(0, |j| {
                    let lower = j.checked_sub(1).map_or(0, at);
                    (at(j) << b) | if b == 0 { 0 } else { lower >> (64 - b) }
                });
                let j = k + q;
                let above = (at(j) >> b) | if b == 0 { 0 } else { at(j + 1) << (64 - b) };
                *w |= below | above;
            }
        }
        out.mask();
        out
    }

    /// Each row (of `words` words) ORed with the rows `s` away along the axis whose index
    /// steps by `stride` rows and runs to `len`: y (`stride` 1, `len` ny) or z (`stride` ny,
    /// `len` nz).
    fn grown_along_rows(&self, s: usize, stride: usize, len: usize) -> Bits {
        let w = self.words;
        let mut out = self.clone();
        let rows = self.n[1] * self.n[2];
        let row = |r: usize| &self.data[r * w..(r + 1) * w];
        for block in (0..rows).step_by(stride * len) {
            for idx in 0..len {
                for off in 0..stride {
                    let r0 = block + idx * stride + off;
                    let dst = &mut out.data[r0 * w..(r0 + 1) * w];
                    if idx >= s {
                        or_into(dst, row(r0 - s * stride));
                    }
                    if idx + s < len {
                        or_into(dst, row(r0 + s * stride));
                    }
                }
            }
        }
        out
    }
}

/// `dst |= src`, word by word.
fn or_into(dst: &mut [u64], src: &[u64]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d |= *s;
    }
}

/// Up to this radius a set grows along an axis in one pass over the rows within it (at most
/// `2 WINDOW + 1` of them); beyond, by doubling passes.
const WINDOW: usize = 8;

/// The passes that grow a set by `r`: 1, 2, 4, ... and what remains, each at most one more
/// than twice the growth so far, so no voxel in between is skipped.
fn steps(r: usize) -> Vec<usize> {
    let (mut out, mut done, mut next) = (Vec::new(), 0usize, 1usize);
    while done < r {
        let s = next.min(r - done);
        out.push(s);
        done += s;
        next = next.saturating_mul(2);
    }
    out
}
