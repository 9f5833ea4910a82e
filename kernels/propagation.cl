// Block Fast Iterative Method on packed 8^3 bricks (8x8x1 in 2D) for the scheme of
// docs/scheme.md. One round: list the pending bricks of the round's colour, relax each into
// `scratch` (its change stamps into `scratch_stamps`) reading other bricks from the `state` and
// `changed` snapshots (so results do not depend on scheduling), commit, and mark the bricks within
// stencil reach of a changed brick pending.
// The host loops while any brick is pending. Build options: -DDIM=2|3; eikonal_scheme.clh and
// brick_layout.clh are prepended by the host.

#define FLAG_CHANGED 1u     /* a value changed: bricks within reach must be relaxed */
#define FLAG_UNCONVERGED 2u /* the brick itself is not locally converged yet */

// ---------------------------------------------------------------------------------------------
// Seed initialisation: work-item = (seed, voxel of the (2r+1)^d block around the seed's voxel).
// r = INIT_RADIUS, a build option: kSeedBlockRadius (rvor/seed_blocks.h), which the host's claims
// and the reference use too.

#define INIT_SIDE (2 * INIT_RADIUS + 1)
#if DIM == 3
#define INIT_BLOCK (INIT_SIDE * INIT_SIDE * INIT_SIDE)
#else
#define INIT_BLOCK (INIT_SIDE * INIT_SIDE)
#endif

// Slot of the block voxel `item` of seed first_seed + item / INIT_BLOCK, or -1 (inactive, outside).
inline long seed_block_slot(int item, int first_seed, __global const float* seeds,
                            __global const uint* activity, __global const int* table, int4 dims,
                            int4 grid, int3* voxel) {
  const int label = first_seed + item / INIT_BLOCK;
  const int cell = item % INIT_BLOCK;
  __global const float* seed = seeds + (size_t)label * SEED_RECORD;
  const int3 centre = convert_int3((float3)(seed[4], seed[5], seed[6]));
  const int3 d =
      (int3)(cell % INIT_SIDE, (cell / INIT_SIDE) % INIT_SIDE, cell / (INIT_SIDE * INIT_SIDE)) -
      (int3)(INIT_RADIUS, INIT_RADIUS, DIM == 3 ? INIT_RADIUS : 0);
  *voxel = centre + d;
  const long slot = slot_at(*voxel, dims, grid, table);
  return slot < 0 || !slot_active(activity, slot) ? -1 : slot;
}

// Marks the blocks of seeds [first_seed, first_seed + seed_count) frozen before their values are
// assigned: `existing` seeds (insertion) keep their values; new seeds' block voxels that were not
// boundary data are reset to +inf, so they take the exact value even if larger (docs/scheme.md).
// A value written here is stamped `stamp` in `changed`, so that the sweep's work avoidance sees it.
__kernel void freeze_seed_blocks(int first_seed, int seed_count, int existing,
                                 __global const float* seeds, __global ulong* state,
                                 __global const uint* activity, __global const int* table,
                                 int4 dims, int4 grid, __global uint* changed, uint stamp,
                                 __global uchar* touched) {
  const int item = get_global_id(0);
  if (item >= seed_count * INIT_BLOCK) return;
  int3 v;
  const long slot = seed_block_slot(item, first_seed, seeds, activity, table, dims, grid, &v);
  if (slot < 0) return;
  const ulong s = state[slot];
  if (existing) {
    state[slot] = s | FROZEN_BIT;
  } else if (!state_frozen(s)) {
    state[slot] = INF_STATE | FROZEN_BIT;
    changed[slot] = stamp;
    touched[slot / BRICK_VOLUME] = 1;
  }
}

// The frozen state of voxel v (slot) at the exact value u0_s(x) = |F_s (x - s)| of seed `label`.
inline ulong exact_seed_state(int3 v, int label, __global const float* seeds) {
  __global const float* seed = seeds + (size_t)label * SEED_RECORD;
  const float3 q = convert_float3(v) - (float3)(seed[0], seed[1], seed[2]);
  return make_state(seed_distance(seed, q), label) | FROZEN_BIT;
}

inline void mark_seed_change(long slot, __global uchar* flags, __global uint* changed, uint stamp,
                             __global uchar* touched) {
  flags[slot / BRICK_VOLUME] = FLAG_CHANGED | FLAG_UNCONVERGED;
  changed[slot] = stamp;
  touched[slot / BRICK_VOLUME] = 1;
}

// Exact values on the new seeds' blocks.
__kernel void initialise_seeds(int first_seed, int seed_count, __global const float* seeds,
                               __global ulong* state, __global const uint* activity,
                               __global const int* table, int4 dims, int4 grid,
                               __global uchar* flags, __global uint* changed, uint stamp,
                               __global uchar* touched) {
  const int item = get_global_id(0);
  if (item >= seed_count * INIT_BLOCK) return;
  int3 v;
  const long slot = seed_block_slot(item, first_seed, seeds, activity, table, dims, grid, &v);
  if (slot < 0) return;
  const ulong candidate = exact_seed_state(v, first_seed + item / INIT_BLOCK, seeds);
  if (candidate < atom_min(&state[slot], candidate))  // the smallest (value, label) stays
    mark_seed_change(slot, flags, changed, stamp, touched);
}

// Block voxels nearer to a seed whose block does not contain them (rvor/seed_blocks.h): claim
// (i, j, k, label), after initialise_seeds, one per voxel. The host chose the seed in double
// precision, so that every engine labels a near-tie alike: the claim replaces the state.
__kernel void claim_seed_voxels(int claim_count, __global const int4* claims,
                                __global const float* seeds, __global ulong* state,
                                __global const uint* activity, __global const int* table, int4 dims,
                                int4 grid, __global uchar* flags, __global uint* changed,
                                uint stamp, __global uchar* touched) {
  const int item = get_global_id(0);
  if (item >= claim_count) return;
  const int4 claim = claims[item];
  const long slot = slot_at(claim.xyz, dims, grid, table);
  if (slot < 0 || !slot_active(activity, slot)) return;
  const ulong claimed = exact_seed_state(claim.xyz, claim.w, seeds);
  if (state[slot] == claimed) return;
  state[slot] = claimed;
  mark_seed_change(slot, flags, changed, stamp, touched);
}

