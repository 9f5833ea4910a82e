#!/usr/bin/env bash
# The engine on a GPU machine that cannot build rvor (no Debian packages, no network): the NVIDIA
# machine the project's `device` tool lends to some tasks.
#
#   scripts/device_bench.sh pack           here, after scripts/build.sh: bundles rvor, test_opencl,
#                                          the libraries they load and this machine's C library
#                                          with its loader into build/device-bundle.tar.xz
#   scripts/device_bench.sh run [BUNDLE]   there, from the repository root: unpacks the bundle,
#                                          points the OpenCL ICD loader at NVIDIA's driver, lists
#                                          the devices, runs test_opencl's engine tests on the GPU
#                                          (the GPU's own paths first; not the CPU variants'
#                                          parametrised cases: a work-item per brick crawls there,
#                                          and they took the whole limit on 2026-12-04), then
#                                          `rvor bench` with the variants a GPU runs (euclidean
#                                          once more with --checked-insert) and, while time is
#                                          left, 512^3 cases; logs and JSON are packed after each
#                                          step into $OUT/device-results.tar.gz (the device tool
#                                          brings back at most 8 files), else into ./device-results
#
# With the device tool: run(command="bash scripts/device_bench.sh run",
#                           carry=["build/device-bundle.tar.xz"], timeout_s=580)
# (at most 200 s of tests, 5 bench runs of 55 s and 512^3 runs of 75 s begun before 400 s: under
# 9.5 minutes, inside one call's 10; session 28's first run took 331 s with 4 bench runs; a session
# has 15 minutes of device time in all, starts included: the environment below shortens a run)
# The programs run through the bundled loader, so the other machine's C library does not matter.
set -euo pipefail
cd "$(dirname "$0")/.."

BUNDLE_DEFAULT=build/device-bundle.tar.xz
PROGRAMS=(rvor test_opencl)

pack() {
  local stage
  stage=$(mktemp -d)
  mkdir -p "$stage/bin" "$stage/lib"
  for program in "${PROGRAMS[@]}"; do
    [[ -x build/bin/$program ]] || { echo "build/bin/$program missing: run scripts/build.sh" >&2; exit 1; }
    cp "build/bin/$program" "$stage/bin/"
    strip --strip-unneeded "$stage/bin/$program"
    # Every library the dynamic loader resolves, the C library and the loader itself included.
    ldd "build/bin/$program" | awk '/=> \//{print $3} /^\t\/lib/{print $1}' | while read -r lib; do
      cp -Ln "$lib" "$stage/lib/" 2>/dev/null || true
    done
  done
  # The driver's OpenCL library links these; they must come from the bundled C library too.
  for compat in libdl.so.2 libpthread.so.0 librt.so.1; do
    cp -Ln "/lib/x86_64-linux-gnu/$compat" "$stage/lib/" 2>/dev/null || true
  done
  tar -C "$stage" -cJf "$BUNDLE_DEFAULT" bin lib
  rm -rf "$stage"
  echo "$BUNDLE_DEFAULT: $(du -h "$BUNDLE_DEFAULT" | cut -f1) ($(git rev-parse --short HEAD))"
}

# NVIDIA's OpenCL library (an ICD, as /etc/OpenCL/vendors/nvidia.icd names it), or nothing.
nvidia_opencl_library() {
  find /usr/local/nvidia /usr/lib /usr/lib64 /lib -name 'libnvidia-opencl.so.1' 2>/dev/null | head -1
}

