//! Making a dataset: the folder prepared, the worlds already there checked, the rest made by
//! worker threads one whole world at a time, and the index rebuilt.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use super::existing::{Existing, description, existing, expected_world_toml};
use super::index::{self, RunFacts};
use super::plan::{Planned, plan};
use super::{Options, Source, Summary, explore, progress, sense};
use crate::folder::{FolderError, Kind, Out, manifest};
use crate::{Error, ExploreRequest, pipeline};

/// Makes this shard's worlds of the dataset in `opts.out`, then rebuilds the index.
pub fn run(sources: &[Source], opts: &Options) -> Result<Summary, Error> {
    let names: Vec<&str> = sources.iter().map(|s| s.name.as_str()).collect();
    for (i, a) in names.iter().enumerate() {
        if names[..i].contains(a) {
            return Err(Error::Usage(format!(
                "two sources are both named '{a}' (world folders are named after the pipeline file or preset): rename one of the files"
            )));
        }
    }
    let all = plan(&names, opts.count, opts.seed);
    prepare_out(&opts.out, &all)?;
    let mine: Vec<&Planned> = all
        .iter()
        .enumerate()
        .filter(|(k, _)| opts.shard.owns(*k))
        .map(|(_, w)| w)
        .collect();

    // Decide what to make before making anything: a folder of another dataset, or made with
    // other options, is an error; a damaged world of this one is made again.
    let mut todo = Vec::new();
    let mut damaged = Vec::new();
    let mut skipped = 0;
    // Worlds another live process on this machine is writing now are left to it.
    let writing = being_written(&opts.out);
    let mut busy = Vec::new();
    for w in &mine {
        if let Some(&pid) = writing.get(&w.name) {
            busy.push((*w, pid));
            continue;
        }
        let expected = expected_world_toml(&sources[w.source], w, opts)?;
        match existing(&opts.out, w, &expected)? {
            Existing::Complete => skipped += 1,
            Existing::Absent => todo.push(*w),
            Existing::Damaged(why) => {
                eprintln!("note: {} is incomplete ({why}); making it again", w.name);
                todo.push(*w);
                damaged.push(w.name.clone());
            }
        }
    }

    let progress = Mutex::new(progress::Progress::new(todo.len(), skipped));
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let meanwhile = AtomicUsize::new(0);
    let jobs = opts.jobs.clamp(1, todo.len().max(1));
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(w) = todo.get(k) else { break };
                    let replace = damaged.contains(&w.name);
                    let result = make_world(&sources[w.source], w, opts, replace);
                    match &result {
                        Ok(Made::Here) => {}
                        Ok(Made::Elsewhere) => {
                            meanwhile.fetch_add(1, Ordering::Relaxed);
                        }
                        Err(e) => failures
                            .lock()
                            .expect("no worker panics holding it")
                            .push(format!("{}: {}", w.name, crate::message(e))),
                    }
                    progress
                        .lock()
                        .expect("no worker panics holding it")
                        .finished(&w.name, result.is_ok());
                }
            });
        }
    });
    progress.into_inner().expect("workers are done").close();
    let meanwhile = meanwhile.into_inner();
    // The worlds other processes were making: finished by now, or still theirs.
    let mut elsewhere = Vec::new();
    for (w, pid) in busy {
        let expected = expected_world_toml(&sources[w.source], w, opts)?;
        match existing(&opts.out, w, &expected) {
            Ok(Existing::Complete) => skipped += 1,
            _ => elsewhere.push((w.name.clone(), pid)),
        }
    }
    if meanwhile > 0 {
        eprintln!(
            "note: {meanwhile} world(s) were made by another process writing into the same folder (a shard) while this run made them: kept"
        );
    }
    if !elsewhere.is_empty() {
        let list: Vec<String> = elsewhere
            .iter()
            .map(|(name, pid)| format!("{name} (process {pid})"))
            .collect();
        eprintln!(
            "note: {} world(s) are being made by another process writing into the same folder, left to it: {}; that run indexes them when it ends (or run this command again then)",
            elsewhere.len(),
            subtgraph_core::error::excerpt_to(&list.join(", "), 400)
        );
    }
    let indexed = index::rebuild(&opts.out)?;
    let failures = failures.into_inner().expect("workers are done");
    if !failures.is_empty() {
        return Err(Error::DatasetFailures {
            failures,
            total: todo.len(),
        });
    }
    // The run's own plugins: its pipelines' and --plugin (a world's world.toml names the same
    // ones, and nothing else is loaded when its worlds are sensed or explored).
    let mut plugins = opts.plugins.clone();
    for s in sources {
        plugins.extend(s.pipeline.plugins.paths.iter().map(PathBuf::from));
    }
    let sensed = match &opts.sense {
        Some(template) => {
            let names: Vec<String> = mine.iter().map(|w| w.name.clone()).collect();
            Some(sense::sense_worlds(
                &opts.out,
                &names,
                template,
                &plugins,
                &|name, scan, of| {
                    if (scan + 1) % 500 == 0 || scan + 1 == of {
                        eprint!("\r  sensing {name}: scan {} of {of}", scan + 1);
                        if scan + 1 == of {
                            eprintln!();
                        }
                    }
                },
            )?)
        }
        None => None,
    };
    let explored = match &opts.explore {
        Some(template) => {
            let names: Vec<String> = mine.iter().map(|w| w.name.clone()).collect();
            let template = ExploreRequest {
                plugins: plugins.clone(),
                ..template.clone()
            };
            Some(explore::explore_worlds(
                &opts.out,
                &names,
                &template,
                &|name, t, of| {
                    eprint!("\r  exploring {name}: {t:.0} of {of:.0} simulated s");
                    if t >= of - 1e-6 {
                        eprintln!();
                    }
                },
            )?)
        }
        None => None,
    };
    Ok(Summary {
        made: todo.len() - meanwhile,
        skipped: skipped + meanwhile,
        elsewhere,
        indexed,
        sensed,
        explored,
    })
}

