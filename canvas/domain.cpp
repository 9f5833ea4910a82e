#include "rvor/domain.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "implicit_shapes.h"
#include "rvor/error.h"
#include "rvor/spec_text.h"

namespace rvor {

namespace {

[[noreturn]] void fail(const std::string& spec, const std::string& why) {
  throw Error("malformed domain '" + spec + "': " + why);
}

std::vector<std::string> trim_each(std::vector<std::string> items) {
  for (std::string& item : items) item = trim_blanks(item);
  return items;
}

std::vector<double> parse_numbers(const std::string& spec, const std::string& list,
                                  std::size_t count) {
  std::vector<double> numbers;
  for (const std::string& item : trim_each(split_commas(list))) {
    if (item.empty()) fail(spec, "empty number (two commas in a row, or a trailing comma?)");
    const std::optional<double> value = parse_decimal(item);
    if (!value) fail(spec, "'" + item + "' is not a finite number");
    numbers.push_back(*value);
  }
  if (numbers.size() != count)
    fail(spec, "expected " + std::to_string(count) + " comma-separated numbers");
  return numbers;
}

void require_positive_extent(const std::string& spec, const Box& box, int dimension) {
  static const char* const axes = "XYZ";
  for (int a = 0; a < dimension; ++a)
    if (!(box.hi[a] > box.lo[a]))
      fail(spec, std::string("empty extent: ") + axes[a] + "1 <= " + axes[a] + "0");
}

std::string lowercase_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return {};
  std::string extension = path.substr(dot);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace

bool DomainSpec::implicit_is_2d() const {
  return kind == Kind::Implicit && ImplicitShape::parse(implicit).dimension() == 2;
}

std::string DomainSpec::description() const {
  const Vec3& lo = bounds.lo;
  const Vec3& hi = bounds.hi;
  switch (kind) {
    case Kind::Box:
      return "box:" + format_spec_number(lo.x()) + "," + format_spec_number(lo.y()) + "," +
             format_spec_number(lo.z()) + "," + format_spec_number(hi.x()) + "," +
             format_spec_number(hi.y()) + "," + format_spec_number(hi.z());
    case Kind::Rectangle:
      return "rect:" + format_spec_number(lo.x()) + "," + format_spec_number(lo.y()) + "," +
             format_spec_number(hi.x()) + "," + format_spec_number(hi.y());
    case Kind::Mesh:
      return "mesh:" + path;
    case Kind::Implicit:
      return "implicit:" + ImplicitShape::parse(implicit).description();
  }
  return {};
}

DomainSpec parse_domain(const std::string& spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos)
    fail(spec, "expected box:..., rect:..., mesh:FILE or implicit:NAME[:k=v,...]");
  const std::string kind = spec.substr(0, colon);
  const std::string rest = spec.substr(colon + 1);

  DomainSpec domain;
  if (kind == "box") {
    const auto n = parse_numbers(spec, rest, 6);
    domain.kind = DomainSpec::Kind::Box;
    domain.bounds = Box{Vec3(n[0], n[1], n[2]), Vec3(n[3], n[4], n[5])};
    require_positive_extent(spec, domain.bounds, 3);
  } else if (kind == "rect") {
    const auto n = parse_numbers(spec, rest, 4);
    domain.kind = DomainSpec::Kind::Rectangle;
    domain.bounds = Box{Vec3(n[0], n[1], 0), Vec3(n[2], n[3], 0)};
    require_positive_extent(spec, domain.bounds, 2);
  } else if (kind == "mesh") {
    const std::string extension = lowercase_extension(rest);
    if (rest.empty()) fail(spec, "no mesh file given");
    if (extension != ".off" && extension != ".obj" && extension != ".stl")
      fail(spec, "mesh files must be .off, .obj or .stl");
    domain.kind = DomainSpec::Kind::Mesh;
    domain.path = rest;
  } else if (kind == "implicit") {
    domain.kind = DomainSpec::Kind::Implicit;
    domain.implicit = rest;
    domain.bounds = ImplicitShape::parse(rest).bounds();
  } else {
    fail(spec, "unknown domain kind '" + kind + "' (box, rect, mesh, implicit)");
  }
  return domain;
}

}  // namespace rvor
