//! What a dataset folder already holds for a planned world: the complete world this run would
//! make (kept), nothing, a damaged copy (made again), or something else (an error saying what).

use std::path::Path;

use super::plan::Planned;
use super::{Options, Source};
use crate::folder::manifest;
use crate::{Error, pipeline};

/// What the dataset folder holds for a planned world.
#[derive(Debug, PartialEq)]
pub(super) enum Existing {
    /// The complete world this run would make.
    Complete,
    /// Nothing.
    Absent,
    /// This world, but with files missing or cut short: made again, replacing only the files
    /// subtgraph wrote.
    Damaged(String),
}

/// The `world.toml` this run writes for world `w`.
pub(super) fn expected_world_toml(
    source: &Source,
    w: &Planned,
    opts: &Options,
) -> Result<String, Error> {
    let mut p = source.pipeline.clone();
    p.world.seed = w.seed;
    pipeline::expected_world_toml(&p, &description(source, w, opts))
}

pub(super) fn description(source: &Source, w: &Planned, opts: &Options) -> String {
    format!(
        "{} (dataset world {} of base seed {})",
        source.description, w.index, opts.seed
    )
}

/// Whether a planned world is already there, complete and made with this run's options
/// (its `world.toml` is byte for byte the one this run would write). A world made with other
/// options (another `--tileset`, `--format`, pipeline or version) or of another dataset is an
/// error naming the difference; nothing is deleted to make room for this run.
pub(super) fn existing(out: &Path, w: &Planned, expected_toml: &str) -> Result<Existing, Error> {
    let dir = out.join(&w.name);
    if std::fs::symlink_metadata(&dir).is_err() {
        return Ok(Existing::Absent);
    }
    let listed = match manifest::read(&dir) {
        Some(manifest::Manifest::Complete(Some(manifest::Kind::World), listed)) => listed,
        Some(manifest::Manifest::Complete(Some(kind), _)) => {
            return Err(Error::Input(format!(
                "{} is a {} (written by `{}`), not a world of this dataset; nothing was changed: give another --out, or move it away",
                dir.display(),
                kind.what(),
                kind.command()
            )));
        }
        _ => {
            let seed = std::fs::read_to_string(dir.join("world.toml"))
                .ok()
                .and_then(|t| recorded_seed(&t));
            match seed {
                Some(seed) if seed != w.seed => {
                    return Err(Error::Input(format!(
                        "{} holds a world of seed {seed}, but this dataset's world of that name has seed {}: it belongs to another dataset (other --seed or pipeline); give another --out, or move it away",
                        dir.display(),
                        w.seed
                    )));
                }
                _ => {
                    return Err(Error::Input(format!(
                        "{} is not a complete world written by subtgraph (no {} list of the files it wrote: made by an older version, or by something else); nothing was changed: move it away to have it made again",
                        dir.display(),
                        manifest::FILE
                    )));
                }
            }
        }
    };
    let damage = manifest::damage(&dir, &listed);
    if !damage.is_empty() {
        return Ok(Existing::Damaged(damage.join(", ")));
    }
    let toml = std::fs::read_to_string(dir.join("world.toml"))
        .map_err(Error::io(format!("reading {}/world.toml", dir.display())))?;
    if toml == expected_toml {
        return Ok(Existing::Complete);
    }
    if let Some(seed) = recorded_seed(&toml).filter(|&s| s != w.seed) {
        return Err(Error::Input(format!(
            "{} holds a world of seed {seed}, but this dataset's world of that name has seed {}: it belongs to another dataset (other --seed or pipeline); give another --out, or move it away",
            dir.display(),
            w.seed
        )));
    }
    Err(Error::Input(format!(
        "{} was made with other options than this run's ({}); nothing was changed: run with the options it was made with, give another --out, or move it away to have it made again",
        dir.display(),
        first_difference(&toml, expected_toml)
    )))
}

/// The first line where a world's `world.toml` and this run's differ (with the line after
/// it, so a new table shows its first key), for messages.
fn first_difference(on_disk: &str, expected: &str) -> String {
    let a: Vec<&str> = on_disk.lines().collect();
    let b: Vec<&str> = expected.lines().collect();
    let n = (0..a.len().max(b.len()))
        .find(|&i| a.get(i) != b.get(i))
        .unwrap_or(0);
    let show = |v: &[&str]| {
        let shown: Vec<&str> = v.iter().skip(n).take(2).copied().collect();
        if shown.is_empty() {
            "nothing".to_owned()
        } else {
            format!(
                "`{}`",
                subtgraph_core::error::excerpt_to(&shown.join(" / "), 100)
            )
        }
    };
    format!(
        "world.toml line {} is {} there and {} in this run",
        n + 1,
        show(&a),
        show(&b)
    )
}

/// `world.seed` of a `world.toml`.
pub fn recorded_seed(world_toml: &str) -> Option<u64> {
    let v: toml::Table = toml::from_str(world_toml).ok()?;
    let seed = v.get("world")?.get("seed")?.as_integer()?;
    u64::try_from(seed).ok()
}
