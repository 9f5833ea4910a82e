#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include "rvor/error.h"
#include "rvor/input_file.h"
#include "rvor/spec_text.h"
#include "surface_mesh.h"

namespace rvor {

namespace {

std::string lowercase_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string extension = dot == std::string::npos ? std::string() : path.substr(dot);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

InputFile open_input(const std::string& path) {
  return open_input_file(path, "mesh file");
}

// Reads a text file line by line, keeping the line number for error messages.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(open_input(path)) {}
  bool next(std::string& line) {
    if (!read_input_line(in_, line, path_, number_ + 1)) return false;
    ++number_;
    return true;
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw Error(path_ + ":" + std::to_string(number_) + ": " + why);
  }

 private:
  std::string path_;
  InputFile in_;
  int number_ = 0;
};

// Numbers are read as whole blank-separated tokens (parse_integer, parse_decimal): "2,5" or
// "1abc" is an error, where std::istream's >> would have stopped at the comma and read 2.
Vec3 parse_point(LineReader& reader, std::istringstream& fields) {
  Vec3 p;
  for (int a = 0; a < 3; ++a) {
    std::string token;
    if (!(fields >> token)) reader.fail("expected x y z, found the end of the line");
    const std::optional<double> value = parse_decimal(token);
    if (!value) reader.fail("expected x y z, three finite numbers, found " + quoted_text(token));
    p[a] = *value;
  }
  return p;
}

// --- OFF ------------------------------------------------------------------------------------
// Next line with content, comments ('#') removed.
bool next_content(LineReader& reader, std::string& line) {
  while (reader.next(line)) {
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t") != std::string::npos) return true;
  }
  return false;
}

// The next integer of an OFF line; `what` names it in the error when it is missing or not one.
long long next_off_integer(LineReader& reader, std::istringstream& fields,
                           const std::string& what) {
  std::string token;
  if (!(fields >> token)) reader.fail("expected " + what + ", found the end of the line");
  const std::optional<long long> value = parse_integer(token);
  if (!value) reader.fail("expected " + what + " (an integer), found " + quoted_text(token));
  return *value;
}

struct OffCounts {
  long long vertices = 0, faces = 0;
};

// "V F E" after the OFF keyword on its line, or else on the next line with content; E, the edge
// count, is not used but must be a number if present.
OffCounts read_off_counts(LineReader& reader, std::istringstream& header) {
  std::istringstream next_line;
  std::istringstream* fields = &header;
  if ((header >> std::ws).eof()) {
    std::string line;
    if (!next_content(reader, line)) reader.fail("missing vertex and face counts");
    next_line.str(line);
    fields = &next_line;
  }
  const long long vertices = next_off_integer(reader, *fields, "the vertex count");
  const long long faces = next_off_integer(reader, *fields, "the face count");
  if (vertices < 0 || faces < 0) reader.fail("negative counts");
  if (std::string edges; *fields >> edges && !parse_decimal(edges))
    reader.fail("expected an edge count after the vertex and face counts, not " +
                quoted_text(edges));
  return {vertices, faces};
}

SurfaceMesh read_off(const std::string& path) {
  LineReader reader(path);
  std::string line;
  if (!next_content(reader, line)) reader.fail("empty file, expected OFF header");
  std::istringstream header(line);
  std::string keyword;
  header >> keyword;
  if (keyword != "OFF") reader.fail("expected OFF header, found " + quoted_text(keyword));
  const OffCounts counts = read_off_counts(reader, header);
  SurfaceMesh mesh;
  for (long long v = 0; v < counts.vertices; ++v) {
    if (!next_content(reader, line)) reader.fail("unexpected end of file in vertices");
    std::istringstream fields(line);
    mesh.vertices.push_back(parse_point(reader, fields));
  }
  for (long long f = 0; f < counts.faces; ++f) {
    if (!next_content(reader, line)) reader.fail("unexpected end of file in faces");
    std::istringstream fields(line);
    const long long corners = next_off_integer(reader, fields, "the face's vertex count");
    if (corners < 3)
      reader.fail("a face with " + std::to_string(corners) + " vertices (at least 3)");
    std::vector<int> polygon;  // grows as indices are read: a huge corner count reserves nothing
    while (static_cast<long long>(polygon.size()) < corners) {
      const long long index = next_off_integer(reader, fields, "a vertex index");
      if (index < 0 || index >= counts.vertices)
        reader.fail("vertex index " + std::to_string(index) + " out of range (0 to " +
                    std::to_string(counts.vertices - 1) + ")");
      polygon.push_back(static_cast<int>(index));
    }
    add_polygon(mesh, polygon);
  }
  if (next_content(reader, line))
    reader.fail("more content than the header's " + std::to_string(counts.faces) + " faces");
  return mesh;
}

// --- OBJ ------------------------------------------------------------------------------------
// "a", "a/b", "a//c", "a/b/c": the vertex index, 1-based or negative (relative to the end); the
// texture and normal indices are not used, but must be integers where given.
int parse_obj_corner(LineReader& reader, const std::string& token, std::size_t vertex_count) {
  const std::vector<std::string> parts = split_at(token, '/');
  const std::optional<long long> index = parse_integer(parts.front());
  bool well_formed = parts.size() <= 3 && index && *index != 0;
  for (std::size_t i = 1; i < parts.size(); ++i)
    well_formed = well_formed && (parts[i].empty() || parse_integer(parts[i]));
  if (!well_formed) reader.fail("bad face vertex " + quoted_text(token));
  const long long resolved =
      *index > 0 ? *index - 1 : static_cast<long long>(vertex_count) + *index;
  if (resolved < 0 || resolved >= static_cast<long long>(vertex_count))
    reader.fail("face vertex " + quoted_text(token) + " out of range");
  return static_cast<int>(resolved);
}

SurfaceMesh read_obj(const std::string& path) {
  LineReader reader(path);
  SurfaceMesh mesh;
  for (std::string line; reader.next(line);) {
    std::istringstream fields(line.substr(0, line.find('#')));
    std::string keyword;
    fields >> keyword;
    if (keyword == "v") {
      mesh.vertices.push_back(parse_point(reader, fields));
    } else if (keyword == "f") {
      std::vector<int> polygon;
      for (std::string token; fields >> token;)
        polygon.push_back(parse_obj_corner(reader, token, mesh.vertices.size()));
      if (polygon.size() < 3) reader.fail("face with fewer than 3 vertices");
      add_polygon(mesh, polygon);
    }  // normals, texture coordinates, groups, materials: not needed for a volume
  }
  return mesh;
}

// --- STL ------------------------------------------------------------------------------------
// STL repeats vertex positions per facet: weld identical positions so edges can be matched.
class VertexWelder {
 public:
  explicit VertexWelder(SurfaceMesh& mesh) : mesh_(mesh) {}
  int index_of(const Vec3& p) {
    const auto inserted = indices_.emplace(std::array<double, 3>{p.x(), p.y(), p.z()},
                                           static_cast<int>(mesh_.vertices.size()));
    if (inserted.second) mesh_.vertices.push_back(p);
    return inserted.first->second;
  }

