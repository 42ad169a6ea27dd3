//! The EuRoC MAV (ASL) folder that ORB-SLAM3, OpenVINS, VINS-Fusion, Basalt and most
//! visual-inertial methods read, and Kalibr's `camchain.yaml` and `imu.yaml` with the true
//! calibration.
//!
//! ```text
//! euroc/mav0/camN/data/<ns>.png, data.csv, sensor.yaml
//! euroc/mav0/imu0/data.csv, sensor.yaml
//! euroc/mav0/state_groundtruth_estimate0/data.csv, sensor.yaml
//! ```
//!
//! EuRoC's body frame is the IMU's (`imu_link`): each sensor's `T_BS` is its pose in it, the
//! ground truth is the IMU's pose in the world (`map`), its velocity and its true biases, at
//! the IMU's rate. Times are nanoseconds of the sequence's clock (the bag's), the images' the
//! middle of their exposure. The images are the camera folder's own files (hard links: no
//! second copy on disk; a copy where the file system has no links).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::camera::CameraModel;
use crate::frames::{Pose, mul};
use crate::imu::{ImuModel, ImuSample};
use crate::trajectory::State;
use crate::write::bag::ns;

/// The EuRoC folder being written.
pub struct Euroc {
    root: PathBuf,
    cameras: Vec<BufWriter<File>>,
    imu: BufWriter<File>,
    truth: BufWriter<File>,
}

