//! The presets: the paper's Table 1 environments, kept as pipeline files in `examples/` and
//! compiled into the binary so `--preset` works wherever the tool is installed.

use subtgraph_core::{ConfigError, Pipeline};

/// `(name, pipeline text)` of every preset.
pub const PRESETS: [(&str, &str); 3] = [
    ("mine", include_str!("../../examples/mine.toml")),
    ("cave", include_str!("../../examples/cave.toml")),
    ("lava-tube", include_str!("../../examples/lava-tube.toml")),
];

/// The text of a preset.
pub fn text(name: &str) -> Option<&'static str> {
    PRESETS.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// The first comment line of a preset: what it is.
pub fn summary(name: &str) -> &'static str {
    text(name)
        .and_then(|t| t.lines().next())
        .map_or("", |l| l.trim_start_matches('#').trim())
}

/// Parses a preset. `None` for an unknown name.
pub fn load(name: &str) -> Option<Pipeline> {
    text(name).map(|t| parse(name, t).expect("presets are valid"))
}

fn parse(name: &str, text: &str) -> Result<Pipeline, ConfigError> {
    Pipeline::parse(text, &format!("examples/{name}.toml"))
}

/// The folder the presets' files are in (`examples/` of the repository): relative paths in a
/// preset are read from there.
pub fn examples_dir() -> std::path::PathBuf {
    let app = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    app.parent().unwrap_or(app).join("examples")
}

/// The preset names, comma separated, for messages.
pub fn names() -> String {
    PRESETS.map(|(n, _)| n).join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_parses_and_has_a_summary() {
        for (name, text) in PRESETS {
            parse(name, text).unwrap();
            assert!(!summary(name).is_empty());
        }
        assert!(load("ice-cave").is_none());
    }
}