 private:
  SurfaceMesh& mesh_;
  std::map<std::array<double, 3>, int> indices_;
};

// What a binary STL's size must be: an 80-byte header, the facet count, 50 bytes a facet.
std::uint64_t binary_stl_size(std::uint32_t facets) {
  return 84 + 50 * static_cast<std::uint64_t>(facets);
}

struct StlStart {
  std::uint64_t size = 0;
  std::uint32_t facets = 0;  // the count a binary header would declare
  std::string text;          // the first 4 KiB
};

StlStart read_stl_start(const std::string& path) {
  InputFile in =
      open_regular_input_file(path, "mesh file", "rvor reads an STL file's size to tell its kind");
  StlStart start;
  in.seekg(0, std::ios::end);
  start.size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  start.text.assign(static_cast<std::size_t>(std::min<std::uint64_t>(start.size, 4096)), ' ');
  in.read(start.text.data(), static_cast<std::streamsize>(start.text.size()));
  if (start.size >= 84) std::memcpy(&start.facets, start.text.data() + 80, 4);
  return start;
}

// A file whose size matches the count in a binary header is binary, whatever it starts with
// (binary headers may start with "solid" too). Of the others, one that starts as ASCII STL does
// ("solid", then a facet or the end) is read as ASCII STL, so that a stray control byte is
// reported where it is; one with a NUL byte past the header, which ASCII STL never holds, is a
// binary file of the wrong size.
bool looks_binary_stl(const StlStart& start) {
  if (start.size < 84) return false;
  if (start.size == binary_stl_size(start.facets)) return true;
  const std::size_t first = start.text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && start.text.compare(first, 5, "solid") == 0 &&
      (start.text.find("facet") != std::string::npos ||
       start.text.find("endsolid") != std::string::npos))
    return false;
  return start.text.find('\0', 80) != std::string::npos;
}

