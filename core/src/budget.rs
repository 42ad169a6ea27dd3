//! Memory estimates made before the memory is used.
//!
//! A world's size follows from a few numbers known before it is made: its cells (levels x
//! rows x cols) and, with a tile set, its tiles times the triangles of each. Generation checks
//! both against a [`Budget`] before laying out the grid and before meshing, so a world too large
//! for the machine is refused with its estimate and the knob to change, never discovered by an
//! allocation failure hours into a run. The estimates are a few multiplications per tile kind,
//! so they cost nothing next to the work they guard.
//!
//! The constants are measured (peak resident memory of `subtgraph generate` over the quantity
//! it scales with, on the presets, every exporter included) and rounded up.

use std::fmt;

use crate::tile::TileKind;

/// Bytes per cell of the whole world during layout and writing: occupancy, tiles, spatial
/// codes, maps (measured: 25 bytes per cell for two levels of 1024 x 1024, with the per-level
/// buffers below).
pub const BYTES_PER_CELL: u64 = 12;

/// Bytes per cell of one level, for the buffers generation reuses level by level (route
/// search, labels).
pub const BYTES_PER_LEVEL_CELL: u64 = 32;

/// Bytes per cell of an imported array, on top of [`BYTES_PER_CELL`]: the values read as
/// `f64` and their codes.
pub const BYTES_PER_IMPORTED_CELL: u64 = 9;

/// Bytes per triangle (visual and collision counted alike) of an assembled world, with its
/// vertices, welding and the exporters' buffers (measured: 48 to 79 on the three presets with
/// every format).
pub const BYTES_PER_TRIANGLE: u64 = 80;

/// How much memory one world may use, and what sets it (named in messages).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Budget {
    /// Bytes.
    pub bytes: u64,
    /// What sets the limit, for messages (`--max-memory`).
    pub knob: String,
    /// Where the number comes from when the user did not give it (`3/4 of this machine's
    /// 25 GB`), for messages; empty when they did.
    pub note: String,
}

impl Budget {
    /// No limit: what library calls without a budget get.
    pub fn unlimited() -> Self {
        Self {
            bytes: u64::MAX,
            knob: "the budget".into(),
            note: String::new(),
        }
    }

    /// Refuses `needed` bytes when they exceed the budget. `what` says what needs them,
    /// `advice` what to change; the error adds the budget and its knob.
    pub fn check(&self, needed: u64, what: &str, advice: &str) -> Result<(), OverBudget> {
        if needed <= self.bytes {
            return Ok(());
        }
        Err(OverBudget {
            what: what.to_owned(),
            needed,
            budget: self.clone(),
            advice: advice.to_owned(),
        })
    }
}

/// Something would need more memory than the [`Budget`] allows: how much, and what to change
/// (make it smaller as `advice` says, or raise the budget's knob).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{what} would need about {} of memory, more than {} allows ({}{}); {advice}, or raise {}",
    Bytes(*.needed),
    budget.knob,
    Bytes(budget.bytes),
    note(&budget.note),
    budget.knob
)]
pub struct OverBudget {
    /// What would need it (`a world of 2 level(s) of 400 x 400 cells`).
    pub what: String,
    /// Bytes it would need.
    pub needed: u64,
    /// The budget it exceeds.
    pub budget: Budget,
    /// What to make smaller.
    pub advice: String,
}

/// `, {note}`, or nothing without a note.
fn note(note: &str) -> String {
    if note.is_empty() {
        String::new()
    } else {
        format!(", {note}")
    }
}

/// A byte count as people read it (`12.7 GB`, decimal units).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bytes(pub u64);

impl fmt::Display for Bytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let b = self.0 as f64;
        match self.0 {
            0..1_000_000 => write!(f, "{:.0} kB", b / 1e3),
            1_000_000..1_000_000_000 => write!(f, "{:.0} MB", b / 1e6),
            1_000_000_000..1_000_000_000_000 => write!(f, "{:.1} GB", b / 1e9),
            _ => write!(f, "{:.1} TB", b / 1e12),
        }
    }
}

/// Bytes a world of this shape needs without geometry.
pub fn layout_bytes(levels: usize, rows: usize, cols: usize) -> u64 {
    let level = (rows as u64).saturating_mul(cols as u64);
    level
        .saturating_mul(levels as u64)
        .saturating_mul(BYTES_PER_CELL)
        .saturating_add(level.saturating_mul(BYTES_PER_LEVEL_CELL))
}

