#!/bin/bash
# A sweep of whole runs through the tool (ctest -L heavy, about a minute): every design field with
# both duals on boxes and rectangles at several seed densities, the implicit domains, a non-convex
# mesh domain, a metric given on a Medit mesh (both engines), scaled metrics. Each run must end
# with exit code 0; the failures are listed with their error line.
# It found two bugs on 2026-12-04: the curved dual's nerve not closed under faces (3D
# hyperbolic_shock) and the scheme diverging for a seed on unidimensional_shock's shock line.
# Usage: cli_sweep.sh PATH/TO/rvor
set -u
rvor=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
failures=0
runs=0
# Without an OpenCL device every run takes the CPU reference ("auto" would refuse).
device=auto
"$rvor" devices | grep -q '^opencl:' || device=cpu
engine=$device  # where run() solves

run() {
  runs=$((runs + 1))
  rm -rf "$out/run"
  local message
  if ! message=$(timeout 300 "$rvor" voronoi --device "$engine" "$@" --out "$out/run" \
    --quiet 2>&1); then
    echo "FAILED: rvor voronoi --device $engine $*: $message"
    failures=$((failures + 1))
  fi
}

for rng in 1 2; do
  for metric in swirl starred hyperbolic_shock unidimensional_shock uniform:50.5,49.5,50.5; do
    for seeds in 100 1000; do
      run --domain rect:-1,-1,1,1 --metric "$metric" --resolution 128 --random-seeds "$seeds" \
        --rng-seed "$rng" --dual both --png
    done
  done
  for case in "box:-1,-1,-1,1,1,1 hyperbolic_shock" "box:1,1,1,11,11,11 radial_shock_3d" \
    "box:-1,-1,-1,1,1,1 uniform:20,-12,20,4,3,30" "box:-1,-1,-1,1,1,1 euclidean"; do
    read -r domain metric <<<"$case"
    for seeds in 150 600; do
      run --domain "$domain" --metric "$metric" --resolution 32 --random-seeds "$seeds" \
        --rng-seed "$rng" --dual both
    done
  done
done
for domain in implicit:sphere implicit:torus implicit:ellipsoid; do
  run --domain "$domain" --metric hyperbolic_shock --resolution 48 --random-seeds 400 --dual both
done
run --domain implicit:disk --metric swirl --resolution 160 --random-seeds 300 --dual both --png

# A non-convex mesh domain: three unit cubes in an L.
cat >"$out/l.off" <<'END_OF_MESH'
OFF
16 28 0
2 0 0
2 1 0
2 1 1
2 0 1
1 1 0
1 1 1
1 0 0
1 0 1
0 0 0
0 0 1
0 1 1
0 1 0
1 2 0
1 2 1
0 2 1
0 2 0
3 0 1 2
3 0 2 3
3 4 5 2
3 4 2 1
3 6 0 3
3 6 3 7
3 7 3 2
3 7 2 5
3 6 4 1
3 6 1 0
3 8 9 10
3 8 10 11
3 8 6 7
3 8 7 9
3 9 7 5
3 9 5 10
3 8 11 4
3 8 4 6
3 4 12 13
3 4 13 5
3 11 10 14
3 11 14 15
3 15 14 13
3 15 13 12
3 10 5 13
3 10 13 14
3 11 15 12
3 11 12 4
END_OF_MESH
for metric in hyperbolic_shock uniform:20,-12,20,4,3,30; do
  run --domain "mesh:$out/l.off" --metric "$metric" --resolution 48 --random-seeds 300 --dual both
done

# A metric given at the vertices of a Medit mesh (the cube [0,2]^3 in six tetrahedra), stronger
# along x near x = 1 and along z at the top.
cat >"$out/m.mesh" <<'MESH'
MeshVersionFormatted 2
Dimension 3
Vertices
8
0 0 0 0
2 0 0 0
0 2 0 0
2 2 0 0
0 0 2 0
2 0 2 0
0 2 2 0
2 2 2 0
Tetrahedra
6
1 2 4 8 0
1 2 6 8 0
1 3 4 8 0
1 3 7 8 0
1 5 6 8 0
1 5 7 8 0
End
MESH
cat >"$out/m.sol" <<'SOL'
MeshVersionFormatted 2
Dimension 3
SolAtVertices
8
1 3
21 0 1 0 0 1
1 0 1 0 0 1
21 0 1 0 0 1
1 0 1 0 0 1
21 0 1 0 0 6
1 0 1 0 0 6
21 0 1 0 0 6
1 0 1 0 0 6
End
SOL
for engine in "$device" cpu; do
  run --domain box:0,0,0,2,2,2 --metric-file "$out/m.sol" --metric-mesh "$out/m.mesh" \
    --resolution 32 --random-seeds 200 --dual both
done
engine=$device
for scale in 0.01 100; do
  run --domain box:1,1,1,11,11,11 --metric "radial_shock_3d:scale=$scale" --resolution 40 \
    --random-seeds 200 --dual both
done
echo "cli_sweep.sh: $runs runs, $failures failed"
[ "$failures" -eq 0 ]
