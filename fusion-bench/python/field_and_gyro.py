"""What each data set asks of the heading: how far the magnetometer's heading strays, and how fast the
gyroscope's heading drifts, both measured against the truth.

Usage:
  python3 field_and_gyro.py DATA_DIR [SUBSET...]
      SUBSET: folders of trial folders under DATA_DIR (default: broad-subset tyrex-subset oxiod-subset
      advio-subset). Each trial folder holds input.csv.gz (t_s,gx,gy,gz,ax,ay,az,mx,my,mz) and truth.csv.gz
      (t_s,qw,qx,qy,qz,movement; sensor -> ENU, row for row with the input). Prints one line per trial and
      the mean per group (disturbed/undisturbed from the name, else meta.json's venue or motion).

Per trial, over the rows whose truth is finite (and, where the truth marks them, scored):
  field_deg   the magnetometer reading turned into the earth frame by the truth; the RMS of its horizontal
              direction about the trial's circular mean: what a filter that trusts the field fully
              would make of heading.
  field_median_deg  the median of its absolute value: a brief disturbance (a magnet passed by) raises the RMS
              but not the median; a building whose field strays everywhere raises both.
  field30_deg the same about its 30-s about its 30-s centred moving mean: the part a heading filter with a memory of
              about 30 s cannot average out.
  gyro30_deg  the RMS of the heading error that 30 s of the gyroscope alone (no bias removed) gathers,
              from the truth's orientation, over windows every 15 s: what the magnetometer has to correct.
  bias_dps    the magnitude of the median, over 0.5-s steps, of the gyroscope's rotation less the truth's, per
              second (device frame): the gyroscope's apparent bias, scale errors included where the phone
              turns mostly one way.
A filter's best heading gain grows with the gyroscope's drift and falls with the field's error (a
Kalman filter's steady-state gain goes as their ratio); docs/ACCURACY.md gives the table.
Needs numpy and scipy.
"""
import gzip
import json
import math
import os
import sys

import numpy as np
from scipy.ndimage import uniform_filter1d
from scipy.spatial.transform import Rotation

SUBSETS = ["broad-subset", "tyrex-subset", "oxiod-subset", "advio-subset"]
WINDOW_S = 30.0


def read(path):
    with gzip.open(path, "rt") as f:
        f.readline()
        return np.loadtxt(f, delimiter=",")


def group(trial_dir, name):
    # As the tuning harness groups (fusion-bench's TuneFilter): the name first, then meta.json.
    if "undisturbed" in name or "NoDist" in name:
        return "undisturbed"
    if "disturbed" in name or "Dist" in name:
        return "disturbed"
    with open(os.path.join(trial_dir, "meta.json")) as f:
        meta = json.load(f)
    for key in ("venue", "motion"):
        if meta.get(key):
            return meta[key]
    return "all"


def gyro_integrated(t, g):
    """The gyroscope's orientation change from the first row, as quaternions [x, y, z, w] per row."""
    out = np.empty((len(t), 4))
    w, x, y, z = 1.0, 0.0, 0.0, 0.0
    out[0] = (0.0, 0.0, 0.0, 1.0)
    for i in range(1, len(t)):
        dt = t[i] - t[i - 1]
        rx, ry, rz = g[i] * dt  # a reading is the rate over the interval that ends at its time
        a = math.sqrt(rx * rx + ry * ry + rz * rz)
        s = math.sin(a / 2) / a if a > 0 else 0.5
        c = math.cos(a / 2)
        bx, by, bz = rx * s, ry * s, rz * s
        w, x, y, z = (w * c - x * bx - y * by - z * bz, w * bx + x * c + y * bz - z * by,
                      w * by - x * bz + y * c + z * bx, w * bz + x * by - y * bx + z * c)
        out[i] = (x, y, z, w)
    return out


def trial_figures(trial_dir):
    rows = read(os.path.join(trial_dir, "input.csv.gz"))
    truth = read(os.path.join(trial_dir, "truth.csv.gz"))
    n = min(len(rows), len(truth))
    rows, truth = rows[:n], truth[:n]
    t = rows[:, 0]
    q = truth[:, 1:5]
    ok = np.all(np.isfinite(q), axis=1) & (np.linalg.norm(np.nan_to_num(q), axis=1) > 0.5)
    ok &= np.all(np.isfinite(rows[:, 1:10]), axis=1)
    if np.any(truth[:, 5] > 0):
        ok &= truth[:, 5] > 0
    xyzw = np.where(ok[:, None], q[:, [1, 2, 3, 0]], [0.0, 0.0, 0.0, 1.0])
    truth_rot = Rotation.from_quat(xyzw)
    field = truth_rot.apply(np.nan_to_num(rows[:, 7:10]))
    direction = np.exp(1j * np.arctan2(field[:, 0], field[:, 1]))
    mean = np.mean(direction[ok])
    field_deg = np.degrees(np.angle(direction[ok] * np.conj(mean)))
    k = max(1, int(round(WINDOW_S / np.median(np.diff(t)))))
    local = uniform_filter1d(direction.real, k) + 1j * uniform_filter1d(direction.imag, k)
    field30_deg = np.degrees(np.angle(direction * np.conj(local)))[ok]
    # Heading error of the gyroscope alone over a window from s to e: the world-frame rotation
    # truth(s) G(s)^-1 G(e) truth(e)^-1, its angle about the vertical.
    gyro = Rotation.from_quat(gyro_integrated(t, np.nan_to_num(rows[:, 1:4])))
    anchor = truth_rot * gyro.inv()
    starts = np.arange(0, n - k, k // 2)
    starts = starts[ok[starts] & ok[starts + k]]
    drift = np.degrees((anchor[starts] * anchor[starts + k].inv()).as_rotvec()[:, 2]) if len(starts) else np.array([np.nan])
    step = max(1, int(round(0.5 / np.median(np.diff(t)))))
    a = np.arange(0, n - step, step)
    a = a[ok[a] & ok[a + step]]
    truth_step = (truth_rot[a].inv() * truth_rot[a + step]).as_rotvec()
    gyro_step = (gyro[a].inv() * gyro[a + step]).as_rotvec()
    excess = (gyro_step - truth_step) / (t[a + step] - t[a])[:, None]
    bias = np.degrees(np.linalg.norm(np.median(excess, axis=0))) if len(a) else np.nan
    return rms(field_deg), float(np.median(np.abs(field_deg))), rms(field30_deg), rms(drift), bias


def rms(a):
    return float(np.sqrt(np.mean(np.square(a))))


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    data = argv[0]
    subsets = argv[1:] or SUBSETS
    print("subset,trial,group,field_deg,field_median_deg,field30_deg,gyro30_deg,bias_dps")
    groups = {}
    for subset in subsets:
        root = os.path.join(data, subset)
        for name in sorted(os.listdir(root)):
            trial_dir = os.path.join(root, name)
            if not os.path.isfile(os.path.join(trial_dir, "truth.csv.gz")):
                continue
            g = group(trial_dir, name)
            figures = trial_figures(trial_dir)
            groups.setdefault((subset, g), []).append(figures)
            print(f"{subset},{name},{g}," + ",".join(f"{v:.1f}" for v in figures), flush=True)
    print("\nsubset,group,trials,field_deg,field_median_deg,field30_deg,gyro30_deg,bias_dps")
    for (subset, g), figures in groups.items():
        m = np.nanmean(np.array(figures), axis=0)
        print(f"{subset},{g},{len(figures)}," + ",".join(f"{v:.1f}" for v in m))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
