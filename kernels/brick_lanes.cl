// CPU variant with SIMD lanes: one work-item relaxes LANES bricks at once, one per lane of 8-wide
// vectors, with exactly the schedule of relax_brick_sweep (propagation.cl) in every lane: the
// same upwind corner, sweeps, work avoidance and stamps. The lanes never depend on each other, so
// a vector visit is LANES independent visits; a lane that has nothing to do there is masked.
//
// Each lane's tile is stored in that brick's sweep frame: coordinates flipped on the axes where
// its upwind corner is on the high side. Then every lane visits the same frame index at the same
// time, and a neighbour is one vector load. A frame offset e is the real offset S e, S the lane's
// diagonal of signs, which only the factorization needs (e^T G q).
//
// Two configurations (docs/scheme.md, "SIMD lanes"):
// - AXIS_LANES, a uniform metric whose stencil has axis offsets only (diagonal metrics): S e = +-e
//   is the same term in every lane, so the neighbours are vector loads at flat offsets. The host
//   passes the stencil's shape as build options, UNIFORM_TERMS (the term count of load_stencil)
//   and UNIFORM_OFFSET_<term><axis> for every term (a comma list does not survive PoCL's option
//   handling): as constants, the loops over terms unroll and the offsets fold.
// - Any other stencil (varying metrics; uniform ones whose flipped offsets are other terms in
//   each lane's frame): each lane loads its voxel's stencil and gathers its neighbours, reading
//   the states only when a change stamp says the voxel is dirty; the solve is vectorised. On a
//   device with AVX2 the stencils and the neighbours in the tiles come with x86 gathers, and only
//   the neighbours beyond a tile (long offsets) one lane at a time; elsewhere each lane does it
//   all in turn.
//
// Measured (callgrind, 64^3, 1000 seeds; docs/scheme.md): kernel instructions of the whole solve,
// relax_brick_sweep -> this kernel, euclidean 1486M -> 664M, radial_shock_3d 4048M -> 2996M, for
// the same evaluations.

// x86 gathers in the general form: where the device compiles with AVX2, unless the host turned
// them off (OpenCLOptions::x86_gathers).
#if defined(__AVX2__) && !defined(NO_X86_GATHERS)
#define X86_GATHERS
#endif

// A cache-line request for a global address. On a CPU device (one address space) clang's builtin
// emits the prefetch instruction; NVIDIA's compiler rejects a __global pointer there, so other
// devices take OpenCL's own prefetch.
#if defined(__x86_64__) || defined(__aarch64__)
#define PREFETCH_GLOBAL(pointer) __builtin_prefetch(pointer)
#else
#define PREFETCH_GLOBAL(pointer) prefetch(pointer, 1)
#endif

#if defined(UNIFORM_METRIC) && defined(UNIFORM_TERMS)
#define AXIS_LANES /* one stencil of axis offsets, constants from the build options */
#define LANE_TERMS UNIFORM_TERMS
#else
#define LANE_TERMS STENCIL_TERMS
#endif

#ifdef AXIS_LANES
inline int3 lane_offset(int i) {
  const int offsets[3 * STENCIL_TERMS] = {
      UNIFORM_OFFSET_0X, UNIFORM_OFFSET_0Y, UNIFORM_OFFSET_0Z, UNIFORM_OFFSET_1X, UNIFORM_OFFSET_1Y,
      UNIFORM_OFFSET_1Z, UNIFORM_OFFSET_2X, UNIFORM_OFFSET_2Y, UNIFORM_OFFSET_2Z, UNIFORM_OFFSET_3X,
      UNIFORM_OFFSET_3Y, UNIFORM_OFFSET_3Z, UNIFORM_OFFSET_4X, UNIFORM_OFFSET_4Y, UNIFORM_OFFSET_4Z,
      UNIFORM_OFFSET_5X, UNIFORM_OFFSET_5Y, UNIFORM_OFFSET_5Z};
  return (int3)(offsets[3 * i], offsets[3 * i + 1], offsets[3 * i + 2]);
}
#endif

#define LANES 8
// Front stepping (state_word.clh): built in only for the solves that step (the host builds this
// kernel twice), since its tests cost the other solves ~8% (euclidean 256^3).
#ifndef FRONT_STEPPING
#define FRONT_STEPPING 0
#endif
#define NO_LANE_LABEL 0xFFFFFFFFu /* a label no neighbour carries (labels have 31 bits) */

typedef float8 lane_float;
typedef int8 lane_mask; /* -1: set, 0: clear */
typedef uint8 lane_uint;

// Whether any lane of m is set: one vector OR tree and one test (PoCL lowers any() to a chain of
// lane extracts and branches).
inline bool lanes_any(lane_mask m) {
  const int4 halves = m.lo | m.hi;
  const int2 quarters = halves.lo | halves.hi;
  return (quarters.x | quarters.y) < 0;
}

// One lane of a private vector array (LANES floats or uints per element).
#define LANE_FLOAT(array, index, lane) (((float*)(array))[(index)*LANES + (lane)])
#define LANE_UINT(array, index, lane) (((uint*)(array))[(index)*LANES + (lane)])

// solve_sorted (eikonal_scheme.clh) for every lane over the LANE_TERMS terms; w sorted ascending,
// +inf last. The term count is the constant, not a parameter, so that even the out-of-line copy
// PoCL compiles has loops it can unroll (a parameter made every build warn "loop not unrolled").
__attribute__((always_inline)) inline lane_float lane_solve_sorted(const lane_float* w,
                                                                   const lane_float* rho) {
  const int n = LANE_TERMS;
  // t_k = w_0 + (b_k + root_k) / a_k stops at the first k with t_k <= w_{k+1}, tested as
  // b_k + root_k <= a_k (w_{k+1} - w_0) (a_k > 0), so that only the chosen t_k is divided out.
  lane_float a = 0.0f, b = 0.0f, pair_sum = 0.0f, numerator = 0.0f, denominator = 1.0f;
  lane_mask done = isinf(w[0]);  // no finite term: +inf
  const lane_mask none = done;
#pragma unroll
  for (int k = 0; k < n; ++k) {
    const lane_float wk = w[k] - w[0];
#pragma unroll
    for (int i = 0; i < k; ++i) {
      const lane_float d = w[i] - w[k];
      pair_sum += rho[i] * rho[k] * d * d;
    }
    a += rho[k];
    b += rho[k] * wk;
    const lane_float reach = b + sqrt(max(0.0f, a - pair_sum));
    const lane_mask stop = k + 1 == n ? (lane_mask)(-1) : reach <= a * (w[k + 1] - w[0]);
    numerator = select(numerator, reach, ~done & stop);
    denominator = select(denominator, a, ~done & stop);
    done |= stop;
  }
  return select(w[0] + numerator / denominator, (lane_float)INFINITY, none);
}

// A visit's neighbours in every lane, n[2i] at frame +e_i and n[2i+1] at -e_i: distance, label
// (LABEL_NONE: none) and seed distance under that label.
typedef struct {
  lane_float distance[2 * STENCIL_TERMS], seed_distance[2 * STENCIL_TERMS];
  lane_uint label[2 * STENCIL_TERMS];
} LaneNeighbours;

// The smaller factorized value of stencil term i's two neighbours under `label` in each lane
// (solve_for_label of eikonal_scheme.clh), +inf where neither carries it; slope = e^T G q / u0(x).
// The neighbour y = x + sigma e gives v + alpha (u0(x) - u0(y) + sigma slope) with u0(y) from the
// tile. factorized_value computes u0(x) - u0(y) without cancellation instead, at a square root
// and a division per neighbour; the float difference loses about 1e-7 of u0, below the 1e-6
// news threshold (RELATIVE_TOLERANCE; docs/scheme.md, "SIMD lanes").
__attribute__((always_inline)) inline lane_float lane_term_value(const LaneNeighbours* nb, int i,
                                                                 lane_uint label, lane_float u0,
                                                                 lane_float slope, lane_float alpha,
                                                                 lane_mask factored) {
  const lane_float ahead = nb->distance[2 * i], behind = nb->distance[2 * i + 1];
  const lane_float ahead_f =
      select(ahead, ahead + alpha * (u0 - nb->seed_distance[2 * i] + slope), factored);
  const lane_float behind_f =
      select(behind, behind + alpha * (u0 - nb->seed_distance[2 * i + 1] - slope), factored);
  return min(select((lane_float)INFINITY, ahead_f, nb->label[2 * i] == label),
             select((lane_float)INFINITY, behind_f, nb->label[2 * i + 1] == label));
}

// The smaller raw distance of stencil term i's two neighbours under `label` in each lane, +inf
// where neither carries it or the term has no weight: what the candidate's floor takes
// (solve_for_label, eikonal_scheme.clh).
__attribute__((always_inline)) inline lane_float lane_term_raw(const LaneNeighbours* nb, int i,
                                                               lane_uint label, lane_float rho) {
  const lane_float raw =
      min(select((lane_float)INFINITY, nb->distance[2 * i], nb->label[2 * i] == label),
          select((lane_float)INFINITY, nb->distance[2 * i + 1], nb->label[2 * i + 1] == label));
  return select(raw, (lane_float)INFINITY, rho == 0.0f);
}

// Sorts the LANE_TERMS terms w ascending, rho alongside, in every lane; stable, as the scalar
// insertion sort.
__attribute__((always_inline)) inline void lane_sort(lane_float* w, lane_float* rho) {
  const int n = LANE_TERMS;
#pragma unroll
  for (int pass = 0; pass + 1 < n; ++pass)
#pragma unroll
    for (int i = 0; i + 1 < n - pass; ++i) {
      const lane_mask swap = w[i + 1] < w[i];
      const lane_float wl = select(w[i], w[i + 1], swap), wh = select(w[i + 1], w[i], swap);
      const lane_float rl = select(rho[i], rho[i + 1], swap), rh = select(rho[i + 1], rho[i], swap);
      w[i] = wl;
      w[i + 1] = wh;
      rho[i] = rl;
      rho[i + 1] = rh;
    }
}