/// Checks the dataset folder before any work: a folder (or nothing yet) where the user can
/// write, holding none of the files the run reads; a folder that is not a dataset's yet must
/// hold nothing but this dataset's worlds: the index files written there would replace a
/// user's files of the same names.
pub fn check_out(out: &Path, all: &[Planned], reading: &[&Path]) -> Result<(), Error> {
    crate::folder::not_current_folder(out)?;
    if out.exists() && !out.is_dir() {
        return Err(Error::Usage(format!(
            "--out {} is a file; give a folder for the dataset",
            out.display()
        )));
    }
    if out.is_dir() && !out.join(index::FACTS_DIR).is_dir() {
        let mut foreign: Vec<String> = std::fs::read_dir(out)
            .map_err(Error::io(format!("reading --out {}", out.display())))?
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| {
                // Another run starting into the same folder at the same time (a shard) may
                // have its write probe there before it marks the folder.
                let temporary = n.starts_with('.')
                    && (n.contains(".partial-") || n.starts_with(".write-test-"));
                // It may also have marked the folder between the check above and this
                // listing: its index is this dataset's too.
                let marked = n == index::FACTS_DIR;
                !temporary && !marked && !all.iter().any(|w| &w.name == n)
            })
            .collect();
        foreign.sort();
        if !foreign.is_empty() {
            return Err(Error::Usage(format!(
                "--out {} already holds files that are not this dataset's ({}); give a new or empty folder",
                out.display(),
                subtgraph_core::error::excerpt_to(&foreign.join(", "), 200)
            )));
        }
    }
    if let Ok(real) = out.canonicalize() {
        if let Some(input) = reading
            .iter()
            .find(|r| r.canonicalize().is_ok_and(|r| r.starts_with(&real)))
        {
            return Err(Error::Usage(format!(
                "--out {} holds {}, which this command reads; write the dataset elsewhere: choose another --out",
                out.display(),
                input.display()
            )));
        }
    }
    #[cfg(unix)]
    if let Some(existing) = out.ancestors().find(|a| a.is_dir()) {
        rustix::fs::access(existing, rustix::fs::Access::WRITE_OK).map_err(|e| {
            Error::io(format!(
                "cannot write into --out {}; choose a folder you can write to",
                out.display()
            ))(e.into())
        })?;
    }
    Ok(())
}

