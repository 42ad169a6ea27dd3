//! Trajectory and times files read a line at a time (issue 37, items 2, 9 and 20): each line
//! is checked as it is read, so a file that is not a trajectory is refused at its first line
//! rather than after it was read whole (a 50 MB file of lines `1` took 70 bytes of memory a
//! byte before), and what is kept is the poses alone (72 bytes each).
//!
//! A line may hold at most [`MAX_LINE`] bytes (a TUM line is under 200, a KITTI line under
//! 400), so a file without line breaks cannot fill the memory either; and a position may be at
//! most [`MAX_POSITION_M`] from the origin, as no trajectory in metres is farther (1e308 made
//! the distances infinite and the pictures empty).

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use crate::Error;

/// The most bytes one line may hold.
pub const MAX_LINE: usize = 4096;

/// The farthest a position may be from the origin along each axis, metres: a million
/// kilometres.
pub const MAX_POSITION_M: f64 = 1e9;

/// The most numbers a line is read with (a KITTI line's twelve, and one to tell more).
const MOST: usize = 13;

fn bad(file: &Path, line: usize, what: impl std::fmt::Display) -> Error {
    Error::Input(format!("{}: line {line}: {what}", file.display()))
}

/// Calls `each(line number, count, numbers)` for every data line of `file` in order (blank
/// lines and `#` comments skipped; numbers separated by white space or commas, each finite):
/// `count` numbers, of which at most the first thirteen are handed over. Stops at the first
/// error, `each`'s or the file's.
pub fn each_row(
    file: &Path,
    mut each: impl FnMut(usize, usize, &[f64]) -> Result<(), Error>,
) -> Result<(), Error> {
    let reading = || Error::io(format!("reading {}", file.display()));
    let mut reader = BufReader::with_capacity(1 << 16, crate::input::open(file)?);
    let mut buf = Vec::with_capacity(256);
    let mut values = [0.0; MOST];
    for line in 1.. {
        buf.clear();
        let n = reader
            .by_ref()
            .take(MAX_LINE as u64 + 1)
            .read_until(b'\n', &mut buf)
            .map_err(reading())?;
        if n == 0 {
            return Ok(());
        }
        if buf.len() > MAX_LINE {
            return Err(bad(
                file,
                line,
                format!(
                    "longer than {MAX_LINE} bytes: not a trajectory (a TUM line `t x y z qx qy qz qw` is under 200 bytes)"
                ),
            ));
        }
        let s = std::str::from_utf8(&buf)
            .map_err(|_| bad(file, line, "not text: is it a trajectory file?"))?
            .trim();
        if s.is_empty() || s.starts_with('#') {
            continue;
        }
        let mut count = 0;
        for word in s.split(|c: char| c.is_whitespace() || c == ',') {
            if word.is_empty() {
                continue;
            }
            let shown = subtgraph_core::error::excerpt(word);
            let x: f64 = word
                .parse()
                .map_err(|_| bad(file, line, format!("'{shown}' is not a number")))?;
            if !x.is_finite() {
                return Err(bad(
                    file,
                    line,
                    format!("{shown} is not a finite number: every time and pose value must be"),
                ));
            }
            if count < MOST {
                values[count] = x;
            }
            count += 1;
        }
        each(line, count, &values[..count.min(MOST)])?;
    }
    unreachable!("the lines end")
}

/// Why a position is not one of a trajectory in metres, if it is not.
pub fn too_far(t: [f64; 3]) -> Option<String> {
    let far = t.iter().copied().find(|x| x.abs() > MAX_POSITION_M)?;
    Some(format!(
        "a position of {far:e} m: more than {MAX_POSITION_M:e} m (a million kilometres) from the origin, which no trajectory in metres is; are the columns in the right order?"
    ))
}
