//! Plugins: the example plugins (a route descriptor, a constraint shape, a tile set and an
//! exporter) build and generate a world end to end through the command line, and every
//! refusal of the loader has its test. The libraries are built by `scripts/build`,
//! which `scripts/test` runs first.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn subtgraph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_subtgraph"))
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("the binary runs")
}

/// Where cargo put this build's libraries.
fn library(crate_name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_BIN_EXE_subtgraph")).parent().unwrap();
    let file = format!(
        "{}{}{}",
        std::env::consts::DLL_PREFIX,
        crate_name.replace('-', "_"),
        std::env::consts::DLL_SUFFIX
    );
    let p = dir.join(file);
    assert!(
        p.is_file(),
        "{} is missing: build the example plugins first with `scripts/build` (scripts/test does)",
        p.display()
    );
    p
}

fn pipeline(dir: &Path, extra_route: &str) -> PathBuf {
    let libs: Vec<String> = ["meander", "y-fork", "ice-cave", "ply"]
        .iter()
        .map(|n| {
            format!(
                "{:?}",
                library(&format!("subtgraph-plugin-{n}"))
                    .display()
                    .to_string()
            )
        })
        .collect();
    let text = format!(
        "[world]\nseed = 3\nrows = 36\ncols = 36\n\
         [topology]\nloops = 0\nt_junctions = 1\nintersections = 0\n\
         [[topology.structure]]\ntype = \"y-fork\"\ncount = 2\n\
         [route]\ntype = \"meander\"\nwavelength = 6\n{extra_route}\
         [tileset]\ntype = \"ice-cave\"\nresolution = 12\n\
         [[export]]\ntype = \"ply\"\n\
         [[export]]\ntype = \"obj\"\n\
         [plugins]\npaths = [{}]\n",
        libs.join(", ")
    );
    let p = dir.join("plugins.toml");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn four_example_plugins_make_a_world_end_to_end() {
    let tmp = tempfile::tempdir().unwrap();
    let p = pipeline(tmp.path(), "");
    let out = tmp.path().join("w");
    let o = subtgraph(&[
        "generate",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The constraint shape: requested and counted.
    let topo: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("topology.json")).unwrap()).unwrap();
    assert_eq!(topo["per_level"][0]["requested"]["y-fork"], 2);
    assert!(
        topo["per_level"][0]["achieved"]["t_junctions"]
            .as_u64()
            .unwrap()
            >= 3
    );
    assert_eq!(topo["connected"], true);
    // The tile set: its materials in the MTL.
    let mtl = std::fs::read_to_string(out.join("mesh/world.mtl")).unwrap();
    assert!(mtl.contains("newmtl ice-wall"), "{mtl}");
    // The exporter: a PLY whose counts match the OBJ.
    let ply = std::fs::read_to_string(out.join("mesh/world.ply")).unwrap();
    let obj = std::fs::read_to_string(out.join("mesh/world.obj")).unwrap();
    let count = |prefix: &str| obj.lines().filter(|l| l.starts_with(prefix)).count();
    assert!(ply.contains(&format!("element vertex {}", count("v "))));
    assert!(ply.contains(&format!("element face {}", count("f "))));
    // The route descriptor is recorded with its parameters in world.toml.
    let toml = std::fs::read_to_string(out.join("world.toml")).unwrap();
    assert!(
        toml.contains("type = \"meander\"") && toml.contains("wavelength = 6"),
        "{toml}"
    );

    // The same world again, with the plugins given on the command line instead.
    let text = std::fs::read_to_string(&p).unwrap();
    let no_plugins = tmp.path().join("no-plugins.toml");
    std::fs::write(&no_plugins, text.split("[plugins]").next().unwrap()).unwrap();
    let again = tmp.path().join("again");
    let mut args = vec![
        "generate".to_owned(),
        no_plugins.display().to_string(),
        "--out".into(),
        again.display().to_string(),
    ];
    for n in ["meander", "y-fork", "ice-cave", "ply"] {
        args.push("--plugin".into());
        args.push(
            library(&format!("subtgraph-plugin-{n}"))
                .display()
                .to_string(),
        );
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = subtgraph(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(out.join("occupancy.npy")).unwrap(),
        std::fs::read(again.join("occupancy.npy")).unwrap()
    );
}

#[test]
fn plugins_list_shows_what_each_registers() {
    let libs: Vec<String> = ["meander", "y-fork", "ice-cave", "ply", "template"]
        .iter()
        .map(|n| {
            library(&format!("subtgraph-plugin-{n}"))
                .display()
                .to_string()
        })
        .collect();
    let mut args = vec!["plugins", "list"];
    args.extend(libs.iter().map(String::as_str));
    let o = subtgraph(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    for (kind, name) in [
        ("route descriptor", "meander"),
        ("constraint shape", "y-fork"),
        ("tile set", "ice-cave"),
        ("exporter", "ply"),
        ("route descriptor", "wiggle"),
    ] {
        assert!(
            text.lines().any(|l| l.contains(kind) && l.contains(name)),
            "{name} in:\n{text}"
        );
    }
    let builtins = String::from_utf8_lossy(&subtgraph(&["plugins", "list"]).stdout).into_owned();
    assert!(
        builtins.contains("parabolic") && builtins.contains("lava-tube"),
        "{builtins}"
    );
}

fn refused(args: &[&str]) -> String {
    let o = subtgraph(args);
    assert!(!o.status.success(), "{args:?} should be refused");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn the_loader_refuses_what_it_cannot_trust_and_says_what_to_rebuild() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("w");
    let o = out.to_str().unwrap();
    let with_plugin = |plugin: &str| {
        refused(&[
            "generate",
            "--preset",
            "cave",
            "--no-mesh",
            "--plugin",
            plugin,
            "--out",
            o,
        ])
    };

    let err = with_plugin("no/such/plugin.so");
    assert!(
        err.contains("no such file") && err.contains("cargo build"),
        "{err}"
    );

    let text = tmp.path().join("not-a-library.so");
    std::fs::write(&text, "hello").unwrap();
    let err = with_plugin(text.to_str().unwrap());
    assert!(
        err.contains("cannot be loaded as a shared library"),
        "{err}"
    );

    // A real shared library without the declaration: a proc-macro from this build.
    let deps = Path::new(env!("CARGO_BIN_EXE_subtgraph"))
        .parent()
        .unwrap()
        .join("deps");
    let foreign = std::fs::read_dir(&deps)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            n.starts_with(&format!("{}serde_derive", std::env::consts::DLL_PREFIX))
                && n.ends_with(std::env::consts::DLL_SUFFIX)
        })
        .expect("serde_derive is built as a shared library");
    let err = with_plugin(foreign.to_str().unwrap());
    assert!(
        err.contains("no `SUBTGRAPH_PLUGIN` symbol") && err.contains("declare_plugin!"),
        "{err}"
    );

    let err = with_plugin(library("subtgraph-test-plugin-old-api").to_str().unwrap());
    assert!(
        err.contains("plugin API 0") && err.contains("rebuild the plugin"),
        "{err}"
    );

    let err = with_plugin(
        library("subtgraph-test-plugin-other-compiler")
            .to_str()
            .unwrap(),
    );
    assert!(
        err.contains("rustc 1.0.0") && err.contains("same compiler"),
        "{err}"
    );

    let err = with_plugin(
        library("subtgraph-test-plugin-other-sources")
            .to_str()
            .unwrap(),
    );
    assert!(
        err.contains("other subtgraph sources") && err.contains("same checkout"),
        "{err}"
    );

    // The same plugin twice: its names are taken.
    let meander = library("subtgraph-plugin-meander");
    let err = refused(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--plugin",
        meander.to_str().unwrap(),
        "--plugin",
        meander.to_str().unwrap(),
        "--out",
        o,
    ]);
    assert!(
        err.contains("'meander'") && err.contains("already registered"),
        "{err}"
    );

    // Nothing was written by any of these.
    assert!(!out.exists());
    assert_eq!(
        std::fs::read_dir(tmp.path()).unwrap().count(),
        1,
        "only the test file remains"
    );
}

