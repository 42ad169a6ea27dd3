//! A LiDAR table: a spinning sensor described in a TOML file, for a model that is not built in.
//!
//! ```toml
//! name = "my-lidar"                 # what sequence.json calls it
//! driver = "ouster"                 # whose messages: ouster, velodyne or livox
//! rate_hz = 10                      # scans a second
//! columns = 1024                    # columns a turn
//! elevations_deg = [15.0, 5.0, -5.0, -15.0]   # one per beam, in ring order
//! azimuth_offsets_deg = [0, 0, 0, 0]          # optional, per beam
//! range_m = [0.5, 100.0]            # nearest and farthest return
//! range_noise_m = 0.02              # one standard deviation
//! grazing_deg = 85                  # optional: no return beyond this incidence angle
//! ```
//!
//! Unknown keys are errors, so a misspelt one is not silently ignored.

use serde::Deserialize;

use super::{Driver, LidarModel, Pattern};
use crate::error::SenseError;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Table {
    name: String,
    driver: String,
    rate_hz: f64,
    columns: usize,
    elevations_deg: Vec<f64>,
    #[serde(default)]
    azimuth_offsets_deg: Option<Vec<f64>>,
    range_m: [f64; 2],
    range_noise_m: f64,
    #[serde(default = "grazing")]
    grazing_deg: f64,
}

fn grazing() -> f64 {
    85.0
}

/// Reads a table (`path` names it in errors). Its numbers are checked by
/// [`LidarModel::check`].
pub fn parse(text: &str, path: &str) -> Result<LidarModel, SenseError> {
    let t: Table = toml::from_str(text).map_err(|e| SenseError::BadLidarTable {
        path: path.to_owned(),
        why: e.message().to_owned(),
    })?;
    let driver = match t.driver.as_str() {
        "ouster" => Driver::Ouster,
        "velodyne" => Driver::Velodyne,
        "livox" => Driver::Livox,
        other => {
            return Err(SenseError::BadLidarTable {
                path: path.to_owned(),
                why: format!("driver '{other}' is not one of ouster, velodyne, livox"),
            });
        }
    };
    let beams = t.elevations_deg.len();
    Ok(LidarModel {
        name: t.name,
        driver,
        pattern: Pattern::Spinning {
            azimuth_offsets_deg: t.azimuth_offsets_deg.unwrap_or_else(|| vec![0.0; beams]),
            elevations_deg: t.elevations_deg,
            columns: t.columns,
        },
        rate_hz: t.rate_hz,
        range_m: t.range_m,
        range_noise_m: t.range_noise_m,
        grazing_deg: t.grazing_deg,
        source: format!("LiDAR table {path}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: &str = r#"
name = "four"
driver = "velodyne"
rate_hz = 10
columns = 360
elevations_deg = [15.0, 5.0, -5.0, -15.0]
range_m = [0.5, 100.0]
range_noise_m = 0.02
"#;

    #[test]
    fn a_table_reads_and_its_mistakes_are_named() {
        let m = LidarModel::named("t.toml", |_| Some(TABLE.into())).unwrap();
        assert_eq!(m.rings(), 4);
        assert_eq!(m.rays_per_scan(), 1440);
        let e = LidarModel::named("t.toml", |_| Some(TABLE.replace("columns", "colums")))
            .unwrap_err()
            .to_string();
        assert!(e.contains("colums"), "{e}");
        let e = LidarModel::named("t.toml", |_| Some(TABLE.replace("100.0", "-3")))
            .unwrap_err()
            .to_string();
        assert!(e.contains("range_m") && e.contains("four"), "{e}");
        let e = LidarModel::named("t.toml", |_| {
            Some(TABLE.replace("rate_hz = 10", "rate_hz = 4000"))
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("rate_hz") && e.contains("1 to 50"), "{e}");
        let e = LidarModel::named("os2-7", |_| None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("os1-32") && e.contains("os2-7"), "{e}");
        let e = LidarModel::named("missing.toml", |_| None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.toml"), "{e}");
    }
}