/// A pose as EuRoC's and Kalibr's 4 x 4 row lists.
fn rows(p: &Pose) -> [[f64; 4]; 4] {
    let m = p.matrix_3x4();
    [
        [m[0], m[1], m[2], m[3]],
        [m[4], m[5], m[6], m[7]],
        [m[8], m[9], m[10], m[11]],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

fn euroc_matrix(p: &Pose) -> String {
    let r = rows(p);
    let mut s = "T_BS:\n  cols: 4\n  rows: 4\n  data: [".to_owned();
    for (i, row) in r.iter().enumerate() {
        if i > 0 {
            s.push_str(",\n         ");
        }
        let row: Vec<String> = row.iter().map(|x| format!("{x:.15}")).collect();
        s.push_str(&row.join(", "));
    }
    s.push_str("]\n");
    s
}

/// A matrix as Kalibr writes one: a YAML list of rows.
fn kalibr_matrix(name: &str, p: &Pose) -> String {
    let mut s = format!("  {name}:\n");
    for row in rows(p) {
        let row: Vec<String> = row.iter().map(|x| format!("{x:.15}")).collect();
        s.push_str(&format!("  - [{}]\n", row.join(", ")));
    }
    s
}

/// Kalibr's `camchain.yaml`: each camera's intrinsics, distortion, resolution, topic, its
/// transform from the IMU (`T_cam_imu`: IMU points into the camera's frame) and from the
/// camera before it (`T_cn_cnm1`), and the IMU's clock offset (`timeshift_cam_imu`:
/// `t_imu = t_cam + shift`).
pub fn camchain(model: &CameraModel, cameras: &[Pose], imu: &Pose, imu_offset_s: f64) -> String {
    let mut s = String::new();
    for (i, (c, pose)) in model.cameras.iter().zip(cameras).enumerate() {
        let l = &c.intrinsics;
        s.push_str(&format!("cam{i}:\n"));
        s.push_str(&kalibr_matrix("T_cam_imu", &pose.inverse().then(imu)));
        if i > 0 {
            s.push_str(&kalibr_matrix(
                "T_cn_cnm1",
                &pose.inverse().then(&cameras[i - 1]),
            ));
        }
        let k = l.distortion.coefficients();
        s.push_str(&format!(
            "  camera_model: pinhole\n  distortion_coeffs: [{}, {}, {}, {}]\n  distortion_model: {}\n  intrinsics: [{}, {}, {}, {}]\n  resolution: [{}, {}]\n  rostopic: /{}/image_raw\n  timeshift_cam_imu: {}\n",
            k[0], k[1], k[2], k[3],
            l.distortion.kalibr_name(),
            l.focal[0], l.focal[1], l.centre[0], l.centre[1],
            l.width, l.height,
            c.name,
            imu_offset_s,
        ));
    }
    s
}

/// Kalibr's `imu.yaml`: the IMU's noise densities and random walks, rate and topic.
pub fn imu_yaml(imu: &ImuModel) -> String {
    format!(
        "imu0:\n  T_i_b:\n  - [1.0, 0.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, 0.0]\n  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n  accelerometer_noise_density: {}\n  accelerometer_random_walk: {}\n  gyroscope_noise_density: {}\n  gyroscope_random_walk: {}\n  model: calibrated\n  rostopic: /imu\n  time_offset: 0.0\n  update_rate: {}\n",
        imu.accelerometer_noise_density,
        imu.accelerometer_random_walk,
        imu.gyroscope_noise_density,
        imu.gyroscope_random_walk,
        imu.rate_hz,
    )
}

impl Euroc {
    /// Starts `root` (`euroc/`) with every sensor's `sensor.yaml`: `cameras` each camera's
    /// optical frame and `imu` the IMU in `base_link`.
    pub fn create(
        root: &Path,
        model: &CameraModel,
        cameras: &[Pose],
        imu: &Pose,
        imu_model: &ImuModel,
    ) -> io::Result<Euroc> {
        let mav = root.join("mav0");
        let mut files = Vec::new();
        for (c, pose) in model.cameras.iter().zip(cameras) {
            let dir = mav.join(&c.name);
            std::fs::create_dir_all(dir.join("data"))?;
            let l = &c.intrinsics;
            let k = l.distortion.coefficients();
            let distortion = match l.distortion {
                crate::camera::lens::Distortion::RadTan { .. } => "radial-tangential",
                crate::camera::lens::Distortion::Equidistant { .. } => "equidistant",
            };
            std::fs::write(
                dir.join("sensor.yaml"),
                format!(
                    "# General sensor definitions.\nsensor_type: camera\ncomment: {} {} ({})\n\n# Sensor extrinsics wrt. the body-frame.\n{}\n# Camera specific definitions.\nrate_hz: {}\nresolution: [{}, {}]\ncamera_model: pinhole\nintrinsics: [{}, {}, {}, {}] #fu, fv, cu, cv\ndistortion_model: {distortion}\ndistortion_coefficients: [{}, {}, {}, {}]\n",
                    model.name,
                    c.name,
                    model.sensor.chip,
                    euroc_matrix(&imu.inverse().then(pose)),
                    model.rate_hz,
                    l.width,
                    l.height,
                    l.focal[0],
                    l.focal[1],
                    l.centre[0],
                    l.centre[1],
                    k[0],
                    k[1],
                    k[2],
                    k[3],
                ),
            )?;
            let mut csv = BufWriter::new(File::create(dir.join("data.csv"))?);
            writeln!(csv, "#timestamp [ns],filename")?;
            files.push(csv);
        }
        let imu_dir = mav.join("imu0");
        std::fs::create_dir_all(&imu_dir)?;
        std::fs::write(
            imu_dir.join("sensor.yaml"),
            format!(
                "#Default imu sensor yaml file\nsensor_type: imu\ncomment: {}\n\n# Sensor extrinsics wrt. the body-frame.\n{}\nrate_hz: {}\n\n# inertial sensor noise model parameters (static)\ngyroscope_noise_density: {}     # [ rad / s / sqrt(Hz) ]   ( gyro \"white noise\" )\ngyroscope_random_walk: {}       # [ rad / s^2 / sqrt(Hz) ] ( gyro bias diffusion )\naccelerometer_noise_density: {}  # [ m / s^2 / sqrt(Hz) ]   ( accel \"white noise\" )\naccelerometer_random_walk: {}    # [ m / s^3 / sqrt(Hz) ].  ( accel bias diffusion )\n",
                imu_model.device,
                euroc_matrix(&Pose::IDENTITY),
                imu_model.rate_hz,
                imu_model.gyroscope_noise_density,
                imu_model.gyroscope_random_walk,
                imu_model.accelerometer_noise_density,
                imu_model.accelerometer_random_walk,
            ),
        )?;
        let mut imu_csv = BufWriter::new(File::create(imu_dir.join("data.csv"))?);
        writeln!(
            imu_csv,
            "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]"
        )?;
        let truth_dir = mav.join("state_groundtruth_estimate0");
        std::fs::create_dir_all(&truth_dir)?;
        std::fs::write(
            truth_dir.join("sensor.yaml"),
            "# The ground truth: the IMU's pose, velocity and biases, exact.\nsensor_type: visual-inertial\ncomment: subtgraph sense's trajectory\n",
        )?;
        let mut truth = BufWriter::new(File::create(truth_dir.join("data.csv"))?);
        writeln!(
            truth,
            "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]"
        )?;
        Ok(Euroc {
            root: root.to_owned(),
            cameras: files,
            imu: imu_csv,
            truth,
        })
    }

    /// An IMU sample, and the ground truth at its true instant (`state` of the body there,
    /// `mount` the IMU in `base_link`).
    pub fn imu(
        &mut self,
        s: &ImuSample,
        state: &State,
        mount: &Pose,
        true_ns: u64,
    ) -> io::Result<()> {
        let [g, a] = [s.gyroscope, s.accelerometer];
        writeln!(
            self.imu,
            "{},{},{},{},{},{},{}",
            ns(s.stamp),
            g[0],
            g[1],
            g[2],
            a[0],
            a[1],
            a[2]
        )?;
        let pose = state.pose.then(mount);
        // The IMU's velocity: the body's plus the turn's about it, in the world.
        let w = state.angular_velocity;
        let r = mount.translation;
        let wr = [
            w[1] * r[2] - w[2] * r[1],
            w[2] * r[0] - w[0] * r[2],
            w[0] * r[1] - w[1] * r[0],
        ];
        let spin = mul(&state.pose.rotation, wr);
        let v = [0, 1, 2].map(|k| state.velocity[k] + spin[k]);
        let q = pose.quaternion();
        let p = pose.translation;
        let [bg, ba] = s.bias;
        writeln!(
            self.truth,
            "{true_ns},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            p[0],
            p[1],
            p[2],
            q[3],
            q[0],
            q[1],
            q[2],
            v[0],
            v[1],
            v[2],
            bg[0],
            bg[1],
            bg[2],
            ba[0],
            ba[1],
            ba[2]
        )
    }

    /// Camera `c`'s image of the frame stamped `stamp_ns`: the file at `image` linked into
    /// `camN/data/`; returns the bytes written (0 for a link).
    pub fn image(&mut self, c: usize, name: &str, stamp_ns: u64, image: &Path) -> io::Result<u64> {
        let file = format!("{stamp_ns}.png");
        let to = self.root.join("mav0").join(name).join("data").join(&file);
        let bytes = link_or_copy(image, &to)?;
        writeln!(self.cameras[c], "{stamp_ns},{file}")?;
        Ok(bytes)
    }

    /// Finishes the files; returns the bytes of the text files.
    pub fn finish(self) -> io::Result<u64> {
        let mut bytes = 0;
        for mut w in self.cameras.into_iter().chain([self.imu, self.truth]) {
            w.flush()?;
            bytes += w.get_ref().metadata()?.len();
        }
        Ok(bytes)
    }
}

/// A hard link to `from` at `to` (no bytes), or a copy (its bytes) where links fail.
pub fn link_or_copy(from: &Path, to: &Path) -> io::Result<u64> {
    match std::fs::hard_link(from, to) {
        Ok(()) => Ok(0),
        Err(_) => std::fs::copy(from, to),
    }
}
