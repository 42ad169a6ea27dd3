//! `world.toml`: the resolved pipeline, which regenerates the world with
//! `subtgraph generate world.toml`.

use subtgraph_core::World;
use subtgraph_core::config::Provenance;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::survey::Survey;

/// Writes `world.toml`.
#[derive(Clone, Copy, Debug, Default)]
pub struct WorldToml;

impl Exporter for WorldToml {
    fn export(
        &self,
        _world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        write_file(
            out,
            "world.toml",
            world_toml_text(survey.record()).as_bytes(),
        )
    }
}

/// The text of `world.toml` for a resolved pipeline: what a world made from it holds, so a
/// dataset run can tell whether a world on disk is the one it would make without making it.
pub fn world_toml_text(resolved: &subtgraph_core::Pipeline) -> String {
    let mut p = resolved.clone();
    if p.generated.is_none() {
        p.generated = Some(Provenance {
            tool: "subtgraph".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            source: None,
        });
    }
    format!(
        "# The resolved pipeline of this world: every range drawn, every level's structure\n\
         # counts written out. `subtgraph generate world.toml --out DIR` makes it again.\n{}",
        p.to_toml()
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn world_toml_parses_back_into_the_resolved_pipeline() {
        let world = crate::test_world();
        let mut out = MemoryWriter::default();
        WorldToml
            .export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let text = std::str::from_utf8(out.get("world.toml").unwrap()).unwrap();
        let back = subtgraph_core::Pipeline::parse(text, "world.toml").unwrap();
        assert_eq!(back.resolve().unwrap().1, world.resolved);
        assert_eq!(back.generated.unwrap().version, env!("CARGO_PKG_VERSION"));
    }
}