// The least u0 over a brick's listed seeds, candidates[begin, end) (rvor/nearest_seeds.h; ties:
// the smaller label), at the EDGE slots of the brick row from `first` (local index), and the list
// entry of that seed (-1: none, or its quarter does not see it: the bit per quarter of
// `candidate_seen`).
inline void nearest_listed_seeds(int brick, int first, uint begin, uint end,
                                 __global const int* candidates,
                                 __global const uchar* candidate_seen, __global const float* seeds,
                                 __global const int4* brick_origins, float* distance, int* entry) {
  const int3 in_brick = local_coordinates(first);
  const int3 v = brick_origins[brick].xyz + in_brick;
  const float8 x = (float8)(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f) + (float)v.x;
  float8 least = (float8)(INFINITY);
  int8 nearest = (int8)(-1);
  // Candidates come in ascending labels, so on a tie the first, smaller label stays.
  for (uint c = begin; c < end; ++c) {
    __global const float* seed = seeds + (size_t)candidates[c] * SEED_RECORD;
    const float8 qx = x - seed[0];
    const float qy = (float)v.y - seed[1], qz = (float)v.z - seed[2];
    // A diagonal metric (the host checks): u0^2 = g11 qx^2 + g22 qy^2 + g33 qz^2.
    const float8 u0 = sqrt(seed[8] * qx * qx + (seed[10] * qy * qy + seed[13] * qz * qz));
    const int8 nearer = u0 < least;
    least = select(least, u0, nearer);
    nearest = select(nearest, (int8)((int)c), nearer);
  }
  vstore8(least, 0, distance);
  vstore8(nearest, 0, entry);
  // The row's quarters (bit q = (x >= 4) + 2 (y >= 4) + 4 (z >= 4), rvor/nearest_seeds.h).
  const int row_quarter = (in_brick.y >= EDGE / 2 ? 2 : 0) + (in_brick.z >= EDGE / 2 ? 4 : 0);
  for (int i = 0; i < EDGE; ++i) {
    const int quarter = row_quarter + (i >= EDGE / 2 ? 1 : 0);
    if (entry[i] >= 0 && !((candidate_seen[entry[i]] >> quarter) & 1)) entry[i] = -1;
  }
}

// The exact start (docs/scheme.md, "Initialisation"), for a uniform diagonal metric, before the
// seed blocks: a work-item per brick row (EDGE slots along x, as vectors). An active slot starts at
// the least u0 over its brick's candidate seeds where its quarter brick sees that seed
// (nearest_listed_seeds); elsewhere, and where inactive, at INF_STATE. Not frozen, stamped as
// changed so that its first visit evaluates it.
// Every brick is pending: it verifies its values and repairs the voxels next to bisectors. (A
// work-item per slot, its seed loads and arithmetic scalar, took 0.33 s of a 1.9 s euclidean solve
// at 256^3 with 1000 seeds: a temporary timer, not kept.)
__kernel void start_at_nearest_seeds(int brick_count, __global const uint* candidate_begin,
                                     __global const int* candidates,
                                     __global const uchar* candidate_seen,
                                     __global const float* seeds,
                                     __global const int4* brick_origins,
                                     __global const uint* activity, __global ulong* state,
                                     __global uchar* flags, __global uint* changed, uint stamp) {
  const int rows = EDGE * EDGE_Z;
  const int brick = (int)(get_global_id(0) / rows);
  if (brick >= brick_count) return;
  const int row = (int)(get_global_id(0) % rows);
  if (row == 0) flags[brick] = FLAG_UNCONVERGED;
  const int first = row * EDGE;  // local index of the row's first slot
  float d[EDGE];
  int e[EDGE];
  nearest_listed_seeds(brick, first, candidate_begin[brick], candidate_begin[brick + 1], candidates,
                       candidate_seen, seeds, brick_origins, d, e);
  const size_t slot = (size_t)brick * BRICK_VOLUME + first;
  for (int i = 0; i < EDGE; ++i) {
    const bool active = slot_active(activity, slot + i);
    state[slot + i] = active && e[i] >= 0 ? make_state(d[i], candidates[e[i]]) : INF_STATE;
    if (active) changed[slot + i] = stamp;
  }
}

// The exact start of an insertion's new seeds (docs/scheme.md, "Insertion on the device"), before
// their blocks, a work-item per row of the listed bricks (those a new seed may lower; the lists of
// listed_bricks[n] are candidates[candidate_begin[n], candidate_begin[n + 1]), with the new seeds'
// labels): where a new seed's u0 lies below a voxel's value (not frozen: the claims decide the seed
// blocks, in double precision), the voxel takes it, as the solve's exact start would, stamped as
// changed and as never evaluated, so that it and its neighbours are evaluated (a voxel with no
// lowered neighbour would otherwise keep it); its brick becomes pending and spreads news. Values
// only decrease, so a voxel no new seed is nearer to keeps its state.
__kernel void lower_to_nearest_seeds(
    int listed_count, __global const int* listed_bricks, __global const uint* candidate_begin,
    __global const int* candidates, __global const uchar* candidate_seen,
    __global const float* seeds, __global const int4* brick_origins, __global const uint* activity,
    __global ulong* state, __global uchar* flags, __global uint* changed, __global uint* evaluated,
    uint stamp, __global uchar* touched) {
  const int rows = EDGE * EDGE_Z;
  const int listed = (int)(get_global_id(0) / rows);
  if (listed >= listed_count) return;
  const int brick = listed_bricks[listed];
  const int first = (int)(get_global_id(0) % rows) * EDGE;
  float d[EDGE];
  int e[EDGE];
  nearest_listed_seeds(brick, first, candidate_begin[listed], candidate_begin[listed + 1],
                       candidates, candidate_seen, seeds, brick_origins, d, e);
  const size_t slot = (size_t)brick * BRICK_VOLUME + first;
  bool lowered = false;
  for (int i = 0; i < EDGE; ++i) {
    if (e[i] < 0 || !slot_active(activity, slot + i)) continue;
    const ulong s = state[slot + i];
    if (state_frozen(s) || !(d[i] < state_distance(s))) continue;
    state[slot + i] = make_state(d[i], candidates[e[i]]);
    changed[slot + i] = stamp;
    evaluated[slot + i] = 0u;
    lowered = true;
  }
  if (lowered) {  // every row writes the same bytes
    flags[brick] = FLAG_CHANGED | FLAG_UNCONVERGED;
    touched[brick] = 1;
  }
}