/// Creates the dataset folder and checks it can be written to, before any world is made
/// (after [`check_out`]).
fn prepare_out(out: &Path, all: &[Planned]) -> Result<(), Error> {
    check_out(out, all, &[])?;
    // The facts folder marks it as a dataset's before anything else is written into it, so
    // shards starting at the same time see each other's files as this dataset's.
    std::fs::create_dir_all(out.join(index::FACTS_DIR)).map_err(Error::io(format!(
        "cannot create the dataset folder --out {}; choose a folder you can write to",
        out.display()
    )))?;
    match crate::folder::sweep_stale(out) {
        Ok(0) | Err(_) => {}
        Ok(n) => {
            eprintln!("note: removed {n} unfinished world folder(s) left by runs that were killed")
        }
    }
    let probe = out.join(format!(".write-test-{}", std::process::id()));
    std::fs::write(&probe, b"")
        .and_then(|()| std::fs::remove_file(&probe))
        .map_err(Error::io(format!(
            "cannot write into --out {}; choose a folder you can write to",
            out.display()
        )))?;
    Ok(())
}

/// The worlds another live process on this machine is writing into `out` now (its hidden
/// `.NAME.partial-*` folder, whose manifest names the process), by name, with the process id.
/// A process on another machine cannot be asked whether it is alive: its worlds are made here
/// too, and whichever process finishes a world second keeps the first one's.
fn being_written(out: &Path) -> std::collections::BTreeMap<String, u32> {
    let here = manifest::Owner::this_process();
    let Ok(entries) = std::fs::read_dir(out) else {
        return Default::default();
    };
    entries
        .flatten()
        .filter_map(|e| {
            let file = e.file_name().to_string_lossy().into_owned();
            let (name, _) = file.strip_prefix('.')?.split_once(".partial-")?;
            match manifest::read(&e.path())? {
                manifest::Manifest::Partial(owner)
                    if owner.host == here.host && owner.pid != here.pid && !owner.is_dead() =>
                {
                    Some((name.to_owned(), owner.pid))
                }
                _ => None,
            }
        })
        .collect()
}

/// Who made a world this run set out to make.
#[derive(Debug, PartialEq, Eq)]
enum Made {
    /// This run.
    Here,
    /// Another process writing into the same folder (a shard), since this run planned it:
    /// the same world, kept.
    Elsewhere,
}

/// Generates one world and writes its folder, then its run facts beside it. A world another
/// process (a shard) wrote since the plan is kept if it is the same world, and ours discarded.
fn make_world(source: &Source, w: &Planned, opts: &Options, replace: bool) -> Result<Made, Error> {
    let mut p = source.pipeline.clone();
    p.world.seed = w.seed;
    let description = description(source, w, opts);
    // Made by another process since the plan: nothing to do.
    if !replace && std::fs::symlink_metadata(opts.out.join(&w.name)).is_ok() {
        let expected = pipeline::expected_world_toml(&p, &description)?;
        if existing(&opts.out, w, &expected)? == Existing::Complete {
            return Ok(Made::Elsewhere);
        }
    }
    let started = Instant::now();
    let budget = crate::memory::per_world(&opts.max_memory, opts.jobs);
    let world = pipeline::generate(&p, &source.components, &description, &budget)?;
    let generation_s = started.elapsed().as_secs_f64();
    if write_world(&world, source, w, opts, replace)? == Made::Elsewhere {
        return Ok(Made::Elsewhere);
    }
    let facts = RunFacts {
        generation_s,
        total_s: started.elapsed().as_secs_f64(),
        visual_triangles: world.mesh().map(|m| m.visual.triangle_count()),
        collision_triangles: world.mesh().map(|m| m.collision.triangle_count()),
    };
    index::write_facts(&opts.out, &w.name, &facts).map_err(Error::io(format!(
        "writing the run facts of {} into {}/{}",
        w.name,
        opts.out.display(),
        index::FACTS_DIR
    )))?;
    Ok(Made::Here)
}

