"""VQF on exactly the samples the project's filter saw, and the peer figures the tests compare with.

Usage:
  python3 vqf_peers.py ROWS.csv[.gz] OUT.csv
      ROWS: an IMU table t_s,gx,gy,gz,ax,ay,az[,mx,my,mz] (fusion replay --rows, or a trial's
      input.csv.gz). Runs VQF with its default parameters (Ts = the median step of t_s), 9D when
      the table has magnetometer columns, else 6D, and writes t_s,qw,qx,qy,qz per row (sensor ->
      ENU). Rows without an accelerometer reading are left out; a missing magnetometer reading
      is passed as zeros (VQF skips the magnetometer update then).
  python3 vqf_peers.py [--offline] ROWS.csv[.gz] OUT.csv  (--offline: vqf.offlineVQF, the acausal variant)
  python3 vqf_peers.py --trials [--offline] DATA_DIR
      Prints subset/trial,total RMSE (deg) of VQF (real-time, or offlineVQF) on every trial of the
      BROAD and Tyrex subsets, scored by `bin/fusion eval --truth` (docs/ACCURACY.md, "Offline").
  python3 vqf_peers.py --figures DATA_DIR OUT.csv
      Regenerates fusion-core/src/test/resources/peers/vqf.csv: for every input listed below,
      the rows via `bin/fusion replay --rows`, VQF on them, and the figures by the project's own
      metric code: `bin/fusion eval --rows` (still-sample tilt, after-motion tilt) for the real
      exports, `bin/fusion eval --truth` (BROAD total RMSE) for the trials, of VQF and of
      vqf.offlineVQF (offline_total_rmse_deg). Needs vqf==2.1.2,
      numpy, pandas and a built fusion command. Intermediate files go to a temporary folder.
See docs/ACCURACY.md ("Peer figures").
"""
import csv
import decimal
import io
import os
import subprocess
import sys
import tempfile

import numpy as np
import pandas as pd

VQF_VERSION = "2.1.2"

# The real exports RealExportsTest replays (and the after-motion windows, s, it checks).
REAL_EXPORTS = [
    "pp-android-soerenarlt",
    "pp-android-wld16/studies/data_science/res/phybox_data",
    "pp-android-wld16/studies/data_science/res/phybox_data_2",
    "pp-degs-adtngrha",
    "pp-ios-foger3",
    "pp-ios-slmaking",
    "sl-android-anurag",
    "sl-android-igor/1",
    "sl-android-igor/bom",
    "sl-android-santollan",
    "sl-ios-lynch/data/2022-09-16_11-15-46",
    "sl-ios-lynch/data/2022-09-16_11-15-46.zip",
    "sl-ios-lynch/data/2022-09-26_15-32-56.zip",
    "sl-ios-siberiawolf",
    "sl-ios-simorxb",
    "sl-unknown-shuhrat",
]
AFTER_MOTION = {"pp-ios-foger3": (74.0, 84.0), "sl-android-anurag": (5.0, 10.0)}
SUBSETS = ["broad-subset", "tyrex-subset"]

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FUSION = os.path.join(REPO, "bin", "fusion")


def run_vqf(rows_path, out_path, offline=False):
    from vqf import VQF, offlineVQF

    table = pd.read_csv(rows_path)
    table = table[np.isfinite(table[["ax", "ay", "az"]].to_numpy()).all(axis=1)]
    t = table["t_s"].to_numpy()
    gyr = np.ascontiguousarray(table[["gx", "gy", "gz"]].to_numpy(dtype=float))
    acc = np.ascontiguousarray(table[["ax", "ay", "az"]].to_numpy(dtype=float))
    ts = float(np.median(np.diff(t)))
    if "mx" in table.columns:
        mag = np.ascontiguousarray(np.nan_to_num(table[["mx", "my", "mz"]].to_numpy(dtype=float), nan=0.0))
        quat = offlineVQF(gyr, acc, mag, ts)["quat9D"] if offline else VQF(ts).updateBatch(gyr, acc, mag)["quat9D"]
    else:
        quat = offlineVQF(gyr, acc, None, ts)["quat6D"] if offline else VQF(ts).updateBatch(gyr, acc)["quat6D"]
    out = pd.DataFrame({"t_s": table["t_s"].map(lambda v: "%.9f" % v), "qw": quat[:, 0], "qx": quat[:, 1], "qy": quat[:, 2], "qz": quat[:, 3]})
    out.to_csv(out_path, index=False)


