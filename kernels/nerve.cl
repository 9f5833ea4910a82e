// Flags the bricks that hold a multi-label grid cell: a cell (the cube, in 2D the square, whose
// corners are voxel centres) based at a voxel of the brick, whose active reached corners carry
// two or more labels. Only their Kuhn simplices witness Delaunay simplices, so the nerve
// extraction on the host (host/src/dual/nerve.cpp) visits only flagged bricks. A cell reaches one
// voxel into the +x/+y/+z neighbouring bricks. Work-item = brick. Build option: -DDIM=2|3;
// state_word.clh and brick_layout.clh are prepended by the host.

#define BLOCK_EDGE (EDGE + 1)
#define BLOCK_EDGE_Z (DIM == 3 ? EDGE + 1 : 1)
#define CORNERS_Z (DIM == 3 ? 2 : 1)

// Label of voxel (a, b, c) of the brick's block, given the ids of the brick and of its +x/+y/+z
// neighbours (neighbours[dx + 2 (dy + 2 dz)], -1 where empty); LABEL_NONE where inactive,
// unreached or outside the canvas.
inline uint block_label(int a, int b, int c, int3 origin, int4 dims, const int* neighbours,
                        __global const ulong* state) {
  const int3 v = origin + (int3)(a, b, c);
  if (v.x >= dims.x || v.y >= dims.y || v.z >= dims.z) return LABEL_NONE;
  const int brick = neighbours[a / EDGE + 2 * (b / EDGE + 2 * (c / EDGE_Z))];
  if (brick < 0) return LABEL_NONE;
  return (uint)(state[(long)brick * BRICK_VOLUME + local_index(v)] & LABEL_NONE);
}

// Whether the corners of the cell based at block voxel (a, b, c) carry two or more labels.
inline bool multi_label_cell(int a, int b, int c, int3 origin, int4 dims, const int* neighbours,
                             __global const ulong* state) {
  uint first = LABEL_NONE;
  for (int dz = 0; dz < CORNERS_Z; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const uint label = block_label(a + dx, b + dy, c + dz, origin, dims, neighbours, state);
        if (label == LABEL_NONE) continue;
        if (first == LABEL_NONE)
          first = label;
        else if (label != first)
          return true;
      }
  return false;
}

__kernel void flag_multi_label_bricks(int brick_count, __global const int4* brick_origins,
                                      __global const int* table, int4 dims, int4 grid,
                                      __global const ulong* state, __global uchar* multi_label) {
  const int brick = get_global_id(0);
  if (brick >= brick_count) return;
  const int3 origin = brick_origins[brick].xyz;
  const int3 base = brick_of_voxel(origin);
  int neighbours[8];
  for (int d = 0; d < 8; ++d)
    neighbours[d] = brick_at(base + (int3)(d & 1, (d >> 1) & 1, d >> 2), grid, table);
  // Most bricks lie inside one Voronoi cell: one pass over the block rules them out.
  uint first = LABEL_NONE;
  bool several = false;
  for (int c = 0; c < BLOCK_EDGE_Z && !several; ++c)
    for (int b = 0; b < BLOCK_EDGE && !several; ++b)
      for (int a = 0; a < BLOCK_EDGE && !several; ++a) {
        const uint label = block_label(a, b, c, origin, dims, neighbours, state);
        if (label == LABEL_NONE) continue;
        if (first == LABEL_NONE) first = label;
        several = label != first;
      }
  bool found = false;
  for (int c = 0; c < EDGE_Z && several && !found; ++c)
    for (int b = 0; b < EDGE && !found; ++b)
      for (int a = 0; a < EDGE && !found; ++a)
        found = multi_label_cell(a, b, c, origin, dims, neighbours, state);
  multi_label[brick] = found ? 1 : 0;
}
