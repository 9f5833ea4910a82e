#!/usr/bin/env bash
# Installs what is missing, builds, and runs the test suite with ctest.
#   scripts/test.sh            default suite (minutes)
#   scripts/test.sh --heavy    also the heavy studies (256^3 convergence, large cases)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
label_filter=(-LE heavy)
for arg in "$@"; do
  case "$arg" in
    --heavy) label_filter=() ;;
    *) echo "scripts/test.sh: unknown option $arg (use --heavy)" >&2; exit 2 ;;
  esac
done
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build_dir="${RVOR_BUILD_DIR:-$root/build}"
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$build_dir/pocl-cache}"
cd "$build_dir"
ctest --output-on-failure --parallel "$(nproc)" "${label_filter[@]}"
