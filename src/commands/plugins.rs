//! `subtgraph plugins list`.

use std::path::PathBuf;

use subtgraph::app::plugins::Plugins;
use subtgraph::app::{Error, PluginsRequest};

/// `plugins`'s subcommands.
#[derive(clap::Subcommand)]
pub enum Command {
    /// Load plugin libraries and list the components each registers (without PATH: the
    /// built-in components).
    List {
        /// Plugin libraries (.so, .dylib, .dll).
        paths: Vec<PathBuf>,
    },
}

/// Lists the components.
pub fn run(c: Command) -> Result<(), Error> {
    let Command::List { paths } = c;
    let mut text = String::new();
    match (PluginsRequest { paths }).run()? {
        Plugins::BuiltIn(all) => {
            text.push_str("built-in components:\n");
            for c in all {
                text.push_str(&format!("  {:<17} {:<16} {}\n", c.kind, c.name, c.summary));
            }
        }
        Plugins::Loaded(plugins) => {
            for p in plugins {
                text.push_str(&format!("{} ({})\n", p.name, p.path));
                for (kind, name, summary) in &p.components {
                    text.push_str(&format!("  {kind:<17} {name:<16} {summary}\n"));
                }
            }
        }
    }
    super::print(&text);
    Ok(())
}
