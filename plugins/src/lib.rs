//! # subtgraph-plugins
//!
//! Route descriptors, constraint shapes, tile sets and exporters from shared libraries, in the
//! same [`Registry`] as the built-ins: the same `type` lookup, the same error messages.
//!
//! ## Writing a plugin
//!
//! A plugin is a `cdylib` crate depending on `subtgraph-core` and `subtgraph-plugins` (the same
//! versions as the `subtgraph` that loads it) that declares itself once:
//!
//! ```ignore
//! fn register(r: &mut subtgraph_plugins::Registrar<'_>) {
//!     r.route_descriptor("meander", "a meandering corridor", |params| {
//!         Ok(Box::new(Meander::from_params(params)?))
//!     });
//! }
//! subtgraph_plugins::declare_plugin!("meander", register);
//! ```
//!
//! ## The ABI rules, and why
//!
//! - Rust has no stable ABI, so trait objects cross the library boundary only between the same
//!   compiler and the same `subtgraph-core`. The declaration carries the plugin API version,
//!   the compiler version, the crate version and a fingerprint of the sources whose types
//!   cross the boundary (a checkout changes them without changing its version); the loader
//!   checks all of them before calling anything, and refuses with what to rebuild.
//! - Each shared library carries its own copy of the standard library, so a panic must never
//!   unwind out of plugin code into the host (the host's runtime would see a foreign exception
//!   and abort). Everything a plugin hands the host is therefore wrapped, in the plugin, by
//!   [`Registrar`]: its factories and every method of what they build run under
//!   `catch_unwind`; a panic becomes an error naming the plugin (for methods that return
//!   plain values, a neutral value is returned and the failure is recorded, and the host turns
//!   it into an error before writing anything).
//! - A loaded library is never unloaded: the code and vtables of everything it made live in it.
//! - Both sides use the system allocator (Rust's default), so memory allocated on one side may
//!   be freed on the other. Do not set a custom `#[global_allocator]` in a plugin.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Arc, Mutex};

use subtgraph_core::World;
use subtgraph_core::budget::TileTriangles;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter};
use subtgraph_core::layout::Layout;
use subtgraph_core::mesh::Material;
use subtgraph_core::params::Params;
use subtgraph_core::registry::{Catalogue, Registry};
use subtgraph_core::route::{RouteDescriptor, Segment};
use subtgraph_core::shape::{Arm, ConstraintShape, Heading, Offset};
use subtgraph_core::survey::Survey;
use subtgraph_core::tile::TileKind;
use subtgraph_core::tileset::{CrossSection, TileContext, TileGeometry, TileSet, TileSetError};

mod loader;

pub use loader::{LoadedPlugin, PluginError, check_failures, load, loaded};

/// The plugin API version: bumped whenever the declaration or [`Registrar`] changes.
pub const API_VERSION: u32 = 6;
/// The compiler that built this copy of the crate.
pub const RUSTC_VERSION: &str = env!("SUBTGRAPH_RUSTC_VERSION");
/// The version of the subtgraph crates this copy belongs to.
pub const CRATE_VERSION: &str = env!("CARGO_PKG_VERSION");
/// A fingerprint of the sources of this crate and `subtgraph-core`: the types that cross the
/// library boundary. Two builds of the same version from different sources differ here.
pub const ABI_FINGERPRINT: &str = env!("SUBTGRAPH_ABI_FINGERPRINT");
/// The symbol a plugin exports.
pub const SYMBOL: &str = "SUBTGRAPH_PLUGIN";

