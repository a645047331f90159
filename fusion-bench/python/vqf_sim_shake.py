"""VQF 6D on the simulated shakes of ShakeTiltTest: the inclination error at the momentary quiet samples.

Usage: python3 vqf_sim_shake.py SHAKE.csv
  (SHAKE.csv: written by `mvn -pl fusion-core test -Dtest=ShakeTiltTest -Dshake.csv=SHAKE.csv`;
   columns t_s, gx..gz, ax..az, quiet (1 at a momentary quiet sample during the shakes), truth qw..qz)
Prints the median and the largest angle between VQF 6D's up and the truth's there, degrees; the test
holds the median it printed (vqf 2.1.2, default parameters).
"""
import sys

import numpy as np
import pandas as pd
from vqf import VQF

d = pd.read_csv(sys.argv[1])
ts = float(np.median(np.diff(d["t_s"].to_numpy())))
gyr = np.ascontiguousarray(d[["gx", "gy", "gz"]].to_numpy())
acc = np.ascontiguousarray(d[["ax", "ay", "az"]].to_numpy())
q = VQF(ts).updateBatch(gyr, acc)["quat6D"]


def up(q):
    """The world's up in the sensor frame for orientations sensor -> world, [w, x, y, z] rows."""
    w, x, y, z = q.T
    return np.column_stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)])


angle = np.degrees(np.arccos(np.clip((up(q) * up(d[["qw", "qx", "qy", "qz"]].to_numpy())).sum(1), -1, 1)))
quiet = np.sort(angle[d["quiet"].to_numpy() == 1])
print("VQF 6D: %d quiet samples, median %.2f deg, largest %.2f deg" % (len(quiet), quiet[len(quiet) // 2], quiet[-1]))
