//! Loading plugin libraries (host side).
#![allow(unsafe_code)]

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use subtgraph_core::registry::{DuplicateName, Registry};

use crate::{
    ABI_FINGERPRINT, API_VERSION, CRATE_VERSION, PluginDeclaration, PluginFailure, PluginInfo,
    RUSTC_VERSION, Registrar, SYMBOL,
};

/// Why a plugin was refused. Each says what to rebuild or fix.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PluginError {
    /// No file at the path.
    #[error("plugin {0}: no such file; build the plugin (cargo build --release) or fix the path")]
    Missing(PathBuf),
    /// A folder was named instead of a library file.
    #[error("plugin {path}: is a folder, not a library; name the library file itself{hint}")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The libraries found in it, as a hint.
        hint: String,
    },
    /// The file is not a loadable library.
    #[error("plugin {path}: cannot be loaded as a shared library: {reason}")]
    Open {
        /// The file.
        path: PathBuf,
        /// What the system said.
        reason: String,
    },
    /// The library has no declaration.
    #[error(
        "plugin {0}: no `{SYMBOL}` symbol; it is not a subtgraph plugin (declare it with \
         subtgraph_plugins::declare_plugin! and build it as a cdylib)"
    )]
    NotAPlugin(PathBuf),
    /// Built against another plugin API.
    #[error(
        "plugin {path}: built for plugin API {found}, this subtgraph speaks {API_VERSION}; rebuild the \
         plugin against subtgraph-plugins {CRATE_VERSION}"
    )]
    Api {
        /// The file.
        path: PathBuf,
        /// Its API version.
        found: u32,
    },
    /// Built by another compiler or against other crate versions.
    #[error(
        "plugin {path}: built with {found_rustc} against subtgraph {found_version}; this subtgraph is \
         built with {RUSTC_VERSION}, version {CRATE_VERSION}. Rebuild the plugin with the same \
         compiler and crate version (Rust has no stable ABI)"
    )]
    Build {
        /// The file.
        path: PathBuf,
        /// Its compiler.
        found_rustc: String,
        /// Its crate version.
        found_version: String,
    },
    /// Built against other sources of the same version (a different checkout).
    #[error(
        "plugin {path}: built against other subtgraph sources (fingerprint {found}, this subtgraph \
         has {ABI_FINGERPRINT}) of the same version; rebuild the plugin against the same checkout \
         or release as this subtgraph"
    )]
    Sources {
        /// The file.
        path: PathBuf,
        /// Its fingerprint.
        found: String,
    },
    /// Its registration panicked.
    #[error("{0}")]
    Panicked(String),
    /// It registered a name that is taken.
    #[error("plugin {path}: {source}")]
    Duplicate {
        /// The file.
        path: PathBuf,
        /// The clash.
        source: DuplicateName,
    },
}

/// A loaded plugin: what it is and what it registered.
#[derive(Debug, Clone)]
pub struct LoadedPlugin {
    /// Its declared name and path.
    pub info: Arc<PluginInfo>,
    /// `(kind, name, summary)` of each component it registered.
    pub components: Vec<(&'static str, String, String)>,
}

/// Libraries stay loaded for the life of the process: the code and vtables of everything a
/// plugin made live in them.
static LIBRARIES: Mutex<Vec<(libloading::Library, LoadedPlugin)>> = Mutex::new(Vec::new());

/// The plugins loaded so far.
pub fn loaded() -> Vec<LoadedPlugin> {
    LIBRARIES
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .map(|(_, p)| p.clone())
        .collect()
}

/// An error for the first failure recorded by any loaded plugin's code (a panic caught inside
/// the plugin), so the host never writes a world a plugin failed to make properly.
pub fn check_failures() -> Result<(), PluginFailure> {
    for p in loaded() {
        if let Some(message) = p
            .info
            .failure
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
        {
            return Err(PluginFailure { message });
        }
    }
    Ok(())
}

/// Loads a plugin library and adds its components to `registry`. Either all its components
/// are added or none.
pub fn load(path: &Path, registry: &mut Registry) -> Result<LoadedPlugin, PluginError> {
    if path.is_dir() {
        let suffix = std::env::consts::DLL_SUFFIX;
        let mut libs: Vec<String> = std::fs::read_dir(path)
            .into_iter()
            .flatten()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(suffix))
            .collect();
        libs.sort();
        let hint = match libs.first() {
            Some(first) => format!(
                ", e.g. {} (the folder holds {})",
                path.join(first).display(),
                libs.join(", ")
            ),
            None => format!(
                " (the folder holds no {suffix} file; `cargo build --release` in the plugin's crate puts it under target/release/)"
            ),
        };
        return Err(PluginError::Folder {
            path: path.to_owned(),
            hint,
        });
    }
    if !path.is_file() {
        return Err(PluginError::Missing(path.to_owned()));
    }
    // SAFETY: loading a library runs its initialisers. That is the point of a plugin, and the
    // user named this file; nothing else is called before the declaration is checked.
    let lib = unsafe { libloading::Library::new(path) }.map_err(|e| PluginError::Open {
        path: path.to_owned(),
        reason: e.to_string(),
    })?;
    let decl: *const PluginDeclaration = {
        // SAFETY: the symbol, if present, is the static `PluginDeclaration` made by
        // `declare_plugin!`; we only take its address here.
        let sym = unsafe { lib.get::<*const PluginDeclaration>(SYMBOL.as_bytes()) };
        match sym {
            Ok(s) => *s,
            Err(_) => return Err(PluginError::NotAPlugin(path.to_owned())),
        }
    };
    // SAFETY: `api_version` is the first field of a `#[repr(C)]` struct in every API version,
    // so it can be read whatever the plugin was built with.
    let api = unsafe { std::ptr::addr_of!((*decl).api_version).read() };
    if api != API_VERSION {
        return Err(PluginError::Api {
            path: path.to_owned(),
            found: api,
        });
    }
    // SAFETY: same API version, so the declaration has this layout; it is a static in the
    // library, which stays loaded.
    let decl: &PluginDeclaration = unsafe { &*decl };
    if decl.rustc_version.text() != RUSTC_VERSION || decl.crate_version.text() != CRATE_VERSION {
        return Err(PluginError::Build {
            path: path.to_owned(),
            found_rustc: decl.rustc_version.text().into_owned(),
            found_version: decl.crate_version.text().into_owned(),
        });
    }
    if decl.abi_fingerprint != ABI_FINGERPRINT {
        return Err(PluginError::Sources {
            path: path.to_owned(),
            found: decl.abi_fingerprint.to_owned(),
        });
    }
    let info = Arc::new(PluginInfo {
        name: decl.name.to_owned(),
        path: path.display().to_string(),
        failure: Mutex::new(None),
    });
    let mut scratch = Registry::empty();
    let components = {
        let mut r = Registrar::new(&mut scratch, info.clone());
        (decl.register)(&mut r).map_err(PluginError::Panicked)?;
        r.registered
    };
    if let Some(f) = info
        .failure
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .take()
    {
        return Err(PluginError::Panicked(f));
    }
    registry
        .merge(scratch)
        .map_err(|source| PluginError::Duplicate {
            path: path.to_owned(),
            source,
        })?;
    let plugin = LoadedPlugin { info, components };
    LIBRARIES
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push((lib, plugin.clone()));
    Ok(plugin)
}
