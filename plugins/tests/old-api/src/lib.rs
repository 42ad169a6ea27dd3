//! Declares plugin API 0: the loader must refuse it before calling anything.

fn register(_: &mut subtgraph_plugins::Registrar<'_>) -> Result<(), String> {
    panic!("must never be called")
}

/// A declaration from an older plugin API.
#[unsafe(no_mangle)]
pub static SUBTGRAPH_PLUGIN: subtgraph_plugins::PluginDeclaration =
    subtgraph_plugins::PluginDeclaration {
        api_version: 0,
        rustc_version: subtgraph_plugins::FixedText::new(subtgraph_plugins::RUSTC_VERSION),
        crate_version: subtgraph_plugins::FixedText::new(subtgraph_plugins::CRATE_VERSION),
        abi_fingerprint: subtgraph_plugins::ABI_FINGERPRINT,
        name: "old-api",
        register,
    };
