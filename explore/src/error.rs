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
    pub fn bounds(what: impl Into<String>, value: impl Quoted, bounds: &str) -> ExploreError {
        ExploreError::OutOfBounds {
            what: what.into(),
            value: value.quoted(),
            bounds: bounds.to_owned(),
        }
    }
}

/// A value as a message quotes it back to the user.
pub trait Quoted {
    /// The value as shown.
    fn quoted(&self) -> String;
}

/// Whole numbers as they are.
macro_rules! quoted_as_written {
    ($($t:ty),*) => {$(
        impl Quoted for $t {
            fn quoted(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
quoted_as_written!(usize, u32, u64, i32, i64);

/// Decimals as [`subtgraph_core::error::number`] shows them (`--duration 1e308` is quoted as
/// `1e308`, not 309 digits), except that a value it would round to 0 is shown in scientific
/// notation (`1e-9`): the user gave something other than 0, and the message must say what.
impl Quoted for f64 {
    fn quoted(&self) -> String {
        let shown = subtgraph_core::error::number(*self);
        if shown == "0" && *self != 0.0 {
            format!("{self:e}")
        } else {
            shown
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_out_of_bounds_are_quoted_short_and_never_as_zero() {
        for (value, shown) in [
            (1e308, "1e308"),
            (f64::MAX, "1.797693e308"),
            (1e-9, "1e-9"),
            (-2.5e-7, "-2.5e-7"),
            (0.0, "0"),
            (f64::NAN, "NaN"),
            (86_400.5, "86400.5"),
        ] {
            let e = ExploreError::bounds("--duration", value, "at most 86400 seconds");
            assert_eq!(
                e.to_string(),
                format!("--duration is {shown}; it must be at most 86400 seconds")
            );
        }
        let e = ExploreError::bounds("--robots", 17usize, "1 to 16");
        assert_eq!(e.to_string(), "--robots is 17; it must be 1 to 16");
    }
}
