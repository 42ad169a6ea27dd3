//! What can go wrong setting up or running an exploration, each variant saying what to change.

/// Why an exploration could not be set up. Nothing is written when one is returned.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExploreError {
    /// The world was made without geometry: there is no rock to drive through or to scan.
    #[error(
        "the world has no mesh (made by generate --no-mesh, or without a [tileset]): robots need its collision surface to drive and scan; generate it again with a tile set"
    )]
    NoMesh,
    /// The world has no start tile (an empty layout).
    #[error(
        "the world has no start tile to put the base station and the robots at: generate a world with at least one passage"
    )]
    NoStart,
    /// No spawn pose near the start has the platform's clearance.
    #[error(
        "no free spot for robot {robot} within {searched_m} m of the start along its passage has the {platform} platform's {clearance_m} m clearance: ask for fewer robots, or a wider passage"
    )]
    NoSpawn {
        /// The robot that found no spot (0 up).
        robot: usize,
        /// How far along the start's passage was searched, metres.
        searched_m: f64,
        /// The platform's name.
        platform: &'static str,
        /// The platform's clearance radius, metres.
        clearance_m: f64,
    },
    /// A name the options do not know (a platform, a LiDAR model, a planner, an option).
    #[error("unknown {what} '{name}'; the known ones are {known}")]
    Unknown {
        /// What was named.
        what: &'static str,
        /// The name given.
        name: String,
        /// The names known.
        known: String,
    },
    /// A number out of its bounds.
    #[error("{what} is {value}; it must be {bounds}")]
    OutOfBounds {
        /// What the number is.
        what: String,
        /// The value given.
        value: String,
        /// What it may be.
        bounds: String,
    },
    /// The map would not fit the memory it may use.
    #[error(
        "the voxel map of this world at {voxel_m} m would need up to {needed_mib} MiB, above the {limit_mib} MiB it may use: use a larger voxel (map_voxel / --map-voxel)"
    )]
    MapTooLarge {
        /// The voxel edge asked for, metres.
        voxel_m: f64,
        /// The worst case, MiB.
        needed_mib: u64,
        /// The limit, MiB.
        limit_mib: u64,
    },
    /// The sensors crate refused a model or platform.
    #[error(transparent)]
    Sense(#[from] subtgraph_sensors::SenseError),
    /// Writing the run folder failed.
    #[error("{what} {path}: {source}")]
    Io {
        /// `writing`, `reading`.
        what: &'static str,
        /// The file.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

impl ExploreError {
    /// A number out of its bounds.
    pub fn bounds(what: impl Into<String>, value: impl ToString, bounds: &str) -> ExploreError {
        ExploreError::OutOfBounds {
            what: what.into(),
            value: value.to_string(),
            bounds: bounds.to_owned(),
        }
    }
}
