"""The pipeline a user would write instead of `fusion replay`: pandas read_csv, VQF, to_csv.

Usage: python3 replay_vqf.py [--offline] TABLE.csv OUT.csv [TABLE.csv OUT.csv ...]
  (TABLE: t_s,gx,gy,gz,ax,ay,az,mx,my,mz; --offline: vqf.offlineVQF, the acausal variant)
Writes t_s,qw,qx,qy,qz (VQF's 9D quaternion, sensor -> ENU) per table. See docs/BENCHMARKS.md.
"""
import sys

import numpy as np
import pandas as pd
from vqf import VQF, offlineVQF

args = sys.argv[1:]
offline = args[:1] == ["--offline"]
if offline:
    args = args[1:]
for inp, outp in zip(args[0::2], args[1::2]):
    table = pd.read_csv(inp)
    t = table["t_s"].to_numpy()
    gyr = np.ascontiguousarray(table[["gx", "gy", "gz"]].to_numpy())
    acc = np.ascontiguousarray(table[["ax", "ay", "az"]].to_numpy())
    mag = np.ascontiguousarray(table[["mx", "my", "mz"]].to_numpy())
    ts = float(np.median(np.diff(t)))
    quat = offlineVQF(gyr, acc, mag, ts)["quat9D"] if offline else VQF(ts).updateBatch(gyr, acc, mag)["quat9D"]
    out = pd.DataFrame({"t_s": t, "qw": quat[:, 0], "qx": quat[:, 1], "qy": quat[:, 2], "qz": quat[:, 3]})
    out.to_csv(outp, index=False)