/// Triangles of one tile, as a tile set estimates them without meshing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TileTriangles {
    /// Visual mesh.
    pub visual: f64,
    /// Collision mesh.
    pub collision: f64,
}

/// The estimated size of a world's meshes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshEstimate {
    /// Tiles (occupied cells).
    pub tiles: u64,
    /// Visual and collision triangles.
    pub triangles: f64,
    /// Bytes at [`BYTES_PER_TRIANGLE`].
    pub bytes: u64,
}

impl MeshEstimate {
    /// From a triangle count.
    pub fn of(tiles: u64, triangles: f64) -> Self {
        Self {
            tiles,
            triangles,
            bytes: (triangles * BYTES_PER_TRIANGLE as f64).min(u64::MAX as f64) as u64,
        }
    }

    /// "about 210.3 million triangles (52000 tiles of about 4044 each)".
    pub fn describe(&self) -> String {
        format!(
            "about {:.1} million triangles: {} tiles of about {:.0} each",
            self.triangles / 1e6,
            self.tiles,
            self.triangles / self.tiles.max(1) as f64
        )
    }
}

/// Sums a per-kind estimate over a world's tiles (their `kinds`, as
/// [`crate::layout::Layout::mesh_estimate`] gives them): one call per kind, one pass over the
/// grid. `None` when `per_kind` has no estimate for a kind the world has.
pub fn mesh_estimate(
    kinds: impl IntoIterator<Item = TileKind>,
    mut per_kind: impl FnMut(TileKind) -> Option<TileTriangles>,
) -> Option<MeshEstimate> {
    let mut counts = [0u64; TileKind::ALL.len()];
    for kind in kinds {
        counts[TileKind::ALL
            .iter()
            .position(|k| *k == kind)
            .expect("every kind is listed")] += 1;
    }
    let mut triangles = 0.0;
    for (kind, &n) in TileKind::ALL.iter().zip(&counts) {
        if n > 0 {
            let t = per_kind(*kind)?;
            triangles += n as f64 * (t.visual + t.collision);
        }
    }
    Some(MeshEstimate::of(counts.iter().sum(), triangles))
}

/// The largest side of an image a world may carry: 8192 pixels (an "8K" texture). Checked from
/// the header when the world is made (issue 37, item 6: a 900-byte PNG claiming 200,000 x
/// 200,000 pixels was copied into the world, and `preview` then asked for 120 GB to draw it).
pub const MAX_IMAGE_SIDE: u32 = 8192;

/// Why a PNG of `width` x `height` pixels is too large for a texture, if it is.
pub fn image_too_large(width: u32, height: u32) -> Option<String> {
    (width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE).then(|| {
        format!(
            "{width} x {height} pixels, more than the {MAX_IMAGE_SIDE} a side an image of a world may have; scale it down"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_refuse_what_exceeds_them_with_the_numbers() {
        let b = Budget {
            bytes: 2_000_000_000,
            knob: "--max-memory".into(),
            note: String::new(),
        };
        assert!(b.check(1_999_999_999, "x", "y").is_ok());
        let e = b
            .check(12_700_000_000, "this world", "use fewer levels")
            .unwrap_err();
        assert_eq!(e.needed, 12_700_000_000);
        assert_eq!(
            e.to_string(),
            "this world would need about 12.7 GB of memory, more than --max-memory allows (2.0 GB); \
             use fewer levels, or raise --max-memory"
        );
        let noted = Budget {
            note: "3/4 of this machine's 25 GB".into(),
            ..b
        };
        assert!(
            noted
                .check(3_000_000_000, "x", "y")
                .unwrap_err()
                .to_string()
                .contains("(2.0 GB, 3/4 of this machine's 25 GB); y")
        );
        assert!(Budget::unlimited().check(u64::MAX, "x", "y").is_ok());
        // 64 levels of 2048 x 2048 cannot overflow the arithmetic.
        assert_eq!(
            layout_bytes(64, 2048, 2048),
            64 * 2048 * 2048 * 12 + 2048 * 2048 * 32
        );
        assert_eq!(layout_bytes(usize::MAX, usize::MAX, 2), u64::MAX);
        assert_eq!(Bytes(5_300_000).to_string(), "5 MB");
    }
}
