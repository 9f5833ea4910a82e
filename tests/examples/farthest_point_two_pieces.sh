#!/usr/bin/env bash
# The library example's farthest-point chain on a domain of two disjoint boxes: the second box is
# as far from the first seed as any voxel can be (no seed reaches it), so the chain must seed it;
# choosing among reached voxels only, it seeded one box and left the other without a label. Fails
# when the example reports voxels reached by no seed, or fails itself.
# Usage: farthest_point_two_pieces.sh FARTHEST_POINT_SEEDS
set -euo pipefail
example=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Two unit cubes, [0,1]^3 and [2,3] x [0,1]^2: vertex x + 2y + 4z of each, two triangles a face.
{
  echo "OFF"
  echo "16 24 0"
  for x0 in 0 2; do
    for z in 0 1; do for y in 0 1; do for x in 0 1; do echo "$((x0 + x)) $y $z"; done; done; done
  done
  for base in 0 8; do
    for face in "0 2 3 1" "4 5 7 6" "0 1 5 4" "2 6 7 3" "0 4 6 2" "1 3 7 5"; do
      read -r a b c d <<<"$face"
      echo "3 $((base + a)) $((base + b)) $((base + c))"
      echo "3 $((base + a)) $((base + c)) $((base + d))"
    done
  done
} >"$work/two_boxes.off"

"$example" euclidean "mesh:$work/two_boxes.off" 48 30 | tee "$work/out.txt"
if grep -q "reached by no seed" "$work/out.txt"; then
  echo "farthest_point_two_pieces.sh: the chain left a piece of the domain without a seed" >&2
  exit 1
fi
