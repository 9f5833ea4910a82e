#include "rvor/selling.h"

#include <cmath>
#include <sstream>
#include <string>

#include <Eigen/Geometry>

#include "rvor/error.h"

namespace rvor {

namespace {

// Selling's algorithm needs a few dozen flips for anisotropy 100 (measured: tests/solver); the cap
// only triggers on input that slipped past the SPD check (e.g. numerically semi-definite).
constexpr int kMaxSellingIterations = 10000;

// A pair of superbase vectors is "acute" (must be flipped) when <b_i, D b_j> exceeds this fraction
// of |b_i|_D |b_j|_D. A tiny positive threshold instead of 0 keeps rounding noise from flipping
// back and forth; the neglected term is then far below the 1e-12 reconstruction accuracy.
constexpr double kAcuteTolerance = 1e-14;

// Superbase vectors hold small integers; doubles represent them exactly and keep the dot
// products with D simple.
using Superbase3 = std::array<Vec3, 4>;
using Superbase2 = std::array<Vec3, 3>;

std::string describe(const Mat3& D, int dimension) {
  std::ostringstream out;
  out.precision(17);
  out << "[";
  for (int r = 0; r < dimension; ++r)
    for (int c = 0; c < dimension; ++c) out << (r || c ? " " : "") << D(r, c);
  out << "]";
  return out.str();
}

// The dimension x dimension block of D, symmetrised; throws unless it is finite and SPD.
Mat3 checked_dual_metric(const Mat3& D, int dimension) {
  if (dimension != 2 && dimension != 3)
    throw Error("selling_decomposition: dimension must be 2 or 3, not " +
                std::to_string(dimension));
  Mat3 S = Mat3::Identity();
  S.topLeftCorner(dimension, dimension) = D.topLeftCorner(dimension, dimension);
  S = 0.5 * (S + S.transpose()).eval();
  const bool finite = D.topLeftCorner(dimension, dimension).allFinite();
  const bool positive = finite && has_positive_pivots(S);
  if (!positive)
    throw Error("selling_decomposition: matrix " + describe(D, dimension) +
                " is not symmetric positive definite");
  return S;
}

// Whether the pair (a, b) is acute, given Da = D a and Db = D b.
bool is_acute(const Vec3& a, const Vec3& Da, const Vec3& b, const Vec3& Db) {
  const double scalar = a.dot(Db);
  if (!(scalar > 0)) return false;  // most pairs; the square root below is not needed for them
  return scalar > kAcuteTolerance * std::sqrt(a.dot(Da) * b.dot(Db));
}

// rho = -<a, D b> in extended precision: superbase vectors grow with the anisotropy, and the
// cancellation in this sum is what limits the accuracy of the reconstruction sum rho e e^T. D is
// symmetric and a, b hold small integers, so the sum is over the 6 entries of D with the exact
// integer coefficients a_r b_c + a_c b_r (off the diagonal): 6 extended products instead of 18.
double weight_of_pair(const Vec3& a, const Vec3& b, const Mat3& D) {
  long double sum = 0;
  for (int r = 0; r < 3; ++r) {
    sum += static_cast<long double>(a[r] * b[r]) * static_cast<long double>(D(r, r));
    for (int c = r + 1; c < 3; ++c)
      sum += static_cast<long double>(a[r] * b[c] + a[c] * b[r]) *
             static_cast<long double>(D(r, c));  // D is symmetric (checked_dual_metric)
  }
  return static_cast<double>(-sum);
}

std::array<int, 3> to_canonical_offset(const Vec3& e) {
  std::array<int, 3> offset{};
  // e is a cross product of integer vectors held in doubles: an exact integer, so the cast is too
  // (std::lround took a fifth of a decomposition).
  for (int a = 0; a < 3; ++a) offset[a] = static_cast<int>(e[a]);
  // e and -e are the same stencil direction: keep the one whose first non-zero component is > 0.
  const int first = offset[0] != 0 ? offset[0] : (offset[1] != 0 ? offset[1] : offset[2]);
  if (first < 0)
    for (int& c : offset) c = -c;
  return offset;
}

void add_term(SellingStencil& stencil, double rho, const Vec3& e) {
  if (!(rho > 0)) return;  // rho == 0 (or rounding noise below 0): the term does not exist
  stencil.weight[stencil.size] = rho;
  stencil.offset[stencil.size] = to_canonical_offset(e);
  ++stencil.size;
}

[[noreturn]] void throw_not_terminating(const Mat3& D, int dimension) {
  throw Error("selling_decomposition: Selling's algorithm did not terminate for " +
              describe(D, dimension) + " (not positive definite?)");
}

// 3D: flip (b_i, b_j, b_k, b_l) -> (-b_i, b_j, b_k + b_i, b_l + b_i) while some pair is acute.
// D b of each superbase vector is kept alongside it and recomputed only for the vectors a flip
// changes (negating b negates D b exactly), so a pair test costs dot products, not matrix
// products, and decides exactly as with D b computed afresh.
Superbase3 obtuse_superbase_3d(const Mat3& D) {
  Superbase3 b = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(-1, -1, -1)};
  Superbase3 Db;
  for (int k = 0; k < 4; ++k) Db[k] = D * b[k];
  for (int iteration = 0; iteration < kMaxSellingIterations; ++iteration) {
    bool flipped = false;
    for (int i = 0; i < 4 && !flipped; ++i)
      for (int j = i + 1; j < 4 && !flipped; ++j) {
        if (!is_acute(b[i], Db[i], b[j], Db[j])) continue;
        for (int k = 0; k < 4; ++k)
          if (k != i && k != j) {
            b[k] += b[i];
            Db[k] = D * b[k];
          }
        b[i] = -b[i];
        Db[i] = -Db[i];
        flipped = true;
      }
    if (!flipped) return b;
  }
  throw_not_terminating(D, 3);
}

// 2D: flip (b_i, b_j, b_k) -> (-b_i, b_j, b_i - b_j) while some pair is acute.
Superbase2 obtuse_superbase_2d(const Mat3& D) {
  Superbase2 b = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, -1, 0)};
  Superbase2 Db;
  for (int k = 0; k < 3; ++k) Db[k] = D * b[k];
  for (int iteration = 0; iteration < kMaxSellingIterations; ++iteration) {
    bool flipped = false;
    for (int i = 0; i < 3 && !flipped; ++i)
      for (int j = i + 1; j < 3 && !flipped; ++j) {
        if (!is_acute(b[i], Db[i], b[j], Db[j])) continue;
        const int k = 3 - i - j;
        b[k] = b[i] - b[j];
        Db[k] = D * b[k];
        b[i] = -b[i];
        Db[i] = -Db[i];
        flipped = true;
      }
    if (!flipped) return b;
  }
  throw_not_terminating(D, 2);
}

}  // namespace

