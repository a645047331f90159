"""The pipeline a user would write instead of `fusion replay`: pandas read_csv, VQF, to_csv.

Usage: python3 replay_vqf.py TABLE.csv OUT.csv   (TABLE: t_s,gx,gy,gz,ax,ay,az,mx,my,mz)
Writes t_s,qw,qx,qy,qz (VQF's 9D quaternion, sensor -> ENU). See docs/BENCHMARKS.md.
"""
import sys

import numpy as np
import pandas as pd
from vqf import VQF

table = pd.read_csv(sys.argv[1])
t = table["t_s"].to_numpy()
gyr = np.ascontiguousarray(table[["gx", "gy", "gz"]].to_numpy())
acc = np.ascontiguousarray(table[["ax", "ay", "az"]].to_numpy())
mag = np.ascontiguousarray(table[["mx", "my", "mz"]].to_numpy())
vqf = VQF(float(np.median(np.diff(t))))
quat = vqf.updateBatch(gyr, acc, mag)["quat9D"]
out = pd.DataFrame({"t_s": t, "qw": quat[:, 0], "qx": quat[:, 1], "qy": quat[:, 2], "qz": quat[:, 3]})
out.to_csv(sys.argv[2], index=False)
