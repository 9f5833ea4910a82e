#pragma once
// Domains a canvas is built on.
#include <string>

#include "rvor/metric_field.h"

namespace rvor {

struct DomainSpec {
  enum class Kind { Box, Rectangle, Mesh, Implicit };
  Kind kind = Kind::Box;
  Box bounds;        // Box / Rectangle: the extent (Rectangle: z = 0); Mesh / Implicit: filled in
                     // by the canvas builder from the mesh bounds or the shape.
  std::string path;  // Mesh: closed triangle mesh (.off, .obj, .stl)
  std::string implicit;  // Implicit: sphere, ellipsoid, torus, disk (2D), with optional params
  int dimension() const { return kind == Kind::Rectangle || implicit_is_2d() ? 2 : 3; }
  bool implicit_is_2d() const;
  std::string description() const;
};

// Parses `box:X0,Y0,Z0,X1,Y1,Z1`, `rect:X0,Y0,X1,Y1`, `mesh:FILE` or `implicit:NAME[:k=v,...]`.
// Throws rvor::Error on malformed specs and empty extents (X1 <= X0 ...).
DomainSpec parse_domain(const std::string& spec);

}  // namespace rvor
