#!/usr/bin/env bash
# Times `fusion replay` of the plain 9D table (2,199,600 rows, default 14 output columns) beside
# the Python pipeline a user would write instead (pandas read_csv + VQF + to_csv,
# fusion-bench/python/replay_vqf.py), in one run, whole processes (JVM start included), with
# /usr/bin/time: wall clock, user and system CPU, maximum resident memory. See docs/BENCHMARKS.md.
#
# Usage: fusion-bench/scripts/table-replay-timing.sh [RUNS] [WORK_DIR]
#   RUNS      replays of each kind (default 3)
#   WORK_DIR  where the table and the outputs go (default a new temporary folder; 600 MB)
# Needs the fusion jar (mvn -B package -DskipTests) and, for the Python part, python3 with pandas
# and vqf (pip install pandas vqf); without them that part is skipped and said so. bin/fusion runs
# the java of FUSION_JAVA or JAVA_HOME if set (with JDK 25 or newer it keeps an AOT cache).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
fusion="$root/bin/fusion"
runs=${1:-3}
work=${2:-$(mktemp -d)}
mkdir -p "$work"
table="$work/table.csv"
fmt="%e s wall, %U s user, %S s sys, %M KB max RSS"
java=${FUSION_JAVA:-}
if [ -z "$java" ] && [ -n "${JAVA_HOME:-}" ]; then java="$JAVA_HOME/bin/java"; fi
echo "machine: $(nproc) cores, $("${java:-java}" -version 2>&1 | head -1), load average $(cut -d' ' -f1-3 /proc/loadavg)"
if [ ! -s "$table" ]; then
  "$fusion" simulate --duration 3600 --rate 611 -o "$table"
fi
echo "table: $table, $(($(wc -l < "$table") - 1)) rows, $(du -m "$table" | cut -f1) MB"
# The first run after a build writes the start-up cache bin/fusion uses (see bin/fusion): do it on
# the first 200,000 rows (with JDK 25 the cache keeps that run's method profiles).
head -n 200001 "$table" > "$work/first.csv"
"$fusion" replay --quiet "$work/first.csv" -o "$work/first-out.csv"
head -n 11 "$table" > "$work/small.csv"
echo "JVM start and a 10-row replay (start-up cache in place):"
for i in 1 2 3; do /usr/bin/time -f "  $fmt" "$fusion" replay --quiet "$work/small.csv" -o "$work/small-out.csv"; done
have_python=1
python3 -c 'import pandas, vqf' 2>/dev/null || have_python=0
for i in $(seq 1 "$runs"); do
  echo "run $i, load average $(cut -d' ' -f1-3 /proc/loadavg)"
  /usr/bin/time -f "  fusion replay -o (synced file): $fmt" "$fusion" replay --quiet "$table" -o "$work/out.csv"
  /usr/bin/time -f "  fusion replay > file:           $fmt" sh -c "'$fusion' replay --quiet '$table' > '$work/out-stdout.csv'"
  if [ "$have_python" = 1 ]; then
    /usr/bin/time -f "  pandas + vqf + to_csv:          $fmt" python3 "$root/fusion-bench/python/replay_vqf.py" "$table" "$work/vqf.csv"
  fi
done
[ "$have_python" = 1 ] || echo "python3 with pandas and vqf not found: the Python pipeline was not timed"
cmp -s "$work/out.csv" "$work/out-stdout.csv" && echo "outputs: -o and standard output give the same $(du -m "$work/out.csv" | cut -f1) MB"
echo "rows/s = 2,199,600 / wall clock; work dir $work (remove it when done)"