// The sweep frame of each lane: real coordinate = base + sign * frame coordinate, per axis.
typedef struct {
  lane_float base_x, base_y, base_z, sign_x, sign_y, sign_z;
} LaneFrame;

// The bricks in the lanes: id (-1: none), the local-index bits its frame flips, origin, the sign
// of each frame axis, and the 3^DIM bricks around it (load_near_bricks).
typedef struct {
  int brick[LANES], flip[LANES];
  int3 origin[LANES], sign[LANES];
  int near[LANES][NEAR_BRICKS];
} LaneBricks;

// The lanes' tiles in their frames: distances, low state words (frozen bit, label), change stamps
// and seed distances (u0 of each voxel under its own label, 0 without one: the factorized terms
// take u0 of a neighbour from here instead of a square root each), with the evaluation stamps of
// the bricks' voxels at frame local indices.
typedef struct {
  lane_float distance[TILE_VOLUME], seed_distance[TILE_VOLUME];
  lane_uint word[TILE_VOLUME], stamp[TILE_VOLUME], evaluated[BRICK_VOLUME];
} LaneTile;

// The seeds of `label` in each lane (NO_LANE_LABEL: seed 0, unused): positions, and with
// SEED_METRIC their h^2 G_s; one 4- or 8-float load per lane, transposed.
#define LANE_COLUMN(v, c) \
  (lane_float)((v##0).c, (v##1).c, (v##2).c, (v##3).c, (v##4).c, (v##5).c, (v##6).c, (v##7).c)
inline void lane_seed_positions(lane_uint label, __global const float* seeds, lane_float* sx,
                                lane_float* sy, lane_float* sz) {
  const uint8 r = select(label, (lane_uint)0u, label == NO_LANE_LABEL) * SEED_RECORD;
  const float4 p0 = vload4(0, seeds + r.s0), p1 = vload4(0, seeds + r.s1),
               p2 = vload4(0, seeds + r.s2), p3 = vload4(0, seeds + r.s3),
               p4 = vload4(0, seeds + r.s4), p5 = vload4(0, seeds + r.s5),
               p6 = vload4(0, seeds + r.s6), p7 = vload4(0, seeds + r.s7);
  *sx = LANE_COLUMN(p, x);
  *sy = LANE_COLUMN(p, y);
  *sz = LANE_COLUMN(p, z);
}

// u0 = |x - s|_{G_s} of frame voxel cf in each lane (x its real coordinates, s = (sx, sy, sz) a
// seed, g = h^2 G_s), G q with q = x - s, and |q|^2.
__attribute__((always_inline)) inline lane_float lane_seed_distance(
    lane_float sx, lane_float sy, lane_float sz, const LaneFrame* frame, int3 cf,
    const lane_float* g, lane_float* gq, lane_float* q_norm2) {
  const lane_float qx = frame->base_x + frame->sign_x * (float)cf.x - sx;
  const lane_float qy = frame->base_y + frame->sign_y * (float)cf.y - sy;
  const lane_float qz = frame->base_z + frame->sign_z * (float)cf.z - sz;
  *q_norm2 = qx * qx + qy * qy + qz * qz;
  gq[0] = g[0] * qx + g[1] * qy + g[3] * qz;
  gq[1] = g[1] * qx + g[2] * qy + g[4] * qz;
  gq[2] = g[3] * qx + g[4] * qy + g[5] * qz;
  return sqrt(max(0.0f, qx * gq[0] + qy * gq[1] + qz * gq[2]));
}

// The seed metrics h^2 G_s of `label` in each lane (NO_LANE_LABEL: seed 0's).
inline void lane_seed_metric(lane_uint label, __global const float* seeds, lane_float* g) {
  const uint8 r = select(label, (lane_uint)0u, label == NO_LANE_LABEL) * SEED_RECORD + 8u;
  const float8 m0 = vload8(0, seeds + r.s0), m1 = vload8(0, seeds + r.s1),
               m2 = vload8(0, seeds + r.s2), m3 = vload8(0, seeds + r.s3),
               m4 = vload8(0, seeds + r.s4), m5 = vload8(0, seeds + r.s5),
               m6 = vload8(0, seeds + r.s6), m7 = vload8(0, seeds + r.s7);
  g[0] = LANE_COLUMN(m, s0);
  g[1] = LANE_COLUMN(m, s1);
  g[2] = LANE_COLUMN(m, s2);
  g[3] = LANE_COLUMN(m, s3);
  g[4] = LANE_COLUMN(m, s4);
  g[5] = LANE_COLUMN(m, s5);
}

// u0 of frame voxel cf under `label` in each lane, with that seed's metric g, G q and |q|^2 (the
// axis form leaves q_norm2 unset: its offsets have length 1, always fully factorized).
__attribute__((always_inline)) inline lane_float lane_label_seed_distance(
    lane_uint label, const LaneFrame* frame, int3 cf, __global const float* seeds, lane_float* g,
    lane_float* gq, lane_float* q_norm2) {
  lane_float sx, sy, sz;
  lane_seed_positions(label, seeds, &sx, &sy, &sz);
#ifdef AXIS_LANES
  // Every seed has the canvas's metric, which is diagonal (the host checks it): G q takes its
  // diagonal only, the same floats as the full product, whose other terms add zeros (g is unset).
  const lane_float qx = frame->base_x + frame->sign_x * (float)cf.x - sx;
  const lane_float qy = frame->base_y + frame->sign_y * (float)cf.y - sy;
  const lane_float qz = frame->base_z + frame->sign_z * (float)cf.z - sz;
  gq[0] = seeds[8] * qx;
  gq[1] = seeds[10] * qy;
  gq[2] = seeds[13] * qz;
  return sqrt(max(0.0f, qx * gq[0] + qy * gq[1] + qz * gq[2]));
#else
  lane_seed_metric(label, seeds, g);
  return lane_seed_distance(sx, sy, sz, frame, cf, g, gq, q_norm2);
#endif
}

// The arguments of lane_gather (one per configuration): the visit (frame local index l, frame
// coordinates cf, tile index p, the voxel's last evaluations), the lanes' tiles and bricks, the
// seeds and buffers for neighbours beyond the tiles, and the outputs: the voxel's stencil
// (per-voxel stencils only) and its neighbours.
#define LANE_GATHER_ARGUMENTS                                                                 \
  lane_mask open, int l, int3 cf, int p, lane_uint last, const LaneTile *tile,                \
      const LaneBricks *bricks, __global const float *seeds, __global const float *stencils,  \
      __global const char *shapes, __global const ulong *state, __global const uint *changed, \
      int4 dims, int4 grid, __global const int *table, uint stride, LaneStencil *st,          \
      LaneNeighbours *nb

#ifdef AXIS_LANES
// The stencil of a uniform metric as every lane sees it.
typedef struct {
  float weight[STENCIL_TERMS];
  float tolerance;  // rounding_tolerance of the stencil
} LaneStencil;

inline void prepare_lane_stencil(__global const float* stencils, __global const char* shapes,
                                 LaneStencil* st) {
  int3 offset[STENCIL_TERMS];
  load_stencil(stencils, shapes, 0, st->weight, offset);
  st->tolerance = rounding_tolerance(st->weight, LANE_TERMS);
}

// Candidate distance for label L in each lane (NO_LANE_LABEL: none) at frame voxel cf, from its
// neighbours; seed_distance: u0 of cf under L.
__attribute__((always_inline)) inline lane_float lane_solve_for_label(
    lane_uint label, const LaneNeighbours* nb, const LaneStencil* st, const LaneFrame* frame,
    int3 cf, __global const float* seeds, lane_float* seed_distance) {
  lane_float g[6], gq[3];
  lane_float q_norm2;  // not needed: unit offsets, factorized in full (offset_factorization_weight)
  const lane_float u0 = lane_label_seed_distance(label, frame, cf, seeds, g, gq, &q_norm2);
  *seed_distance = u0;
  const lane_mask factored = u0 > 0.0f;
  const lane_float inverse_u0 = select((lane_float)0.0f, 1.0f / u0, factored);
  // e^T G q for a frame offset e is e . (S G q).
  const lane_float sgx = frame->sign_x * gq[0], sgy = frame->sign_y * gq[1];
  const lane_float sgz = frame->sign_z * gq[2];
  lane_float w[STENCIL_TERMS], rho[STENCIL_TERMS];
  lane_float least_raw = INFINITY;
#pragma unroll
  for (int i = 0; i < LANE_TERMS; ++i) {
    const float3 e = convert_float3(lane_offset(i));  // a frame offset
    const lane_float eGq = e.x * sgx + e.y * sgy + e.z * sgz;
    w[i] = lane_term_value(nb, i, label, u0, eGq * inverse_u0, 1.0f, factored);
    rho[i] = st->weight[i];
    least_raw = min(least_raw, lane_term_raw(nb, i, label, rho[i]));
  }
  lane_sort(w, rho);
  return max(lane_solve_sorted(w, rho), least_raw);
}

inline void lane_voxel_metric(LaneStencil* st) {}  // one stencil: nothing per voxel

// The neighbours of frame slot p in every lane: the same flat offsets, one vector load each.
// Returns the lanes where one changed since `last` (or that never evaluated the voxel).
inline lane_mask lane_gather(LANE_GATHER_ARGUMENTS) {
  lane_mask dirty = last == 0u;
#pragma unroll
  for (int i = 0; i < LANE_TERMS; ++i) {
    const int ahead = p + tile_offset(lane_offset(i)), behind = p - tile_offset(lane_offset(i));
    nb->distance[2 * i] = tile->distance[ahead];
    nb->distance[2 * i + 1] = tile->distance[behind];
    nb->label[2 * i] = tile->word[ahead] & LABEL_NONE;
    nb->label[2 * i + 1] = tile->word[behind] & LABEL_NONE;
    nb->seed_distance[2 * i] = tile->seed_distance[ahead];
    nb->seed_distance[2 * i + 1] = tile->seed_distance[behind];
    dirty |= (tile->stamp[ahead] > last) | (tile->stamp[behind] > last);
  }
  return open & dirty;
}

#else
// Any stencil: each lane's voxel has its own (a varying metric, or a uniform one whose flipped
// offsets are other terms in each lane's frame), so the neighbours are gathered lane by lane;
// the solve is vectorised.
typedef struct {
  lane_float rho[STENCIL_TERMS];  // weights rho_i / h^2, 0 past the voxel's terms
  lane_float ex[STENCIL_TERMS], ey[STENCIL_TERMS], ez[STENCIL_TERMS];  // real offsets
  lane_float d[6];                                                     // D / h^2
  // |e_i|^2 and 1 / (1.25 |e_i|^2), for offset_factorization_weight: once per visit, not per label
  lane_float e_norm2[STENCIL_TERMS], offset_scale[STENCIL_TERMS];
  // The shape (offset set) each lane decoded last and its offsets, kept across visits: a lane's
  // next voxel mostly has the same shape, and then lane_terms skips the shape table's gathers.
  int8 shape_seen;
  int8 seen_x[STENCIL_TERMS], seen_y[STENCIL_TERMS], seen_z[STENCIL_TERMS];
} LaneStencil;

inline void prepare_lane_stencil(__global const float* stencils, __global const char* shapes,
                                 LaneStencil* st) {
  st->shape_seen = -1;  // no shape yet
  for (int i = 0; i < STENCIL_TERMS; ++i) st->seen_x[i] = st->seen_y[i] = st->seen_z[i] = 0;
}

// D / h^2 = sum_i rho_i e_i e_i^T per lane (stencil_dual_metric), for the factorization weight,
// and the offsets' lengths for the offset weight.
inline void lane_voxel_metric(LaneStencil* st) {
  for (int n = 0; n < 6; ++n) st->d[n] = 0.0f;
#pragma unroll
  for (int i = 0; i < STENCIL_TERMS; ++i) {
    st->e_norm2[i] = st->ex[i] * st->ex[i] + st->ey[i] * st->ey[i] + st->ez[i] * st->ez[i];
    st->offset_scale[i] =
        select((lane_float)0.0f, 0.8f / st->e_norm2[i], st->e_norm2[i] > 0.0f);  // 1 / 1.25
    const lane_float x = st->rho[i] * st->ex[i], y = st->rho[i] * st->ey[i];
    const lane_float z = st->rho[i] * st->ez[i];
    st->d[0] += x * st->ex[i];
    st->d[1] += x * st->ey[i];
    st->d[2] += y * st->ey[i];
    st->d[3] += x * st->ez[i];
    st->d[4] += y * st->ez[i];
    st->d[5] += z * st->ez[i];
  }
}

// m2 with compensated_m2 (eikonal_scheme.clh) in the lanes of `lanes`, one lane at a time, and
// `m2` in the others: few visits take it (in the band, under strong anisotropy). Kept out of line:
// inlined, its arrays cost the label pass 2.6% (radial_shock_3d 128^3, six alternations).
__attribute__((noinline)) lane_float lanes_compensated_m2(const lane_float* d, const lane_float* g,
                                                          lane_mask lanes, lane_float m2) {
  int chosen[LANES];
  float values[LANES];
  vstore8(lanes, 0, chosen);
  vstore8(m2, 0, values);
  for (int k = 0; k < LANES; ++k) {
    if (!chosen[k]) continue;
    float dk[6], gk[6];
    for (int i = 0; i < 6; ++i) dk[i] = LANE_FLOAT(d, i, k), gk[i] = LANE_FLOAT(g, i, k);
    values[k] = compensated_m2(dk, gk);
  }
  return vload8(0, values);
}

// factorization_weight (eikonal_scheme.clh) per lane, g = h^2 G_s.
inline lane_float lane_factorization_weight(const lane_float* d, const lane_float* g) {
  const lane_float a00 = d[0] * g[0] + d[1] * g[1] + d[3] * g[3];
  const lane_float a01 = d[0] * g[1] + d[1] * g[2] + d[3] * g[4];
  const lane_float a02 = d[0] * g[3] + d[1] * g[4] + d[3] * g[5];
  const lane_float a10 = d[1] * g[0] + d[2] * g[1] + d[4] * g[3];
  const lane_float a11 = d[1] * g[1] + d[2] * g[2] + d[4] * g[4];
  const lane_float a12 = d[1] * g[3] + d[2] * g[4] + d[4] * g[5];
  const lane_float a20 = d[3] * g[0] + d[4] * g[1] + d[5] * g[3];
  const lane_float a21 = d[3] * g[1] + d[4] * g[2] + d[5] * g[4];
  const lane_float a22 = d[3] * g[3] + d[4] * g[4] + d[5] * g[5];
  const lane_float trace = a00 + a11 + a22;
  const lane_float trace_square =
      a00 * a00 + a11 * a11 + a22 * a22 + 2.0f * (a01 * a10 + a02 * a20 + a12 * a21);
  lane_float m2 = trace_square - 2.0f * trace + (float)DIM;
  const lane_float slack = M2_ROUNDING * FLT_EPSILON * (d[0] + d[2] + d[5]) * (g[0] + g[2] + g[5]);
  const lane_mask in_band =  // m2_needs_compensation per lane
      (slack > M2_SLACK_FOR_COMPENSATION) & (m2 > 0.04f - slack) & (m2 < 0.09f + slack);
  if (lanes_any(in_band)) m2 = lanes_compensated_m2(d, g, in_band, m2);
  return clamp((0.09f - m2) / 0.05f, 0.0f, 1.0f);
}

// offset_factorization_weight (eikonal_scheme.clh) per lane, with 1 / (1.25 |e|^2) given.
inline lane_float lane_offset_factorization_weight(lane_float p_norm2, lane_float e_norm2,
                                                   lane_float offset_scale) {
  return clamp((p_norm2 - e_norm2) * offset_scale, 0.0f, 1.0f);
}

__attribute__((always_inline)) inline lane_float lane_solve_for_label(
    lane_uint label, const LaneNeighbours* nb, const LaneStencil* st, const LaneFrame* frame,
    int3 cf, __global const float* seeds, lane_float* seed_distance) {
  lane_float g[6], gq[3];
  lane_float q_norm2;
  const lane_float u0 = lane_label_seed_distance(label, frame, cf, seeds, g, gq, &q_norm2);
  *seed_distance = u0;
  const lane_float alpha = select((lane_float)0.0f, lane_factorization_weight(st->d, g), u0 > 0.0f);
  const lane_mask factored = alpha > 0.0f;
  const lane_float inverse_u0 = select((lane_float)0.0f, 1.0f / u0, factored);
  lane_float w[STENCIL_TERMS], rho[STENCIL_TERMS];
  lane_float least_raw = INFINITY;
#pragma unroll
  for (int i = 0; i < STENCIL_TERMS; ++i) {
    const lane_float eGq = st->ex[i] * gq[0] + st->ey[i] * gq[1] + st->ez[i] * gq[2];
    const lane_float term_alpha =
        alpha * lane_offset_factorization_weight(q_norm2, st->e_norm2[i], st->offset_scale[i]);
    // A missing term (weight 0) is left out, as past the scalar stencil's term count.
    w[i] =
        select(lane_term_value(nb, i, label, u0, eGq * inverse_u0, term_alpha, term_alpha > 0.0f),
               (lane_float)INFINITY, st->rho[i] == 0.0f);
    rho[i] = st->rho[i];
    least_raw = min(least_raw, lane_term_raw(nb, i, label, rho[i]));
  }
  lane_sort(w, rho);
  return max(lane_solve_sorted(w, rho), least_raw);
}

// Neighbour j of lane k's voxel at real position `position`, the voxel `slot` at offset e beyond
// the lane's tile: its state, and its seed distance under its own label (computed, as the tile
// holds none for it).
inline void put_far_neighbour(int k, int j, long slot, int3 position, int3 e,
                              __global const ulong* state, __global const float* seeds,
                              LaneNeighbours* nb) {
  const ulong value = state[slot];
  const uint label = (uint)value & LABEL_NONE;
  LANE_FLOAT(nb->distance, j, k) = state_distance(value);
  LANE_UINT(nb->label, j, k) = label;
  if (label >= TENTATIVE_LABEL) return;
  __global const float* seed = seeds + (size_t)label * SEED_RECORD;
  const float3 y = convert_float3(position + e);
  LANE_FLOAT(nb->seed_distance, j, k) =
      seed_distance(seed, y - (float3)(seed[0], seed[1], seed[2]));
}

// Lane k's stencil at its voxel `real` and the states of its neighbours (gather_far of
// propagation.cl in the lane's frame: the tile where a neighbour lands in it, else the state).
// Returns whether one changed since `last`; only then are the stencil and the states written
// (most visits find the voxel clean).
__attribute__((always_inline)) inline bool lane_gather_one(
    int k, int real, int3 cf, int p, uint last, const LaneTile* tile, const LaneBricks* bricks,
    __global const float* seeds, __global const float* stencils, __global const char* shapes,
    __global const ulong* state, __global const uint* changed, int4 dims, int4 grid,
    __global const int* table, uint stride, LaneStencil* st, LaneNeighbours* nb) {
  float weight[STENCIL_TERMS];
  int3 offset[STENCIL_TERMS];
  const int terms = load_stencil(stencils, shapes, (size_t)bricks->brick[k] * BRICK_VOLUME + real,
                                 weight, offset);
  const int3 sign = bricks->sign[k];
  // Where each neighbour is: a frame tile index (>= 0), or -2 - its slot, or -1 for none.
  long where[2 * STENCIL_TERMS];
  bool near = true;  // every offset within one voxel: tile indices without tests (gather_near)
  for (int i = 0; i < terms; ++i) {
    const int3 e = sign * offset[i];
    near = near && (uint)(e.x + 1) <= 2u && (uint)(e.y + 1) <= 2u && (uint)(e.z + 1) <= 2u;
    where[2 * i] = p + tile_offset(e);
    where[2 * i + 1] = p - tile_offset(e);
  }
  bool dirty = last == 0;
  if (near) {
    for (int j = 0; j < 2 * terms; ++j) dirty = dirty || LANE_UINT(tile->stamp, where[j], k) > last;
  } else {
    const int3 position = bricks->origin[k] + local_coordinates(real);
    for (int j = 0; j < 2 * terms; ++j) {
      const int3 e = j & 1 ? -offset[j / 2] : offset[j / 2];
      if (inside_tile(cf + sign * e)) {  // where[j] is right
        dirty = dirty || LANE_UINT(tile->stamp, where[j], k) > last;
      } else {
        const long other =
            neighbour_slot(position + e, bricks->origin[k], dims, grid, table, bricks->near[k]);
        where[j] = other < 0 ? -1 : -2 - other;
        dirty = dirty || (other >= 0 && far_changed(changed, other, last, stride));
      }
    }
  }
  if (!dirty) return false;
  for (int i = 0; i < terms; ++i) {
    LANE_FLOAT(st->rho, i, k) = weight[i];
    LANE_FLOAT(st->ex, i, k) = (float)offset[i].x;
    LANE_FLOAT(st->ey, i, k) = (float)offset[i].y;
    LANE_FLOAT(st->ez, i, k) = (float)offset[i].z;
  }
  for (int j = 0; j < 2 * terms; ++j) {
    const long w = where[j];
    if (w >= 0) {
      LANE_FLOAT(nb->distance, j, k) = LANE_FLOAT(tile->distance, w, k);
      LANE_UINT(nb->label, j, k) = LANE_UINT(tile->word, w, k) & LABEL_NONE;
      LANE_FLOAT(nb->seed_distance, j, k) = LANE_FLOAT(tile->seed_distance, w, k);
    } else if (w < -1) {
      put_far_neighbour(k, j, -2 - w, bricks->origin[k] + local_coordinates(real),
                        j & 1 ? -offset[j / 2] : offset[j / 2], state, seeds, nb);
    }
  }
  return true;
}

#ifdef X86_GATHERS
// x86 gathers (a CPU device with AVX2: PoCL compiles for the host's features): lane k's element
// index[k] of `base`, or `fallback` where the mask is clear (nothing is read there). OpenCL C has
// no gather, and PoCL's vectorisers do not form one from LANES scalar loads.
typedef float v8sf __attribute__((vector_size(32)));
typedef int v8si __attribute__((vector_size(32)));
inline float8 gather_float8(const float* base, int8 index, lane_mask mask, float8 fallback) {
  return __builtin_astype(
      __builtin_ia32_gatherd_ps256(__builtin_astype(fallback, v8sf), base,
                                   __builtin_astype(index, v8si), __builtin_astype(mask, v8sf), 4),
      float8);
}
inline int8 gather_int8(const int* base, int8 index, lane_mask mask, int8 fallback) {
  return __builtin_astype(
      __builtin_ia32_gatherd_d256(__builtin_astype(fallback, v8si), base,
                                  __builtin_astype(index, v8si), __builtin_astype(mask, v8si), 4),
      int8);
}
// The same with a byte index (scale 1), for the shape table's chars.
inline int8 gather_bytes8(const char* base, int8 byte_index, lane_mask mask) {
  return __builtin_astype(__builtin_ia32_gatherd_d256(
                              __builtin_astype((int8)0, v8si), (const int*)base,
                              __builtin_astype(byte_index, v8si), __builtin_astype(mask, v8si), 1),
                          int8);
}
// A global buffer as a plain pointer for the gathers: on a CPU device both are the same memory.
#define AS_PLAIN(type, pointer) ((const type*)(ulong)(pointer))

// Element f of every lane's private lane array: index f * LANES + k.
inline int8 lane_elements(int8 f) {
  return f * LANES + (int8)(0, 1, 2, 3, 4, 5, 6, 7);
}

// A visit's stencils in every lane, as gathered vectors: weights, real offsets, and the flat
// tile offsets of the lane's frame.
typedef struct {
  float8 weight[STENCIL_TERMS];
  int8 delta[STENCIL_TERMS];  // flat tile offsets in each lane's frame (real offsets: st->seen_*)
  lane_mask in_tile[2 * STENCIL_TERMS];  // side j of each lane's term j / 2 lies in its tile
} LaneTerms;

// The stencils of frame voxel l in the lanes of `open` (lane_gather_one's load_stencil and frame
// offsets); returns the lanes whose stencil neighbours all lie in the tile.
inline lane_mask lane_terms(lane_mask open, int l, int3 cf, const LaneBricks* bricks,
                            __global const float* stencils, __global const char* shapes,
                            LaneStencil* st, LaneTerms* terms) {
  const int8 flip = vload8(0, bricks->flip);
#ifdef UNIFORM_METRIC
  const int8 record = 0;
#else
  const int8 record = (vload8(0, bricks->brick) * BRICK_VOLUME + ((int8)l ^ flip)) * STENCIL_RECORD;
#endif
  const int8 sign_x = select((int8)1, (int8)-1, (flip & (EDGE - 1)) != 0);
  const int8 sign_y = select((int8)1, (int8)-1, (flip & (EDGE * (EDGE - 1))) != 0);
  const int8 sign_z = select((int8)1, (int8)-1, (flip & (EDGE * EDGE * (EDGE_Z - 1))) != 0);
  const int8 shape = gather_int8(AS_PLAIN(int, stencils), record + STENCIL_TERMS, open, (int8)0);
  const lane_mask fresh = open & (shape != st->shape_seen);
  if (lanes_any(fresh)) {
    const int8 shape_byte = shape * (3 * STENCIL_TERMS);
#pragma unroll
    for (int i = 0; i < STENCIL_TERMS; ++i) {
      // The term's 3 chars, read as the int that ends with them (starts with them for term 0, so
      // that no read passes the shape's end); little-endian.
      const int8 word =
          gather_bytes8(AS_PLAIN(char, shapes), shape_byte + (i == 0 ? 0 : 3 * i - 1), fresh);
      const int8 w = i == 0 ? word << 8 : word;
      st->seen_x[i] = select(st->seen_x[i], (w << 16) >> 24, fresh);
      st->seen_y[i] = select(st->seen_y[i], (w << 8) >> 24, fresh);
      st->seen_z[i] = select(st->seen_z[i], w >> 24, fresh);
    }
    st->shape_seen = select(st->shape_seen, shape, fresh);
  }
  lane_mask inside = open;
#pragma unroll
  for (int i = 0; i < STENCIL_TERMS; ++i) {
    terms->weight[i] = gather_float8(AS_PLAIN(float, stencils), record + i, open, (float8)0.0f);
    const int8 fx = sign_x * st->seen_x[i], fy = sign_y * st->seen_y[i];
    const int8 fz = sign_z * st->seen_z[i];
    // Both neighbours in the tile (every offset within one voxel, or a longer one that stays
    // inside): then the tile holds their states, and their stamps as the scalar path reads them.
    const lane_mask ahead_inside = (cf.x + fx >= -1) & (cf.x + fx <= EDGE) & (cf.y + fy >= -1) &
                                   (cf.y + fy <= EDGE) & (cf.z + fz >= -TILE_PAD_Z) &
                                   (cf.z + fz < EDGE_Z + TILE_PAD_Z);
    const lane_mask behind_inside = (cf.x - fx >= -1) & (cf.x - fx <= EDGE) & (cf.y - fy >= -1) &
                                    (cf.y - fy <= EDGE) & (cf.z - fz >= -TILE_PAD_Z) &
                                    (cf.z - fz < EDGE_Z + TILE_PAD_Z);
    const lane_mask missing = terms->weight[i] == 0.0f;
    inside &= missing | (ahead_inside & behind_inside);
    terms->in_tile[2 * i] = ~missing & ahead_inside;
    terms->in_tile[2 * i + 1] = ~missing & behind_inside;
    terms->delta[i] = fx + TILE_EDGE * (fy + TILE_EDGE * fz);
  }
  return inside;
}

// The lanes of `open` where a stencil neighbour in the tile has a change stamp newer than `last`
// (or that never evaluated the voxel); the neighbours beyond the tile are lane_far_sides's.
inline lane_mask lane_dirty_inside(lane_mask open, int p, lane_uint last, const LaneTile* tile,
                                   const LaneTerms* terms) {
  lane_mask dirty = open & (last == 0u);
#pragma unroll
  for (int j = 0; j < 2 * STENCIL_TERMS; ++j) {
    const lane_mask side = open & terms->in_tile[j];
    const int8 at = j & 1 ? p - terms->delta[j / 2] : terms->delta[j / 2] + p;
    dirty |=
        side & (as_uint8(gather_int8((const int*)tile->stamp, lane_elements(at), side, 0)) > last);
  }
  return dirty;
}

// Writes every lane's stencil and its neighbours in the tile: gathered in the lanes of `dirty`,
// the values of "no term" and "no neighbour" elsewhere (lane_fill_far writes the others).
inline void lane_fill_inside(lane_mask dirty, int p, const LaneTile* tile, const LaneTerms* terms,
                             LaneStencil* st, LaneNeighbours* nb) {
#pragma unroll
  for (int i = 0; i < STENCIL_TERMS; ++i) {
    const lane_mask term = dirty & (terms->weight[i] != 0.0f);
    st->rho[i] = select(0.0f, terms->weight[i], term);
    st->ex[i] = select(0.0f, convert_float8(st->seen_x[i]), term);
    st->ey[i] = select(0.0f, convert_float8(st->seen_y[i]), term);
    st->ez[i] = select(0.0f, convert_float8(st->seen_z[i]), term);
    for (int side = 0; side < 2; ++side) {
      const int j = 2 * i + side;
      const lane_mask read = dirty & terms->in_tile[j];
      const int8 at = lane_elements(side ? p - terms->delta[i] : p + terms->delta[i]);
      nb->distance[j] = gather_float8((const float*)tile->distance, at, read, INFINITY);
      nb->seed_distance[j] = gather_float8((const float*)tile->seed_distance, at, read, 0.0f);
      nb->label[j] =
          as_uint8(gather_int8((const int*)tile->word, at, read, (int8)LABEL_NONE)) & LABEL_NONE;
    }
  }
}

// Lane k's real offset of term i (lane_terms decoded it).
inline int3 lane_term_offset(const LaneStencil* st, int i, int k) {
  return (int3)((int)LANE_UINT(st->seen_x, i, k), (int)LANE_UINT(st->seen_y, i, k),
                (int)LANE_UINT(st->seen_z, i, k));
}

// The stencil neighbours beyond the tiles of the lanes of `rest` (a term whose side j leaves the
// tile): their slots in `far` (-1: none), and the lanes where one changed (far_changed); lanes
// already dirty by their neighbours in the tile skip that test.
inline lane_mask lane_far_sides(lane_mask rest, lane_mask dirty_inside, int l, lane_uint last,
                                const LaneBricks* bricks, const LaneStencil* st,
                                const LaneTerms* terms, int4 dims, int4 grid,
                                __global const int* table, __global const uint* changed,
                                uint stride, long far[LANES][2 * STENCIL_TERMS]) {
  int rests[LANES], dirty[LANES];
  uint lasts[LANES];
  vstore8(rest, 0, rests);
  vstore8(last, 0, lasts);
  vstore8(dirty_inside, 0, dirty);
  for (int k = 0; k < LANES; ++k) {
    if (!rests[k]) continue;
    const int3 position = bricks->origin[k] + local_coordinates(l ^ bricks->flip[k]);
    for (int j = 0; j < 2 * STENCIL_TERMS; ++j) {
      far[k][j] = -1;
      const int i = j / 2;
      if (LANE_UINT(terms->in_tile, j, k) || LANE_FLOAT(terms->weight, i, k) == 0.0f)
        continue;  // in the tile, or no term
      const int3 e = lane_term_offset(st, i, k) * (j & 1 ? -1 : 1);
      const long other =
          neighbour_slot(position + e, bricks->origin[k], dims, grid, table, bricks->near[k]);
      far[k][j] = other;
      if (!dirty[k] && other >= 0 && far_changed(changed, other, lasts[k], stride)) dirty[k] = -1;
    }
  }
  return rest & vload8(0, dirty);
}

// The neighbours beyond the tiles (lane_far_sides's slots) in the lanes of `dirty`: their states,
// and their seed distances from the lane's voxel under their own labels.
inline void lane_fill_far(lane_mask dirty, int l, const LaneBricks* bricks, const LaneStencil* st,
                          __global const float* seeds, __global const ulong* state,
                          long far[LANES][2 * STENCIL_TERMS], LaneNeighbours* nb) {
  int dirties[LANES];
  vstore8(dirty, 0, dirties);
  for (int k = 0; k < LANES; ++k) {
    if (!dirties[k]) continue;
    const int3 position = bricks->origin[k] + local_coordinates(l ^ bricks->flip[k]);
    for (int j = 0; j < 2 * STENCIL_TERMS; ++j)
      if (far[k][j] >= 0)
        put_far_neighbour(k, j, far[k][j], position,
                          lane_term_offset(st, j / 2, k) * (j & 1 ? -1 : 1), state, seeds, nb);
  }
}
#endif

// The lanes of `open` one at a time (lane_gather_one), after the clearing of every lane's stencil
// and neighbours (devices without x86 gathers); returns those that are dirty.
inline lane_mask lane_gather_each(LANE_GATHER_ARGUMENTS) {
  int opened[LANES];
  uint lasts[LANES];
  vstore8(open, 0, opened);
  vstore8(last, 0, lasts);
  int dirty[LANES];
  for (int k = 0; k < LANES; ++k)
    dirty[k] = opened[k] && lane_gather_one(k, l ^ bricks->flip[k], cf, p, lasts[k], tile, bricks,
                                            seeds, stencils, shapes, state, changed, dims, grid,
                                            table, stride, st, nb)
                   ? -1
                   : 0;
  return open & vload8(0, dirty);
}

inline lane_mask lane_gather(LANE_GATHER_ARGUMENTS) {
#ifdef X86_GATHERS
  // The gathers' indices are 32-bit: the stencil records of the whole brick grid must fit.
  if ((long)grid.x * grid.y * grid.z * (BRICK_VOLUME * STENCIL_RECORD) <= (long)INT_MAX) {
    LaneTerms terms;
    const lane_mask inside = lane_terms(open, l, cf, bricks, stencils, shapes, st, &terms);
    const lane_mask rest = open & ~inside;
    lane_mask dirty = lane_dirty_inside(open, p, last, tile, &terms);
    long far[LANES][2 * STENCIL_TERMS];
    if (lanes_any(rest))
      dirty |= lane_far_sides(rest, dirty, l, last, bricks, st, &terms, dims, grid, table, changed,
                              stride, far);
    if (!lanes_any(dirty)) return dirty;
    lane_fill_inside(dirty, p, tile, &terms, st, nb);
    if (lanes_any(rest & dirty)) lane_fill_far(rest & dirty, l, bricks, st, seeds, state, far, nb);
    return dirty;
  }
#endif
  for (int i = 0; i < STENCIL_TERMS; ++i) {
    st->rho[i] = 0.0f;
    st->ex[i] = st->ey[i] = st->ez[i] = 0.0f;
    nb->distance[2 * i] = nb->distance[2 * i + 1] = INFINITY;
    nb->label[2 * i] = nb->label[2 * i + 1] = LABEL_NONE;
    nb->seed_distance[2 * i] = nb->seed_distance[2 * i + 1] = 0.0f;
  }
  return lane_gather_each(open, l, cf, p, last, tile, bricks, seeds, stencils, shapes, state,
                          changed, dims, grid, table, stride, st, nb);
}
#endif

// Inlined in the axis form only (callgrind, 64^3 kernels: euclidean 684M -> 664M instructions
// inlined, radial_shock_3d 2996M -> 3046M).
#ifdef AXIS_LANES
#define BEST_CANDIDATE_INLINE __attribute__((always_inline))
#else
#define BEST_CANDIDATE_INLINE
#endif

// best_candidate (eikonal_scheme.clh) in the lanes of `lanes`: the smallest (distance, label) over
// the distinct labels of the neighbours; +inf and LABEL_NONE without a labelled neighbour.
BEST_CANDIDATE_INLINE inline void lane_best_candidate(lane_mask lanes, const LaneNeighbours* nb,
                                                      LaneStencil* st, const LaneFrame* frame,
                                                      int3 cf, __global const float* seeds,
                                                      lane_float* best_distance,
                                                      lane_uint* best_label,
                                                      lane_float* best_seed_distance) {
  const int neighbours = 2 * LANE_TERMS;
  *best_distance = INFINITY;
  *best_label = LABEL_NONE;
  *best_seed_distance = 0.0f;
  lane_voxel_metric(st);
  // The distinct labels in ascending order: each pass takes the least label above the last one.
  lane_uint above = 0u;  // labels >= above are still to do
  for (int pass = 0; pass < neighbours; ++pass) {
    lane_uint label = LABEL_NONE;
#pragma unroll
    for (int j = 0; j < neighbours; ++j)
      label = min(label, select((lane_uint)LABEL_NONE, nb->label[j], nb->label[j] >= above));
    const lane_mask valid = lanes & (label < TENTATIVE_LABEL);  // ascending: the rest are not
    if (!lanes_any(valid)) break;
    const lane_uint solved = select((lane_uint)NO_LANE_LABEL, label, valid);
    lane_float u0;
    const lane_float t = lane_solve_for_label(solved, nb, st, frame, cf, seeds, &u0);
    const lane_mask better =
        valid & ~isinf(t) &
        ((t < *best_distance) | ((t == *best_distance) & (label < *best_label)));
    *best_distance = select(*best_distance, t, better);
    *best_label = select(*best_label, label, better);
    *best_seed_distance = select(*best_seed_distance, u0, better);
    above = label + 1u;
  }
}

// The seed distance of every tile voxel under its own label (LaneTile), once the lanes are loaded.
inline void lane_tile_seed_distances(LaneTile* tile, const LaneFrame* frame,
                                     __global const float* seeds) {
  int p = 0;
  for (int tz = 0; tz < TILE_EDGE_Z; ++tz)
    for (int ty = 0; ty < TILE_EDGE; ++ty)
      for (int tx = 0; tx < TILE_EDGE; ++tx, ++p) {
        const lane_uint label = tile->word[p] & LABEL_NONE;
        const lane_mask labelled = label < TENTATIVE_LABEL;
        if (!lanes_any(labelled)) {
          tile->seed_distance[p] = 0.0f;
          continue;
        }
        const lane_uint seed = select((lane_uint)NO_LANE_LABEL, label, labelled);
        lane_float g[6], gq[3], q_norm2;
        const int3 cf = (int3)(tx - 1, ty - 1, tz - TILE_PAD_Z);
        tile->seed_distance[p] =
            select((lane_float)0.0f,
                   lane_label_seed_distance(seed, frame, cf, seeds, g, gq, &q_norm2), labelled);
      }
}

// significant_change (eikonal_scheme.clh) per lane.
inline lane_mask lane_significant_change(lane_float u, lane_uint u_label, lane_float t,
                                         lane_uint t_label) {
  const lane_mask u_inf = isinf(u), t_inf = isinf(t);
  const lane_mask moved = fabs(u - t) > RELATIVE_TOLERANCE * max(u, t);
  return (u_label != t_label) | select(moved, u_inf ^ t_inf, u_inf | t_inf);
}

// rounding_rise (eikonal_scheme.clh) per lane.
inline lane_mask lane_rounding_rise(lane_float u, lane_uint u_label, lane_float t,
                                    lane_uint t_label, lane_float tolerance) {
  return (u_label == t_label) & (t > u) & ~isinf(t) & (t - u <= tolerance * t);
}

// lane_significant_change between the states as readers see them: a tentative state (and an
// unreached one) reads as +inf without a label.
inline lane_mask lane_visible_change(lane_float u, lane_uint u_label, lane_float t,
                                     lane_uint t_label) {
  const lane_mask u_hidden = u_label >= TENTATIVE_LABEL, t_hidden = t_label >= TENTATIVE_LABEL;
  return lane_significant_change(
      select(u, (lane_float)INFINITY, u_hidden), select(u_label, (lane_uint)LABEL_NONE, u_hidden),
      select(t, (lane_float)INFINITY, t_hidden), select(t_label, (lane_uint)LABEL_NONE, t_hidden));
}

// rounding_tolerance (eikonal_scheme.clh) of each lane's stencil at the visit just solved.
#ifdef AXIS_LANES
inline lane_float lane_rounding_tolerance(const LaneStencil* st) {
  return st->tolerance;  // one stencil: computed once (prepare_lane_stencil)
}
#else
inline lane_float lane_rounding_tolerance(const LaneStencil* st) {
  lane_float least = INFINITY, most = 0.0f;
#pragma unroll
  for (int i = 0; i < STENCIL_TERMS; ++i) {
    least = min(least, select((lane_float)INFINITY, st->rho[i], st->rho[i] > 0.0f));
    most = max(most, st->rho[i]);
  }
  return select((lane_float)RELATIVE_TOLERANCE,
                clamp(0.5f * FLT_EPSILON * sqrt(most / least), (lane_float)RELATIVE_TOLERANCE,
                      (lane_float)MOST_ROUNDING_TOLERANCE),
                most > 0.0f);
}
#endif

// The smallest distance in `runs` runs of `length` consecutive slots of brick `brick` (+inf
// without one), the runs `stride` slots apart from slot `first`: a layer of the brick across an
// axis.
inline float layer_minimum(__global const ulong* state, int brick, int first, int length, int runs,
                           int stride) {
  if (brick < 0) return INFINITY;
  __global const ulong* slots = state + (size_t)brick * BRICK_VOLUME;
  float least = INFINITY;
  for (int r = 0; r < runs; ++r)
    for (int i = 0; i < length; ++i)
      least = min(least, state_distance(slots[first + stride * r + i]));
  return least;
}

// upwind_corner_of_layers (propagation.cl) from the state instead of a tile: per axis, whether
// the two layers at its high side (its last, the next brick's first) hold a smaller distance than
// the two at its low side.
inline int upwind_corner_of_faces(const int* near, __global const ulong* state) {
  const int centre = 13, below[3] = {12, 10, 4}, above[3] = {14, 16, 22};  // in near
  // A layer across axis a at local coordinate c: its first slot, run length, runs and stride.
  const int length[3] = {1, EDGE, EDGE * EDGE};
  const int runs[3] = {EDGE * EDGE_Z, EDGE_Z, 1};
  const int stride[3] = {EDGE, EDGE * EDGE, 0};
  const int step[3] = {1, EDGE, EDGE * EDGE};  // slots between layers
  const int last[3] = {EDGE - 1, EDGE - 1, EDGE_Z - 1};
  int corner = 0;
  for (int a = 0; a < DIM; ++a) {
    const float low =
        min(layer_minimum(state, near[below[a]], step[a] * last[a], length[a], runs[a], stride[a]),
            layer_minimum(state, near[centre], 0, length[a], runs[a], stride[a]));
    const float high =
        min(layer_minimum(state, near[centre], step[a] * last[a], length[a], runs[a], stride[a]),
            layer_minimum(state, near[above[a]], 0, length[a], runs[a], stride[a]));
    if (high < low) corner |= 1 << a;
  }
  return corner;
}

// upwind_corner (propagation.cl) of a brick, from the state instead of a tile.
inline int upwind_corner_of(const int* near, __global const ulong* state) {
  __global const ulong* brick = state + (size_t)near[13] * BRICK_VOLUME;  // near[13]: the brick
  float u[8];
  for (int c = 0; c < 8; ++c) u[c] = state_distance(brick[brick_corner_index(c)]);
  return corners_reached(u) ? upwind_corner_of_corners(u) : upwind_corner_of_faces(near, state);
}

// Tile slot `real` of lane k's brick, stored at frame index f: distance, low word, change stamp.
inline void put_lane_slot(int k, int f, ulong s, uint stamp, LaneTile* tile) {
  LANE_FLOAT(tile->distance, f, k) = state_distance(s);
  LANE_UINT(tile->word, f, k) = (uint)s;
  LANE_UINT(tile->stamp, f, k) = stamp;
}

// `length` consecutive slots of brick `brick` (-1: none) from `within`, to lane k's frame tile
// from f on in steps of `step`; `inside`: the brick being relaxed (its own change stamps).
inline void load_lane_run(int k, int f, int step, int brick, int within, int length, bool inside,
                          __global const ulong* state, __global const uint* changed, uint stride,
                          LaneTile* tile) {
  if (brick < 0) {
    for (int i = 0; i < length; ++i) put_lane_slot(k, f + step * i, INF_STATE, 0u, tile);
    return;
  }
  const size_t slot = (size_t)brick * BRICK_VOLUME + within;
  for (int i = 0; i < length; ++i) {
    const uint stamp = inside ? changed[slot + i] : outside_stamp(changed[slot + i], stride);
    put_lane_slot(k, f + step * i, state[slot + i], stamp, tile);
  }
}

// A row of EDGE slots of brick `brick` (-1: none) from `within` (load_lane_run): one vector load
// of the states and of the stamps, then the lane's stores.
// In the brick's own rows, tentative states at or below the threshold are released: their label
// becomes visible and they count as changed at the round's base stamp. Returns the released
// slots of the row (bit i: slot within + i).
__attribute__((always_inline)) inline uint load_lane_row(
    int k, int f, int step, int brick, int within, bool inside, __global const ulong* state,
    __global const uint* changed, uint stride, float threshold, uint round_base, LaneTile* tile) {
  if (brick < 0) {
    load_lane_run(k, f, step, brick, within, EDGE, inside, state, changed, stride, tile);
    return 0u;
  }
  const size_t slot = (size_t)brick * BRICK_VOLUME + within;
  // Two halves of ulong4: a ulong8 is passed to PoCL's builtins in a 512-bit register, and a CPU
  // without AVX-512 warns that this changes the ABI.
  const ulong4 first_half = vload4(0, state + slot), second_half = vload4(1, state + slot);
  const uint8 low = (uint8)(convert_uint4(first_half), convert_uint4(second_half));
  const uint8 c = vload8(0, changed + slot);
  const float8 distance =
      as_float8((uint8)(convert_uint4(first_half >> 32), convert_uint4(second_half >> 32)));
  const uint8 label = low & LABEL_NONE;
  const int8 released =
      FRONT_STEPPING && inside ? TENTATIVE(label) & (distance <= threshold) : (int8)0;
  const uint8 stamp = select(inside ? c : OUTSIDE_STAMP(c, stride), (uint8)round_base, released);
  const uint8 word = select(low, low & ~TENTATIVE_LABEL, released);
  float d[EDGE];
  uint w[EDGE], t[EDGE];
  vstore8(distance, 0, d);
  vstore8(word, 0, w);
  vstore8(stamp, 0, t);
  for (int i = 0; i < EDGE; ++i) {
    LANE_FLOAT(tile->distance, f + step * i, k) = d[i];
    LANE_UINT(tile->word, f + step * i, k) = w[i];
    LANE_UINT(tile->stamp, f + step * i, k) = t[i];
  }
  const uint8 bits = select((uint8)0u, (uint8)(1u, 2u, 4u, 8u, 16u, 32u, 64u, 128u), released);
  const uint4 pairs = bits.lo | bits.hi;
  const uint2 quads = pairs.lo | pairs.hi;
  return quads.x | quads.y;
}

// Whether a visit reads the tile's edges and corners (the voxels outside the brick that are not
// next to one of its faces): axis offsets reach the faces only, so those are not loaded (at 256^3,
// about a quarter of the cache lines a tile load touches).
#ifdef AXIS_LANES
#define TILE_EDGES_READ false
#else
#define TILE_EDGES_READ true
#endif

// Loads lane k's brick into its frame tile (load_tile of propagation.cl, row by row, straight
// into the flipped positions) with its evaluation stamps; returns its corner. The tile words are
// the low state halves (frozen bit, label), with the frozen bit also set on inactive brick voxels
// so the sweep skips them.
inline int load_lane(int k, int brick, __global const ulong* state, __global const uint* changed,
                     __global const int* table, __global const int4* brick_origins, int4 grid,
                     uint stride, __global const uint* activity, __global const uint* evaluated,
                     __global const float* stencils, float threshold, uint round_base,
                     LaneTile* tile, LaneFrame* frame, LaneBricks* bricks, int3* released_lo,
                     int3* released_hi) {
  const int3 origin = brick_origins[brick].xyz;
  *released_lo = (int3)(EDGE, EDGE, EDGE);
  *released_hi = (int3)(-1, -1, -1);
  int* near = bricks->near[k];
  load_near_bricks(origin, grid, table, near);
  const int corner = upwind_corner_of(near, state);
  const int fx = corner & 1, fy = (corner >> 1) & 1, fz = (corner >> 2) & 1;
  const int flip = corner_flip(corner);
  const size_t brick_slot = (size_t)brick * BRICK_VOLUME;
  for (int tz = 0; tz < TILE_EDGE_Z; ++tz) {
    const int z = tz - TILE_PAD_Z;
    const int bz = DIM == 3 ? (z < 0 ? 0 : z < EDGE_Z ? 1 : 2) : 1;
    for (int ty = 0; ty < TILE_EDGE; ++ty) {
      const int y = ty - 1;
      const int by = y < 0 ? 0 : y < EDGE ? 1 : 2;
      const int row = EDGE * ((y & (EDGE - 1)) + EDGE * (DIM == 3 ? z & (EDGE - 1) : 0));
      const int* bricks = near + 3 * (by + 3 * bz);  // the bricks at x - 1, x, x + 1
      const int f_row = TILE_EDGE * (mirrored(ty, fy, TILE_EDGE - 1) +
                                     TILE_EDGE * mirrored(tz, fz, TILE_EDGE_Z - 1));
      const int f_first = f_row + mirrored(0, fx, TILE_EDGE - 1), step = fx ? -1 : 1;
      const bool inner = brick_row(by, bz);        // its ends are x faces
      const bool read = TILE_EDGES_READ || inner;  // else tile edges: +inf, never read
      const bool face = TILE_EDGES_READ || face_row(by, bz);
      load_lane_run(k, f_first, step, read ? bricks[0] : -1, row + EDGE - 1, 1, false, state,
                    changed, stride, tile);
      const uint released =
          load_lane_row(k, f_first + step, step, face ? bricks[1] : -1, row, inner, state, changed,
                        stride, threshold, round_base, tile);
      if (FRONT_STEPPING && released) {  // the box of released voxels, in frame coordinates
        const int first = mirrored(ctz(released), fx, EDGE - 1);
        const int last = mirrored(31 - clz(released), fx, EDGE - 1);
        const int3 lo = (int3)(min(first, last), mirrored(y, fy, EDGE - 1),
                               DIM == 3 ? mirrored(z, fz, EDGE_Z - 1) : 0);
        const int3 hi = (int3)(max(first, last), lo.y, lo.z);
        *released_lo = min(*released_lo, lo);
        *released_hi = max(*released_hi, hi);
      }
      load_lane_run(k, f_first + step * (EDGE + 1), step, read ? bricks[2] : -1, row, 1, false,
                    state, changed, stride, tile);
    }
  }
#ifndef AXIS_LANES
  // The sweeps read each voxel's stencil record, one lane at a time (lane_gather_one): a cache
  // miss at each first visit once the canvas outgrows the cache (perf: the record load was the
  // hottest instruction of radial_shock_3d's gather at 128^3). Requested for the whole brick now,
  // the records arrive while the tile loads (docs/scheme.md, "Stencil prefetch").
  __global const float* records = stencils + brick_slot * STENCIL_RECORD;
  for (int i = 0; i < BRICK_VOLUME * STENCIL_RECORD; i += 64 / sizeof(float))
    PREFETCH_GLOBAL(records + i);
#endif
  // Inactive voxels are skipped like frozen ones; the evaluation stamps go to frame positions.
  for (int w = 0; w < BRICK_VOLUME / 32; ++w) {
    const uint bits = activity[brick_slot / 32 + w];
    for (int b = 0; b < 32; ++b) {
      const int real = 32 * w + b;
      const int l = real ^ flip;
      const bool active = (bits >> b) & 1u;
      if (!active) LANE_UINT(tile->word, tile_index(local_coordinates(l)), k) |= (uint)FROZEN_BIT;
      LANE_UINT(tile->evaluated, l, k) = active ? evaluated[brick_slot + real] : 0u;
    }
  }
  const float3 o = convert_float3(origin);
  LANE_FLOAT(&frame->base_x, 0, k) = o.x + mirrored(0, fx, EDGE - 1);
  LANE_FLOAT(&frame->base_y, 0, k) = o.y + mirrored(0, fy, EDGE - 1);
  LANE_FLOAT(&frame->base_z, 0, k) = o.z + mirrored(0, fz, EDGE_Z - 1);
  LANE_FLOAT(&frame->sign_x, 0, k) = fx ? -1.0f : 1.0f;
  LANE_FLOAT(&frame->sign_y, 0, k) = fy ? -1.0f : 1.0f;
  LANE_FLOAT(&frame->sign_z, 0, k) = fz ? -1.0f : 1.0f;
  bricks->brick[k] = brick;
  bricks->flip[k] = flip;
  bricks->origin[k] = origin;
  bricks->sign[k] = (int3)(fx ? -1 : 1, fy ? -1 : 1, fz ? -1 : 1);
  return corner;
}

// An empty lane: no brick, nothing to relax (its tile is never read, but holds +inf).
inline void clear_lane(int k, LaneTile* tile, LaneFrame* frame, LaneBricks* bricks) {
  bricks->brick[k] = -1;
  bricks->flip[k] = 0;
  bricks->origin[k] = bricks->sign[k] = (int3)(0, 0, 0);
  for (int f = 0; f < TILE_VOLUME; ++f) put_lane_slot(k, f, INF_STATE | FROZEN_BIT, 0u, tile);
  for (int l = 0; l < BRICK_VOLUME; ++l) LANE_UINT(tile->evaluated, l, k) = 0u;
  LANE_FLOAT(&frame->base_x, 0, k) = LANE_FLOAT(&frame->base_y, 0, k) =
      LANE_FLOAT(&frame->base_z, 0, k) = 0.0f;
  LANE_FLOAT(&frame->sign_x, 0, k) = LANE_FLOAT(&frame->sign_y, 0, k) =
      LANE_FLOAT(&frame->sign_z, 0, k) = 1.0f;
}

// Writes lane k's results: the relaxed brick to scratch (when anything was written), its
// evaluation stamps and, when a value changed significantly, its change stamps to scratch_stamps
// (commit_bricks publishes them). Returns the least tentative distance of the brick (+inf without
// one).
inline float store_lane(int k, int brick, int position, int corner, uint brick_flags,
                        const LaneTile* tile, __global ulong* scratch,
                        __global uint* scratch_stamps, __global uint* evaluated,
                        __global const uint* activity) {
  float least_tentative = INFINITY;
  const int fx = corner & 1, fy = (corner >> 1) & 1, fz = (corner >> 2) & 1;
  const size_t brick_slot = (size_t)brick * BRICK_VOLUME;
  __global ulong* relaxed = scratch + (size_t)position * BRICK_VOLUME;
  __global uint* stamps = scratch_stamps + (size_t)position * BRICK_VOLUME;
  for (int z = 0; z < EDGE_Z; ++z)
    for (int y = 0; y < EDGE; ++y) {  // a row in real order, its frame positions l and p
      const int row = EDGE * (y + EDGE * z);
      const uint active = (activity[(brick_slot + row) / 32] >> (row % 32)) & 0xFFu;
      const int3 f = (int3)(0, mirrored(y, fy, EDGE - 1), mirrored(z, fz, EDGE_Z - 1));
      const int l_row = EDGE * (f.y + EDGE * f.z), p_row = tile_index(f);
      if (active == 0xFFu) {  // the usual case: whole rows as vectors
        uint distance[EDGE], word[EDGE], stamp[EDGE], evaluation[EDGE];
        for (int x = 0; x < EDGE; ++x) {
          const int fxx = mirrored(x, fx, EDGE - 1);
          distance[x] = as_uint(LANE_FLOAT(tile->distance, p_row + fxx, k));
          word[x] = LANE_UINT(tile->word, p_row + fxx, k);
          if (FRONT_STEPPING && TENTATIVE(word[x] & LABEL_NONE))
            least_tentative = min(least_tentative, as_float(distance[x]));
          stamp[x] = LANE_UINT(tile->stamp, p_row + fxx, k);
          evaluation[x] = LANE_UINT(tile->evaluated, l_row + fxx, k);
        }
        if (brick_flags != 0) {  // as ulong4 halves, as in load_lane_row
          const uint8 d = vload8(0, distance), w = vload8(0, word);
          vstore4((convert_ulong4(d.lo) << 32) | convert_ulong4(w.lo), 0, relaxed + row);
          vstore4((convert_ulong4(d.hi) << 32) | convert_ulong4(w.hi), 1, relaxed + row);
        }
        vstore8(vload8(0, evaluation), 0, evaluated + brick_slot + row);
        if (brick_flags & FLAG_CHANGED) vstore8(vload8(0, stamp), 0, stamps + row);
        continue;
      }
      for (int x = 0; x < EDGE; ++x) {
        const int real = row + x, fxx = mirrored(x, fx, EDGE - 1);
        const int l = l_row + fxx, p = p_row + fxx;
        if (!((active >> x) & 1u)) {
          if (brick_flags != 0) relaxed[real] = INF_STATE;
          if (brick_flags & FLAG_CHANGED) stamps[real] = 0u;
          continue;
        }
        if (FRONT_STEPPING && TENTATIVE(LANE_UINT(tile->word, p, k) & LABEL_NONE))
          least_tentative = min(least_tentative, LANE_FLOAT(tile->distance, p, k));
        if (brick_flags != 0)
          relaxed[real] = ((ulong)as_uint(LANE_FLOAT(tile->distance, p, k)) << 32) |
                          (ulong)LANE_UINT(tile->word, p, k);
        evaluated[brick_slot + real] = LANE_UINT(tile->evaluated, l, k);
        if (brick_flags & FLAG_CHANGED) stamps[real] = LANE_UINT(tile->stamp, p, k);
      }
    }
  return least_tentative;
}

// brick_news (brick_layout.clh) of lane k from its box of changes in frame coordinates.
inline uint lane_news(int k, int corner, int lo[3][LANES], int hi[3][LANES], uint packed_reach) {
  const int last[3] = {EDGE - 1, EDGE - 1, EDGE_Z - 1};
  int real_lo[3], real_hi[3];
  for (int a = 0; a < 3; ++a) {
    const bool reversed = (corner >> a) & 1;  // a reversed axis swaps the box's ends
    real_lo[a] = mirrored(reversed ? hi[a][k] : lo[a][k], reversed, last[a]);
    real_hi[a] = mirrored(reversed ? lo[a][k] : hi[a][k], reversed, last[a]);
  }
  return brick_news((int3)(real_lo[0], real_lo[1], real_lo[2]),
                    (int3)(real_hi[0], real_hi[1], real_hi[2]), packed_reach);
}

// The stencil records of frame voxel l in every lane, requested one visit ahead, so that the
// record gathers of the next visit find them in L1 rather than L2, where load_lane's prefetch put
// them (docs/scheme.md, "Gathers in the general form"). Axis lanes and uniform metrics have one
// record for the canvas.
inline void prefetch_lane_records(int l, const LaneBricks* bricks, __global const float* stencils) {
#if !defined(AXIS_LANES) && !defined(UNIFORM_METRIC)
  for (int k = 0; k < LANES; ++k)
    PREFETCH_GLOBAL(stencils +
                    ((size_t)max(bricks->brick[k], 0) * BRICK_VOLUME + (l ^ bricks->flip[k])) *
                        STENCIL_RECORD);
#endif
}

__kernel void relax_brick_lanes(BRICK_SWEEP_ARGUMENTS) {
  const int first = get_global_id(0) * LANES;
  if (first >= count) return;
  LaneTile lane_tile;
  LaneTile* tile = &lane_tile;
  LaneFrame frame;
  LaneBricks bricks;
  int corner[LANES] = {0}, brick[LANES];
  uint live[LANES];
  int released_lo[3][LANES], released_hi[3][LANES];
  for (int k = 0; k < LANES; ++k) {
    brick[k] = first + k < count ? list[first + k] : -1;
    live[k] = brick[k] >= 0 ? 0xFFFFFFFFu : 0u;
    int3 lo = (int3)(EDGE, EDGE, EDGE), hi = (int3)(-1, -1, -1);
    if (brick[k] < 0)
      clear_lane(k, tile, &frame, &bricks);
    else
      corner[k] =
          load_lane(k, brick[k], state, changed, table, brick_origins, grid, stride, activity,
                    evaluated, stencils, threshold, round_base, tile, &frame, &bricks, &lo, &hi);
    released_lo[0][k] = lo.x, released_lo[1][k] = lo.y, released_lo[2][k] = lo.z;
    released_hi[0][k] = hi.x, released_hi[1][k] = hi.y, released_hi[2][k] = hi.z;
  }
  LaneStencil st;
  prepare_lane_stencil(stencils, shapes, &st);
  lane_tile_seed_distances(tile, &frame, seeds);
  lane_mask running = as_int8(vload8(0, live));
  lane_uint brick_flags = select((lane_uint)0u, (lane_uint)FLAG_UNCONVERGED, running);
  lane_uint lane_updates = 0;
  // The box of each lane's significant changes, in frame coordinates (empty: lo > hi), starting
  // from the tentative states its load released.
  int8 changed_lo_x = vload8(0, released_lo[0]), changed_lo_y = vload8(0, released_lo[1]);
  int8 changed_lo_z = vload8(0, released_lo[2]);
  int8 changed_hi_x = vload8(0, released_hi[0]), changed_hi_y = vload8(0, released_hi[1]);
  int8 changed_hi_z = vload8(0, released_hi[2]);
  brick_flags |=
      select((lane_uint)0u, (lane_uint)(FLAG_WRITTEN | FLAG_CHANGED), changed_lo_x <= changed_hi_x);
  uint tick = 0;
  for (int sweep = 0; sweep < max_sweeps && lanes_any(running); ++sweep) {
    const int flip = corner_flip(sweep_reversal(sweep));
    lane_mask sweep_changed = 0;
    for (int n = 0; n < BRICK_VOLUME; ++n) {
      ++tick;
      const int l = n ^ flip;
      if (n + 1 < BRICK_VOLUME) prefetch_lane_records((n + 1) ^ flip, &bricks, stencils);
      const int3 c = local_coordinates(l);
      const int p = tile_index(c);
      const lane_uint word = tile->word[p];
      const lane_mask open = running & ((word & (uint)FROZEN_BIT) == 0u);
      if (!lanes_any(open)) continue;
      const lane_uint last = tile->evaluated[l];
      LaneNeighbours nb;
      const lane_mask lanes =
          lane_gather(open, l, c, p, last, tile, &bricks, seeds, stencils, shapes, state, changed,
                      dims, grid, table, stride, &st, &nb);
      if (!lanes_any(lanes)) continue;
      const uint stamp = round_base + tick;
      tile->evaluated[l] = select(last, (lane_uint)stamp, lanes);
      lane_float best, best_seed_distance;
      lane_uint best_label;
      lane_best_candidate(lanes, &nb, &st, &frame, c, seeds, &best, &best_label,
                          &best_seed_distance);
      lane_updates -= as_uint8(lanes);
      // Above the threshold, the value is kept tentative (state_word.clh).
      if (FRONT_STEPPING)
        best_label |=
            select((lane_uint)0u, (lane_uint)TENTATIVE_LABEL, (best > threshold) & ~isinf(best));
      const lane_float current = tile->distance[p];
      const lane_uint current_label = word & LABEL_NONE;
      const lane_mask differs =
          lanes & ((as_uint8(best) != as_uint8(current)) | (best_label != current_label));
      if (!lanes_any(differs)) continue;
      const lane_mask silent = lane_rounding_rise(current, current_label, best, best_label,
                                                  lane_rounding_tolerance(&st));
      tile->distance[p] = select(current, best, differs);
      tile->word[p] = select(word, best_label, differs);
      tile->seed_distance[p] = select(tile->seed_distance[p], best_seed_distance, differs);
      brick_flags |= select((lane_uint)0u, (lane_uint)FLAG_WRITTEN, differs);
      const lane_mask significant =
          differs & ~silent &
          (FRONT_STEPPING ? lane_visible_change(current, current_label, best, best_label)
                          : lane_significant_change(current, current_label, best, best_label));
      tile->stamp[p] = select(tile->stamp[p], (lane_uint)stamp, significant);
      sweep_changed |= significant;
      changed_lo_x = min(changed_lo_x, select((int8)EDGE, (int8)c.x, significant));
      changed_lo_y = min(changed_lo_y, select((int8)EDGE, (int8)c.y, significant));
      changed_lo_z = min(changed_lo_z, select((int8)EDGE, (int8)c.z, significant));
      changed_hi_x = max(changed_hi_x, select((int8)-1, (int8)c.x, significant));
      changed_hi_y = max(changed_hi_y, select((int8)-1, (int8)c.y, significant));
      changed_hi_z = max(changed_hi_z, select((int8)-1, (int8)c.z, significant));
    }
    brick_flags |= select((lane_uint)0u, (lane_uint)FLAG_CHANGED, running & sweep_changed);
    brick_flags &=
        select((lane_uint)0xFFFFFFFFu, (lane_uint)~FLAG_UNCONVERGED, running & ~sweep_changed);
    running &= sweep_changed;
  }
  uint lane_flags[LANES];
  vstore8(brick_flags, 0, lane_flags);
  int lo[3][LANES], hi[3][LANES];
  vstore8(changed_lo_x, 0, lo[0]);
  vstore8(changed_lo_y, 0, lo[1]);
  vstore8(changed_lo_z, 0, lo[2]);
  vstore8(changed_hi_x, 0, hi[0]);
  vstore8(changed_hi_y, 0, hi[1]);
  vstore8(changed_hi_z, 0, hi[2]);
  for (int k = 0; k < LANES; ++k) {
    if (brick[k] < 0) continue;
    const float least = store_lane(k, brick[k], first + k, corner[k], lane_flags[k], tile, scratch,
                                   scratch_stamps, evaluated, activity);
    if (FRONT_STEPPING) least_tentative[brick[k]] = least;
    flags[brick[k]] = (uchar)lane_flags[k];
    news[brick[k]] = lane_news(k, corner[k], lo, hi, reader_reach[brick[k]]);
  }
  const uint4 pairs = lane_updates.lo + lane_updates.hi;
  atom_add(update_counter, (ulong)(pairs.x + pairs.y + pairs.z + pairs.w));
}
