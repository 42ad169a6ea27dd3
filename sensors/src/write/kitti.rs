//! The KITTI odometry layout and the TUM trajectory: what SLAM benchmarks and `evo` read.
//!
//! - `kitti/velodyne/NNNNNN.bin`: a scan's returns as `float32` `x y z intensity` in the
//!   sensor frame, in firing order (KITTI's own scans are motion-distorted too, and its
//!   readers reconstruct each point's time from its azimuth);
//! - `kitti/poses.txt`: the LiDAR's pose at each scan's start as 12 numbers (`[R | t]` row by
//!   row) in the world folder's frame: not moved to start at the origin, so a return moved by
//!   its pose lands on the world's mesh;
//! - `kitti/times.txt`: each scan's start, seconds from the sequence's start;
//! - `kitti/calib.txt`: `P0`..`P3` and `Tr`, all identity: there is no camera, and the LiDAR's
//!   frame stands in for it, so tools that apply `Tr` change nothing;
//! - `kitti/velodyne/imu.csv` and `timestamps.txt`: the IMU samples (`timestamp, ax, ay, az,
//!   gx, gy, gz`) and the scans' start times, beside the scans, which is where GenZ-LIO's
//!   folder reader looks for them (KITTI readers list only the `.bin` files);
//! - `ground_truth.tum`: `time x y z qx qy qz qw` per scan, the same poses with their times.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::frames::Pose;
use crate::lidar::scan::Scan;
use subtgraph_core::direct_file::{DirectFile, Spool};

/// The KITTI and TUM files being written.
pub struct Kitti {
    dir: std::path::PathBuf,
    poses: BufWriter<File>,
    times: BufWriter<File>,
    stamps: BufWriter<File>,
    imu: BufWriter<File>,
    buf: Vec<u8>,
    /// The scans' files' buffer, reused.
    spool: Option<Spool>,
    /// Bytes written.
    pub bytes: u64,
    /// Whether each scan gets its `labels/NNNNNN.label` (under conditions).
    labels: bool,
}

/// The TUM ground truth.
pub struct Tum {
    file: BufWriter<File>,
    /// Bytes written.
    pub bytes: u64,
}

fn create(p: &Path) -> io::Result<BufWriter<File>> {
    Ok(BufWriter::with_capacity(1 << 16, File::create(p)?))
}

impl Kitti {
    /// Starts the files under `dir` (`kitti/`, which must exist); with `labels`, each scan
    /// gets `labels/NNNNNN.label` beside it as SemanticKITTI lays its labels out (a
    /// little-endian `uint32` per point of the `.bin`, in its order), holding what made each
    /// return ([`crate::conditions::Kind`]).
    pub fn create(dir: &Path, labels: bool) -> io::Result<Kitti> {
        std::fs::create_dir_all(dir.join("velodyne"))?;
        if labels {
            std::fs::create_dir_all(dir.join("labels"))?;
        }
        let identity = "1 0 0 0 0 1 0 0 0 0 1 0";
        let calib = format!(
            "P0: {identity}\nP1: {identity}\nP2: {identity}\nP3: {identity}\nTr: {identity}\n"
        );
        std::fs::write(dir.join("calib.txt"), &calib)?;
        // No header line: GenZ-LIO reads the file with numpy's loadtxt.
        let imu = create(&dir.join("velodyne/imu.csv"))?;
        Ok(Kitti {
            dir: dir.to_owned(),
            poses: create(&dir.join("poses.txt"))?,
            times: create(&dir.join("times.txt"))?,
            stamps: create(&dir.join("velodyne/timestamps.txt"))?,
            imu,
            buf: Vec::new(),
            spool: Some(Spool::new()?),
            bytes: calib.len() as u64,
            labels,
        })
    }

    /// A scan, and the LiDAR's pose at its start.
    pub fn scan(&mut self, scan: &Scan, pose: &Pose) -> io::Result<()> {
        self.buf.clear();
        for p in scan.points.iter().filter(|p| p.valid) {
            for v in [p.xyz[0], p.xyz[1], p.xyz[2], p.reflectance] {
                self.buf.extend_from_slice(&v.to_le_bytes());
            }
        }
        let name = format!("velodyne/{:06}.bin", scan.index);
        let spool = self
            .spool
            .take()
            .ok_or_else(|| io::Error::other("an earlier KITTI scan failed to write"))?;
        let mut file = DirectFile::create(&self.dir.join(name), spool)?;
        file.write_all(&self.buf)?;
        self.spool = Some(file.finish()?);
        if self.labels {
            let kinds: Vec<u8> = scan
                .points
                .iter()
                .filter(|p| p.valid)
                .flat_map(|p| u32::from(p.kind).to_le_bytes())
                .collect();
            let name = self.dir.join(format!("labels/{:06}.label", scan.index));
            std::fs::write(name, &kinds)?;
            self.bytes += kinds.len() as u64;
        }
        let m = pose.matrix_3x4();
        let line: Vec<String> = m.iter().map(|x| format!("{x:.9e}")).collect();
        let pose_line = line.join(" ") + "\n";
        let time_line = format!("{:.6e}\n", scan.start);
        let stamp_line = format!("{:.9}\n", scan.start);
        self.poses.write_all(pose_line.as_bytes())?;
        self.times.write_all(time_line.as_bytes())?;
        self.stamps.write_all(stamp_line.as_bytes())?;
        self.bytes +=
            (self.buf.len() + pose_line.len() + time_line.len() + stamp_line.len()) as u64;
        Ok(())
    }

    /// An IMU sample for GenZ-LIO's folder reader.
    pub fn imu(
        &mut self,
        stamp: f64,
        gyroscope: [f64; 3],
        accelerometer: [f64; 3],
    ) -> io::Result<()> {
        let a = accelerometer;
        let g = gyroscope;
        let line = format!(
            "{stamp:.9},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n",
            a[0], a[1], a[2], g[0], g[1], g[2]
        );
        self.bytes += line.len() as u64;
        self.imu.write_all(line.as_bytes())
    }

    /// Flushes every file.
    pub fn finish(mut self) -> io::Result<u64> {
        self.poses.flush()?;
        self.times.flush()?;
        self.stamps.flush()?;
        self.imu.flush()?;
        if let Some(spool) = self.spool.take() {
            spool.close()?;
        }
        Ok(self.bytes)
    }
}

impl Tum {
    /// Starts `ground_truth.tum` at `path`.
    pub fn create(path: &Path) -> io::Result<Tum> {
        let mut file = create(path)?;
        let head =
            b"# time x y z qx qy qz qw: the LiDAR's pose at each scan's start, world frame\n";
        file.write_all(head)?;
        Ok(Tum {
            file,
            bytes: head.len() as u64,
        })
    }

    /// A pose at time `t`.
    pub fn pose(&mut self, t: f64, pose: &Pose) -> io::Result<()> {
        let [x, y, z] = pose.translation;
        let [qx, qy, qz, qw] = pose.quaternion();
        let line = format!("{t:.9} {x:.9} {y:.9} {z:.9} {qx:.9} {qy:.9} {qz:.9} {qw:.9}\n");
        self.bytes += line.len() as u64;
        self.file.write_all(line.as_bytes())
    }

    /// Flushes the file.
    pub fn finish(mut self) -> io::Result<u64> {
        self.file.flush()?;
        Ok(self.bytes)
    }
}