/// What a plugin exports, under [`SYMBOL`]. Made by [`declare_plugin!`].
#[repr(C)]
pub struct PluginDeclaration {
    /// [`API_VERSION`] of the plugin's build. First, so it can be read before anything else.
    pub api_version: u32,
    /// [`RUSTC_VERSION`] of the plugin's build. Read before the compiler is known to be the
    /// same, so it is a [`FixedText`], whose layout every compiler agrees on (`&str`'s is not
    /// guaranteed).
    pub rustc_version: FixedText,
    /// [`CRATE_VERSION`] of the plugin's build; a [`FixedText`] for the same reason.
    pub crate_version: FixedText,
    /// [`ABI_FINGERPRINT`] of the plugin's build.
    pub abi_fingerprint: &'static str,
    /// The plugin's name.
    pub name: &'static str,
    /// Registers the plugin's components; runs the plugin's code under `catch_unwind`.
    pub register: fn(&mut Registrar<'_>) -> Result<(), String>,
}

/// Text of at most [`FixedText::CAPACITY`] bytes stored inline, with a `#[repr(C)]` layout:
/// the declaration's version strings are read before the loader knows the plugin was built by
/// the same compiler, and the layout of `&str` is not guaranteed across compilers.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct FixedText {
    len: u32,
    bytes: [u8; FixedText::CAPACITY],
}

impl FixedText {
    /// The longest text a `FixedText` holds, in bytes.
    pub const CAPACITY: usize = 124;

    /// `text` stored inline; a text longer than [`Self::CAPACITY`] fails to compile in a
    /// `static` (and panics elsewhere).
    pub const fn new(text: &str) -> FixedText {
        let b = text.as_bytes();
        assert!(
            b.len() <= Self::CAPACITY,
            "a FixedText holds at most 124 bytes"
        );
        let mut bytes = [0u8; Self::CAPACITY];
        let mut i = 0;
        while i < b.len() {
            bytes[i] = b[i];
            i += 1;
        }
        FixedText {
            len: b.len() as u32,
            bytes,
        }
    }

    /// The text (bytes that are not UTF-8, from a damaged or foreign library, replaced).
    pub fn text(&self) -> std::borrow::Cow<'_, str> {
        let len = (self.len as usize).min(Self::CAPACITY);
        String::from_utf8_lossy(&self.bytes[..len])
    }
}

/// A plugin's code failed: it panicked (caught inside the plugin) or registered a name that
/// is taken. The message names the plugin and the call; fix or remove the plugin.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct PluginFailure {
    /// What failed, naming the plugin.
    pub message: String,
}

/// Declares a plugin: `declare_plugin!("name", register_fn)`.
#[macro_export]
macro_rules! declare_plugin {
    ($name:expr, $register:path) => {
        fn __subtgraph_register(r: &mut $crate::Registrar<'_>) -> Result<(), String> {
            // The declaration's function returns the failure's text: what crosses the
            // library boundary.
            r.run_guarded("register", |r| $register(r))
                .map_err(|e| e.message)
        }

        /// The plugin's declaration, read by `subtgraph` when it loads this library.
        #[unsafe(no_mangle)]
        pub static SUBTGRAPH_PLUGIN: $crate::PluginDeclaration = $crate::PluginDeclaration {
            api_version: $crate::API_VERSION,
            rustc_version: $crate::FixedText::new($crate::RUSTC_VERSION),
            crate_version: $crate::FixedText::new($crate::CRATE_VERSION),
            abi_fingerprint: $crate::ABI_FINGERPRINT,
            name: $name,
            register: __subtgraph_register,
        };
    };
}

/// Who a component comes from, and whether its code has failed.
#[derive(Debug)]
pub struct PluginInfo {
    /// The plugin's declared name.
    pub name: String,
    /// The library's path.
    pub path: String,
    /// The first panic caught in the plugin's code.
    pub failure: Mutex<Option<String>>,
}

impl PluginInfo {
    fn fail(&self, what: &str, payload: Box<dyn std::any::Any + Send>) -> String {
        let text = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".into());
        let message = format!(
            "plugin '{}' ({}) panicked in {what}: {text}",
            self.name, self.path
        );
        let mut f = self.failure.lock().unwrap_or_else(|e| e.into_inner());
        if f.is_none() {
            *f = Some(message.clone());
        }
        message
    }
}

