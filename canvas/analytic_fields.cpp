// The analytic metric fields of the thesis (M. Rouxel-Labbé, "Anisotropic mesh generation",
// 2016), with the parameters of its reference implementation; formulas in DESIGN.md.
// Every field is built so that at() is finite and SPD everywhere, including the points where the
// formula's eigenvector is undefined (there the two eigenvalues agree or a choice is documented).
#include "analytic_fields.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "rvor/error.h"

namespace rvor::fields {

namespace {

const Vec3 kUnitX = Vec3::UnitX();

Box square_domain(double lo, double hi) {
  return Box{Vec3(lo, lo, 0), Vec3(hi, hi, 0)};  // 2D boxes are flat (z = 0)
}

Box cube_domain(double lo, double hi) {
  return Box{Vec3::Constant(lo), Vec3::Constant(hi)};
}

std::string format_number(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

// Unit vector along v, or `fallback` when v has no direction (zero or not finite). Dividing by
// the largest component first keeps very small or very large vectors from under/overflowing.
Vec3 direction_or(const Vec3& v, const Vec3& fallback) {
  const double largest = v.cwiseAbs().maxCoeff();
  if (!(largest > 0) || !std::isfinite(largest)) return fallback;
  const Vec3 w = v / largest;
  return w / w.norm();
}

// G with eigenvalue g_along along the unit vector n and g_across in every direction orthogonal
// to it (in the xy plane in 2D, where G(2,2) = 1). Frame-free, so no second vector is needed.
Mat3 axial_metric(int dimension, const Vec3& n, double g_along, double g_across) {
  Mat3 G = g_across * Mat3::Identity() + (g_along - g_across) * n * n.transpose();
  if (dimension == 2) {
    G.row(2).setZero();
    G.col(2).setZero();
    G(2, 2) = 1.0;
  }
  return G;
}

// Shared behaviour: name, dimension, scale and natural domain; subclasses give the unscaled G.
class AnalyticField : public MetricField {
 public:
  AnalyticField(std::string name, int dimension, double scale, std::optional<Box> domain)
      : name_(std::move(name)), dimension_(dimension), scale_(scale), domain_(std::move(domain)) {
    // An infinite factor made the tensor's zeros NaN (0 * inf), and the error a "not finite"
    // with a -nan in it; a finite one too large for float is named where the canvas stores it.
    if (!std::isfinite(scale_ * scale_))
      throw Error("metric " + name_ + ": scale " + format_number(scale_) +
                  " overflows float: the tensor is scale^2 times the field's, and scale^2 is "
                  "past even double's range (canvases keep tensors in float, up to about 3.4e38)");
  }

  int dimension() const override { return dimension_; }
  std::optional<Box> natural_domain() const override { return domain_; }
  std::string description() const override {
    return name_ + details() + " (scale " + format_number(scale_) + ")";
  }

  Mat3 at(const Vec3& p) const final {
    Mat3 G = unscaled_at(p);
    const double factor = scale_ * scale_;
    if (dimension_ == 3) return factor * G;
    G.topLeftCorner<2, 2>() *= factor;  // the unused z entry stays 1
    return G;
  }

 protected:
  virtual Mat3 unscaled_at(const Vec3& p) const = 0;
  virtual std::string details() const { return ""; }

 private:
  std::string name_;
  int dimension_;
  double scale_;
  std::optional<Box> domain_;
};

class EuclideanField final : public AnalyticField {
 public:
  EuclideanField(int dimension, double scale)
      : AnalyticField("euclidean", dimension, scale, std::nullopt) {}
  bool is_uniform() const override { return true; }

 private:
  Mat3 unscaled_at(const Vec3&) const override { return Mat3::Identity(); }
};

class UniformField final : public AnalyticField {
 public:
  UniformField(int dimension, const Mat3& G, double scale)
      : AnalyticField("uniform", dimension, scale, std::nullopt), G_(G) {}
  bool is_uniform() const override { return true; }

 private:
  Mat3 unscaled_at(const Vec3&) const override { return G_; }
  std::string details() const override {
    const SolTensor c = tensor_to_sol(G_);
    const int count = dimension() == 2 ? 3 : 6;
    std::string text = " [";
    for (int i = 0; i < count; ++i) text += (i ? " " : "") + format_number(c[i]);
    return text + "]";
  }

  Mat3 G_;
};

// A spiral flow around the origin: strong anisotropy on the ring r ~ 1 where a ~ 50, isotropic
// (10^4 I) at the origin, where a = 0; that is also the limit of the formula there, so the
// undefined direction of v1 at the origin does not matter.
class SwirlField final : public AnalyticField {
 public:
  explicit SwirlField(double scale) : AnalyticField("swirl", 2, scale, square_domain(-1, 1)) {}

 private:
  static constexpr double kLambda = 3.0;
  static constexpr double kSize = 1e4;  // multiplies both eigenvalues of G

  Mat3 unscaled_at(const Vec3& p) const override {
    const double r = std::hypot(p.x(), p.y());
    const double f = (std::cbrt(r) + r) / 2;
    const double a = std::abs(50 * (1 - (f - 1) * (f - 1)));
    return axial_metric(2, swirl_direction(p.x(), p.y(), r), kSize / (1 + a), kSize);
  }

  // v1 = J u + (1 - r^2)^2 u with u = p rotated by lambda and J the rotation by +90 degrees.
  static Vec3 swirl_direction(double x, double y, double r) {
    const double c = std::cos(kLambda), s = std::sin(kLambda);
    const double ux = x * c - y * s, uy = x * s + y * c;
    const double w = (1 - r * r) * (1 - r * r);
    return direction_or(Vec3(-uy + w * ux, ux + w * uy, 0), kUnitX);
  }
};

// A star-shaped shock: F eigenvalues l1/h along the vector field g and 1/h across it. g = 0 only at
// the origin, where l1 = 1 = l2: G = I/h^2 there, the limit of the formula.
class StarredField final : public AnalyticField {
 public:
  explicit StarredField(double scale) : AnalyticField("starred", 2, scale, square_domain(-1, 1)) {}

 private:
  static constexpr double kH = 0.05;

  Mat3 unscaled_at(const Vec3& p) const override {
    const double x = p.x(), y = p.y();
    const Vec3 g(3 * x * x - x * y / 5 - y * y + 3 * x * x / 10, -x * x / 10 - 2 * x * y, 0);
    const double l1 = std::max(0.1, 1 / (1 + std::hypot(g.x(), g.y())));
    return axial_metric(2, direction_or(g, kUnitX), (l1 / kH) * (l1 / kH), (1 / kH) * (1 / kH));
  }
};

// A shock along the curve 2x = sin 5y. v never vanishes: its x component 2T + 3x^2 + y^2 could
// only be 0 at the origin, where T = 1/delta.
class HyperbolicShockField final : public AnalyticField {
 public:
  HyperbolicShockField(int dimension, double scale)
      : AnalyticField("hyperbolic_shock", dimension, scale,
                      dimension == 2 ? square_domain(-1, 1) : cube_domain(-1, 1)),
        h_(dimension == 2 ? 0.1 : 0.05) {}

 private:
  static constexpr double kDelta = 0.6;

  Mat3 unscaled_at(const Vec3& p) const override {
    const double x = p.x(), y = p.y();
    // T = (1 - tanh^2 s) / delta, written as 1 / (delta cosh^2 s) to avoid cancellation.
    const double cosh_s = std::cosh((2 * x - std::sin(5 * y)) / kDelta);
    const double T = 1 / (kDelta * cosh_s * cosh_s);
    const Vec3 v(2 * T + 3 * x * x + y * y, -5 * T * std::cos(5 * y) + 2 * x * y, 0);
    const double across = 1 / (h_ * h_);
    return axial_metric(dimension(), direction_or(v, kUnitX), v.squaredNorm() * across, across);
  }

  double h_;
};

// Two axis-aligned shocks (Yang & Liu), on the lines x = 0.6 and y = 0.3.
class UnidimensionalShockField final : public AnalyticField {
 public:
  explicit UnidimensionalShockField(double scale)
      : AnalyticField("unidimensional_shock", 2, scale, square_domain(-1, 1)) {}

 private:
  static double eigenvalue(double distance) {
    return 1 / (0.0025 + 0.2 * (1 - std::exp(-std::abs(distance))));
  }

  Mat3 unscaled_at(const Vec3& p) const override {
    const double h1 = eigenvalue(p.x() - 0.6), h2 = eigenvalue(p.y() - 0.3);
    return Vec3(h1 * h1, h2 * h2, 1).asDiagonal();
  }
};

// A spherical shock (Yang & Liu) on the sphere r = 7: F eigenvalue 1/h1 along the radius, 1 along
// the sphere. At the origin (outside the natural domain) the radius has no direction: G = I/h1^2
// there, the larger eigenvalue in every direction, so that sizes are never overestimated.
class RadialShock3dField final : public AnalyticField {
 public:
  explicit RadialShock3dField(double scale)
      : AnalyticField("radial_shock_3d", 3, scale, cube_domain(1, 11)) {}

 private:
  Mat3 unscaled_at(const Vec3& p) const override {
    const double r2 = p.squaredNorm();
    const double h1 = 0.025 + (1 - std::exp(-0.01 * std::abs(r2 - 49)));
    const double radial = 1 / (h1 * h1);
    const Vec3 n = direction_or(p, Vec3::Zero());
    if (n.isZero()) return radial * Mat3::Identity();
    return axial_metric(3, n, radial, 1.0);
  }
};

}  // namespace

std::unique_ptr<MetricField> make_euclidean(int dimension, double scale) {
  return std::make_unique<EuclideanField>(dimension, scale);
}

std::unique_ptr<MetricField> make_uniform(int dimension, const Mat3& G, double scale) {
  return std::make_unique<UniformField>(dimension, G, scale);
}

std::unique_ptr<MetricField> make_swirl(double scale) {
  return std::make_unique<SwirlField>(scale);
}

std::unique_ptr<MetricField> make_starred(double scale) {
  return std::make_unique<StarredField>(scale);
}

std::unique_ptr<MetricField> make_hyperbolic_shock(int dimension, double scale) {
  return std::make_unique<HyperbolicShockField>(dimension, scale);
}

std::unique_ptr<MetricField> make_unidimensional_shock(double scale) {
  return std::make_unique<UnidimensionalShockField>(scale);
}

std::unique_ptr<MetricField> make_radial_shock_3d(double scale) {
  return std::make_unique<RadialShock3dField>(scale);
}

}  // namespace rvor::fields