// ---------------------------------------------------------------------------------------------
// CPU-friendly variant: one work-item sweeps its brick Gauss-Seidel, starting from its upwind
// corner, until a sweep changes nothing significant (or max_sweeps; later sweeps flip direction).
//
// Work avoidance: T(x) depends only on the states of x's stencil neighbours, so a voxel none of
// whose neighbours changed significantly (docs/scheme.md, "Convergence") since its last evaluation
// is skipped, just as a brick is not re-activated by insignificant changes. Per slot, `evaluated`
// holds the stamp of the last evaluation and `changed` the stamp of the last significant change
// (0: never / unknown, so the host fills both with 0 before a solve), as 32-bit numbers that grow
// over a solve and the insertions that follow it (seed initialisation stamps what it writes). A
// stamp is round_base + tick, tick in [1, stride) counting evaluations of this brick within the
// round (stride: a power of two). A neighbour inside the brick was seen iff it changed before x's
// evaluation; one outside was read from the round's snapshot, so x saw it iff it changed in an
// earlier round than x's last evaluation. Any bit change is committed (FLAG_WRITTEN), so stamps
// always describe `state`.
//
// The brick is relaxed in a tile (brick_layout.clh) holding its states and, around it, the
// snapshot's: neighbours one voxel away (every neighbour for Euclidean-like stencils) are read at
// flat offsets without tests. The tile's change stamps are comparable with `>` for both kinds of
// neighbour: inside, the stamps; outside, the round base after the change's round (0 for never):
// it exceeds x's last evaluation exactly when the change's round is not earlier than that one.

#define FLAG_WRITTEN 4u /* the brick's working copy differs from the state: commit it */

// The axes a relaxation's sweep reverses against its first (bit a: axis a): first the upwind
// corner, then each axis reversed on its own, then the pairs and all three. A front that meets
// the brick from another side along one axis (a bisector, the plane of a seed) is carried by the
// sweep that reverses that axis alone (docs/scheme.md, "Sweeps per relaxation").
inline int sweep_reversal(int sweep) {
  const int order[8] = {0, 1, 2, 4, 3, 5, 6, 7};
  return DIM == 3 ? order[sweep % 8] : sweep % 4;
}

// Most stencil neighbours lie in the 3^DIM bricks around the brick being relaxed: their indices
// are looked up once per brick; a longer offset (strong anisotropy) goes through the table.
#define NEAR_BRICKS 27
inline void load_near_bricks(int3 origin, int4 grid, __global const int* table, int* near) {
  const int3 b = brick_of_voxel(origin);
  for (int n = 0; n < NEAR_BRICKS; ++n) {
    const int3 d = (int3)(n % 3, (n / 3) % 3, n / 9) - (int3)(1, 1, 1);
    near[n] = DIM == 2 && d.z != 0 ? -1 : brick_at(b + d, grid, table);
  }
}

inline long neighbour_slot(int3 y, int3 origin, int4 dims, int4 grid, __global const int* table,
                           const int* near) {
  const int3 edge = (int3)(EDGE, EDGE, EDGE_Z);
  const int3 d = y - origin + edge;  // in [0, 3 edge) inside the bricks around
  if (d.x < 0 || d.y < 0 || d.z < 0 || d.x >= 3 * EDGE || d.y >= 3 * EDGE || d.z >= 3 * EDGE_Z)
    return slot_at(y, dims, grid, table);
  const int3 b = d / edge;
  const int brick = near[b.x + 3 * (b.y + 3 * b.z)];
  return brick < 0 ? -1 : (long)brick * BRICK_VOLUME + local_index(y);
}

// A change stamp of another brick as the tile holds it (see above): 0 stays 0, any other moves to
// the start of the next round. A macro so that uint and uint8 (brick_lanes.cl) share the rule.
#define OUTSIDE_STAMP(stamp, stride) \
  select(((stamp) & ~((stride)-1u)) + (stride), (stamp)&0u, (stamp) == 0u)
inline uint outside_stamp(uint stamp, uint stride) {
  return OUTSIDE_STAMP(stamp, stride);
}

// Copies `length` consecutive slots from `slot` (-1: an absent brick) to the tile at q.
inline void load_tile_run(ulong* tile, uint* tile_stamp, int q, __global const ulong* state,
                          __global const uint* changed, long slot, int length, bool inside,
                          uint stride) {
  if (slot < 0) {
    for (int i = 0; i < length; ++i) {
      tile[q + i] = INF_STATE;
      tile_stamp[q + i] = 0;
    }
  } else if (inside) {
    for (int i = 0; i < length; ++i) {
      tile[q + i] = state[slot + i];
      tile_stamp[q + i] = changed[slot + i];
    }
  } else {
    for (int i = 0; i < length; ++i) {
      tile[q + i] = state[slot + i];
      tile_stamp[q + i] = outside_stamp(changed[slot + i], stride);
    }
  }
}

