//! Records the compiler version, so a plugin built by another compiler is refused at load.
fn main() {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let out = std::process::Command::new(rustc)
        .arg("-V")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
        .unwrap_or_else(|_| "unknown rustc".into());
    println!("cargo:rustc-env=SUBTGRAPH_RUSTC_VERSION={out}");
    println!("cargo:rerun-if-env-changed=RUSTC");
}
