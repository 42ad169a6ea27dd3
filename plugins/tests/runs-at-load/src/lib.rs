//! A valid plugin that registers nothing, whose library runs a constructor as soon as the
//! system loads it (before the loader reads its declaration, as any shared library may):
//! the constructor writes the file `SUBTGRAPH_TEST_MARKER` names. The tests of issue 37 show
//! that reading or sensing a world folder whose `world.toml` names this library never loads
//! it unless the user names it (`--plugin`): the marker never appears.

fn register(_: &mut subtgraph_plugins::Registrar<'_>) {}

subtgraph_plugins::declare_plugin!("runs-at-load", register);

/// Writes the marker file, if the test asked for one.
#[cfg(target_os = "linux")]
extern "C" fn at_load() {
    if let Some(path) = std::env::var_os("SUBTGRAPH_TEST_MARKER") {
        let _ = std::fs::write(path, b"this library's code ran\n");
    }
}

/// The constructor: the dynamic loader calls every function of `.init_array` when it loads
/// the library, before `dlopen` returns.
// SAFETY: `at_load` takes nothing and returns nothing, as an `.init_array` entry must; it only
// reads the environment and writes a file.
#[cfg(target_os = "linux")]
#[used]
#[unsafe(link_section = ".init_array")]
static AT_LOAD: extern "C" fn() = at_load;
