//! Records what a plugin must match to be loaded: the compiler version, and a fingerprint of
//! the sources whose types cross the library boundary (this crate and `subtgraph-core`). The
//! crate version alone is not enough: a checkout changes those types without changing its
//! version, and a plugin built against other sources would be read with the wrong layout.
use std::path::{Path, PathBuf};

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

fn main() {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = std::process::Command::new(rustc)
        .arg("-V")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
        .unwrap_or_else(|_| "unknown rustc".into());
    println!("cargo:rustc-env=SUBTGRAPH_RUSTC_VERSION={version}");
    println!("cargo:rerun-if-env-changed=RUSTC");

    let here = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let mut files = Vec::new();
    for dir in [here.join("src"), here.join("../core/src")] {
        println!("cargo:rerun-if-changed={}", dir.display());
        sources(&dir, &mut files);
    }
    // Sorted by path relative to its crate, so the fingerprint does not depend on where the
    // checkout is.
    let mut named: Vec<(String, PathBuf)> = files
        .into_iter()
        .map(|p| {
            let rel = p
                .strip_prefix(&here)
                .map(|r| r.to_string_lossy().into_owned())
                .unwrap_or_else(|_| p.to_string_lossy().into_owned());
            (rel, p)
        })
        .collect();
    named.sort();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for (rel, path) in &named {
        for b in rel.bytes().chain(std::fs::read(path).unwrap_or_default()) {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    println!("cargo:rustc-env=SUBTGRAPH_ABI_FINGERPRINT={h:016x}");
}