SellingStencil selling_decomposition(const Mat3& D_in, int dimension) {
  const Mat3 D = checked_dual_metric(D_in, dimension);
  SellingStencil stencil;
  if (dimension == 3) {
    const Superbase3 b = obtuse_superbase_3d(D);
    // D = sum_{i<j} -<b_i, D b_j> e_ij e_ij^T with e_ij = b_k x b_l, {k, l} the other indices.
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        int other[2], n = 0;
        for (int k = 0; k < 4; ++k)
          if (k != i && k != j) other[n++] = k;
        add_term(stencil, weight_of_pair(b[i], b[j], D), b[other[0]].cross(b[other[1]]));
      }
  } else {
    const Superbase2 b = obtuse_superbase_2d(D);
    // D = sum_k -<b_i, D b_j> e_k e_k^T with e_k the perpendicular of the third vector b_k.
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        const Vec3& third = b[3 - i - j];
        add_term(stencil, weight_of_pair(b[i], b[j], D), Vec3(-third.y(), third.x(), 0));
      }
  }
  return stencil;
}

namespace {

// "canvas voxel (i, j, k) at (x, y, z): metric"
std::string voxel_metric_text(const Canvas& canvas, std::size_t slot) {
  const VoxelIndex v = canvas.voxel_of(slot);
  const Vec3 p = canvas.world_of(v);
  std::ostringstream where;
  where << "canvas voxel (" << v.i << ", " << v.j << ", " << v.k << ") at (" << p.x() << ", "
        << p.y() << ", " << p.z() << "): metric";
  return where.str();
}

// The offsets depend on the tensor alone, so no resolution and no engine takes a longer one.
void require_storable_offsets(const Canvas& canvas, std::size_t slot,
                              const SellingStencil& stencil) {
  for (int i = 0; i < stencil.size; ++i)
    for (int a = 0; a < 3; ++a) {
      const int e = stencil.offset[i][a];
      if (std::abs(e) <= kMostStencilOffset) continue;
      throw Error(voxel_metric_text(canvas, slot) + " " +
                  describe(canvas.metric_at(slot), canvas.dimension) +
                  " is too anisotropic for rvor's stencils: its Selling stencil has an offset of " +
                  std::to_string(e) + " voxels along " + "xyz"[a] + ", past the " +
                  std::to_string(kMostStencilOffset) +
                  " either engine stores (the offsets follow the metric's anisotropy and "
                  "orientation, not the resolution; anisotropy up to ~150 fits at any "
                  "orientation)");
    }
}

}  // namespace

SellingStencil canvas_selling_decomposition(const Canvas& canvas, std::size_t slot, const Mat3& D) {
  SellingStencil stencil;
  try {
    stencil = selling_decomposition(D, canvas.dimension);
  } catch (const Error&) {
    const std::string problem = metric_problem(canvas.metric_at(slot), canvas.dimension);
    throw Error(voxel_metric_text(canvas, slot) + " " +
                (problem.empty() ? "has no Selling decomposition" : problem));
  }
  require_storable_offsets(canvas, slot, stencil);
  return stencil;
}

}  // namespace rvor