SurfaceMesh read_binary_stl(const std::string& path, const StlStart& start) {
  const std::uint32_t count = start.facets;
  const std::uint64_t expected = binary_stl_size(count);
  const std::string sizes = "its header declares " + std::to_string(count) + " facets, 84 + 50 * " +
                            std::to_string(count) + " = " + std::to_string(expected) +
                            " bytes, and the file has " + std::to_string(start.size);
  // Facets past the count were dropped, as were extra bytes: a cube with a cavity lost its cavity.
  // Writers that pad their files are refused too: which bytes are padding cannot be told.
  if (start.size > expected)
    throw Error(path + ": binary STL larger than its facet count says: " + sizes + " (" +
                std::to_string((start.size - expected) / 50) + " facets and " +
                std::to_string((start.size - expected) % 50) +
                " bytes more); rvor reads a binary STL only when its size matches its count");
  if (start.size < expected)
    throw Error(path + ": truncated binary STL at facet " + std::to_string((start.size - 84) / 50) +
                ": " + sizes);
  InputFile in = open_input(path);
  in.seekg(84);
  SurfaceMesh mesh;
  VertexWelder welder(mesh);
  for (std::uint32_t f = 0; f < count; ++f) {
    float record[12];  // normal, then three vertices
    char attribute[2];
    in.read(reinterpret_cast<char*>(record), sizeof record);
    in.read(attribute, sizeof attribute);
    if (!in) throw Error(path + ": cannot read binary STL at facet " + std::to_string(f));
    std::vector<int> triangle;
    for (int v = 1; v <= 3; ++v) {
      const Vec3 p(record[3 * v], record[3 * v + 1], record[3 * v + 2]);
      if (!p.allFinite()) throw Error(path + ": non-finite vertex in facet " + std::to_string(f));
      triangle.push_back(welder.index_of(p));
    }
    add_polygon(mesh, triangle);
  }
  return mesh;
}

SurfaceMesh read_ascii_stl(const std::string& path) {
  LineReader reader(path);
  SurfaceMesh mesh;
  VertexWelder welder(mesh);
  std::vector<int> loop;
  bool seen_solid = false, in_loop = false;
  for (std::string line; reader.next(line);) {
    std::istringstream fields(line);
    std::string keyword;
    if (!(fields >> keyword)) continue;
    if (keyword == "solid") seen_solid = true;
    if (!seen_solid) reader.fail("expected 'solid' (ASCII STL) or a binary STL");
    if (keyword == "outer") loop.clear(), in_loop = true;
    if (keyword == "endloop") in_loop = false;
    if (keyword == "vertex") loop.push_back(welder.index_of(parse_point(reader, fields)));
    if (keyword == "endloop") {
      // A polygon would have been cut into triangles, then found open: STL facets are triangles.
      if (loop.size() != 3)
        reader.fail("facet with " + std::to_string(loop.size()) +
                    " vertices (STL facets are triangles)");
      add_polygon(mesh, loop);
      loop.clear();
    }
  }
  if (!seen_solid) throw Error(path + ": empty STL file");
  if (in_loop) reader.fail("the file ends inside a facet (truncated?)");
  return mesh;
}

}  // namespace

SurfaceMesh read_surface_mesh(const std::string& path) {
  const std::string extension = lowercase_extension(path);
  if (extension == ".off") return read_off(path);
  if (extension == ".obj") return read_obj(path);
  if (extension == ".stl") {
    const StlStart start = read_stl_start(path);
    return looks_binary_stl(start) ? read_binary_stl(path, start) : read_ascii_stl(path);
  }
  throw Error("mesh file " + path + ": unsupported format (expected .off, .obj or .stl)");
}

std::string point_text(const Vec3& p) {
  std::ostringstream text;
  text.precision(10);  // coordinates far from the origin (UTM) still tell points apart
  text << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return text.str();
}

