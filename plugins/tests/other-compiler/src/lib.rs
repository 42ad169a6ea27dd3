//! Claims another compiler: the loader must refuse it before calling anything.

fn register(_: &mut subtgraph_plugins::Registrar<'_>) -> Result<(), String> {
    panic!("must never be called")
}

/// A declaration as another compiler's build would have it.
#[unsafe(no_mangle)]
pub static SUBTGRAPH_PLUGIN: subtgraph_plugins::PluginDeclaration =
    subtgraph_plugins::PluginDeclaration {
        api_version: subtgraph_plugins::API_VERSION,
        rustc_version: subtgraph_plugins::FixedText::new("rustc 1.0.0 (a28ed8e2a 2015-05-13)"),
        crate_version: subtgraph_plugins::FixedText::new(subtgraph_plugins::CRATE_VERSION),
        abi_fingerprint: subtgraph_plugins::ABI_FINGERPRINT,
        name: "other-compiler",
        register,
    };
