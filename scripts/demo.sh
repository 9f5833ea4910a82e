#!/usr/bin/env bash
# Installs what is missing, builds rvor (Release, into build/), and runs the main job on a built-in
# default: a 3D Riemannian Voronoi diagram of 300 seeds under the hyperbolic_shock metric, on the
# OpenCL engine (PoCL here), with its straight Delaunay dual.
# Extra arguments are passed to `rvor voronoi` (e.g. --device cpu, --resolution 128).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build_dir="${RVOR_BUILD_DIR:-$root/build}"
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$build_dir/pocl-cache}"
out="$root/rvor-out/demo"
"$build_dir/bin/rvor" voronoi \
  --domain box:-1,-1,-1,1,1,1 --metric hyperbolic_shock --resolution 96 \
  --random-seeds 300 --rng-seed 7 --vtu --dual straight --out "$out" --overwrite "$@"
echo
echo "Open $out/canvas.vtu in ParaView (cell data 'label', 'distance'), or $out/voronoi.vdb in any OpenVDB tool."