// Fills the tile row by row: a row is the last voxel of the brick before, a row of this brick's
// (or its neighbour's across y or z) and the first voxel of the brick after.
inline void load_tile(ulong* tile, uint* tile_stamp, __global const ulong* state,
                      __global const uint* changed, const int* near, uint stride) {
  int p = 0;
  for (int z = -TILE_PAD_Z; z < EDGE_Z + TILE_PAD_Z; ++z) {
    const int bz = DIM == 3 ? (z < 0 ? 0 : z < EDGE_Z ? 1 : 2) : 1;
    for (int y = -1; y <= EDGE; ++y, p += TILE_EDGE) {
      const int by = y < 0 ? 0 : y < EDGE ? 1 : 2;
      const int row = EDGE * ((y & (EDGE - 1)) + EDGE * (DIM == 3 ? z & (EDGE - 1) : 0));
      const int* bricks = near + 3 * (by + 3 * bz);  // the bricks at x - 1, x, x + 1
      const long before = bricks[0] < 0 ? -1 : (long)bricks[0] * BRICK_VOLUME + row + EDGE - 1;
      const long own = bricks[1] < 0 ? -1 : (long)bricks[1] * BRICK_VOLUME + row;
      const long after = bricks[2] < 0 ? -1 : (long)bricks[2] * BRICK_VOLUME + row;
      load_tile_run(tile, tile_stamp, p, state, changed, before, 1, false, stride);
      load_tile_run(tile, tile_stamp, p + 1, state, changed, own, EDGE, brick_row(by, bz), stride);
      load_tile_run(tile, tile_stamp, p + EDGE + 1, state, changed, after, 1, false, stride);
    }
  }
}

// The corner a sweep starts from, as the direction bits of the sweep (bit a: axis a descending).
// Information flows from small values to large ones, so starting there lets one sweep carry an
// incoming front through the whole brick. A brick whose corner voxels all hold a value (reached,
// or started at the nearest seeds' distances) takes, per axis, the side whose four corners hold
// the smaller value (u: corner c = (c & 1, c & 2, c & 4), each bit its high end): 8 reads.
// Otherwise, where a front may be coming in, upwind_corner_of_layers looks at the faces.
// docs/scheme.md "Upwind corner" has the measurements.
inline bool corners_reached(const float* u) {
  bool reached = true;
  for (int c = 0; c < 8; ++c) reached = reached && !isinf(u[c]);
  return reached;
}

inline int upwind_corner_of_corners(const float* u) {
  int corner = 0;
  for (int a = 0; a < DIM; ++a) {
    float low = INFINITY, high = INFINITY;
    for (int c = 0; c < 8; ++c) {
      if ((c >> a) & 1)
        high = min(high, u[c]);
      else
        low = min(low, u[c]);
    }
    if (high < low) corner |= 1 << a;
  }
  return corner;
}

// The local index of brick corner c (upwind_corner_of_corners).
inline int brick_corner_index(int c) {
  return local_index((int3)(c & 1 ? EDGE - 1 : 0, c & 2 ? EDGE - 1 : 0, c & 4 ? EDGE_Z - 1 : 0));
}

// Per axis, the side whose face layer of the brick, or of the neighbour beyond it, holds the
// smaller value.
inline int upwind_corner_of_layers(const ulong* tile) {
  const int edge[3] = {EDGE, EDGE, EDGE_Z};
  int corner = 0;
  for (int a = 0; a < DIM; ++a) {
    float low = INFINITY, high = INFINITY;
    for (int m = 0; m < EDGE * EDGE_Z; ++m) {  // the layers c_a = -1, 0, edge - 1, edge
      const int p = m % EDGE, q = m / EDGE;
      for (int layer = 0; layer < 4; ++layer) {
        const int at = layer < 2 ? layer - 1 : edge[a] + layer - 3;
        const int3 c = a == 0 ? (int3)(at, p, q) : a == 1 ? (int3)(p, at, q) : (int3)(p, q, at);
        const float u = state_distance(tile[tile_index(c)]);
        if (layer < 2)
          low = min(low, u);
        else
          high = min(high, u);
      }
    }
    if (high < low) corner |= 1 << a;
  }
  return corner;
}

inline int upwind_corner(const ulong* tile) {
  float u[8];
  for (int c = 0; c < 8; ++c)
    u[c] = state_distance(tile[tile_index(local_coordinates(brick_corner_index(c)))]);
  return corners_reached(u) ? upwind_corner_of_corners(u) : upwind_corner_of_layers(tile);
}

// The tile offsets of a stencil's terms; returns whether every offset stays within one voxel per
// axis (inside the tile from any brick voxel). One pass with scalar compares: separate passes, the
// second on int3 vectors, took ~4% of radial_shock_3d's instructions more.
inline bool tile_offsets(const int3* offset, int terms, int* flat) {
  bool near = true;
  for (int i = 0; i < terms; ++i) {
    const int3 e = offset[i];
    near = near && (uint)(e.x + 1) <= 2u && (uint)(e.y + 1) <= 2u && (uint)(e.z + 1) <= 2u;
    flat[i] = tile_offset(e);
  }
  return near;
}

// Gathers the neighbour states of tile slot p (brick coordinates c) into nb (nb[2i] at +e_i,
// nb[2i+1] at -e_i) and returns whether one changed since `last`, x's last evaluation (or x was
// never evaluated). gather_near: every offset within one voxel, so all neighbours are in the tile.
inline bool gather_near(const ulong* tile, const uint* tile_stamp, int p, const int* flat,
                        int terms, uint last, ulong* nb) {
  bool dirty = last == 0;
  for (int i = 0; i < terms; ++i) {
    nb[2 * i] = tile[p + flat[i]];
    nb[2 * i + 1] = tile[p - flat[i]];
    dirty = dirty || tile_stamp[p + flat[i]] > last || tile_stamp[p - flat[i]] > last;
  }
  return dirty;
}

// Whether the voxel at `slot` of another brick changed in or after the round of `last`: its value
// is read from the round's snapshot, so an evaluation saw it iff it changed in an earlier round
// (the tile's stamps are finer, but only the tile has them). No stamp of this round is in
// `changed` yet (commit_bricks publishes them).
inline bool far_changed(__global const uint* changed, long slot, uint last, uint stride) {
  return changed[slot] >= (last & ~(stride - 1));
}

