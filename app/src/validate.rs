//! `validate`: a pipeline file checked without meshing: its syntax, keys and component names,
//! that its layout can be made, and that its tile set can build that layout. Quick even for
//! large worlds (`generate` makes the mesh).

use std::path::PathBuf;

use subtgraph_core::{Budget, Layout, Pipeline, Registry};

use crate::Error;
use crate::pipeline::{self, PipelineSource};

/// What `validate` is asked.
#[derive(Clone, Debug, Default)]
pub struct ValidateRequest {
    /// The pipeline file.
    pub pipeline: PathBuf,
    /// Plugin libraries besides the pipeline's `[plugins] paths`.
    pub plugins: Vec<PathBuf>,
}

/// A valid pipeline's world, as its seed lays it out.
#[derive(Clone, Debug)]
pub struct Validated {
    /// The layout (no mesh).
    pub layout: Layout,
}

impl ValidateRequest {
    /// Checks the pipeline; an error says what is wrong, a pipeline that parses but whose
    /// world cannot be made naming the file.
    pub fn run(&self) -> Result<Validated, Error> {
        let (p, _) = PipelineSource::File(self.pipeline.clone()).load()?;
        let registry = crate::registry_with(&p, &self.plugins)?;
        let layout = match layout_checked(&p, &registry) {
            Ok(l) => l,
            Err(e @ subtgraph_core::Error::Config(_)) => return Err(e.into()),
            Err(source) => {
                return Err(Error::Unmakeable {
                    pipeline: self.pipeline.clone(),
                    source: Box::new(source),
                });
            }
        };
        pipeline::check_plugins()?;
        Ok(Validated { layout })
    }
}

/// The layout of a pipeline's world, checked by its tile set as `generate` checks it before
/// meshing ([`subtgraph_core::assembly::check`]: passages that fit the tiles and the levels,
/// hazards and ramps it can make), without meshing. Every component is built once, exporters
/// included.
fn layout_checked(p: &Pipeline, registry: &Registry) -> Result<Layout, subtgraph_core::Error> {
    let components = p.build(registry)?;
    let layout = subtgraph_core::layout_with(p, &components, &Budget::unlimited())?;
    if let Some(t) = &components.tileset {
        subtgraph_core::assembly::check(&layout, t.tileset.as_ref()).map_err(|e| {
            subtgraph_core::Error::Component {
                component: "tile set",
                name: t.name.clone(),
                message: e.to_string(),
            }
        })?;
    }
    Ok(layout)
}
