"""VQF on exactly the samples the project's filter saw, and the peer figures the tests compare with.

Usage:
  python3 vqf_peers.py ROWS.csv[.gz] OUT.csv
      ROWS: an IMU table t_s,gx,gy,gz,ax,ay,az[,mx,my,mz] (fusion replay --rows, or a trial's
      input.csv.gz). Runs VQF with its default parameters (Ts = the median step of t_s), 9D when
      the table has magnetometer columns, else 6D, and writes t_s,qw,qx,qy,qz per row (sensor ->
      ENU). Rows without an accelerometer reading are left out; a missing magnetometer reading
      is passed as zeros (VQF skips the magnetometer update then).
  python3 vqf_peers.py [--offline|--6d] ROWS.csv[.gz] OUT.csv
      --offline: vqf.offlineVQF, the acausal variant; --6d: gyroscope and accelerometer only, the
      magnetometer columns ignored.
  python3 vqf_peers.py --trials [--offline|--6d] DATA_DIR
      Prints subset/trial,total RMSE (deg) of VQF (real-time 9D, offlineVQF 9D, or real-time 6D) on
      every trial of the subsets below, scored by `bin/fusion eval --truth` (docs/ACCURACY.md, "Offline").
  python3 vqf_peers.py --figures DATA_DIR OUT.csv
      Regenerates fusion-core/src/test/resources/peers/vqf.csv: for every input listed below,
      the rows via `bin/fusion replay --rows`, VQF on them, and the figures by the project's own
      metric code: `bin/fusion eval --rows` (still-sample tilt, after-motion tilt) for the real
      exports, `bin/fusion eval --truth` (BROAD total RMSE) for the trials, of VQF 9D
      (total_rmse_deg), of vqf.offlineVQF 9D (offline_total_rmse_deg) and of VQF 6D
      (total_rmse_6d_deg). Needs vqf==2.1.2, numpy, pandas and a built fusion command.
      Intermediate files go to a temporary folder.

Heading-offset scoring: a 6D figure (VQF 6D, or a trial without magnetometer) is scored with one
constant heading offset per trial removed (`fusion eval --6d`). So is every figure of a trial whose
meta.json declares `"scoring": "6d: ..."` (the ADVIO subset: its truth has no north), whatever the
method: there total_rmse_deg and offline_total_rmse_deg are 9D estimates scored with the offset
removed, as the subset's README scores every method.
See docs/ACCURACY.md ("Peer figures").
"""
import csv
import decimal
import io
import json
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
SUBSETS = ["broad-subset", "tyrex-subset", "oxiod-subset", "advio-subset"]

# The figures per trial: metric name -> variant of run_vqf.
TRIAL_METRICS = [("total_rmse_deg", "9d"), ("offline_total_rmse_deg", "offline"), ("total_rmse_6d_deg", "6d")]

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FUSION = os.path.join(REPO, "bin", "fusion")


def run_vqf(rows_path, out_path, offline=False, six_d=False):
    """VQF on the IMU table at rows_path, written to out_path: 9D when the table has magnetometer columns and not
    six_d, else 6D; real-time, or offlineVQF when offline."""
    from vqf import VQF, offlineVQF

    table = pd.read_csv(rows_path)
    if six_d:
        table = table.drop(columns=[c for c in ("mx", "my", "mz") if c in table.columns])
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


def heading_offset_scored(trial_dir):
    """True when the trial's meta.json declares that every method is scored with one constant heading offset removed
    (`"scoring": "6d: ..."`, the ADVIO subset)."""
    meta = os.path.join(trial_dir, "meta.json")
    if not os.path.exists(meta):
        return False
    with open(meta) as f:
        return str(json.load(f).get("scoring", "")).startswith("6d")


def trial_figures(data, variant):
    """(subset/trial, total RMSE) of VQF on every trial of the subsets: variant "9d" (real-time), "offline"
    (vqf.offlineVQF, 9D) or "6d" (real-time, no magnetometer). A 6D estimate, and every estimate of a trial whose
    meta.json declares the 6d scoring, is scored with one constant heading offset removed."""
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
                run_vqf(inp, est, offline=variant == "offline", six_d=variant == "6d")
                has_mag = "mx" in pd.read_csv(inp, nrows=1).columns
                six_d_score = not has_mag or variant == "6d" or heading_offset_scored(d)
                row = csv_row(fusion("eval", "--csv", *(["--6d"] if six_d_score else []), "--truth", truth, est))
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
    for metric, variant in TRIAL_METRICS:
        lines += ["%s,%s,%s," % (trial, metric, value) for trial, value in trial_figures(data, variant)]
    with open(out_path, "w") as f:
        f.write("# VQF %s (Python package vqf, default parameters; 9D, 6D without magnetometer) on the rows the project's\n" % VQF_VERSION)
        f.write("# filter steps on; figures by the project's metric code. Trials: total RMSE of VQF 9D (total_rmse_deg), of\n")
        f.write("# vqf.offlineVQF 9D (offline_total_rmse_deg) and of VQF 6D (total_rmse_6d_deg, one heading offset per trial\n")
        f.write("# removed); on a subset whose trials' meta.json declare the 6d scoring (advio-subset) every figure has the\n")
        f.write("# heading offset removed. Regenerate (the data beside the repository):\n")
        f.write("#   python3 fusion-bench/python/vqf_peers.py --figures ../shared/data fusion-core/src/test/resources/peers/vqf.csv\n")
        f.write("input,metric,value,samples\n")
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    if sys.argv[1] == "--figures":
        figures(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "--trials":
        # python3 vqf_peers.py --trials [--offline|--6d] DATA_DIR: VQF's total RMSE per trial of the subsets
        flag = sys.argv[2] if sys.argv[2] in ("--offline", "--6d") else None
        for name, value in trial_figures(sys.argv[3 if flag else 2], {"--offline": "offline", "--6d": "6d"}.get(flag, "9d")):
            print("%s,%s" % (name, value))
    elif sys.argv[1] == "--offline":
        run_vqf(sys.argv[2], sys.argv[3], offline=True)
    elif sys.argv[1] == "--6d":
        run_vqf(sys.argv[2], sys.argv[3], six_d=True)
    else:
        run_vqf(sys.argv[1], sys.argv[2])
