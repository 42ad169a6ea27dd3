//! Hidden temporary folders (`.NAME.partial-PID-STAMP`) and what happens to them when a run
//! ends early.
//!
//! - Ctrl-C (SIGINT), SIGTERM and SIGHUP: [`install_signal_handlers`] removes every temporary
//!   folder this process is writing, then exits with the signal's usual status (130, 143, 129).
//! - SIGKILL or a power cut leave the folder behind with its `partial` manifest; the next run
//!   into the same parent removes it once the process that wrote it is gone
//!   ([`sweep_stale`]). A folder of a live process, or of one on another host (a dataset
//!   folder shared over NFS), is left alone.
//! - SIGXFSZ (a file-size limit, `ulimit -f`) would kill the process silently mid-write; it is
//!   caught, so the write fails with "File too large" and is handled like a full disk.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::manifest::{self, Manifest};

/// What to clean up if the process is stopped.
#[derive(Clone, Debug, PartialEq)]
enum Cleanup {
    /// A temporary folder of this process: removed whole.
    Partial(PathBuf),
    /// An old world moved aside while being replaced: only its listed files are removed.
    Replaced(PathBuf),
}

static IN_PROGRESS: Mutex<Vec<Cleanup>> = Mutex::new(Vec::new());

fn registry() -> std::sync::MutexGuard<'static, Vec<Cleanup>> {
    IN_PROGRESS.lock().unwrap_or_else(|e| e.into_inner())
}

/// A temporary folder registered for clean-up until dropped.
pub(super) struct Registered(Cleanup);

impl Registered {
    pub(super) fn partial(path: &Path) -> Registered {
        let c = Cleanup::Partial(path.to_owned());
        registry().push(c.clone());
        Registered(c)
    }

    pub(super) fn replaced(path: &Path) -> Registered {
        let c = Cleanup::Replaced(path.to_owned());
        registry().push(c.clone());
        Registered(c)
    }
}

impl Drop for Registered {
    fn drop(&mut self) {
        let mut r = registry();
        if let Some(i) = r.iter().position(|c| *c == self.0) {
            r.swap_remove(i);
        }
    }
}

/// Catches SIGINT, SIGTERM and SIGHUP (clean up, then exit) and SIGXFSZ (so a file-size limit
/// fails the write instead of killing the process). Call once, at the start of `main`.
pub fn install_signal_handlers() {
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};
        let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        if let Err(e) = signal_hook::flag::register(SIGXFSZ, flag) {
            eprintln!(
                "warning: cannot catch SIGXFSZ ({e}); a file-size limit will stop the process without a message"
            );
        }
        match signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
            Ok(mut signals) => {
                std::thread::spawn(move || {
                    if let Some(sig) = signals.forever().next() {
                        let removed = clean_up_now();
                        if removed > 0 {
                            eprintln!(
                                "\nstopped by signal {sig}: removed {removed} unfinished folder(s); nothing else was changed"
                            );
                        }
                        std::process::exit(128 + sig);
                    }
                });
            }
            Err(e) => eprintln!(
                "warning: cannot catch Ctrl-C ({e}); an interrupted run may leave a hidden .NAME.partial-* folder, removed by the next run"
            ),
        }
    }
}

/// Removes what this process is writing; returns how many folders it removed.
fn clean_up_now() -> usize {
    let pending: Vec<Cleanup> = registry().clone();
    let mut removed = 0;
    for c in &pending {
        match c {
            Cleanup::Partial(p) => {
                remove_partial(p);
                removed += usize::from(!p.exists());
            }
            Cleanup::Replaced(p) => {
                if super::remove_listed(p).is_ok() {
                    removed += 1;
                }
            }
        }
    }
    removed
}

/// Removes temporary folder `p` while writer threads may still be adding files to it: its
/// contents, then its manifest and the folder; when a writer made a file meanwhile, the
/// manifest is put back and it goes again. A folder left behind in the end still says whose
/// it is, so the next run's [`sweep_stale`] removes it.
fn remove_partial(p: &Path) {
    let keep = p.join(manifest::FILE);
    let saved = fs::read(&keep).ok();
    for _ in 0..4 {
        let Ok(entries) = fs::read_dir(p) else { return };
        for entry in entries.flatten() {
            let path = entry.path();
            if path != keep {
                let _ = match entry.file_type() {
                    Ok(t) if t.is_dir() => fs::remove_dir_all(&path),
                    _ => fs::remove_file(&path),
                };
            }
        }
        let _ = fs::remove_file(&keep);
        if fs::remove_dir(p).is_ok() {
            return;
        }
        if let Some(bytes) = &saved {
            let _ = fs::write(&keep, bytes);
        }
    }
}

/// Removes the temporary folders in `parent` left by runs that were killed (their process is
/// gone); returns how many. Folders of live processes, of other hosts, and anything without
/// our `partial` manifest are left alone.
pub fn sweep_stale(parent: &Path) -> std::io::Result<usize> {
    let mut removed = 0;
    let entries = match fs::read_dir(parent) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(e),
    };
    for entry in entries {
        let entry = entry?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        if !name.starts_with('.') || !name.contains(".partial-") || !entry.file_type()?.is_dir() {
            continue;
        }
        if let Some(Manifest::Partial(owner)) = manifest::read(&entry.path())
            && owner.is_dead()
        {
            fs::remove_dir_all(entry.path())?;
            removed += 1;
        }
    }
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_dead_processes_partial_folders_are_swept() {
        let dir = tempfile::tempdir().unwrap();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead_pid = child.id();
        child.wait().unwrap();
        let mut dead = manifest::Owner::this_process();
        dead.pid = dead_pid;
        dead.start = 1;
        let alive = manifest::Owner::this_process();
        let mut elsewhere = dead.clone();
        elsewhere.host = "another-machine".into();
        for (name, owner) in [
            (".a.partial-1-1", Some(&dead)),
            (".b.partial-2-2", Some(&alive)),
            (".c.partial-3-3", Some(&elsewhere)),
            (".d.partial-4-4", None),
        ] {
            let p = dir.path().join(name);
            fs::create_dir(&p).unwrap();
            fs::write(p.join("world.obj"), b"...").unwrap();
            if let Some(o) = owner {
                fs::write(p.join(manifest::FILE), manifest::partial_text(o)).unwrap();
            }
        }
        assert_eq!(sweep_stale(dir.path()).unwrap(), 1);
        let mut left: Vec<String> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        left.sort();
        assert_eq!(left, [".b.partial-2-2", ".c.partial-3-3", ".d.partial-4-4"]);
    }
}