// Longer offsets: the tile where they land in it, else the state (far_changed).
inline bool gather_far(const ulong* tile, const uint* tile_stamp, int p, int3 c, const int3* offset,
                       const int* flat, int terms, uint last, __global const ulong* state,
                       __global const uint* changed, int3 origin, int4 dims, int4 grid,
                       __global const int* table, const int* near, uint stride, ulong* nb) {
  bool dirty = last == 0;
  for (int i = 0; i < terms; ++i) {
    for (int s = 0; s < 2; ++s) {
      const int3 e = s == 0 ? offset[i] : -offset[i];
      ulong value = INF_STATE;
      if (inside_tile(c + e)) {
        const int q = p + (s == 0 ? flat[i] : -flat[i]);
        value = tile[q];
        dirty = dirty || tile_stamp[q] > last;
      } else {
        const long other = neighbour_slot(origin + c + e, origin, dims, grid, table, near);
        if (other >= 0) {
          value = state[other];
          dirty = dirty || far_changed(changed, other, last, stride);
        }
      }
      nb[2 * i + s] = value;
    }
  }
  return dirty;
}

// The arguments of the brick-sweeping kernels (this one and relax_brick_lanes, brick_lanes.cl),
// which the host sets alike; threshold and least_tentative serve front stepping, which only
// relax_brick_lanes does.
#define BRICK_SWEEP_ARGUMENTS                                                                     \
  __global const int *list, int count, __global const ulong *state, __global ulong *scratch,      \
      __global uint *scratch_stamps, __global const float *stencils, __global const char *shapes, \
      __global const int *table, __global const int4 *brick_origins, int4 dims, int4 grid,        \
      __global const float *seeds, __global uchar *flags, __global ulong *update_counter,         \
      int max_sweeps, __global uint *evaluated, __global uint *changed, uint round_base,          \
      uint stride, __global const uint *activity, __global const uint *reader_reach,              \
      __global uint *news, float threshold, __global float *least_tentative

__kernel void relax_brick_sweep(BRICK_SWEEP_ARGUMENTS) {
  const int position = get_global_id(0);
  if (position >= count) return;
  const int brick = list[position];
  // Private: this variant is for CPUs, where the tile stays in the core's cache between visits.
  ulong tile[TILE_VOLUME];
  uint tile_stamp[TILE_VOLUME];
  const size_t brick_slot = (size_t)brick * BRICK_VOLUME;
  const int3 origin = brick_origins[brick].xyz;
  int near[NEAR_BRICKS];
  load_near_bricks(origin, grid, table, near);
  load_tile(tile, tile_stamp, state, changed, near, stride);
  const int corner = upwind_corner(tile);
  uint active[BRICK_VOLUME / 32];  // the brick's activity bits: no stencil read for inactive voxels
  for (int w = 0; w < BRICK_VOLUME / 32; ++w) active[w] = activity[brick_slot / 32 + w];
  uint brick_flags = FLAG_UNCONVERGED;
  // The box of the voxels whose change was significant (brick_news; empty: lo > hi).
  int3 changed_lo = (int3)(EDGE, EDGE, EDGE), changed_hi = (int3)(-1, -1, -1);
  ulong updates = 0;
  uint tick = 0;
#ifdef UNIFORM_METRIC  // one stencil for every active voxel, prepared once
  float weight[STENCIL_TERMS];
  int3 offset[STENCIL_TERMS];
  int flat[STENCIL_TERMS];
  const int terms = load_stencil(stencils, shapes, 0, weight, offset);
  const bool near_stencil = tile_offsets(offset, terms, flat);
  float eGe[STENCIL_TERMS];
  term_lengths_squared(seeds, offset, terms, eGe);
#else
  const float* eGe = 0;
#endif
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    const int direction = corner ^ sweep_reversal(sweep);
    bool sweep_changed = false;
    const int flip = corner_flip(direction);
    for (int n = 0; n < BRICK_VOLUME; ++n) {
      ++tick;
      const int l = n ^ flip;
      const int3 c = local_coordinates(l);
      const int p = tile_index(c);
      if (!(active[l / 32] & (1u << (l % 32)))) continue;
      const size_t slot = brick_slot + l;
      const ulong current = tile[p];
      if (state_frozen(current)) continue;
#ifndef UNIFORM_METRIC
      float weight[STENCIL_TERMS];
      int3 offset[STENCIL_TERMS];
      int flat[STENCIL_TERMS];
      const int terms = load_stencil(stencils, shapes, slot, weight, offset);
      if (terms == 0) continue;
      const bool near_stencil = tile_offsets(offset, terms, flat);
#endif
      const uint last = evaluated[slot];
      ulong nb[2 * STENCIL_TERMS];
      const bool dirty = near_stencil
                             ? gather_near(tile, tile_stamp, p, flat, terms, last, nb)
                             : gather_far(tile, tile_stamp, p, c, offset, flat, terms, last, state,
                                          changed, origin, dims, grid, table, near, stride, nb);
      if (!dirty) continue;
      const uint stamp = round_base + tick;
      evaluated[slot] = stamp;
      const ulong best =
          best_candidate(nb, weight, offset, terms, convert_float3(origin + c), seeds, eGe);
      ++updates;
      if (best != current) {
        tile[p] = best;
        brick_flags |= FLAG_WRITTEN;
        if (is_news(current, best, weight, terms)) {
          tile_stamp[p] = stamp;
          sweep_changed = true;
          changed_lo = min(changed_lo, c);
          changed_hi = max(changed_hi, c);
        }
      }
    }
    if (sweep_changed)
      brick_flags |= FLAG_CHANGED;
    else {
      brick_flags &= ~FLAG_UNCONVERGED;
      break;
    }
  }
  if (brick_flags != 0) {  // commit_bricks copies it back, the stamps when one changed
    __global ulong* relaxed = scratch + (size_t)position * BRICK_VOLUME;
    __global uint* stamps = scratch_stamps + (size_t)position * BRICK_VOLUME;
    for (int l = 0; l < BRICK_VOLUME; ++l) {
      relaxed[l] = tile[tile_index(local_coordinates(l))];
      if (brick_flags & FLAG_CHANGED) stamps[l] = tile_stamp[tile_index(local_coordinates(l))];
    }
  }
  flags[brick] = (uchar)brick_flags;
  news[brick] = brick_news(changed_lo, changed_hi, reader_reach[brick]);
  atom_add(update_counter, updates);
}

