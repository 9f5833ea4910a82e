#!/usr/bin/env bash
# Reproduces the lane counts of docs/scheme.md ("Tried and not kept", sessions 12 and 14): where
# the SIMD lanes' visits and label passes go, how often values change significantly, and how often
# consecutive voxels change stencil shape. Measurement only: it applies lane_counters.patch to a
# clean working tree, builds, runs `rvor bench` once per counted class (the upd/voxel column then
# holds that class per voxel) and reverts the patch.
# Usage: docs/measurements/lane_counters.sh [RESOLUTION [SEEDS [BENCH_OPTION...]]]
#        (defaults 128 and 1000; e.g. `128 1000 --front-step 3` for session 19's counts)
#        docs/measurements/lane_counters.sh --check   (only whether the patch still applies; ctest
#        runs this, so a kernel change that breaks the patch is caught: regenerate the patch then)
set -euo pipefail
cd "$(dirname "$0")/../.."
patch=docs/measurements/lane_counters.patch
if [ "${1:-}" = "--check" ]; then
  if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    echo "lane_counters.sh --check: not a git checkout, skipped"
    exit 77
  fi
  git apply --check "$patch" || {
    echo "lane_counters.sh: $patch no longer applies to kernels/ and host/; apply its hunks by" \
      "hand, check the counts, and regenerate it with git diff -- host kernels" >&2
    exit 1
  }
  echo "lane_counters.sh --check: $patch applies"
  exit 0
fi
resolution=${1:-128}
seeds=${2:-1000}
extra=("${@:3}")  # more rvor bench options, passed to every run
git diff --quiet -- kernels host || { echo "lane_counters.sh: kernels/ or host/ has changes; commit them first" >&2; exit 1; }
git apply "$patch"
trap 'git apply -R "$patch"; scripts/build.sh >/dev/null' EXIT
scripts/build.sh >/dev/null
export POCL_CACHE_DIR=$PWD/build/pocl-cache
classes=("" "lane slots" "running lanes" "open lanes" "evaluations" "vector visits that evaluate"
  "significant changes" "first values" "label switches" "same-label changes"
  "same label, > 1e-1" "same label, 1e-2..1e-1" "same label, 1e-3..1e-2" "same label, 1e-4..1e-3"
  "same label, 1e-5..1e-4" "same label, <= 1e-5" "relaxations changing nothing"
  "label passes" "label passes improving no lane")
for metric in "euclidean --domain box:-1,-1,-1,1,1,1" "radial_shock_3d --domain box:1,1,1,11,11,11"; do
  for n in $(seq 1 18); do
    # shellcheck disable=SC2086  # $metric holds the metric and its --domain option
    value=$(RVOR_LANE_COUNT=$n build/bin/rvor bench --metric $metric --resolution "$resolution" \
      --seeds "$seeds" --no-reference --no-fastsweeping --quiet "${extra[@]}" | sed -n 2p |
      awk '{print $6}')
    unit="per voxel"
    [ "$n" = 16 ] && unit="per brick"  # counted 512 per relaxation
    printf '%-20s %-32s %s %s\n' "${metric%% *}" "${classes[$n]}" "$value" "$unit"
  done
  # shellcheck disable=SC2086
  RVOR_SHAPE_CHANGES=1 build/bin/rvor bench --metric $metric --resolution "$resolution" \
    --seeds "$seeds" --no-reference --no-fastsweeping --quiet "${extra[@]}" 2>&1 >/dev/null |
    sed -n "s/^shape changes/${metric%% *} shape changes/p"
done
