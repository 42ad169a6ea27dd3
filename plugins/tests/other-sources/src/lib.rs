//! Claims the right compiler and version but other sources (as a plugin built against an
//! older checkout would): the loader must refuse it before calling anything.

fn register(_: &mut subtgraph_plugins::Registrar<'_>) -> Result<(), String> {
    panic!("must never be called")
}

/// A declaration as a build from another checkout of the same version would have it.
#[unsafe(no_mangle)]
pub static SUBTGRAPH_PLUGIN: subtgraph_plugins::PluginDeclaration =
    subtgraph_plugins::PluginDeclaration {
        api_version: subtgraph_plugins::API_VERSION,
        rustc_version: subtgraph_plugins::FixedText::new(subtgraph_plugins::RUSTC_VERSION),
        crate_version: subtgraph_plugins::FixedText::new(subtgraph_plugins::CRATE_VERSION),
        abi_fingerprint: "0000000000000000",
        name: "other-sources",
        register,
    };