/// Writes a generated world's folder. When the folder appeared while this run made the world
/// (another process writing into the same folder got there first) and holds the same world,
/// that is no failure: [`Made::Elsewhere`], and our copy is discarded. The folder writer's
/// words about `--force` never reach the user: `dataset` has no such flag.
fn write_world(
    world: &subtgraph_core::World,
    source: &Source,
    w: &Planned,
    opts: &Options,
    replace: bool,
) -> Result<Made, Error> {
    let dest = opts.out.join(&w.name);
    let out = Out {
        path: &dest,
        kind: Kind::World,
        force: replace,
        reading: &[],
    };
    let e = match pipeline::write_folder(world, &source.components.exporters, &out) {
        Ok(()) => return Ok(Made::Here),
        Err(e) => e,
    };
    if !matches!(
        e,
        FolderError::AppearedMeanwhile { .. } | FolderError::Exists(_)
    ) {
        return Err(e.into());
    }
    let mut p = source.pipeline.clone();
    p.world.seed = w.seed;
    let expected = pipeline::expected_world_toml(&p, &description(source, w, opts))?;
    let there = existing(&opts.out, w, &expected);
    if let FolderError::AppearedMeanwhile { kept, .. } = &e {
        if matches!(there, Ok(Existing::Complete)) {
            crate::folder::remove_listed(kept).map_err(Error::io(format!(
                "removing the duplicate {}",
                kept.display()
            )))?;
            return Ok(Made::Elsewhere);
        }
        return Err(e.into());
    }
    match there {
        Ok(Existing::Complete) => Ok(Made::Elsewhere),
        // Another dataset's world, or one made with other options: that message says what to do.
        Err(other) => Err(other),
        Ok(_) => Err(Error::Input(format!(
            "{} appeared while this run was making it, and does not hold this world complete; nothing was changed: run the same command again to make it",
            dest.display()
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::Shard;

    #[test]
    fn a_world_another_process_wrote_since_the_plan_is_kept_not_a_failure() {
        let dir = tempfile::tempdir().unwrap();
        let mut pipeline = crate::presets::load("cave").unwrap();
        pipeline.tileset = None;
        let registry = crate::registry();
        let source = Source {
            name: "cave".into(),
            description: "preset cave".into(),
            components: pipeline.build(&registry).unwrap(),
            pipeline,
            registry,
        };
        let opts = Options {
            count: 1,
            seed: 5,
            out: dir.path().join("d"),
            jobs: 1,
            shard: Shard::ALL,
            max_memory: subtgraph_core::Budget::unlimited(),
            sense: None,
            plugins: Vec::new(),
            explore: None,
        };
        let sources = std::slice::from_ref(&source);
        // This run planned cave-0000; another process then made it.
        run(sources, &opts).unwrap();
        let w = &plan(&["cave"], 1, 5)[0];
        let before = std::fs::read(opts.out.join("cave-0000/topology.json")).unwrap();
        let made = make_world(&source, w, &opts, false);
        assert_eq!(
            made.expect("the same world, made meanwhile, is no failure"),
            Made::Elsewhere
        );
        // The same, when it appears while this run generates it (after the check above).
        let mut p = source.pipeline.clone();
        p.world.seed = w.seed;
        let world = pipeline::generate(
            &p,
            &source.components,
            &description(&source, w, &opts),
            &opts.max_memory,
        )
        .unwrap();
        assert_eq!(
            write_world(&world, &source, w, &opts, false).unwrap(),
            Made::Elsewhere
        );
        assert_eq!(
            std::fs::read(opts.out.join("cave-0000/topology.json")).unwrap(),
            before
        );
        // A folder of another dataset that appears meanwhile is an error naming real flags.
        let other = Planned {
            seed: w.seed + 1,
            ..w.clone()
        };
        let e = write_world(&world, &source, &other, &opts, false).unwrap_err();
        let text = crate::message(&e);
        assert!(text.contains("belongs to another dataset"), "{text}");
        assert!(!text.contains("--force"), "{text}");
        let leftovers = std::fs::read_dir(&opts.out)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .contains("partial")
            })
            .count();
        assert_eq!(leftovers, 0);
    }
}
