#!/usr/bin/env bash
# Reproduces the figures of the metric .vdb guards (README, "--metric-vdb"; canvas/vdb_io.cpp,
# canvas/vdb_metric_field.cpp): how long a large constant-grid file takes to load (the archive is
# read once in a child process, then by rvor), the memory and time of its refusal before any
# value is read (--memory-budget below its recorded voxels), and what random single-bit flips of
# a small metric file do (exit 0: read as data, 1: an error naming the file, anything else: rvor
# died, which the guard is there to prevent). Run from the repository root after a build:
#   bash docs/measurements/vdb_guard.sh [RVOR] [FLIPS]
# RVOR defaults to build/bin/rvor (give an older build to compare), FLIPS to 300.
set -euo pipefail
rvor=${1:-build/bin/rvor}
flips=${2:-300}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
c++ -O1 -std=c++17 docs/measurements/constant_metric_vdb.cpp -o "$work/make" \
  -lopenvdb -ltbb -lImath-3_1
"$work/make" "$work/large.vdb" 300
"$work/make" "$work/small.vdb" 20
echo "large.vdb: $(stat -c %s "$work/large.vdb") bytes, six 300^3 grids"
run() {
  /usr/bin/time -f "%e s, %M KB peak" "$rvor" voronoi --domain box:0.1,0.1,0.1,0.9,0.9,0.9 \
    --resolution 16 --random-seeds 3 --device cpu --out "$work/out" --overwrite "$@" 2>&1 |
    grep -E "building canvas|error|peak" || true
}
echo "== load (fits the default budget)"
run --metric-vdb "$work/large.vdb"
echo "== refused with --memory-budget 100M"
run --metric-vdb "$work/large.vdb" --memory-budget 100M
echo "== $flips random single-bit flips of small.vdb ($(stat -c %s "$work/small.vdb") bytes)"
python3 - "$rvor" "$work" "$flips" <<'PY'
import random, subprocess, sys
rvor, work, flips = sys.argv[1], sys.argv[2], int(sys.argv[3])
random.seed(5)
data = open(f"{work}/small.vdb", "rb").read()
outcomes = {}
for _ in range(flips):
    damaged = bytearray(data)
    damaged[random.randrange(len(data))] ^= 1 << random.randrange(8)
    open(f"{work}/flipped.vdb", "wb").write(damaged)
    run = subprocess.run(["timeout", "60", rvor, "voronoi", "--domain", "box:0.2,0.2,0.2,0.8,0.8,0.8",
                          "--metric-vdb", f"{work}/flipped.vdb", "--resolution", "12",
                          "--random-seeds", "2", "--device", "cpu", "--out", f"{work}/out",
                          "--overwrite"], capture_output=True, text=True)
    died = "died on its voxel data" in run.stderr
    key = {0: "read", 1: "error (reader died, caught)" if died else "error"}.get(run.returncode,
                                                                                 f"rvor died ({run.returncode})")
    outcomes[key] = outcomes.get(key, 0) + 1
for key, count in sorted(outcomes.items()):
    print(f"  {key}: {count}")
PY