// ---------------------------------------------------------------------------------------------
// GPU-friendly variant: a work-group per brick, in 2^DIM phases by the parities of the voxel
// coordinates; in each phase a work-item updates one voxel of that parity class, reading the
// brick from local memory. Selling offsets are primitive vectors (never even in every component),
// so no voxel reads a stencil neighbour of its own class: a phase is a set of independent updates,
// as in a sequential sweep. (Updating every voxel at once, Jacobi, can cycle: two voxels near a
// bisector hand each other's label back and forth; it never converged on 64^3 with 1000 seeds.)
// Iterations (all phases) repeat until one changes nothing significant, or `iterations`. Barriers
// sit inside the loops, so every exit must be the same for every work-item: all read one flag.

#define PHASES (DIM == 3 ? 8 : 4)
#define PHASE_VOXELS (BRICK_VOLUME / PHASES) /* the work-group size */

// Local index of the voxel work-item w updates in phase p: coordinates 2 (w's sub-brick
// coordinates) + p's parity bits.
inline int phase_voxel(int w, int p) {
  const int3 c = 2 * (int3)(w % (EDGE / 2), (w / (EDGE / 2)) % (EDGE / 2), w / (EDGE * EDGE / 4)) +
                 (int3)(p & 1, (p >> 1) & 1, (p >> 2) & 1);
  return c.x + EDGE * (c.y + EDGE * c.z);
}

// The states of v's stencil neighbours (nb[2i] at +e_i, nb[2i+1] at -e_i): from the brick's
// copy in local memory inside it, else from the state.
inline void gather_for_phases(int3 v, int3 origin, const int3* offset, int terms,
                              __local const ulong* values, __global const ulong* state, int4 dims,
                              int4 grid, __global const int* table, ulong* nb) {
  for (int i = 0; i < terms; ++i) {
    for (int s = 0; s < 2; ++s) {
      const int3 y = s == 0 ? v + offset[i] : v - offset[i];
      ulong value = INF_STATE;
      if (inside_brick(y, origin)) {
        value = values[local_index(y)];
      } else {
        const long slot = slot_at(y, dims, grid, table);
        if (slot >= 0) value = state[slot];
      }
      nb[2 * i + s] = value;
    }
  }
}

#define PHASE_MASK_WORDS (BRICK_VOLUME / 32)

// Whether a stencil neighbour inside the brick (the only ones that change during a relaxation:
// the others are read from the state, which the round's other bricks do not write) is marked in
// one of the masks of changed voxels.
inline bool neighbour_marked(int3 c, const int3* offset, int terms, __local const uint* mask,
                             __local const uint* other_mask) {
  for (int i = 0; i < terms; ++i)
    for (int s = 0; s < 2; ++s) {
      const int3 y = s == 0 ? c + offset[i] : c - offset[i];
      if (!inside_brick(y, (int3)(0, 0, 0))) continue;
      const int n = local_index(y);
      if (((mask[n / 32] | other_mask[n / 32]) >> (n % 32)) & 1u) return true;
    }
  return false;
}

// Whether a stencil neighbour changed significantly since `last`, voxel c's last evaluation in an
// earlier relaxation (0: never evaluated), by the stamps of the brick sweeps: exact inside the
// brick, far_changed outside it.
inline bool changed_since(int3 c, int3 origin, const int3* offset, int terms, uint last,
                          uint stride, size_t brick_slot, __global const uint* changed, int4 dims,
                          int4 grid, __global const int* table) {
  if (last == 0) return true;
  for (int i = 0; i < terms; ++i)
    for (int s = 0; s < 2; ++s) {
      const int3 y = s == 0 ? c + offset[i] : c - offset[i];
      if (inside_brick(y, (int3)(0, 0, 0))) {
        if (changed[brick_slot + local_index(y)] > last) return true;
      } else {
        const long slot = slot_at(origin + y, dims, grid, table);
        if (slot >= 0 && far_changed(changed, slot, last, stride)) return true;
      }
    }
  return false;
}

// The new state of brick voxel l (unchanged when frozen or inactive); counts an update in *updates
// and tells in *news whether the new state is news (is_news; left false when not evaluated). A
// voxel is evaluated only where a neighbour changed since its last evaluation: in the first
// iteration by the stamps (changed_since), in any by the masks of the news of the last iteration
// and of this one (mask, other_mask). Masks and stamps both record news only, as the brick sweeps'
// stamps do, so a skipped voxel misses no more than changes below the news threshold.
inline ulong phase_update(int l, size_t brick_slot, int3 origin, __local const ulong* values,
                          __global const ulong* state, __global const float* stencils,
                          __global const char* shapes, __global const uint* activity, int4 dims,
                          int4 grid, __global const int* table, __global const float* seeds,
                          bool first, __local const uint* mask, __local const uint* other_mask,
                          __global uint* evaluated, __global const uint* changed, uint stamp,
                          uint stride, uint* updates, bool* news) {
  const ulong current = values[l];
  if (state_frozen(current) || !slot_active(activity, brick_slot + l)) return current;
  float weight[STENCIL_TERMS];
  int3 offset[STENCIL_TERMS];
  const int terms = load_stencil(stencils, shapes, brick_slot + l, weight, offset);
  if (terms == 0) return current;
  const int3 c = local_coordinates(l);
  if (!neighbour_marked(c, offset, terms, mask, other_mask) &&
      !(first && changed_since(c, origin, offset, terms, evaluated[brick_slot + l], stride,
                               brick_slot, changed, dims, grid, table)))
    return current;
  evaluated[brick_slot + l] = stamp;
  const int3 v = origin + c;
  ulong nb[2 * STENCIL_TERMS];
  gather_for_phases(v, origin, offset, terms, values, state, dims, grid, table, nb);
  ++*updates;
#ifdef UNIFORM_METRIC
  float eGe[STENCIL_TERMS];
  term_lengths_squared(seeds, offset, terms, eGe);
#else
  const float* eGe = 0;
#endif
  const ulong best = best_candidate(nb, weight, offset, terms, convert_float3(v), seeds, eGe);
  *news = is_news(current, best, weight, terms);
  return best;
}