def fusion(*args):
    return subprocess.run([FUSION, *args], check=True, capture_output=True, text=True).stdout


def csv_row(text):
    """The one data row of `fusion eval --csv`'s output, as a dict of column name to cell."""
    return next(csv.DictReader(io.StringIO(text)))


def figure(cell):
    """A committed figure: two decimals rounded half up from the CSV's six (as the Markdown table rounds), or the
    dash of a figure without samples."""
    return str(decimal.Decimal(cell).quantize(decimal.Decimal("0.01"), decimal.ROUND_HALF_UP)) if cell else "\u2014"


def trial_figures(data, offline):
    """(subset/trial, total RMSE) of VQF, real-time or offline (vqf.offlineVQF), on every trial of the subsets."""
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        est = os.path.join(tmp, "vqf.csv")
        for subset in SUBSETS:
            for trial in sorted(os.listdir(os.path.join(data, subset))):
                d = os.path.join(data, subset, trial)
                if not os.path.isdir(d):
                    continue
                inp = next(os.path.join(d, f) for f in ("input.csv.gz", "input.csv") if os.path.exists(os.path.join(d, f)))
                truth = next(os.path.join(d, f) for f in ("truth.csv.gz", "truth.csv") if os.path.exists(os.path.join(d, f)))
                run_vqf(inp, est, offline)
                has_mag = "mx" in pd.read_csv(inp, nrows=1).columns
                row = csv_row(fusion("eval", "--csv", *([] if has_mag else ["--6d"]), "--truth", truth, est))
                out.append(("%s/%s" % (subset, trial), figure(row["total_deg"])))
    return out


def figures(data, out_path):
    import vqf

    assert vqf.__version__ == VQF_VERSION if hasattr(vqf, "__version__") else True
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        rows, est = os.path.join(tmp, "rows.csv"), os.path.join(tmp, "vqf.csv")
        for name in REAL_EXPORTS:
            fusion("replay", "--quiet", os.path.join(data, "realdata", name), "-o", os.devnull, "--rows", rows)
            run_vqf(rows, est)
            window = AFTER_MOTION.get(name)
            args = ["eval", "--csv", "--rows", rows] + (["--after", "%g:%g" % window] if window else []) + [est]
            row = csv_row(fusion(*args))
            still_n, still = row["still_samples"], figure(row["still_tilt_median_deg"])
            after_n, after = row["after_motion_samples"], figure(row["after_motion_tilt_median_deg"])
            lines.append("realdata/%s,still_tilt_median_deg,%s,%s" % (name, still, still_n))
            if window:
                lines.append("realdata/%s,after_motion_tilt_median_deg_%g_%g_s,%s,%s" % (name, window[0], window[1], after, after_n))
    for metric, offline in (("total_rmse_deg", False), ("offline_total_rmse_deg", True)):
        lines += ["%s,%s,%s," % (trial, metric, value) for trial, value in trial_figures(data, offline)]
    with open(out_path, "w") as f:
        f.write("# VQF %s (Python package vqf, default parameters; 9D, 6D without magnetometer) on the rows the project's\n" % VQF_VERSION)
        f.write("# filter steps on; figures by the project's metric code. Regenerate (the data beside the repository):\n")
        f.write("#   python3 fusion-bench/python/vqf_peers.py --figures ../shared/data fusion-core/src/test/resources/peers/vqf.csv\n")
        f.write("input,metric,value,samples\n")
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    if sys.argv[1] == "--figures":
        figures(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "--trials":
        # python3 vqf_peers.py --trials [--offline] DATA_DIR: VQF's total RMSE per trial of the subsets
        offline = sys.argv[2] == "--offline"
        for name, value in trial_figures(sys.argv[3 if offline else 2], offline):
            print("%s,%s" % (name, value))
    elif sys.argv[1] == "--offline":
        run_vqf(sys.argv[2], sys.argv[3], True)
    else:
        run_vqf(sys.argv[1], sys.argv[2])
