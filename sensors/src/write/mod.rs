//! The sequence folder's files: the ROS 2 bag ([`bag`], over [`mcap`] and [`cdr`]), the KITTI
//! folder and the TUM ground truth ([`kitti`]); `sequence.json` is written by
//! [`crate::sequence`]. The bag and the KITTI scans, most of the bytes, go around the page
//! cache ([`subtgraph_core::direct_file`]).

pub mod bag;
pub mod camera_msgs;
pub mod cdr;
pub mod euroc;
pub mod image;
pub mod kitti;
pub mod mcap;
pub mod tum_rgbd;

use crate::error::SenseError;

/// Which of the optional outputs to write (`sequence.json` and `ground_truth.tum` always are,
/// and with a camera its folder `camera/`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Formats {
    /// `bag/`.
    pub bag: bool,
    /// `kitti/`.
    pub kitti: bool,
    /// `euroc/` (cameras).
    pub euroc: bool,
    /// `tum/` (an RGB-D camera).
    pub tum: bool,
}

/// The names `--format` takes.
pub const NAMES: [&str; 4] = ["bag", "kitti", "euroc", "tum-rgbd"];

impl Default for Formats {
    fn default() -> Self {
        Formats {
            bag: true,
            kitti: true,
            euroc: false,
            tum: false,
        }
    }
}

impl Formats {
    /// From `--format` values (each may be a comma list); none given means both.
    pub fn parse(values: &[String]) -> Result<Formats, SenseError> {
        let names: Vec<&str> = values
            .iter()
            .flat_map(|v| v.split(','))
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        if names.is_empty() {
            return Ok(Formats::default());
        }
        let mut f = Formats {
            bag: false,
            kitti: false,
            euroc: false,
            tum: false,
        };
        for n in names {
            match n {
                "bag" => f.bag = true,
                "kitti" => f.kitti = true,
                "euroc" => f.euroc = true,
                "tum-rgbd" => f.tum = true,
                other => {
                    return Err(SenseError::Unknown {
                        what: "output format",
                        name: other.to_owned(),
                        known: NAMES.join(", "),
                    });
                }
            }
        }
        Ok(f)
    }

    /// The outputs of `--format` values for a sequence with or without a LiDAR and with a
    /// camera that has depth or not (`None`: no camera): none given means the bag, KITTI
    /// with a LiDAR, EuRoC with a camera and TUM RGB-D with an RGB-D camera; one that
    /// holds what the sequence does not have is refused.
    pub fn for_sensors(
        values: &[String],
        lidar: bool,
        camera: Option<bool>,
    ) -> Result<Formats, SenseError> {
        let given = values
            .iter()
            .any(|v| v.split(',').any(|s| !s.trim().is_empty()));
        let mut f = Formats::parse(values)?;
        if !given {
            f.kitti = lidar;
            f.euroc = camera == Some(false);
            f.tum = camera == Some(true);
            return Ok(f);
        }
        let refuse = |name: &str, why: &str| {
            Err(SenseError::OutOfBounds {
                what: "--format".into(),
                value: name.to_owned(),
                bounds: why.to_owned(),
            })
        };
        if f.kitti && !lidar {
            return refuse(
                "kitti",
                "left out with --lidar none (the KITTI folder holds LiDAR scans)",
            );
        }
        if f.euroc && camera.is_none() {
            return refuse(
                "euroc",
                "used with a --camera (the EuRoC folder holds images)",
            );
        }
        if f.tum && camera != Some(true) {
            return refuse(
                "tum-rgbd",
                "used with an RGB-D camera, like --camera d435i (the TUM RGB-D folder holds colour and depth)",
            );
        }
        Ok(f)
    }
}