# Environment, for a dry run elsewhere: ICD_LIBRARY (default NVIDIA's), BENCH_DEVICE (default the
# first GPU `rvor devices` lists), RESOLUTION (default 256, the standard cases'); to fit a shorter
# call: TEST_SECONDS (default 200), TEST_FILTER (test_opencl's --gtest_filter), VARIANTS (default
# "voxel_phases brick_sweep"), INSERTIONS (default 3), EXTRA_UNTIL (default 400: no 512^3 case
# begins later; 0: none).
run() {
  local bundle=${1:-$BUNDLE_DEFAULT} archive_dir=${OUT:-$PWD/device-results} root=/tmp/rvor-device
  local out=$root/results
  [[ -f $bundle ]] || { echo "no bundle at $bundle: run 'scripts/device_bench.sh pack' first" >&2; exit 1; }
  rm -rf "$root" && mkdir -p "$out" "$archive_dir" "$root/vendors"
  save_results() { tar -C "$out" -czf "$archive_dir/device-results.tar.gz" .; }
  if command -v xz >/dev/null; then
    tar -C "$root" -xJf "$bundle"
  else
    python3 -c "import sys, tarfile; tarfile.open(sys.argv[1]).extractall(sys.argv[2])" "$bundle" "$root"
  fi
  local icd=${ICD_LIBRARY:-$(nvidia_opencl_library)}
  [[ -n $icd ]] || { echo "libnvidia-opencl.so.1 not found" >&2; exit 1; }
  echo "$icd" >"$root/vendors/device.icd"
  export OCL_ICD_VENDORS=$root/vendors
  local libraries
  libraries="$root/lib:$(dirname "$icd")"
  launch_for() {  # SECONDS PROGRAM ARGS...: through the bundled loader, at most SECONDS
    local seconds=$1 program=$2
    shift 2
    timeout "$seconds" "$root/lib/ld-linux-x86-64.so.2" --library-path "$libraries" \
      "$root/bin/$program" "$@"
  }

  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>&1 | tee "$out/gpu.txt" || true
  launch_for 60 rvor devices | tee "$out/devices.txt"
  local device=${BENCH_DEVICE:-$(awk '/\[GPU/{print $1; exit}' "$out/devices.txt")}
  [[ -n $device ]] || { echo "no OpenCL GPU in 'rvor devices'" >&2; exit 1; }

  # The tests of what a GPU runs first (the session, insertions, voxel phases' cases), then the
  # rest while TEST_SECONDS last (not the CPU variants' parametrised cases: a work-item per brick
  # crawls on a GPU). TEST_FILTER replaces both with one filter.
  local first_tests='VoronoiSession.*:OpenCLInsertion.*:InsertionExactStart.*:Variants/*VoxelPhases*:OpenCLExactStart.*'
  local cpu_variants='Variants/*BrickLanes*:Variants/*BrickSweep*'
  local -a passes=("$first_tests" "-$first_tests:$cpu_variants")
  [[ -n ${TEST_FILTER:-} ]] && passes=("$TEST_FILTER")
  local pass=0 budget=${TEST_SECONDS:-200} started=$SECONDS
  for filter in "${passes[@]}"; do
    local left=$((budget - (SECONDS - started)))
    ((left > 5)) || break
    pass=$((pass + 1))
    echo "== test_opencl on $device, pass $pass ($left s): $filter"
    if RVOR_TEST_DEVICE=$device launch_for "$left" test_opencl --gtest_filter="$filter" \
      >"$out/test_opencl_$pass.log" 2>&1; then
      echo passed
    else
      echo "FAILED or timed out (rc $?)"
    fi
    grep -E '^\[ +FAILED ' "$out/test_opencl_$pass.log" | head -20 || true
    echo "$(grep -c '^\[       OK \]' "$out/test_opencl_$pass.log") tests passed, last: $(grep '^\[ RUN' "$out/test_opencl_$pass.log" | tail -1)"
  done
  save_results

  local -A domains=([euclidean]="box:-1,-1,-1,1,1,1" [radial_shock_3d]="box:1,1,1,11,11,11")
  bench_case() {  # SECONDS VARIANT METRIC RESOLUTION [FLAG]
    local seconds=$1 variant=$2 metric=$3 resolution=$4 flag=${5:-}
    local name="bench_${variant}_${metric}_$resolution${flag//-/_}"
    echo "== rvor bench --device $device --variant $variant --metric $metric --resolution $resolution $flag"
    launch_for "$seconds" rvor bench --device "$device" --variant "$variant" --metric "$metric" \
      --domain "${domains[$metric]}" \
      --resolution "$resolution" --no-reference --insert "${INSERTIONS:-3}" --repeat 2 --json \
      ${flag:+"$flag"} >"$out/$name.json" 2>"$out/$name.log" ||
      echo "rc $?: $(tail -1 "$out/$name.log")"
    grep -E '"(seconds|voxels_per_second|updates_per_voxel|bytes_per_voxel|fastsweeping_ratio|insert_fraction|insert_mean_seconds|insert_mean_round_seconds|insert_mean_rounds)"' \
      "$out/$name.json" | tr -d ' \n' || true
    echo
    save_results
  }
  for variant in ${VARIANTS:-voxel_phases brick_sweep}; do
    for metric in euclidean radial_shock_3d; do
      bench_case 55 "$variant" "$metric" "${RESOLUTION:-256}"
    done
  done
  # Insertions with a caller's field, checked every call (Propagator::insert), for comparison.
  bench_case 55 voxel_phases euclidean "${RESOLUTION:-256}" --checked-insert
  # Larger canvases while the call's time lasts (SECONDS counts from the script's start).
  for metric in euclidean radial_shock_3d; do
    if ((SECONDS < ${EXTRA_UNTIL:-400})); then
      bench_case 75 voxel_phases "$metric" "${EXTRA_RESOLUTION:-512}"
    fi
  done
}

case ${1:-} in
  pack) pack ;;
  run) shift; run "$@" ;;
  *) sed -n 2,18p "$0" >&2; exit 2 ;;
esac
