//! The memory budget of `generate` and `dataset` (`--max-memory`): how much one run may use,
//! by default a share of the machine's physical memory, so a world too large for the machine
//! is refused up front with its estimate (see [`subtgraph_core::budget`]) instead of ending in
//! an allocation failure.

use subtgraph_core::Budget;
use subtgraph_core::budget::Bytes;

use crate::Error;

/// The share of physical memory a run may use by default: the rest is left to the system,
/// page cache and whatever else runs.
const DEFAULT_SHARE: f64 = 0.75;

/// The budget assumed when physical memory cannot be read (not Linux, no `/proc`).
const FALLBACK_BYTES: u64 = 8_000_000_000;

/// Physical memory in bytes, from `/proc/meminfo` (`MemTotal`), on Linux.
pub fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    meminfo_total(&text)
}

fn meminfo_total(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let mut words = line.split_whitespace().skip(1);
    let n: u64 = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") | None => n.checked_mul(1024),
        _ => None,
    }
}

/// The largest size taken: 10^18 bytes (an exabyte), well within 64 bits.
pub const MAX_SIZE: f64 = 1e18;

/// Parses a size: bytes, or a number with a unit, `k`/`M`/`G`/`T` (powers of 1000) or
/// `Ki`/`Mi`/`Gi`/`Ti` (powers of 1024), with or without a trailing `B`: `16G`, `512MiB`, `1.5GB`.
/// Errors name `--max-memory`: [`parse_size_of`] names another option.
pub fn parse_size(text: &str) -> Result<u64, Error> {
    parse_size_of(text, "--max-memory", "16G")
}

/// [`parse_size`] of the option `knob` (in messages, with `example` as a size it takes): from
/// 1M to [`MAX_SIZE`] bytes, each refusal saying which end was passed, or how sizes are
/// written.
pub fn parse_size_of(text: &str, knob: &str, example: &str) -> Result<u64, Error> {
    let t = text.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let unit = unit.trim();
    let unit = unit.strip_suffix(['B', 'b']).unwrap_or(unit);
    let factor: f64 = match unit {
        "" => 1.0,
        "k" | "K" => 1e3,
        "M" | "m" => 1e6,
        "G" | "g" => 1e9,
        "T" | "t" => 1e12,
        "Ki" | "ki" => 1024.0,
        "Mi" | "mi" => 1024.0 * 1024.0,
        "Gi" | "gi" => 1024.0 * 1024.0 * 1024.0,
        "Ti" | "ti" => 1024.0 * 1024.0 * 1024.0 * 1024.0,
        _ => f64::NAN,
    };
    let value = number.parse::<f64>().map(|n| n * factor);
    let shown = subtgraph_core::error::excerpt(text);
    match value {
        Ok(v) if (1e6..MAX_SIZE).contains(&v) => Ok(v as u64),
        Ok(v) if (0.0..1e6).contains(&v) => Err(Error::Usage(format!(
            "{knob} {shown}: too small: give a size of at least 1M, like {example}, 512M or 2GiB"
        ))),
        Ok(v) if v >= MAX_SIZE => Err(Error::Usage(format!(
            "{knob} {shown}: too large: a size may be at most 1000000T (10^18 bytes, within 64 bits); give one like {example}, 512M or 2GiB"
        ))),
        _ => Err(Error::Usage(format!(
            "{knob} {shown}: give a size like {example}, 512M or 2GiB"
        ))),
    }
}

/// The budget of a run: `--max-memory` when given, else three quarters of physical memory.
pub fn budget(max_memory: Option<&str>) -> Result<Budget, Error> {
    match max_memory {
        Some(text) => Ok(Budget {
            bytes: parse_size(text)?,
            knob: "--max-memory".into(),
            note: String::new(),
        }),
        None => Ok(match physical_memory() {
            Some(total) => Budget {
                bytes: (total as f64 * DEFAULT_SHARE) as u64,
                knob: "--max-memory".into(),
                note: format!("by default 3/4 of this machine's {}", Bytes(total)),
            },
            None => Budget {
                bytes: FALLBACK_BYTES,
                knob: "--max-memory".into(),
                note: "by default, as this machine's memory is unknown".into(),
            },
        }),
    }
}

/// One world's share of a budget when `jobs` worlds are made at once.
pub fn per_world(budget: &Budget, jobs: usize) -> Budget {
    if jobs <= 1 {
        return budget.clone();
    }
    let whole = if budget.note.is_empty() {
        String::new()
    } else {
        format!("; {}", budget.note)
    };
    Budget {
        bytes: budget.bytes / jobs as u64,
        knob: budget.knob.clone(),
        note: format!(
            "each world's share of {} over dataset --jobs {jobs}{whole}",
            Bytes(budget.bytes)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_meminfo_parse() {
        assert_eq!(parse_size("16G").unwrap(), 16_000_000_000);
        assert_eq!(parse_size("512MiB").unwrap(), 512 << 20);
        assert_eq!(parse_size("1.5GB").unwrap(), 1_500_000_000);
        assert_eq!(parse_size("2000000").unwrap(), 2_000_000);
        assert!(parse_size("12 parsecs").is_err());
        assert!(
            parse_size("10")
                .unwrap_err()
                .to_string()
                .contains("at least 1M")
        );
        assert!(parse_size("-4G").is_err());
        let m = "MemTotal:       24684084 kB\nMemFree:        23132068 kB\n";
        assert_eq!(meminfo_total(m), Some(24684084 * 1024));
        assert_eq!(meminfo_total("nothing"), None);
        let b = per_world(&budget(Some("8G")).unwrap(), 4);
        assert_eq!(b.bytes, 2_000_000_000);
        assert_eq!(b.knob, "--max-memory");
        assert!(
            b.note.contains("share of 8.0 GB over dataset --jobs 4"),
            "{}",
            b.note
        );
    }
}
