#!/usr/bin/env bash
# Times, whole processes (JVM start included), with /usr/bin/time (wall, CPU, peak RSS), in one run:
#  1. `fusion replay` causal and `--offline` of one simulated hour at 200 Hz (720,000 rows), beside
#     the Python pipeline (pandas read_csv + vqf.offlineVQF + to_csv, fusion-bench/python/replay_vqf.py);
#  2. a dataset of 40 tables of 50,000 rows each: `fusion replay ALL -o DIR/` (one process, all
#     cores) against one `fusion replay` process per file, causal and offline, beside the Python
#     pipeline over the same files (one process, offlineVQF). See docs/BENCHMARKS.md.
#
# Usage: fusion-bench/scripts/offline-batch-timing.sh [WORK_DIR]   (default a new temporary folder; 1.5 GB)
# Needs the fusion jar (mvn -B package -DskipTests); python3 with pandas and vqf for the Python rows.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
fusion="$root/bin/fusion"
work=${1:-$(mktemp -d)}
mkdir -p "$work/set" "$work/out"
fmt="%e s wall, %U s user, %S s sys, %M KB max RSS"
echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
hour="$work/hour.csv"
[ -s "$hour" ] || "$fusion" simulate --duration 3600 --rate 200 -o "$hour"
for k in $(seq -w 1 40); do
  [ -s "$work/set/r$k.csv" ] || "$fusion" simulate --duration 250 --rate 200 --seed "$k" -o "$work/set/r$k.csv"
done
"$fusion" replay --quiet "$work/set/r01.csv" -o "$work/warm.csv" # writes the start-up cache once
have_python=1
python3 -c 'import pandas, vqf' 2>/dev/null || have_python=0
echo "one hour at 200 Hz, 720,000 rows:"
/usr/bin/time -f "  fusion replay (causal):      $fmt" "$fusion" replay --quiet "$hour" -o "$work/hour-causal.csv"
/usr/bin/time -f "  fusion replay --offline:     $fmt" "$fusion" replay --quiet --offline "$hour" -o "$work/hour-offline.csv"
/usr/bin/time -f "  --offline, -Xmx64m:          $fmt" env FUSION_JAVA_OPTS=-Xmx64m "$fusion" replay --quiet --offline "$hour" -o "$work/hour-offline64.csv"
if [ "$have_python" = 1 ]; then
  /usr/bin/time -f "  pandas + offlineVQF + to_csv: $fmt" python3 "$root/fusion-bench/python/replay_vqf.py" --offline "$hour" "$work/hour-vqf.csv"
fi
echo "40 tables of 50,000 rows (2,000,000 rows):"
for mode in "" "--offline"; do
  label=${mode:-causal}
  rm -rf "$work/out"; mkdir -p "$work/out"
  /usr/bin/time -f "  batch, one process ($label):      $fmt" "$fusion" replay $mode "$work"/set/*.csv -o "$work/out/" 2>"$work/batch.log" || { cat "$work/batch.log"; exit 1; }
  tail -n 1 "$work/batch.log" | sed 's/^/    /'
  /usr/bin/time -f "  one process per file ($label):    $fmt" sh -c "for f in '$work'/set/*.csv; do '$fusion' replay --quiet $mode \"\$f\" -o '$work/out/one.csv'; done"
done
if [ "$have_python" = 1 ]; then
  pairs=""
  for f in "$work"/set/*.csv; do pairs="$pairs $f $work/out/vqf-$(basename "$f")"; done
  /usr/bin/time -f "  pandas + offlineVQF + to_csv, one process: $fmt" python3 "$root/fusion-bench/python/replay_vqf.py" --offline $pairs
fi
[ "$have_python" = 1 ] || echo "python3 with pandas and vqf not found: the Python rows were not timed"
echo "rows/s = rows / wall clock; work dir $work (remove it when done)"
