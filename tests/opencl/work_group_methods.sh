#!/usr/bin/env bash
# The engine under one of PoCL's work-group methods (how PoCL turns a work-group into loops):
# it must run to completion and give the default method's results. ctest runs one test per method.
#
# Debian 12's PoCL 3.1 has no `cbs` method: it prints "Unknown work group generation method" and
# uses its default, so a test that only sets POCL_WORK_GROUP_METHOD=cbs tests the default twice.
# Here a method PoCL does not know is caught (cbs is then skipped, exit 77; any other method
# fails), and each method compiles into its own kernel cache, so that its tests never run on
# work-groups another method compiled, whatever PoCL's cache keys hold (3.1's hold the method).
#
# Usage: work_group_methods.sh BIN_DIR METHOD   (BIN_DIR holds rvor and test_opencl)
set -euo pipefail
bin=$1
method=$2
build_dir=$(cd "$bin/.." && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
default_cache=${POCL_CACHE_DIR:-$build_dir/pocl-cache}
method_cache=$build_dir/pocl-cache-method-$method

devices=$("$bin/rvor" devices)  # a failing `rvor devices` fails the test, not skips it
if ! grep -q 'Portable Computing Language' <<<"$devices"; then
  echo "work_group_methods.sh: no PoCL device, skipped"
  exit 77
fi

# Whether PoCL knows the method: its warning appears only while compiling, so into a fresh cache.
POCL_WORK_GROUP_METHOD=$method POCL_CACHE_DIR=$scratch/probe-cache "$bin/rvor" voronoi \
  --device pocl --domain rect:0,0,1,1 --resolution 16 --random-seeds 3 --out "$scratch/probe" \
  --quiet 2>"$scratch/probe.err" || { cat "$scratch/probe.err" >&2; exit 1; }
if grep -q 'Unknown work group generation method' "$scratch/probe.err"; then
  if [ "$method" = cbs ]; then
    echo "work_group_methods.sh: this PoCL has no cbs work-group method, skipped"
    exit 77
  fi
  echo "work_group_methods.sh: PoCL does not know the work-group method '$method'" >&2
  exit 1
fi

# Under the method: the engine tests against the CPU reference, every variant.
POCL_WORK_GROUP_METHOD=$method POCL_CACHE_DIR=$method_cache "$bin/test_opencl" \
  --gtest_filter='Variants/*:OpenCLInsertion.*:Fields/*:Domains/*' --gtest_brief=1

# The same results as the default method: the brick-lanes field bit for bit (canvas.vtu), and the
# voxel-phases variant (whose work-groups have barriers) with the same updates and relaxations.
run_cases() {  # run_cases NAME [environment...]
  local name=$1
  shift
  env "$@" "$bin/rvor" voronoi --device pocl --domain rect:-1,-1,1,1 --metric swirl \
    --resolution 64 --random-seeds 40 --vtu --out "$scratch/$name-2d" --quiet
  env "$@" "$bin/rvor" voronoi --device pocl --domain box:-1,-1,-1,1,1,1 \
    --metric hyperbolic_shock --resolution 24 --random-seeds 30 --vtu --out "$scratch/$name-3d" \
    --quiet
  env "$@" "$bin/rvor" bench --device pocl --variant voxel_phases --metric hyperbolic_shock \
    --domain box:-1,-1,-1,1,1,1 --resolution 24 --seeds 30 --no-reference --no-fastsweeping \
    --json --quiet | /usr/bin/python3 -c 'import json, sys
case = json.load(sys.stdin)["cases"][0]
print(case["updates_per_voxel"], case["relaxations_per_brick"])' >"$scratch/$name-phases.txt"
}
run_cases default -u POCL_WORK_GROUP_METHOD POCL_CACHE_DIR="$default_cache"
run_cases method POCL_WORK_GROUP_METHOD="$method" POCL_CACHE_DIR="$method_cache"
for output in 2d/canvas.vtu 3d/canvas.vtu phases.txt; do
  if ! cmp -s "$scratch/default-$output" "$scratch/method-$output"; then
    echo "work_group_methods.sh: $output differs between the default work-group method and" \
      "'$method'" >&2
    exit 1
  fi
done
echo "work_group_methods.sh: '$method' passes the engine tests and gives the default's results"
