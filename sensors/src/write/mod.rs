//! The sequence folder's files: the ROS 2 bag ([`bag`], over [`mcap`] and [`cdr`]), the KITTI
//! folder and the TUM ground truth ([`kitti`]); `sequence.json` is written by
//! [`crate::sequence`]. The bag and the KITTI scans, most of the bytes, go around the page
//! cache ([`subtgraph_core::direct_file`]).

pub mod bag;
pub mod cdr;
pub mod kitti;
pub mod mcap;

use crate::error::SenseError;

/// Which of the optional outputs to write (`sequence.json` and `ground_truth.tum` always are).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Formats {
    /// `bag/`.
    pub bag: bool,
    /// `kitti/`.
    pub kitti: bool,
}

/// The names `--format` takes.
pub const NAMES: [&str; 2] = ["bag", "kitti"];

impl Default for Formats {
    fn default() -> Self {
        Formats {
            bag: true,
            kitti: true,
        }
    }
}

impl Formats {
    /// From `--format` values (each may be a comma list); none given means both.
    pub fn parse(values: &[String]) -> Result<Formats, SenseError> {
        let names: Vec<&str> = values
            .iter()
            .flat_map(|v| v.split(','))
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        if names.is_empty() {
            return Ok(Formats::default());
        }
        let mut f = Formats {
            bag: false,
            kitti: false,
        };
        for n in names {
            match n {
                "bag" => f.bag = true,
                "kitti" => f.kitti = true,
                other => {
                    return Err(SenseError::Unknown {
                        what: "output format",
                        name: other.to_owned(),
                        known: NAMES.join(", "),
                    });
                }
            }
        }
        Ok(f)
    }
}
