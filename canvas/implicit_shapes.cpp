#include "implicit_shapes.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "rvor/error.h"
#include "rvor/spec_text.h"

namespace rvor {

namespace {

// Each key's values as written, in the order the keys came: a value is read as a number only
// once its key is known to the shape ("axis=z" is an unknown parameter, not a bad number).
struct Parameters {
  std::vector<std::string> keys;
  std::map<std::string, std::vector<std::string>> values;
};

[[noreturn]] void fail(const std::string& spec, const std::string& why) {
  throw Error("malformed domain 'implicit:" + spec + "': " + why);
}

double parse_number(const std::string& spec, const std::string& text) {
  const std::optional<double> value = parse_decimal(text);
  if (!value) fail(spec, quoted_text(text) + " is not a finite number");
  return *value;
}

// "k=v,w,k2=v2": a token without '=' continues the previous key's value list.
Parameters parse_parameters(const std::string& spec, const std::string& list) {
  Parameters parameters;
  if (list.empty()) return parameters;  // "sphere:" means no parameters
  std::string current;
  for (const std::string& item : split_commas(list)) {
    const std::string token = trim_blanks(item);
    if (token.empty()) fail(spec, "empty parameter (two commas in a row, or a trailing comma?)");
    const auto equals = token.find('=');
    if (equals == std::string::npos) {
      if (current.empty()) fail(spec, "expected key=value, got " + quoted_text(token));
      parameters.values[current].push_back(token);
      continue;
    }
    current = trim_blanks(token.substr(0, equals));
    if (current.empty()) fail(spec, "empty parameter name");
    if (parameters.values.count(current))
      fail(spec, "parameter " + quoted_text(current) + " given twice");
    parameters.keys.push_back(current);
    parameters.values[current].push_back(trim_blanks(token.substr(equals + 1)));
  }
  return parameters;
}

// The first parameter the shape does not take, named with those it does.
void require_known(const std::string& spec, const Parameters& parameters, const std::string& name,
                   const std::vector<std::string>& known) {
  for (const std::string& key : parameters.keys) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    fail(spec, "unknown parameter " + quoted_text(key) + " for shape '" + name +
                   "' (known: " + list + ")");
  }
}

// Removes and returns a parameter of `count` values, or `fallback` when absent.
std::vector<double> take(const std::string& spec, Parameters& parameters, const std::string& key,
                         std::size_t count, const std::vector<double>& fallback) {
  auto found = parameters.values.find(key);
  if (found == parameters.values.end()) return fallback;
  const std::vector<std::string> texts = found->second;
  parameters.values.erase(found);
  if (texts.size() != count)
    fail(spec, "parameter '" + key + "' needs " + std::to_string(count) + " value(s)");
  std::vector<double> values;
  for (const std::string& text : texts) values.push_back(parse_number(spec, text));
  return values;
}

double take_radius(const std::string& spec, Parameters& parameters, const std::string& key,
                   double fallback) {
  const double value = take(spec, parameters, key, 1, {fallback})[0];
  if (value < 0) fail(spec, "parameter '" + key + "' must be >= 0");
  return value;
}

}  // namespace

std::string format_spec_number(double value) {
  // 10 significant digits where they give the value back, else 17 (which always do): a domain
  // 1e14 wide by 1e3 must not be written as one of zero width. strtod, not stod: a subnormal
  // would make stod throw out of an error message.
  std::ostringstream out;
  out.precision(10);
  out << value;
  if (std::strtod(out.str().c_str(), nullptr) == value) return out.str();
  std::ostringstream full;
  full.precision(17);
  full << value;
  return full.str();
}

