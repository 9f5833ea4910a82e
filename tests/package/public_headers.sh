#!/usr/bin/env bash
# Every public header (host/include/rvor) is what a user includes alone: each must compile on its
# own under C++17 with warnings a user's project may treat as errors (sign and width conversions,
# shadowing among them), and none may bring in OpenVDB, CGAL or OpenCL headers, which stay behind
# the library's boundary. Fails naming the header and the first diagnostics.
# Usage: public_headers.sh SOURCE_DIR CXX EIGEN_INCLUDE_DIRS (the last ';'-separated, as CMake lists)
set -euo pipefail
source_dir=$1
cxx=$2
IFS=';' read -r -a eigen_dirs <<<"$3"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

flags=(-std=c++17 -Wall -Wextra -Wpedantic -Werror -Wconversion -Wsign-conversion -Wshadow
       -Wold-style-cast -Wnon-virtual-dtor -fsyntax-only -I"$source_dir/host/include")
for dir in "${eigen_dirs[@]}"; do [[ -n $dir ]] && flags+=(-isystem "$dir"); done

failed=0
for header in "$source_dir"/host/include/rvor/*.h; do
  name=$(basename "$header")
  echo "#include <rvor/$name>" >"$work/$name.cpp"
  if ! "$cxx" "${flags[@]}" -H "$work/$name.cpp" 2>"$work/$name.log"; then
    echo "rvor/$name does not compile on its own:" >&2
    grep -v '^\.' "$work/$name.log" | grep -m 5 'error' >&2 || true
    failed=1
  fi
  # -H lists every header included, one per line, dotted by depth.
  if leaked=$(grep -E '^\.+ .*/(openvdb|CGAL|CL)/' "$work/$name.log"); then
    echo "rvor/$name includes a third-party header the library keeps to itself:" >&2
    echo "$leaked" | head -3 >&2
    failed=1
  fi
done
if ((failed)); then exit 1; fi
echo "public_headers.sh: every public header compiles on its own, strict warnings, no OpenVDB/CGAL/OpenCL"
