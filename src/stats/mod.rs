//! placeholder
use std::path::{Path, PathBuf};
/// Crop.
#[derive(Clone, Copy, Debug)]
pub enum Crop {
    /// c
    Common,
    /// p
    Pad,
}
impl std::str::FromStr for Crop {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "common" => Ok(Crop::Common),
            "pad" => Ok(Crop::Pad),
            _ => Err(format!("--crop {s}: write common or pad")),
        }
    }
}
/// run
pub fn run(_i: &[PathBuf], _o: &Path, _c: Crop) -> anyhow::Result<String> {
    anyhow::bail!("todo")
}
