"""Reads a fusion export back with the external readers and prints what they found, one row a line.

  read_export.py euroc MAV0_FOLDER   evo: the orientation with evo's EuRoC trajectory reader
                                     (file_interface.read_euroc_csv_trajectory), imu0 and mag0
                                     with evo's CSV reader (file_interface.csv_read_matrix)
  read_export.py kalibr FOLDER       imu0.csv as kalibr_bagcreater parses it (csv module, the
                                     time string split into s and ns, float values), imu.yaml with PyYAML as kalibr loads it
  read_export.py ros2 FILE.mcap      the MCAP file with the mcap package and mcap-ros2-support's
                                     CDR decoder, and again with rosbags (AnyReader)
  read_export.py configs FOLDER      fusion allan's noise configurations with OpenCV's FileStorage
                                     (cv2), the reader OpenVINS, VINS and ORB-SLAM3 load them with,
                                     and imu.yaml with PyYAML as kalibr loads it

Output lines: "<table> <field> ..." with every number as Python's repr (the shortest decimal
that reads back to the same double), so the caller can compare them to the last digit.
"""
import csv
import os
import sys


def euroc(mav0):
    from evo.tools import file_interface as fi
    traj = fi.read_euroc_csv_trajectory(os.path.join(mav0, "state_groundtruth_estimate0", "data.csv"))
    print("pose", len(traj.timestamps))
    for t, p, q in zip(traj.timestamps, traj.positions_xyz, traj.orientations_quat_wxyz):
        print("pose_row", repr(float(t)), *(repr(float(v)) for v in q), *(repr(float(v)) for v in p))
    for table in ("imu0", "mag0"):
        path = os.path.join(mav0, table, "data.csv")
        if not os.path.exists(path):
            continue
        rows = fi.csv_read_matrix(path, delim=",", comment_str="#")
        print(table, len(rows))
        for r in rows:
            print(table + "_row", int(r[0]), *(repr(float(v)) for v in r[1:]))


def kalibr(folder):
    import yaml
    with open(os.path.join(folder, "imu0.csv"), newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = list(reader)
    print("header", ",".join(header))
    print("imu0", len(rows))
    for r in rows:
        # As kalibr_bagcreater: the seconds are all but the last nine digits, the nanoseconds those nine.
        ns = int(r[0][0:-9]) * 1000000000 + int(r[0][-9:])
        print("imu0_row", ns, *(repr(float(v)) for v in r[1:7]))
    with open(os.path.join(folder, "imu.yaml")) as f:
        conf = yaml.safe_load(f)
    for k in sorted(conf):
        print("yaml", k, repr(conf[k]))


def ros2(path):
    from pathlib import Path
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rosbags.highlevel import AnyReader
    with open(path, "rb") as f:
        for _, channel, message, m in make_reader(f, decoder_factories=[DecoderFactory()]).iter_decoded_messages():
            ros2_row("mcap", channel.topic, message.log_time, m)
    with AnyReader([Path(path)]) as reader:
        for connection, t, raw in reader.messages():
            ros2_row("rosbags", connection.topic, t, reader.deserialize(raw, connection.msgtype))


def ros2_row(reader, topic, log_time, m):
    """One message: log time, stamp, frame_id, the values, the covariances' first entry, the largest magnitude
    off their diagonals, then the diagonals of the angular velocity and linear acceleration covariances
    (of the magnetic field's on imu/mag)."""
    if topic == "imu/mag":
        values = [m.magnetic_field.x, m.magnetic_field.y, m.magnetic_field.z]
        covariances = [list(m.magnetic_field_covariance)]
        diagonals = [list(m.magnetic_field_covariance)]
    else:
        q, w, a = m.orientation, m.angular_velocity, m.linear_acceleration
        values = [q.w, q.x, q.y, q.z, w.x, w.y, w.z, a.x, a.y, a.z]
        covariances = [list(m.orientation_covariance), list(m.angular_velocity_covariance), list(m.linear_acceleration_covariance)]
        diagonals = covariances[1:]
    first = [c[0] for c in covariances]
    off = max(abs(v) for c in covariances for i, v in enumerate(c) if i not in (0, 4, 8))
    diagonal = [c[i] for c in diagonals for i in (0, 4, 8)]
    print(reader + ":" + topic, log_time, m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id,
          *(repr(float(v)) for v in values + first + [off] + diagonal))


def configs(folder):
    import cv2
    import yaml
    with open(os.path.join(folder, "imu.yaml")) as f:
        for k, v in sorted(yaml.safe_load(f).items()):
            print("kalibr", k, repr(v))
    for name, keys in (("kalibr_imu_chain.yaml", None),
                       ("vins_imu.yaml", ["acc_n", "gyr_n", "acc_w", "gyr_w"]),
                       ("orbslam3_imu.yaml", ["IMU.NoiseGyro", "IMU.NoiseAcc", "IMU.GyroWalk", "IMU.AccWalk", "IMU.Frequency"])):
        fs = cv2.FileStorage(os.path.join(folder, name), cv2.FILE_STORAGE_READ)
        if not fs.isOpened():
            raise SystemExit("cv2.FileStorage cannot open " + name)
        if keys is None:
            node = fs.getNode("imu0")
            for k in node.keys():
                n = node.getNode(k)
                if n.isString():
                    print(name, k, n.string())
                elif n.isSeq():
                    print(name, k, *(repr(float(n.at(i).at(j).real())) for i in range(n.size()) for j in range(n.at(i).size())))
                else:
                    print(name, k, repr(float(n.real())))
        else:
            for k in keys:
                n = fs.getNode(k)
                if n.empty():
                    raise SystemExit(name + ": no " + k)
                print(name, k, repr(float(n.real())))
        fs.release()


if __name__ == "__main__":
    {"euroc": euroc, "kalibr": kalibr, "ros2": ros2, "configs": configs}[sys.argv[1]](sys.argv[2])
