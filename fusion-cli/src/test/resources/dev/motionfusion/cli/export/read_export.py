"""Reads a fusion export back with the external readers and prints what they found, one row a line.

  read_export.py euroc MAV0_FOLDER   evo: the orientation with evo's EuRoC trajectory reader
                                     (file_interface.read_euroc_csv_trajectory), imu0 and mag0
                                     with evo's CSV reader (file_interface.csv_read_matrix)
  read_export.py kalibr FOLDER       imu0.csv as kalibr_bagcreater parses it (csv module, int ns,
                                     float values), imu.yaml with PyYAML as kalibr loads it

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
        ns = int(r[0])
        print("imu0_row", ns, *(repr(float(v)) for v in r[1:7]))
    with open(os.path.join(folder, "imu.yaml")) as f:
        conf = yaml.safe_load(f)
    for k in sorted(conf):
        print("yaml", k, repr(conf[k]))


if __name__ == "__main__":
    {"euroc": euroc, "kalibr": kalibr}[sys.argv[1]](sys.argv[2])