#[test]
fn a_panic_inside_a_plugin_is_an_error_naming_it_not_an_abort() {
    let tmp = tempfile::tempdir().unwrap();
    let p = pipeline(tmp.path(), "panic_after = 0.5\n");
    let out = tmp.path().join("w");
    let o = subtgraph(&[
        "generate",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "an error exit, not an abort");
    let err = String::from_utf8_lossy(&o.stderr);
    let last = err.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("error: plugin 'meander'") && last.contains("panicked"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
    // A plugin's own validation errors read like the built-ins'.
    let bad = tmp.path().join("bad.toml");
    let text = std::fs::read_to_string(&p)
        .unwrap()
        .replace("wavelength = 6", "wavelength = 1");
    std::fs::write(&bad, text).unwrap();
    let err = refused(&["validate", bad.to_str().unwrap()]);
    assert!(
        err.contains("route.wavelength: must be at least 2 cells"),
        "{err}"
    );
}

#[test]
fn a_plugin_tile_set_estimates_its_meshes_before_any_tile_is_made() {
    // The loader's wrapper forwards `TileSet::estimate` and `detail_advice` (it once skipped
    // them, so a plugin's world was measured on its first tiles and the advice lost).
    let tmp = tempfile::tempdir().unwrap();
    let p = pipeline(tmp.path(), "");
    let out = tmp.path().join("w");
    let o = subtgraph(&[
        "generate",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--max-memory",
        "1M",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "a 1 MB budget was enough");
    assert!(err.contains("estimated"), "{err}");
    assert!(err.contains("lower [tileset] resolution"), "{err}");
    assert!(!out.exists());
}