/// What a plugin registers its components with; every component is wrapped so its panics are
/// caught inside the plugin.
pub struct Registrar<'a> {
    registry: &'a mut Registry,
    info: Arc<PluginInfo>,
    /// `(kind, name, summary)` of everything registered.
    pub registered: Vec<(&'static str, String, String)>,
}

impl<'a> Registrar<'a> {
    /// A registrar adding to `registry` on behalf of a plugin.
    pub fn new(registry: &'a mut Registry, info: Arc<PluginInfo>) -> Self {
        Self {
            registry,
            info,
            registered: Vec::new(),
        }
    }

    /// Runs plugin code, turning a panic into an error naming the plugin.
    pub fn run_guarded<T>(
        &mut self,
        what: &str,
        f: impl FnOnce(&mut Self) -> T,
    ) -> Result<T, PluginFailure> {
        let info = self.info.clone();
        catch_unwind(AssertUnwindSafe(|| f(self))).map_err(|p| PluginFailure {
            message: info.fail(what, p),
        })
    }

    fn origin(&self) -> String {
        format!("plugin '{}' ({})", self.info.name, self.info.path)
    }

    fn note(
        &mut self,
        kind: &'static str,
        name: &str,
        summary: &str,
        result: Result<(), subtgraph_core::registry::DuplicateName>,
    ) {
        match result {
            Ok(()) => self
                .registered
                .push((kind, name.to_owned(), summary.to_owned())),
            Err(e) => {
                let mut f = self.info.failure.lock().unwrap_or_else(|e| e.into_inner());
                f.get_or_insert(e.to_string());
            }
        }
    }

    /// Registers a component in one catalogue: its factory, and everything the factory
    /// builds, run under `catch_unwind` here in the plugin.
    fn add<T: ?Sized + 'static, F>(
        &mut self,
        catalogue: fn(&mut Registry) -> &mut Catalogue<T>,
        wrap: fn(Box<T>, Arc<PluginInfo>) -> Box<T>,
        name: &str,
        summary: &str,
        factory: F,
    ) where
        F: Fn(&Params) -> Result<Box<T>, ConfigError> + Send + Sync + 'static,
    {
        let info = self.info.clone();
        let label = name.to_owned();
        let origin = self.origin();
        let target = catalogue(self.registry);
        let kind = target.kind();
        let result = target.register(
            name,
            &origin,
            summary,
            Arc::new(move |p: &Params| {
                let inner = guarded_build(&info, &label, kind, p, &factory)?;
                Ok(wrap(inner, info.clone()))
            }),
        );
        self.note(kind, name, summary, result);
    }

    /// Registers a route descriptor.
    pub fn route_descriptor<F>(&mut self, name: &str, summary: &str, factory: F)
    where
        F: Fn(&Params) -> Result<Box<dyn RouteDescriptor>, ConfigError> + Send + Sync + 'static,
    {
        self.add(
            |r| &mut r.route_descriptors,
            |inner, info| Box::new(Guarded { inner, info }),
            name,
            summary,
            factory,
        );
    }

    /// Registers a constraint shape.
    pub fn constraint_shape<F>(&mut self, name: &str, summary: &str, factory: F)
    where
        F: Fn(&Params) -> Result<Box<dyn ConstraintShape>, ConfigError> + Send + Sync + 'static,
    {
        self.add(
            |r| &mut r.constraint_shapes,
            |inner, info| Box::new(Guarded { inner, info }),
            name,
            summary,
            factory,
        );
    }

    /// Registers a tile set.
    pub fn tileset<F>(&mut self, name: &str, summary: &str, factory: F)
    where
        F: Fn(&Params) -> Result<Box<dyn TileSet>, ConfigError> + Send + Sync + 'static,
    {
        self.add(
            |r| &mut r.tilesets,
            |inner, info| Box::new(Guarded { inner, info }),
            name,
            summary,
            factory,
        );
    }

    /// Registers an exporter.
    pub fn exporter<F>(&mut self, name: &str, summary: &str, factory: F)
    where
        F: Fn(&Params) -> Result<Box<dyn Exporter>, ConfigError> + Send + Sync + 'static,
    {
        self.add(
            |r| &mut r.exporters,
            |inner, info| Box::new(Guarded { inner, info }),
            name,
            summary,
            factory,
        );
    }
}

