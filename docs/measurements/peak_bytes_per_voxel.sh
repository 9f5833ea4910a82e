#!/usr/bin/env bash
# Reproduces the per-voxel peak memory of `rvor voronoi` that the memory estimates rest on
# (canvas/memory_budget.cpp, README "Using the library"): the peak resident memory at 160^3 less
# that at 96^3, over the voxels added, so that what does not grow with the canvas cancels.
# Usage: docs/measurements/peak_bytes_per_voxel.sh METRIC DOMAIN [VORONOI_OPTION...]
#   e.g. euclidean box:-1,-1,-1,1,1,1
#        radial_shock_3d box:1,1,1,11,11,11 --device cpu
#        euclidean box:-1,-1,-1,1,1,1 --vtu
set -euo pipefail
cd "$(dirname "$0")/../.."
metric=$1 domain=$2
shift 2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The peak in kB of a run at resolution $1 with the options after it.
peak_kilobytes() {
  local resolution=$1
  shift
  /usr/bin/time -f %M build/bin/rvor voronoi --domain "$domain" --metric "$metric" \
    --resolution "$resolution" --random-seeds 100 --quiet --overwrite --out "$out/run" "$@" \
    2>&1 >/dev/null | tail -n 1
}
small=$(peak_kilobytes 96 "$@")
large=$(peak_kilobytes 160 "$@")
awk -v small="$small" -v large="$large" -v what="$metric on $domain $*" 'BEGIN {
  printf "%s: %.1f B per voxel (peaks %d kB at 96^3, %d kB at 160^3)\n", what,
    (large - small) * 1024 / (160 ^ 3 - 96 ^ 3), small, large }'
