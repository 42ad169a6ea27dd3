//! ROS 2 messages in CDR (little-endian XCDR1, as rmw implementations write them), and their
//! definitions as MCAP schemas carry them.
//!
//! A message is written straight into the buffer it will be stored in (an MCAP chunk), so a
//! point cloud's megabyte is copied once; alignment is counted from the byte after the four
//! encapsulation bytes, wherever that is in the buffer.

use crate::frames::Pose;

/// Writes CDR into a buffer, aligning from `base`.
pub struct Cdr<'a> {
    buf: &'a mut Vec<u8>,
    base: usize,
}

impl<'a> Cdr<'a> {
    /// Starts a message at the end of `buf`: the encapsulation header (CDR, little-endian).
    pub fn new(buf: &'a mut Vec<u8>) -> Cdr<'a> {
        buf.extend_from_slice(&[0, 1, 0, 0]);
        let base = buf.len();
        Cdr { buf, base }
    }

    fn align(&mut self, n: usize) {
        let pad = (n - (self.buf.len() - self.base) % n) % n;
        self.buf.resize(self.buf.len() + pad, 0);
    }

    /// A `uint8` or `bool`.
    pub fn u8(&mut self, v: u8) {
        self.buf.push(v);
    }

    /// A `uint32`.
    pub fn u32(&mut self, v: u32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// An `int32`.
    pub fn i32(&mut self, v: i32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// A `float64`.
    pub fn f64(&mut self, v: f64) {
        self.align(8);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// A `string`: its length with the terminating NUL, its bytes, the NUL.
    pub fn string(&mut self, s: &str) {
        self.u32(s.len() as u32 + 1);
        self.buf.extend_from_slice(s.as_bytes());
        self.buf.push(0);
    }

    /// A `uint8[]` of `len` bytes that `fill` appends.
    pub fn bytes_with(&mut self, len: usize, fill: impl FnOnce(&mut Vec<u8>)) {
        self.u32(len as u32);
        let before = self.buf.len();
        fill(self.buf);
        debug_assert_eq!(self.buf.len() - before, len);
    }

    /// A `std_msgs/Header`.
    pub fn header(&mut self, stamp_ns: u64, frame: &str) {
        self.i32((stamp_ns / 1_000_000_000) as i32);
        self.u32((stamp_ns % 1_000_000_000) as u32);
        self.string(frame);
    }

    /// A `geometry_msgs/Vector3` (or `Point`).
    pub fn vector(&mut self, v: [f64; 3]) {
        for x in v {
            self.f64(x);
        }
    }

    /// A `geometry_msgs/Quaternion`, `[x, y, z, w]`.
    pub fn quaternion(&mut self, q: [f64; 4]) {
        for x in q {
            self.f64(x);
        }
    }

    /// A fixed array of `float64`.
    pub fn f64s(&mut self, v: &[f64]) {
        for &x in v {
            self.f64(x);
        }
    }

    /// A `geometry_msgs/Pose` (position, orientation).
    pub fn pose(&mut self, p: &Pose) {
        self.vector(p.translation);
        self.quaternion(p.quaternion());
    }
}

/// A `sensor_msgs/PointField`: name, offset, datatype (7 `FLOAT32`, 6 `UINT32`, 4 `UINT16`,
/// 2 `UINT8`, 8 `FLOAT64`), count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    /// Its name.
    pub name: &'static str,
    /// Byte offset in a point.
    pub offset: u32,
    /// `sensor_msgs/PointField` datatype constant.
    pub datatype: u8,
}

/// `FLOAT32`.
pub const FLOAT32: u8 = 7;
/// `FLOAT64`.
pub const FLOAT64: u8 = 8;
/// `UINT32`.
pub const UINT32: u8 = 6;
/// `UINT16`.
pub const UINT16: u8 = 4;
/// `UINT8`.
pub const UINT8: u8 = 2;

/// A `sensor_msgs/PointCloud2`; `fill` appends `height * width * point_step` bytes of points.
#[allow(clippy::too_many_arguments)]
pub fn point_cloud2(
    buf: &mut Vec<u8>,
    stamp_ns: u64,
    frame: &str,
    height: u32,
    width: u32,
    fields: &[Field],
    point_step: u32,
    is_dense: bool,
    fill: impl FnOnce(&mut Vec<u8>),
) {
    let mut c = Cdr::new(buf);
    c.header(stamp_ns, frame);
    c.u32(height);
    c.u32(width);
    c.u32(fields.len() as u32);
    for f in fields {
        c.string(f.name);
        c.u32(f.offset);
        c.u8(f.datatype);
        c.u32(1);
    }
    c.u8(0);
    c.u32(point_step);
    c.u32(width * point_step);
    let len = (height * width * point_step) as usize;
    c.bytes_with(len, fill);
    c.u8(u8::from(is_dense));
}

/// A `sensor_msgs/Imu` with no orientation (covariance -1, as REP 145 says for an IMU that
/// does not estimate one) and the noise variances of its readings.
pub fn imu(
    buf: &mut Vec<u8>,
    stamp_ns: u64,
    frame: &str,
    gyroscope: [f64; 3],
    accelerometer: [f64; 3],
    variances: [f64; 2],
) {
    let mut c = Cdr::new(buf);
    c.header(stamp_ns, frame);
    c.quaternion([0.0, 0.0, 0.0, 1.0]);
    let mut cov = [0.0; 9];
    cov[0] = -1.0;
    c.f64s(&cov);
    c.vector(gyroscope);
    c.f64s(&diagonal3(variances[0]));
    c.vector(accelerometer);
    c.f64s(&diagonal3(variances[1]));
}

fn diagonal3(v: f64) -> [f64; 9] {
    [v, 0.0, 0.0, 0.0, v, 0.0, 0.0, 0.0, v]
}

/// A `nav_msgs/Odometry`: `child` at `pose` in `frame`, moving with `linear` and `angular`
/// velocities in the child frame.
#[allow(clippy::too_many_arguments)]
pub fn odometry(
    buf: &mut Vec<u8>,
    stamp_ns: u64,
    frame: &str,
    child: &str,
    pose: &Pose,
    linear: [f64; 3],
    angular: [f64; 3],
    variance: f64,
) {
    let mut c = Cdr::new(buf);
    c.header(stamp_ns, frame);
    c.string(child);
    c.pose(pose);
    let mut cov = [0.0; 36];
    for i in 0..6 {
        cov[i * 7] = variance;
    }
    c.f64s(&cov);
    c.vector(linear);
    c.vector(angular);
    c.f64s(&cov);
}

/// A `tf2_msgs/TFMessage` of `(parent, child, transform)`.
pub fn tf_message(buf: &mut Vec<u8>, stamp_ns: u64, transforms: &[(&str, &str, Pose)]) {
    let mut c = Cdr::new(buf);
    c.u32(transforms.len() as u32);
    for (parent, child, t) in transforms {
        c.header(stamp_ns, parent);
        c.string(child);
        c.vector(t.translation);
        c.quaternion(t.quaternion());
    }
}

const SEPARATOR: &str =
    "================================================================================\n";

pub(crate) fn definition(main: &str, deps: &[&str]) -> String {
    let mut s = main.to_owned();
    for d in deps {
        s.push_str(SEPARATOR);
        s.push_str(d);
    }
    s
}

pub(crate) const HEADER: &str =
    "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n";
pub(crate) const TIME: &str = "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";
const VECTOR3: &str = "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n";
const POINT: &str = "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n";
const QUATERNION: &str =
    "MSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";

/// The `ros2msg` definition of a message type, with its dependencies, as rosbag2 stores it;
/// `None` for a type this module does not write (the cameras' are in `camera_msgs`).
pub fn schema(type_name: &str) -> Option<String> {
    let definition = match type_name {
        "sensor_msgs/msg/PointCloud2" => definition(
            "std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\nbool is_bigendian\nuint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n",
            &[
                HEADER,
                TIME,
                "MSG: sensor_msgs/PointField\nuint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\nuint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\nuint8 datatype\nuint32 count\n",
            ],
        ),
        "sensor_msgs/msg/Imu" => definition(
            "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance\n",
            &[HEADER, TIME, QUATERNION, VECTOR3],
        ),
        "nav_msgs/msg/Odometry" => definition(
            "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n",
            &[
                HEADER,
                TIME,
                "MSG: geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\nfloat64[36] covariance\n",
                "MSG: geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
                POINT,
                QUATERNION,
                "MSG: geometry_msgs/TwistWithCovariance\ngeometry_msgs/Twist twist\nfloat64[36] covariance\n",
                "MSG: geometry_msgs/Twist\ngeometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n",
                VECTOR3,
            ],
        ),
        "tf2_msgs/msg/TFMessage" => definition(
            "geometry_msgs/TransformStamped[] transforms\n",
            &[
                "MSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n",
                HEADER,
                TIME,
                "MSG: geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n",
                VECTOR3,
                QUATERNION,
            ],
        ),
        _ => return None,
    };
    Some(definition)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_aligned_from_after_the_encapsulation_header() {
        let mut buf = vec![9u8; 3];
        let mut c = Cdr::new(&mut buf);
        c.u8(1);
        c.f64(2.0);
        c.string("ab");
        assert_eq!(buf[3..7], [0, 1, 0, 0]);
        // 1 byte, then 7 of padding before the float64 at offset 8 from the data's start.
        assert_eq!(buf[7], 1);
        assert_eq!(buf[8..15], [0; 7]);
        assert_eq!(f64::from_le_bytes(buf[15..23].try_into().unwrap()), 2.0);
        assert_eq!(buf[23..27], 3u32.to_le_bytes());
        assert_eq!(&buf[27..30], b"ab\0");
    }
}
