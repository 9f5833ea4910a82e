#pragma once
// Built-in implicit shapes of `implicit:NAME[:k=v,...]` domains (private to rvor_canvas).
#include <string>

#include "rvor/metric_field.h"

namespace rvor {

// A closed shape given by a signed distance bound: negative inside, positive outside, and never
// larger in magnitude than the true distance to the surface. The builder relies on that bound to
// skip whole blocks of voxels that cannot touch the surface.
class ImplicitShape {
 public:
  enum class Kind { Sphere, Ellipsoid, Torus, Disk };

  // Parses "NAME[:k=v,...]" (the part after "implicit:"). Vector values continue over commas:
  // "sphere:center=1,2,3,r=0.5". Throws rvor::Error naming the spec when malformed.
  static ImplicitShape parse(const std::string& spec);

  int dimension() const { return kind_ == Kind::Disk ? 2 : 3; }
  // Conservative signed distance at p (z ignored in 2D).
  double signed_distance_bound(const Vec3& p) const;
  bool contains(const Vec3& p) const { return signed_distance_bound(p) <= 0.0; }
  bool is_convex() const;
  // Axis-aligned bounds of the shape (z = 0 in 2D); may be degenerate (radius 0).
  Box bounds() const;
  // Canonical form with every parameter, e.g. "sphere:center=0,0,0,r=1".
  std::string description() const;

 private:
  Kind kind_ = Kind::Sphere;
  Vec3 center_ = Vec3::Zero();
  Vec3 radii_ = Vec3::Ones();  // sphere/disk: x; ellipsoid: a,b,c; torus: x = R, y = r
};

// A number as written back into a domain spec: 10 significant digits, or 17 where 10 would not
// give the value back.
std::string format_spec_number(double value);

}  // namespace rvor
