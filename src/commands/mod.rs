//! One file per subcommand: its arguments, its request, and what it prints.

pub mod dataset;
pub mod explore;
pub mod generate;
pub mod plugins;
pub mod presets;
pub mod preview;
pub mod report;
pub mod score;
pub mod sense;
pub mod stats;
pub mod validate;

use std::io::Write;

/// Prints to standard output; a closed one (`| head`) is not an error.
pub fn print(text: &str) {
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// Says on standard error which exporters were left out under `--no-mesh`, one line each.
pub fn note_skipped(names: &[String]) {
    for name in names {
        eprintln!(
            "note: skipping exporter '{name}': it writes geometry, and --no-mesh asked for none"
        );
    }
}