namespace {

// The vertices at the ends of open edges (used by one triangle).
std::vector<int> open_edge_vertices(const std::map<std::pair<int, int>, int>& edge_uses) {
  std::vector<int> vertices;
  for (const auto& [edge, uses] : edge_uses)
    if (uses == 1) vertices.insert(vertices.end(), {edge.first, edge.second});
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

// What lies by the open edge a-b: a vertex of another open edge inside it (a T-junction), or the
// open-edge vertex nearest a, which a gap or an unwelded copy puts there (an OFF or OBJ written
// from STL facets repeats every vertex). Without this the message named an edge and its
// vertices, which hid the cause.
std::string open_edge_cause(const SurfaceMesh& mesh,
                            const std::map<std::pair<int, int>, int>& edge_uses, int a, int b) {
  const Vec3 &pa = mesh.vertices[a], &pb = mesh.vertices[b];
  const double length = (pb - pa).norm();
  int nearest = -1;
  double best = HUGE_VAL;
  for (const int w : open_edge_vertices(edge_uses)) {
    if (w == a || w == b) continue;
    const Vec3& p = mesh.vertices[w];
    const double along = (p - pa).dot(pb - pa) / (length * length);
    if (along > 1e-9 && along < 1 - 1e-9 && (pa + along * (pb - pa) - p).norm() <= 1e-9 * length)
      return "; vertex " + std::to_string(w) + " " + point_text(p) +
             " lies inside it: a T-junction (split its triangle at that vertex)";
    const double d = (p - pa).norm();
    if (d < best) best = d, nearest = w;
  }
  if (nearest < 0) return "";
  std::ostringstream text;
  text.precision(3);
  text << "; vertex " << a << " ";
  if (best == 0)
    text << "has the position of vertex " << nearest
         << ", also on an open edge: the file's vertices are not merged (welded)";
  else
    text << "lies " << best << " from vertex " << nearest << " "
         << point_text(mesh.vertices[nearest]) << ", the nearest vertex on another open edge"
         << (best < 1e-3 * length ? ": a gap (merge such vertices)" : "");
  return text.str();
}

}  // namespace

void require_closed(const SurfaceMesh& mesh, const std::string& path) {
  if (mesh.triangles.empty()) throw Error("mesh file " + path + " has no triangles");
  std::map<std::pair<int, int>, int> edge_uses;
  std::map<std::pair<int, int>, int> edge_triangle;  // the first triangle along each edge
  for (std::size_t n = 0; n < mesh.triangles.size(); ++n)
    for (int e = 0; e < 3; ++e) {
      const int a = mesh.triangles[n][e], b = mesh.triangles[n][(e + 1) % 3];
      const std::pair<int, int> edge{std::min(a, b), std::max(a, b)};
      if (edge_uses[edge]++ == 0) edge_triangle[edge] = static_cast<int>(n);
    }
  // Open edges (one triangle) first: an open surface is the likelier mistake.
  std::size_t open = 0, non_manifold = 0;
  const std::pair<const std::pair<int, int>, int>*first_open = nullptr,
                                             *first_non_manifold = nullptr;
  for (const auto& entry : edge_uses) {
    if (entry.second < 2 && open++ == 0) first_open = &entry;
    if (entry.second > 2 && non_manifold++ == 0) first_non_manifold = &entry;
  }
  if (open + non_manifold == 0) return;
  const auto* example = first_open ? first_open : first_non_manifold;
  throw Error(
      "mesh " + path + (first_open ? " is not closed: " : " is not manifold: ") +
      std::to_string(open) + " edge(s) used by one triangle, " + std::to_string(non_manifold) +
      " by more than two; e.g. the edge between vertices " + std::to_string(example->first.first) +
      " and " + std::to_string(example->first.second) +
      " (0-based; in an STL file, in the order they first appear) from " +
      point_text(mesh.vertices[example->first.first]) + " to " +
      point_text(mesh.vertices[example->first.second]) + " is used by " +
      std::to_string(example->second) + " triangle(s), the first triangle " +
      std::to_string(edge_triangle.at(example->first)) +
      " (0-based, polygons counted as the triangles they are cut into)" +
      (first_open ? open_edge_cause(mesh, edge_uses, example->first.first, example->first.second)
                  : "") +
      "; a mesh domain must be a closed manifold surface");
}

Box bounds_of(const SurfaceMesh& mesh) {
  Box box{Vec3::Constant(HUGE_VAL), Vec3::Constant(-HUGE_VAL)};
  for (const auto& t : mesh.triangles)  // a vertex no triangle uses bounds nothing
    for (const int v : t) {
      box.lo = box.lo.cwiseMin(mesh.vertices[v]);
      box.hi = box.hi.cwiseMax(mesh.vertices[v]);
    }
  return box;
}

}  // namespace rvor
