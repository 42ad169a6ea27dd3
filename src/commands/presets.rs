//! `subtgraph presets`.

use subtgraph::app::Error;
use subtgraph::presets;

/// Lists the presets.
pub fn run() -> Result<(), Error> {
    let mut text = String::new();
    for (name, _) in presets::PRESETS {
        text.push_str(&format!("{name:<10} {}\n", presets::summary(name)));
    }
    text.push_str(
        "\nUse one with `subtgraph generate --preset NAME --out DIR`; their files are in examples/.\n",
    );
    super::print(&text);
    Ok(())
}