// The brick sweeps' arguments: max_sweeps is the most iterations; no front stepping (threshold,
// least_tentative unused).
__kernel __attribute__((reqd_work_group_size(PHASE_VOXELS, 1, 1))) void relax_voxel_phases(
    BRICK_SWEEP_ARGUMENTS) {
  const int iterations = max_sweeps;
  __local ulong values[BRICK_VOLUME];
  // The box of the voxels whose change was significant, lo then hi (brick_news; empty: lo > hi):
  // only the bricks that read it are activated, as after a brick sweep. (Every brick within reach
  // was: an insertion into a 48^3 canvas then relaxed 584 bricks where brick_sweep relaxed 166.)
  __local int changed_box[6];
  // changed_voxels[it % 3]: the voxels whose change in iteration `it` was news (is_news, as the
  // stamps: with every rounding rise marked there, the voxels beside a seed kept waking each other
  // and anisotropy 141 along an axis never settled; bit l of word l / 32);
  // iteration `it` clears iteration it + 1's, which nobody reads or writes before a barrier.
  __local uint changed_voxels[3][PHASE_MASK_WORDS];
  // changed_in[it % 3]: iteration `it` changed a value significantly. Iteration `it` resets the
  // flag of iteration it + 2: nobody reads it any more, and nobody sets it before a barrier.
  __local int changed_in[3];
  // Any value written, significant or not: committed (FLAG_WRITTEN), so that the evaluation
  // stamps describe `state`, as after a brick sweep.
  __local int written;
  __local uint brick_updates;
  const int position = get_group_id(0);
  const int w = get_local_id(0);
  const int brick = list[position];
  const size_t brick_slot = (size_t)brick * BRICK_VOLUME;
  const int3 origin = brick_origins[brick].xyz;
  __global uint* stamps = scratch_stamps + (size_t)position * BRICK_VOLUME;
  for (int p = 0; p < PHASES; ++p) {
    values[phase_voxel(w, p)] = state[brick_slot + phase_voxel(w, p)];
    stamps[phase_voxel(w, p)] = 0u;  // commit_bricks: no new change stamp
  }
  if (w < 3) {
    changed_in[w] = 0;
    changed_box[w] = EDGE;
    changed_box[3 + w] = -1;
  }
  if (w == 0) {
    brick_updates = 0;
    written = 0;
  }
  if (w < PHASE_MASK_WORDS) {  // iteration 0 reads masks 0 and 2 (none changed before it)
    changed_voxels[0][w] = 0;
    changed_voxels[2][w] = 0;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  uint updates = 0;
  bool changed_ever = false, changed_last = false, wrote = false;
  int3 changed_lo = (int3)(EDGE, EDGE, EDGE), changed_hi = (int3)(-1, -1, -1);
  for (int it = 0; it < iterations; ++it) {
    __local uint* changed_now = changed_voxels[it % 3];
    __local const uint* changed_before = changed_voxels[(it + 2) % 3];
    if (w < PHASE_MASK_WORDS) changed_voxels[(it + 1) % 3][w] = 0;
    for (int p = 0; p < PHASES; ++p) {
      const int l = phase_voxel(w, p);
      bool news = false;
      // Stamps in (it, p) order, below round_base + stride (the host's stride covers them).
      const uint stamp = round_base + 1 + it * PHASES + p;
      const ulong best =
          phase_update(l, brick_slot, origin, values, state, stencils, shapes, activity, dims, grid,
                       table, seeds, it == 0, changed_now, changed_before, evaluated, changed,
                       stamp, stride, &updates, &news);
      if (best != values[l]) {
        wrote = true;
        if (news) {
          atomic_or(&changed_now[l / 32], 1u << (l % 32));
          const int3 c = local_coordinates(l);
          stamps[l] = stamp;
          changed_in[it % 3] = 1;
          changed_lo = min(changed_lo, c);
          changed_hi = max(changed_hi, c);
        }
        values[l] = best;
      }
      barrier(CLK_LOCAL_MEM_FENCE);
    }
    changed_last = changed_in[it % 3] != 0;
    if (w == 0) changed_in[(it + 2) % 3] = 0;
    changed_ever = changed_ever || changed_last;
    if (!changed_last) break;
  }
  for (int p = 0; p < PHASES; ++p)
    scratch[(size_t)position * BRICK_VOLUME + phase_voxel(w, p)] = values[phase_voxel(w, p)];
  atomic_add(&brick_updates, updates);
  if (wrote) written = 1;
  if (changed_lo.x <= changed_hi.x) {
    atomic_min(&changed_box[0], changed_lo.x);
    atomic_min(&changed_box[1], changed_lo.y);
    atomic_min(&changed_box[2], changed_lo.z);
    atomic_max(&changed_box[3], changed_hi.x);
    atomic_max(&changed_box[4], changed_hi.y);
    atomic_max(&changed_box[5], changed_hi.z);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (w == 0) {
    flags[brick] = (uchar)((changed_ever ? FLAG_CHANGED : 0u) |
                           (changed_last ? FLAG_UNCONVERGED : 0u) | (written ? FLAG_WRITTEN : 0u));
    news[brick] =
        brick_news((int3)(changed_box[0], changed_box[1], changed_box[2]),
                   (int3)(changed_box[3], changed_box[4], changed_box[5]), reader_reach[brick]);
    atom_add(update_counter, (ulong)brick_updates);
  }
}

// ---------------------------------------------------------------------------------------------
// Round bookkeeping.

// Copies relaxed bricks back into the state and their new change stamps (0: none) into `changed`
// (a work-item per voxel of the listed bricks), and marks them touched. The relaxations left
// `changed` as it was, so what they read of their neighbours' stamps did not depend on how far
// those had got (an insertion relaxes neighbouring bricks in the same round).
__kernel void commit_bricks(__global const int* list, int count, __global const ulong* scratch,
                            __global const uint* scratch_stamps, __global ulong* state,
                            __global uint* changed, __global const uchar* flags,
                            __global uchar* touched) {
  const size_t item = get_global_id(0);
  const int position = item / BRICK_VOLUME;
  if (position >= count) return;
  const int brick = list[position];
  const uchar brick_flags = flags[brick];
  if (brick_flags == 0) return;
  if (item % BRICK_VOLUME == 0) touched[brick] = 1;
  const size_t slot = (size_t)brick * BRICK_VOLUME + item % BRICK_VOLUME;
  state[slot] = scratch[item];
  if ((brick_flags & FLAG_CHANGED) && scratch_stamps[item] != 0u)
    changed[slot] = scratch_stamps[item];
}

// The listed bricks' states one after another in scratch (a work-item per voxel), so that an
// insertion reads what it touched back in one transfer rather than one per brick.
__kernel void gather_bricks(__global const int* list, int count, __global const ulong* state,
                            __global ulong* scratch) {
  const size_t item = get_global_id(0);
  if (item / BRICK_VOLUME >= (size_t)count) return;
  scratch[item] = state[(size_t)list[item / BRICK_VOLUME] * BRICK_VOLUME + item % BRICK_VOLUME];
}

// At the start of a solve or insertion: a brick becomes pending when it is unconverged or a brick
// within stencil reach changed (gathered per brick, so there are no write races). The host then
// clears the flags.
__kernel void activate_bricks(int brick_count, __global const int4* brick_origins,
                              __global const int* table, int4 grid, int4 reach,
                              __global const uchar* flags, __global uchar* pending) {
  const int brick = get_global_id(0);
  if (brick >= brick_count) return;
  bool activate = pending[brick] != 0 || (flags[brick] & FLAG_UNCONVERGED) != 0;
  const int3 b = brick_of_voxel(brick_origins[brick].xyz);
  for (int dz = -reach.z; dz <= reach.z && !activate; ++dz)
    for (int dy = -reach.y; dy <= reach.y && !activate; ++dy)
      for (int dx = -reach.x; dx <= reach.x && !activate; ++dx) {
        const int other = brick_at(b + (int3)(dx, dy, dz), grid, table);
        activate = other >= 0 && (flags[other] & FLAG_CHANGED) != 0;
      }
  if (activate) pending[brick] = 1;
}

// After a round (a work-item per listed brick, after commit_bricks): an unconverged brick stays
// pending, and a brick that changed makes the bricks around pending that read a changed value:
// those its `news` mask names (brick_layout.clh), or, with FAR_READERS, every brick within
// stencil reach. Its flags are cleared. Only the round's bricks are visited, so a round costs what
// it relaxes, not the canvas. Concurrent work-items may set the same pending byte, always to 1.
__kernel void spread_activation(__global const int* list, int count,
                                __global const int4* brick_origins, __global const int* table,
                                int4 grid, int4 reach, __global uchar* flags,
                                __global uchar* pending, __global const uint* news) {
  const int position = get_global_id(0);
  if (position >= count) return;
  const int brick = list[position];
  const uint f = flags[brick];
  flags[brick] = 0;
  if (f & FLAG_UNCONVERGED) pending[brick] = 1;
  if (!(f & FLAG_CHANGED)) return;
  const int3 b = brick_of_voxel(brick_origins[brick].xyz);
  const uint directions = news[brick];
  if (!(directions & FAR_READERS)) {
    for (int d = 0; d < 27; ++d) {
      if (!((directions >> d) & 1u)) continue;
      const int other = brick_at(b + direction_offset(d), grid, table);
      if (other >= 0) pending[other] = 1;
    }
    return;
  }
  for (int dz = -reach.z; dz <= reach.z; ++dz)
    for (int dy = -reach.y; dy <= reach.y; ++dy)
      for (int dx = -reach.x; dx <= reach.x; ++dx) {
        const int other = brick_at(b + (int3)(dx, dy, dz), grid, table);
        if (other >= 0) pending[other] = 1;
      }
}

// Bricks of one colour (parities of the brick coordinates) share no face, edge or corner, so
// relaxing one colour per round reads fresh values of all neighbours (Gauss-Seidel between
// bricks). colours == 1: every pending brick, every round.
inline int brick_colour(int3 b) {
  return (b.x & 1) | (b.y & 1) << 1 | (DIM == 3 ? (b.z & 1) << 2 : 0);
}

// Lists the pending bricks of the round's colour (order is irrelevant: a brick's result depends
// only on the snapshot) and counts them in counts[0]; counts[1] tells whether any brick of any
// colour was pending.
__kernel void compact_active(int brick_count, __global uchar* pending,
                             __global const int4* brick_origins, int colours, int colour,
                             __global int* list, __global int* counts) {
  const int brick = get_global_id(0);
  if (brick >= brick_count) return;
  if (!pending[brick]) return;
  counts[1] = 1;
  if (colours > 1 && brick_colour(brick_of_voxel(brick_origins[brick].xyz)) != colour) return;
  pending[brick] = 0;
  list[atomic_inc(&counts[0])] = brick;
}

// The first `count` listed bricks become pending again (a list the host does not relax: more
// bricks than the scratch holds).
__kernel void pend_listed(__global const int* list, int count, __global uchar* pending) {
  const int position = get_global_id(0);
  if (position < count) pending[list[position]] = 1;
}

// Front stepping (brick_lanes, docs/scheme.md): the least tentative distance over all bricks, as
// float bits (distances are positive, so their bits order as the floats do).
__kernel void least_tentative_of(int brick_count, __global const float* least_tentative,
                                 __global uint* least_bits) {
  const int brick = get_global_id(0);
  if (brick >= brick_count) return;
  const float least = least_tentative[brick];
  if (!isinf(least)) atomic_min(least_bits, as_uint(least));
}

// The bricks holding a tentative distance at or below the threshold become pending: their
// relaxation releases it (load_lane_row, brick_lanes.cl).
__kernel void pend_below_threshold(int brick_count, float threshold,
                                   __global const float* least_tentative, __global uchar* pending) {
  const int brick = get_global_id(0);
  if (brick >= brick_count) return;
  if (least_tentative[brick] <= threshold) pending[brick] = 1;
}
