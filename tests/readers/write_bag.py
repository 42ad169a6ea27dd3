"""Writes TUM trajectories into a ROS 2 bag (MCAP storage) with rosbags, a writer that is not
ours, so `subtgraph score --trajectory BAG` is tested on a bag as ROS 2 tools write them.

    write_bag.py BAG [--zstd] TOPIC:TYPE:FILE.tum ...

TYPE is the message type (`nav_msgs/msg/Odometry`, `geometry_msgs/msg/PoseStamped`,
`geometry_msgs/msg/PoseWithCovarianceStamped`, `geometry_msgs/msg/TransformStamped`, or
`std_msgs/msg/String` for a topic that is not a pose); each TUM line becomes one message whose
header stamp is the line's time (whole nanoseconds) and whose log time is the same. With --zstd
the MCAP chunks are Zstandard-compressed (rosbags' storage compression), else uncompressed.
"""
import sys
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

store = get_typestore(Stores.LATEST)
T = store.types
Time = T["builtin_interfaces/msg/Time"]
Header = T["std_msgs/msg/Header"]
Point = T["geometry_msgs/msg/Point"]
Quaternion = T["geometry_msgs/msg/Quaternion"]
Vector3 = T["geometry_msgs/msg/Vector3"]
Pose = T["geometry_msgs/msg/Pose"]
PoseWithCovariance = T["geometry_msgs/msg/PoseWithCovariance"]
Twist = T["geometry_msgs/msg/Twist"]
TwistWithCovariance = T["geometry_msgs/msg/TwistWithCovariance"]
Transform = T["geometry_msgs/msg/Transform"]


def message(kind, ns, row):
    header = Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="map")
    x, y, z, qx, qy, qz, qw = row[1:]
    pose = Pose(position=Point(x=x, y=y, z=z), orientation=Quaternion(x=qx, y=qy, z=qz, w=qw))
    cov = np.zeros(36)
    if kind == "nav_msgs/msg/Odometry":
        twist = TwistWithCovariance(
            twist=Twist(linear=Vector3(x=0.0, y=0.0, z=0.0), angular=Vector3(x=0.0, y=0.0, z=0.0)),
            covariance=cov,
        )
        return T[kind](
            header=header,
            child_frame_id="base_link",
            pose=PoseWithCovariance(pose=pose, covariance=cov),
            twist=twist,
        )
    if kind == "geometry_msgs/msg/PoseStamped":
        return T[kind](header=header, pose=pose)
    if kind == "geometry_msgs/msg/PoseWithCovarianceStamped":
        return T[kind](header=header, pose=PoseWithCovariance(pose=pose, covariance=cov))
    if kind == "geometry_msgs/msg/TransformStamped":
        return T[kind](
            header=header,
            child_frame_id="base_link",
            transform=Transform(
                translation=Vector3(x=x, y=y, z=z), rotation=pose.orientation
            ),
        )
    if kind == "std_msgs/msg/String":
        return T[kind](data=f"pose at {ns} ns")
    sys.exit(f"unknown type {kind}")


def main():
    bag = Path(sys.argv[1])
    zstd = "--zstd" in sys.argv[2:]
    specs = [a for a in sys.argv[2:] if a != "--zstd"]
    writer = Writer(bag, version=8, storage_plugin=StoragePlugin.MCAP)
    if zstd:
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    with writer:
        for spec in specs:
            topic, kind, tum = spec.split(":")
            conn = writer.add_connection(topic, kind, typestore=store)
            for line in Path(tum).read_text().splitlines():
                if not line.strip() or line.startswith("#"):
                    continue
                row = [float(v) for v in line.split()]
                ns = round(row[0] * 1e9)
                data = store.serialize_cdr(message(kind, ns, row), kind)
                writer.write(conn, ns, data)


if __name__ == "__main__":
    main()