ImplicitShape ImplicitShape::parse(const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  static const std::map<std::string, std::vector<std::string>> kKnown = {
      {"sphere", {"center", "r"}},
      {"ellipsoid", {"center", "a", "b", "c"}},
      {"torus", {"center", "R", "r"}},
      {"disk", {"center", "r"}}};
  const auto known = kKnown.find(name);
  if (known == kKnown.end())
    fail(spec, "unknown shape " + quoted_text(name) + " (sphere, ellipsoid, torus, disk)");
  Parameters parameters =
      colon == std::string::npos ? Parameters{} : parse_parameters(spec, spec.substr(colon + 1));
  require_known(spec, parameters, name, known->second);

  ImplicitShape shape;
  if (name == "disk") {
    const auto c = take(spec, parameters, "center", 2, {0, 0});
    shape.center_ = Vec3(c[0], c[1], 0);
  } else {
    const auto c = take(spec, parameters, "center", 3, {0, 0, 0});
    shape.center_ = Vec3(c[0], c[1], c[2]);
  }

  if (name == "sphere" || name == "disk") {
    shape.kind_ = name == "sphere" ? Kind::Sphere : Kind::Disk;
    shape.radii_ = Vec3::Constant(take_radius(spec, parameters, "r", 1.0));
  } else if (name == "ellipsoid") {
    shape.kind_ = Kind::Ellipsoid;
    shape.radii_ =
        Vec3(take_radius(spec, parameters, "a", 1.0), take_radius(spec, parameters, "b", 0.75),
             take_radius(spec, parameters, "c", 0.5));
  } else {
    shape.kind_ = Kind::Torus;
    shape.radii_ =
        Vec3(take_radius(spec, parameters, "R", 1.0), take_radius(spec, parameters, "r", 0.25), 0);
  }
  return shape;
}

double ImplicitShape::signed_distance_bound(const Vec3& p) const {
  const Vec3 q = p - center_;
  switch (kind_) {
    case Kind::Sphere:
      return q.norm() - radii_.x();
    case Kind::Disk:
      return q.head<2>().norm() - radii_.x();
    case Kind::Torus: {
      // Distance to the core circle (radius R in the xy plane) minus the tube radius.
      const double rho = q.head<2>().norm() - radii_.x();
      return std::hypot(rho, q.z()) - radii_.y();
    }
    case Kind::Ellipsoid: {
      // |q / radii| - 1 is (1 / min radius)-Lipschitz, so scaling by the smallest radius keeps
      // it below the true distance.
      const double smallest = radii_.minCoeff();
      if (smallest <= 0) return std::numeric_limits<double>::infinity();  // no volume
      return (q.cwiseQuotient(radii_).norm() - 1.0) * smallest;
    }
  }
  return std::numeric_limits<double>::infinity();
}

bool ImplicitShape::is_convex() const {
  switch (kind_) {
    case Kind::Sphere:
    case Kind::Ellipsoid:
    case Kind::Disk:
      return true;
    case Kind::Torus:
      return false;
  }
  return false;
}

Box ImplicitShape::bounds() const {
  Vec3 half = radii_;
  if (kind_ == Kind::Sphere) half = Vec3::Constant(radii_.x());
  if (kind_ == Kind::Disk) half = Vec3(radii_.x(), radii_.x(), 0);
  if (kind_ == Kind::Torus) {
    const double outer = radii_.x() + radii_.y();
    half = Vec3(outer, outer, radii_.y());
  }
  return Box{center_ - half, center_ + half};
}

std::string ImplicitShape::description() const {
  const Vec3& c = center_;
  const std::string center3 = "center=" + format_spec_number(c.x()) + "," +
                              format_spec_number(c.y()) + "," + format_spec_number(c.z());
  switch (kind_) {
    case Kind::Sphere:
      return "sphere:" + center3 + ",r=" + format_spec_number(radii_.x());
    case Kind::Disk:
      return "disk:center=" + format_spec_number(c.x()) + "," + format_spec_number(c.y()) +
             ",r=" + format_spec_number(radii_.x());
    case Kind::Torus:
      return "torus:" + center3 + ",R=" + format_spec_number(radii_.x()) +
             ",r=" + format_spec_number(radii_.y());
    case Kind::Ellipsoid:
      return "ellipsoid:" + center3 + ",a=" + format_spec_number(radii_.x()) +
             ",b=" + format_spec_number(radii_.y()) + ",c=" + format_spec_number(radii_.z());
  }
  return {};
}

}  // namespace rvor
