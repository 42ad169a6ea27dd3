//! `subtgraph sense`'s host: what the sensors crate needs from the command line, namely a
//! world folder's world rebuilt from its `world.toml` with every built-in and the plugins it
//! names, and the atomic folder of [`crate::folder`].
//!
//! Why rebuild rather than read the folder's `mesh/collision.obj`: the OBJ exists only when
//! the world was exported to OBJ, carries no materials (which set the LiDAR's intensities),
//! and is slower to parse than the world is to make again (see docs/src/sensors.md for the
//! numbers); a world records its seed and its whole resolved pipeline, so it comes back
//! exactly, and `sense` checks the rebuilt graph against the folder's.

use std::path::Path;

use subtgraph_sensors::{Host, SenseError};

/// The command line as the sensors' host.
pub struct CommandLine;

impl Host for CommandLine {
    fn world(&self, folder: &Path) -> Result<subtgraph_core::World, String> {
        let run = || -> anyhow::Result<subtgraph_core::World> {
            let (mut p, _) = crate::make::load_pipeline(Some(&folder.join("world.toml")), None)?;
            // The exporters write files; the world is what is wanted.
            p.export.clear();
            let registry = crate::make::registry_with(&p, &[])?;
            let components = crate::make::build(&p, &registry, false)?;
            let budget = crate::memory::budget(None)?;
            crate::make::generate(&p, &components, &folder.display().to_string(), &budget)
        };
        run().map_err(|e| {
            format!(
                "rebuilding the world of {}: {}",
                folder.display(),
                crate::make::message(&e)
            )
        })
    }

    fn write_folder(
        &self,
        out: &Path,
        force: bool,
        fill: &mut dyn FnMut(&Path) -> Result<(), SenseError>,
    ) -> Result<(), SenseError> {
        if let Some((parent, n)) = crate::folder::sweep_stale_beside(out) {
            eprintln!(
                "note: removed {n} unfinished folder(s) in {} left by runs that were killed",
                parent.display()
            );
        }
        let mut failure = None;
        let placed = crate::folder::write_atomically(out, force, |w| {
            fill(w.root()).map_err(|e| {
                let message = e.to_string();
                failure = Some(e);
                anyhow::anyhow!(message)
            })
        });
        match (placed, failure) {
            (Ok(()), _) => Ok(()),
            (Err(_), Some(e)) => Err(e),
            (Err(e), None) => Err(SenseError::Host(e.to_string())),
        }
    }

    fn progress(&self, scan: u64, of: u64) {
        if (scan + 1) % 500 == 0 || scan + 1 == of {
            eprint!("\r  scan {} of {of}", scan + 1);
            if scan + 1 == of {
                eprintln!();
            }
        }
    }
}
