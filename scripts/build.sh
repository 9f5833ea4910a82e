#!/usr/bin/env bash
# Configures and builds rvor (Release) into build/ (or $RVOR_BUILD_DIR). Extra args go to cmake.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${RVOR_BUILD_DIR:-$root/build}"
jobs="${RVOR_JOBS:-$(nproc)}"
export CCACHE_BASEDIR="$root"
cmake -S "$root" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build_dir" --parallel "$jobs"