fn guarded_build<T: ?Sized>(
    info: &PluginInfo,
    name: &str,
    kind: &str,
    params: &Params,
    factory: &(dyn Fn(&Params) -> Result<Box<T>, ConfigError> + Send + Sync),
) -> Result<Box<T>, ConfigError> {
    catch_unwind(AssertUnwindSafe(|| factory(params))).unwrap_or_else(|p| {
        Err(params.error("type", info.fail(&format!("building {kind} '{name}'"), p)))
    })
}

/// A plugin's component, whose every method runs under `catch_unwind` in the plugin.
struct Guarded<T: ?Sized> {
    inner: Box<T>,
    info: Arc<PluginInfo>,
}

impl<T: ?Sized> Guarded<T> {
    fn failed(&self) -> bool {
        self.info
            .failure
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .is_some()
    }

    fn call<R>(&self, what: &str, neutral: impl FnOnce() -> R, f: impl FnOnce(&T) -> R) -> R {
        // After a failure the plugin is not called again: the run is already lost, and the
        // first message is the useful one.
        if self.failed() {
            return neutral();
        }
        match catch_unwind(AssertUnwindSafe(|| f(&self.inner))) {
            Ok(r) => r,
            Err(p) => {
                self.info.fail(what, p);
                neutral()
            }
        }
    }

    fn try_call<R, E>(
        &self,
        what: &str,
        err: impl FnOnce(String) -> E,
        f: impl FnOnce(&T) -> Result<R, E>,
    ) -> Result<R, E> {
        if self.failed() {
            let f = self
                .info
                .failure
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .clone();
            return Err(err(f.unwrap_or_default()));
        }
        match catch_unwind(AssertUnwindSafe(|| f(&self.inner))) {
            Ok(r) => r,
            Err(p) => Err(err(self.info.fail(what, p))),
        }
    }
}

#[deny(clippy::missing_trait_methods)] // a new defaulted method must be forwarded, not skipped
impl RouteDescriptor for Guarded<dyn RouteDescriptor> {
    fn offset(&self, t: f64, segment: &Segment) -> f64 {
        self.call("RouteDescriptor::offset", || 0.0, |d| d.offset(t, segment))
    }
    fn samples(&self, segment: &Segment) -> usize {
        self.call("RouteDescriptor::samples", || 1, |d| d.samples(segment))
    }
    fn guide(&self, segment: &Segment) -> Vec<[i32; 2]> {
        self.call("RouteDescriptor::guide", Vec::new, |d| d.guide(segment))
    }
    fn turn_cost(&self) -> u32 {
        self.call("RouteDescriptor::turn_cost", || 0, |d| d.turn_cost())
    }
}

#[deny(clippy::missing_trait_methods)] // a new defaulted method must be forwarded, not skipped
impl ConstraintShape for Guarded<dyn ConstraintShape> {
    fn footprint(&self) -> Vec<Offset> {
        self.call(
            "ConstraintShape::footprint",
            || vec![(0, 0)],
            |s| s.footprint(),
        )
    }
    fn arms(&self) -> Vec<Arm> {
        self.call("ConstraintShape::arms", Vec::new, |s| s.arms())
    }
    fn rotations(&self) -> u8 {
        self.call("ConstraintShape::rotations", || 1, |s| s.rotations())
    }
    fn clearance(&self) -> i32 {
        self.call("ConstraintShape::clearance", || 2, |s| s.clearance())
    }
    fn fits(&self, rows: usize, cols: usize) -> Result<(), ConfigError> {
        self.try_call(
            "ConstraintShape::fits",
            |m| Params::default().error("", m),
            |s| s.fits(rows, cols),
        )
    }
    fn drawn(
        &self,
        rows: usize,
        cols: usize,
        rng: &mut subtgraph_core::rng::WorldRng,
    ) -> Option<Box<dyn ConstraintShape>> {
        // What the plugin draws is plugin code too: wrapped like the shape itself.
        self.call(
            "ConstraintShape::drawn",
            || None,
            |s| s.drawn(rows, cols, rng),
        )
        .map(|inner| {
            Box::new(Guarded {
                inner,
                info: self.info.clone(),
            }) as Box<dyn ConstraintShape>
        })
    }
    fn objective(
        &self,
        from: [i32; 2],
        heading: Heading,
        rows: usize,
        cols: usize,
        rng: &mut subtgraph_core::rng::WorldRng,
    ) -> [i32; 2] {
        self.call(
            "ConstraintShape::objective",
            || from,
            |s| s.objective(from, heading, rows, cols, rng),
        )
    }
}

