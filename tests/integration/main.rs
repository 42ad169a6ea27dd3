//! The integration tests, one binary of modules (as ripgrep does): one link instead of one per
//! file, and helpers in `common` that every module shares without `#[allow(dead_code)]` (a
//! helper no module uses is a warning here, as it should be).
//!
//! Run one module's tests with `cargo test --test integration cli::` (or any part of a test's
//! path). To add a file: put it in this folder, declare it below (`mod my_tests;`), and write
//! `use crate::common;` at its top instead of `mod common;`.

mod camera_haze;
mod camera_raster;
mod cameras;
mod common;

mod artifacts;
mod centrelines;
mod chambers;
mod cli;
mod conditions;
mod dataset;
mod declines;
mod doc_commands;
mod drive;
mod elevation;
mod explore;
mod export_physics;
mod export_scenes;
mod exports;
mod ground_truth;
mod guarantees;
mod hazards;
mod hidden_artifacts;
mod hostile_configs;
mod limits;
mod mesh_files;
mod messages;
mod mine_services;
mod mine_walls;
mod one_surface;
mod passages;
mod plugins;
mod preview;
mod ramps;
mod reliability;
mod reliability_round3;
mod report;
mod room_and_pillar;
mod rubble;
mod score;
mod segmentation;
mod sense;
mod sensor_surface;
mod source_checks;
mod stats;
mod tasks;
mod textures;
mod tilesets;
mod trajectory;
