#!/bin/bash
# A sweep of whole runs through the tool (ctest -L heavy, a few minutes): every design field with
# both duals on boxes and rectangles at several seed densities, the implicit domains, scaled
# metrics. Each run must end with exit code 0; the failures are listed with their error line.
# It found two bugs on 2026-12-04: the curved dual's nerve not closed under faces (3D
# hyperbolic_shock) and the scheme diverging for a seed on unidimensional_shock's shock line.
# Usage: cli_sweep.sh PATH/TO/rvor
set -u
rvor=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
failures=0
runs=0

run() {
  runs=$((runs + 1))
  rm -rf "$out/run"
  local message
  if ! message=$(timeout 300 "$rvor" voronoi "$@" --out "$out/run" --quiet 2>&1); then
    echo "FAILED: rvor voronoi $*: $message"
    failures=$((failures + 1))
  fi
}

for rng in 1 2; do
  for metric in swirl starred hyperbolic_shock unidimensional_shock uniform:50.5,49.5,50.5; do
    for seeds in 100 1000; do
      run --domain rect:-1,-1,1,1 --metric "$metric" --resolution 128 --random-seeds "$seeds" \
        --rng-seed "$rng" --dual both --png
    done
  done
  for case in "box:-1,-1,-1,1,1,1 hyperbolic_shock" "box:1,1,1,11,11,11 radial_shock_3d" \
    "box:-1,-1,-1,1,1,1 uniform:20,-12,20,4,3,30" "box:-1,-1,-1,1,1,1 euclidean"; do
    read -r domain metric <<<"$case"
    for seeds in 150 600; do
      run --domain "$domain" --metric "$metric" --resolution 32 --random-seeds "$seeds" \
        --rng-seed "$rng" --dual both
    done
  done
done
for domain in implicit:sphere implicit:torus implicit:ellipsoid; do
  run --domain "$domain" --metric hyperbolic_shock --resolution 48 --random-seeds 400 --dual both
done
run --domain implicit:disk --metric swirl --resolution 160 --random-seeds 300 --dual both --png
for scale in 0.01 100; do
  run --domain box:1,1,1,11,11,11 --metric "radial_shock_3d:scale=$scale" --resolution 40 \
    --random-seeds 200 --dual both
done
echo "cli_sweep.sh: $runs runs, $failures failed"
[ "$failures" -eq 0 ]
