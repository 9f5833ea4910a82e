#!/usr/bin/env bash
# scripts/demo.sh passes its extra arguments to `rvor voronoi`; one that its default job also sets
# replaces the default (rvor refuses an option given twice: "--resolution 128" failed). Runs the
# script in a copy of the tree whose install and build steps do nothing and whose build/bin/rvor
# is RVOR, on the CPU reference at small sizes.
# Usage: demo_arguments.sh SOURCE_DIR RVOR
set -euo pipefail
source_dir=$1
rvor=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/scripts" "$work/build/bin"
cp "$source_dir/scripts/demo.sh" "$work/scripts/"
printf '#!/bin/sh\nexit 0\n' >"$work/scripts/install-deps.sh"
cp "$work/scripts/install-deps.sh" "$work/scripts/build.sh"
chmod +x "$work/scripts/"*.sh
ln -s "$rvor" "$work/build/bin/rvor"
failed=0

# Runs demo.sh with the arguments, then checks `KEY VALUE` pairs of report.json in DIR.
check() {
  local dir=$1 expected=$2
  shift 2
  if ! RVOR_BUILD_DIR="$work/build" "$work/scripts/demo.sh" --quiet "$@" >"$work/log" 2>&1; then
    echo "FAILED: demo.sh $*:" >&2
    cat "$work/log" >&2
    failed=1
    return
  fi
  local report
  report=$(tr -d ' \n' <"$dir/report.json")
  for pair in $expected; do
    grep -qF -- "\"${pair%%=*}\":${pair#*=}" <<<"$report" || {
      echo "FAILED: demo.sh $*: report.json lacks ${pair%%=*} = ${pair#*=}" >&2
      failed=1
    }
  done
}

check "$work/rvor-out/demo" "resolution=24 seeds=300" --resolution 24 --device cpu
printf '0 0 0\n0.5 0.5 0.5\n-0.5 0.2 0.1\n0.3 -0.6 0.4\n0.1 0.1 -0.7\n' >"$work/five.xyz"
check "$work/other" "resolution=20 seeds=5" --device=cpu --out "$work/other" --resolution=20 \
  --seeds "$work/five.xyz" --metric euclidean
grep -qF "Open $work/other/canvas.vtu" "$work/log" || {
  echo "FAILED: demo.sh --out: its last line names another directory:" >&2
  cat "$work/log" >&2
  failed=1
}
[ "$failed" -eq 0 ] && echo "demo_arguments.sh: extra arguments replace the default job's"
exit "$failed"
