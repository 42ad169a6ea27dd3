//! The TUM RGB-D folder (Sturm et al., IROS 2012) that RGB-D SLAM methods and their
//! evaluation tools read: an RGB-D camera's colour and depth images, their lists, the pairs
//! that belong together, and the camera's ground-truth trajectory.
//!
//! ```text
//! tum/rgb/<t>.png      the colour image (the camera folder's own file, linked)
//! tum/depth/<t>.png    16-bit depth, 5,000 a metre (TUM's scale: 1 = 0.2 mm), 0 for none
//! tum/rgb.txt, tum/depth.txt        "timestamp filename", seconds with six decimals
//! tum/associations.txt              "t rgb/t.png t depth/t.png" (the same instant: aligned)
//! tum/groundtruth.txt               "timestamp tx ty tz qx qy qz qw": the colour camera's
//!                                   optical frame in the world, at each frame
//! ```
//!
//! A depth pixel is zero outside the camera's depth range and beyond 13.1 m (the most 16 bits
//! hold at TUM's scale); the float depth in metres is the camera folder's.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use super::euroc::link_or_copy;
use crate::frames::Pose;

/// TUM's depth scale: a pixel value of 5,000 is one metre.
pub const DEPTH_SCALE: f64 = 5000.0;

/// The TUM RGB-D folder being written.
pub struct TumRgbd {
    root: PathBuf,
    rgb: BufWriter<File>,
    depth: BufWriter<File>,
    pairs: BufWriter<File>,
    truth: BufWriter<File>,
}

impl TumRgbd {
    /// Starts the folder `root`.
    pub fn create(root: &Path) -> io::Result<TumRgbd> {
        std::fs::create_dir_all(root.join("rgb"))?;
        std::fs::create_dir_all(root.join("depth"))?;
        let open = |name: &str, head: &str| -> io::Result<BufWriter<File>> {
            let mut w = BufWriter::new(File::create(root.join(name))?);
            w.write_all(head.as_bytes())?;
            Ok(w)
        };
        Ok(TumRgbd {
            root: root.to_owned(),
            rgb: open(
                "rgb.txt",
                "# color images\n# file: 'subtgraph sense'\n# timestamp filename\n",
            )?,
            depth: open(
                "depth.txt",
                "# depth maps\n# file: 'subtgraph sense'\n# timestamp filename\n",
            )?,
            pairs: open("associations.txt", "")?,
            truth: open(
                "groundtruth.txt",
                "# ground truth trajectory\n# file: 'subtgraph sense'\n# timestamp tx ty tz qx qy qz qw\n",
            )?,
        })
    }

    /// A frame at `t` seconds: the colour image file at `rgb` (linked), the depth in metres
    /// (`near`..`far`, else 0) and the camera's pose. Returns the bytes of the files made.
    pub fn frame(
        &mut self,
        t: f64,
        rgb: &Path,
        depth: &[f32],
        width: usize,
        range: [f64; 2],
        pose: &Pose,
    ) -> io::Result<u64> {
        let name = format!("{t:.6}");
        let mut bytes = link_or_copy(rgb, &self.root.join(format!("rgb/{name}.png")))?;
        let values: Vec<u16> = depth
            .iter()
            .map(|&d| {
                let d = f64::from(d);
                if d >= range[0] && d <= range[1] {
                    let v = (d * DEPTH_SCALE).round();
                    if v <= f64::from(u16::MAX) {
                        v as u16
                    } else {
                        0
                    }
                } else {
                    0
                }
            })
            .collect();
        let png = super::image::png16(width, depth.len() / width.max(1), &values);
        bytes += png.len() as u64;
        std::fs::write(self.root.join(format!("depth/{name}.png")), png)?;
        writeln!(self.rgb, "{name} rgb/{name}.png")?;
        writeln!(self.depth, "{name} depth/{name}.png")?;
        writeln!(self.pairs, "{name} rgb/{name}.png {name} depth/{name}.png")?;
        let p = pose.translation;
        let q = pose.quaternion();
        writeln!(
            self.truth,
            "{name} {:.6} {:.6} {:.6} {:.9} {:.9} {:.9} {:.9}",
            p[0], p[1], p[2], q[0], q[1], q[2], q[3]
        )?;
        Ok(bytes)
    }

    /// Finishes the lists; returns their bytes.
    pub fn finish(self) -> io::Result<u64> {
        let mut bytes = 0;
        for mut w in [self.rgb, self.depth, self.pairs, self.truth] {
            w.flush()?;
            bytes += w.get_ref().metadata()?.len();
        }
        Ok(bytes)
    }
}
