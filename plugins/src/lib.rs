//! # subtgraph-plugins
//!
//! Loading route descriptors, constraint shapes, tile sets and exporters from shared
//! libraries into the same [`Registry`](subtgraph_core::Registry) the built-ins use. The
//! registry is already plugin-ready (plain data owned by the host, looked up by name at run
//! time); the loader itself comes with the plugins stage.
