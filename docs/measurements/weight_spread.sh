#!/usr/bin/env bash
# Reproduces docs/scheme.md's counts of stencil weight spread ("Convergence", the change
# tolerance): builds weight_spread.cpp against the project's libraries in build/ and runs it.
# Usage: docs/measurements/weight_spread.sh   (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
c++ -std=c++17 -O2 -Ihost/include -isystem /usr/include/eigen3 docs/measurements/weight_spread.cpp \
  build/canvas/librvor_fields.a build/host/librvor_solver.a build/canvas/librvor_core.a \
  -o "$out/weight_spread"
"$out/weight_spread"
