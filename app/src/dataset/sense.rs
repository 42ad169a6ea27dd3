//! `dataset --sense`: a sensor sequence for every world of the run's share, written to
//! `sequences/NAME/` inside the dataset folder once the worlds are made.
//!
//! Why after the worlds and one world at a time: a sequence is ray cast on every core already
//! (its scans are independent), and it holds the world, its ray caster and one chunk of scans,
//! so sensing worlds side by side would multiply the memory without making it faster. Why a
//! folder of its own rather than inside each world: a world folder is complete, listed and
//! byte-identical whatever the run; a sequence is `sense`'s folder, written and replaced by its
//! rules (`complete sense` in its `.subtgraph-files`).
//!
//! Each sequence is written atomically by [`crate::sense::run`], so a run stopped part way (an
//! error, Ctrl-C, the disk limit) leaves the worlds and the sequences it finished, and running
//! the same command again makes only what is missing: a complete sequence is kept, a damaged
//! one of ours is made again, anything else in its place is refused.

use std::path::{Path, PathBuf};

use subtgraph_sensors::SenseRequest;

use crate::folder::manifest::{self, Kind, Manifest};
use crate::{Error, sense};

/// The folder of the sequences, inside the dataset folder.
pub const SEQUENCES_DIR: &str = "sequences";

/// What the sensing of a dataset did.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Sensed {
    /// Sequences written by this run.
    pub made: usize,
    /// Complete sequences found and kept.
    pub kept: usize,
    /// Scans written by this run.
    pub scans: u64,
    /// Bytes written by this run.
    pub bytes: u64,
}

/// Checks `template`'s names and bounds (model, platform, route, rates, formats, duration)
/// before any world is made, so a typo does not cost a dataset.
pub fn check(template: &SenseRequest) -> Result<(), Error> {
    if let Some(d) = template.duration
        && !(d > 0.0 && d.is_finite())
    {
        return Err(Error::Usage(format!(
            "--sense-duration {d}: give a positive number of seconds (or leave it out for each world's whole route)"
        )));
    }
    subtgraph_sensors::request::options(template, 0)?;
    Ok(())
}

/// Writes the sequence of each world `names` lists that is complete in the dataset folder
/// `out` (a world another shard makes, or one that failed, is left out: the dataset says so),
/// as `template` asks (its `world`, `out` and `force` are set here), the worlds rebuilt with
/// `plugins` (the run's own: its pipelines' and `--plugin`). `progress` is told the world, the
/// scan and the scan count.
pub fn sense_worlds(
    out: &Path,
    names: &[String],
    template: &SenseRequest,
    plugins: &[PathBuf],
    progress: &dyn Fn(&str, u64, u64),
) -> Result<Sensed, Error> {
    let dir = out.join(SEQUENCES_DIR);
    std::fs::create_dir_all(&dir).map_err(Error::io(format!("creating {}", dir.display())))?;
    let mut done = Sensed::default();
    for name in names {
        let world = out.join(name);
        if !world.join("world.toml").is_file() {
            continue;
        }
        let seq = dir.join(name);
        let force = match manifest::read(&seq) {
            Some(Manifest::Complete(Some(Kind::Sense), files)) => {
                let damage = manifest::damage(&seq, &files);
                if damage.is_empty() {
                    same_options(&seq, template)?;
                    done.kept += 1;
                    continue;
                }
                eprintln!(
                    "note: {} is incomplete ({}); making it again",
                    seq.display(),
                    damage.join(", ")
                );
                true
            }
            // Anything else there (a user's folder, another command's) is refused by `sense`.
            _ => false,
        };
        let request = SenseRequest {
            world,
            out: seq,
            force,
            ..template.clone()
        };
        let sensed =
            sense::run_with(&request, plugins, &|k, n| progress(name, k, n)).map_err(|source| {
                Error::Sequence {
                    world: name.clone(),
                    source: Box::new(source),
                }
            })?;
        done.made += 1;
        done.scans += sensed.summary.scans;
        done.bytes += sensed.summary.bytes;
    }
    Ok(done)
}

/// Refuses a complete sequence made with other options than `template`'s (or whose options
/// are not recorded: made by an older version), naming them; nothing is changed.
fn same_options(seq: &Path, template: &SenseRequest) -> Result<(), Error> {
    let path = seq.join(crate::sense_options::FILE);
    let recorded: Option<serde_json::Value> = std::fs::read(&path)
        .ok()
        .and_then(|b| serde_json::from_slice(&b).ok());
    let Some(recorded) = recorded else {
        return Err(Error::Input(format!(
            "{} records no sensor options (no readable {}: made by an older version), so whether this run would make it alike is unknown; nothing was changed: move it away to have it made again",
            seq.display(),
            crate::sense_options::FILE
        )));
    };
    let differ =
        crate::sense_options::differences(&recorded, &crate::sense_options::record(template));
    if differ.is_empty() {
        return Ok(());
    }
    Err(Error::Input(format!(
        "{} was made with other sensor options than this run's ({}); nothing was changed: run with the options it was made with, give another --out, or move it away to have it made again",
        seq.display(),
        differ.join("; ")
    )))
}
