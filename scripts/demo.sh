#!/usr/bin/env bash
# Installs what is missing, builds rvor (Release, into build/), and runs the main job on a built-in
# default: a 3D Riemannian Voronoi diagram of 300 seeds under the hyperbolic_shock metric, on the
# OpenCL engine (PoCL here), with its straight Delaunay dual.
# Extra arguments are passed to `rvor voronoi` (e.g. --device cpu, --resolution 128); one that the
# default job also sets (--resolution, --out, --seeds for --random-seeds, ...) replaces it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build_dir="${RVOR_BUILD_DIR:-$root/build}"
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$build_dir/pocl-cache}"
out="$root/rvor-out/demo"

# Whether the extra arguments give any of the options named (as "--name VALUE" or "--name=VALUE").
extra=("$@")
gives() {
  local arg option
  for arg in "${extra[@]}"; do
    for option in "$@"; do
      [[ $arg == "$option" || $arg == "$option="* ]] && return 0
    done
  done
  return 1
}

# The default job, less each option the extra arguments give: rvor refuses an option given twice,
# so "--resolution 128" after the default's "--resolution 96" failed.
job=()
gives --domain || job+=(--domain "box:-1,-1,-1,1,1,1")
gives --metric --metric-file --metric-mesh --metric-vdb || job+=(--metric hyperbolic_shock)
gives --resolution || job+=(--resolution 96)
gives --random-seeds --seeds || job+=(--random-seeds 300)
gives --rng-seed --seeds || job+=(--rng-seed 7)
gives --vtu || job+=(--vtu)
gives --dual || job+=(--dual straight)
gives --overwrite || job+=(--overwrite)
if gives --out; then
  for ((n = 0; n < ${#extra[@]}; n++)); do
    case ${extra[n]} in
      --out) out=${extra[n + 1]:-} ;;
      --out=*) out=${extra[n]#--out=} ;;
    esac
  done
else
  job+=(--out "$out")
fi
"$build_dir/bin/rvor" voronoi "${job[@]}" "$@"
echo
echo "Open $out/canvas.vtu in ParaView (cell data 'label', 'distance'), or $out/voronoi.vdb in any OpenVDB tool."
