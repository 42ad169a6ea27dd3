//! # subtgraph-plot
//!
//! Plots without a plotting crate: a [`Figure`] is a list of rectangles, lines and labels in
//! figure units, laid out once and written twice, as SVG text ([`Figure::to_svg`]) and as a
//! PNG by a small rasteriser with a built-in bitmap font ([`to_png`]), so both show the same
//! and the same numbers always give the same bytes. [`bars`], [`boxes`] and [`heatmap`] lay
//! out the usual kinds of plot with titled, labelled axes.
//!
//! `stats` draws its report with it and `score` its per-level pictures; nothing here knows
//! about worlds.

pub mod charts;
pub mod figure;
mod font;
pub mod raster;
mod summary;

pub use charts::{bars, boxes, heatmap, viridis};
pub use figure::{Anchor, Figure, PALETTE, Rgb, Shape, text_width};
pub use raster::to_png;
pub use summary::Summary;