#[deny(clippy::missing_trait_methods)] // a new defaulted method must be forwarded, not skipped
impl TileSet for Guarded<dyn TileSet> {
    fn tile(&self, ctx: &TileContext<'_>) -> Result<TileGeometry, TileSetError> {
        self.try_call("TileSet::tile", TileSetError::Plugin, |t| t.tile(ctx))
    }
    fn materials(&self) -> Vec<Material> {
        self.call("TileSet::materials", Vec::new, |t| t.materials())
    }
    fn pitch(&self) -> Option<f64> {
        self.call("TileSet::pitch", || None, |t| t.pitch())
    }
    fn opening(&self, layout: &Layout) -> Option<CrossSection> {
        self.call("TileSet::opening", || None, |t| t.opening(layout))
    }
    fn check(&self, layout: &Layout) -> Result<(), TileSetError> {
        self.try_call("TileSet::check", TileSetError::Plugin, |t| t.check(layout))
    }
    fn estimate(&self, layout: &Layout, kind: TileKind) -> Option<TileTriangles> {
        self.call("TileSet::estimate", || None, |t| t.estimate(layout, kind))
    }
    fn detail_advice(&self) -> Option<String> {
        self.call("TileSet::detail_advice", || None, |t| t.detail_advice())
    }
    fn texture_scale(&self) -> f32 {
        self.call("TileSet::texture_scale", || 4.0, |t| t.texture_scale())
    }
    fn textures(&self, seed: u64) -> Result<Vec<subtgraph_core::mesh::ImageFile>, TileSetError> {
        self.call("TileSet::textures", || Ok(Vec::new()), |t| t.textures(seed))
    }
    fn makes_hazards(&self) -> bool {
        self.call("TileSet::makes_hazards", || false, |t| t.makes_hazards())
    }
    fn ramp(&self, layout: &Layout, shaft: &subtgraph_core::grid::Shaft) -> Option<Vec<[f64; 3]>> {
        self.call("TileSet::ramp", || None, |t| t.ramp(layout, shaft))
    }
    fn floor_lift(&self, layout: &Layout, cell: subtgraph_core::grid::Cell) -> [f64; 2] {
        self.call(
            "TileSet::floor_lift",
            || [0.0, 0.0],
            |t| t.floor_lift(layout, cell),
        )
    }
    fn fixtures(
        &self,
        layout: &Layout,
        visual: &subtgraph_core::mesh::Mesh,
        axes: &[(
            subtgraph_core::grid::Cell,
            &subtgraph_core::tileset::PassageAxis,
        )],
    ) -> Result<subtgraph_core::mesh::Fixtures, TileSetError> {
        self.try_call("TileSet::fixtures", TileSetError::Plugin, |t| {
            t.fixtures(layout, visual, axes)
        })
    }
}

#[deny(clippy::missing_trait_methods)] // a new defaulted method must be forwarded, not skipped
impl Exporter for Guarded<dyn Exporter> {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        self.try_call("Exporter::export", ExportError::Plugin, |e| {
            e.export(world, survey, out)
        })
    }
    fn needs_geometry(&self) -> bool {
        self.call("Exporter::needs_geometry", || false, |e| e.needs_geometry())
    }
}
