// Medit ASCII .mesh / .sol reading and writing.
//
// Both formats are read as a stream of whitespace-separated tokens (line breaks carry no
// meaning in Medit files: MMG, Gmsh and Medit itself lay out keywords and counts differently),
// while remembering each token's line so that every error can say "FILE:LINE: problem".
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <sstream>
#include <string_view>

#include "medit_internal.h"
#include "rvor/atomic_file.h"
#include "rvor/error.h"
#include "rvor/input_file.h"
#include "rvor/medit.h"
#include "rvor/spec_text.h"

namespace rvor {

namespace {

struct Token {
  std::string_view text;
  int line = 0;
};

bool starts_like_keyword(std::string_view text) {
  return !text.empty() && std::isalpha(static_cast<unsigned char>(text[0])) != 0;
}

std::string lowercase(std::string_view text) {
  std::string result(text);
  for (char& c : result) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return result;
}

// Keywords of the sections a value can run into when a section is shorter than its count says
// (anything else that is not a number is reported as such).
bool is_section_keyword(std::string_view text) {
  if (!starts_like_keyword(text)) return false;
  static constexpr std::string_view keywords[] = {"meshversionformatted",
                                                  "dimension",
                                                  "vertices",
                                                  "edges",
                                                  "triangles",
                                                  "tetrahedra",
                                                  "quadrilaterals",
                                                  "pyramids",
                                                  "prisms",
                                                  "hexahedra",
                                                  "corners",
                                                  "requiredvertices",
                                                  "ridges",
                                                  "requirededges",
                                                  "requiredtriangles",
                                                  "requiredquadrilaterals",
                                                  "requiredtetrahedra",
                                                  "normals",
                                                  "tangents",
                                                  "normalatvertices",
                                                  "tangentatvertices",
                                                  "normalattrianglevertices",
                                                  "solatvertices",
                                                  "end"};
  const std::string lower = lowercase(text);
  return std::find(std::begin(keywords), std::end(keywords), lower) != std::end(keywords);
}

std::string read_whole_file(const std::string& path) {
  InputFile in = open_input_file(path, "Medit file");
  std::string whole;
  // Read by chunks, each checked as it comes: binary Medit files (.meshb, .solb) start with the
  // int 1, and text never holds a NUL byte, so a binary file (or /dev/zero) is refused at its
  // first chunk rather than after reading it whole.
  std::string chunk(std::size_t{1} << 20, '\0');
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    const std::string_view read(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (read.find('\0') != std::string_view::npos)
      throw Error(path +
                  ": a binary file (binary Medit .meshb/.solb is not supported: write ASCII "
                  ".mesh/.sol)");
    whole += read;
  }
  if (in.bad()) throw Error(path + ": read error");
  return whole;
}

// Parses a real the way strtod does, but without locale dependence and on a string_view.
bool parse_real(std::string_view text, double& value) {
  if (!text.empty() && text[0] == '+') {
    text.remove_prefix(1);
    // from_chars takes a '-', so "+-1" would pass for -1.
    if (!text.empty() && text[0] == '-') return false;
  }
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  if (result.ptr != end) return false;
  // Overflow and underflow: from_chars leaves `value` alone; strtod gives +-inf or a denormal.
  if (result.ec == std::errc::result_out_of_range)
    value = std::strtod(std::string(text).c_str(), nullptr);
  return true;
}

// The token stream of one Medit file. `#` starts a comment that runs to the end of the line.
class MeditTokens {
 public:
  explicit MeditTokens(std::string path) : path_(std::move(path)), text_(read_whole_file(path_)) {
    position_ = byte_order_mark_length(text_);
  }

  const std::string& path() const { return path_; }
  // The line of the last token read (error messages at the end of a file point at the last
  // line that holds something).
  int line() const { return last_line_; }

  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw Error(path_ + ":" + std::to_string(line) + ": " + problem);
  }

  bool at_end() {
    skip_blanks_and_comments();
    return position_ >= text_.size();
  }

  Token next() {
    const Token token = peek();
    position_ += token.text.size();
    last_line_ = token.line;
    return token;
  }

  Token peek() {
    skip_blanks_and_comments();
    std::size_t end = position_;
    while (end < text_.size() && !std::isspace(static_cast<unsigned char>(text_[end]))) ++end;
    return {std::string_view(text_).substr(position_, end - position_), line_};
  }

  // `describe()` names what was expected ("vertex 6 of 8 in the Vertices section"); it is only
  // called when reporting an error, so callers pay nothing for a good message.
  template <typename Describe>
  Token next_value(Describe describe) {
    if (at_end()) fail(last_line_, "truncated file: it ends where " + describe() + " was expected");
    const Token token = next();
    if (is_section_keyword(token.text))
      fail(token.line, "truncated section: found " + quoted_text(token.text) + " where " +
                           describe() + " was expected");
    return token;
  }

  template <typename Describe>
  double real(Describe describe) {
    const Token token = next_value(describe);
    double value = 0;
    if (!parse_real(token.text, value)) not_a_number(token, describe());
    return value;
  }

  template <typename Describe>
  long long integer(Describe describe) {
    const Token token = next_value(describe);
    if (const std::optional<long long> value = parse_integer(token.text)) return *value;
    double as_real = 0;
    if (parse_real(token.text, as_real))
      fail(token.line, quoted_text(token.text) + " is not an integer (" + describe() + ")");
    not_a_number(token, describe());
  }

  // How many entries of `values` values each the rest of the file can hold at most (each value
  // takes a character and a separator): a bound for reserving before the entries are read.
  std::size_t entries_bound(int values) const {
    return (text_.size() - std::min(position_, text_.size())) / (2 * std::max(1, values)) + 1;
  }

  // A count that introduces a section: a non-negative int.
  int count(const std::string& section) {
    const auto describe = [&] { return "the number of entries of the " + section + " section"; };
    const long long value = integer(describe);
    if (value < 0 || value > INT_MAX)
      fail(last_line_,
           "invalid count " + std::to_string(value) + " for the " + section + " section");
    return static_cast<int>(value);
  }

 private:
  [[noreturn]] void not_a_number(const Token& token, const std::string& what) const {
    fail(token.line, quoted_text(token.text) + " is not a number (" + what + ")");
  }

  void skip_blanks_and_comments() {
    while (position_ < text_.size()) {
      const char c = text_[position_];
      if (c == '\n') {
        ++line_;
        ++position_;
      } else if (c == '#') {
        while (position_ < text_.size() && text_[position_] != '\n') ++position_;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        ++position_;
      } else {
        return;
      }
    }
  }

  std::string path_;
  std::string text_;
  std::size_t position_ = 0;
  int line_ = 1;
  int last_line_ = 1;
};

// The value after MeshVersionFormatted, in a .mesh as in a .sol: 3 and 4 only widen integers in
// binary files; their ASCII layout is the same.
void read_format_version(MeditTokens& tokens) {
  const long long version = tokens.integer([] { return std::string("the format version"); });
  if (version < 1 || version > 4)
    tokens.fail(tokens.line(), "unsupported MeshVersionFormatted " + std::to_string(version) +
                                   " (expected 1 to 4)");
}

// "vertex 6 of 8 in the Vertices section": 1-based, as in the file.
std::string entry_name(const char* entry, int index, int count, const std::string& section) {
  return std::string(entry) + " " + std::to_string(index + 1) + " of " + std::to_string(count) +
         " in the " + section + " section";
}

// Sections that rvor does not use, with the number of values per entry, so that they can be
// skipped exactly. Sections missing from this table are skipped up to the next keyword.
int values_per_entry_of_skipped_section(const std::string& lower_name, int dimension) {
  static const std::array<std::pair<const char*, int>, 15> fixed = {{
      {"corners", 1},
      {"requiredvertices", 1},
      {"ridges", 1},
      {"requirededges", 1},
      {"requiredtriangles", 1},
      {"requiredquadrilaterals", 1},
      {"requiredtetrahedra", 1},
      {"quadrilaterals", 5},
      {"pyramids", 6},
      {"prisms", 7},
      {"hexahedra", 9},
      {"normalatvertices", 2},
      {"tangentatvertices", 2},
      {"normalattrianglevertices", 3},
      {"tangentatedges", 3},
  }};
  for (const auto& [name, width] : fixed)
    if (lower_name == name) return width;
  if (lower_name == "normals" || lower_name == "tangents") return dimension;
  return 0;
}

void skip_section(MeditTokens& tokens, const Token& keyword, int dimension) {
  const std::string section(keyword.text);
  const int width = values_per_entry_of_skipped_section(lowercase(section), dimension);
  if (width == 0) {
    // Unknown layout: its values cannot start with a letter, the next keyword does.
    while (!tokens.at_end() && !starts_like_keyword(tokens.peek().text)) tokens.next();
    return;
  }
  const int count = tokens.count(section);
  for (int i = 0; i < count; ++i)
    for (int k = 0; k < width; ++k)
      tokens.next_value([&] { return entry_name("entry", i, count, section); });
}

// The largest vertex index met in element sections and where, checked once Vertices is known
// (Medit does not require Vertices to come first).
struct IndexRangeCheck {
  long long largest = 0;
  int line = 0;
  std::string section;
};

class MeshReader {
 public:
  explicit MeshReader(const std::string& path) : tokens_(path) {}

  MeditMesh read() {
    while (!tokens_.at_end()) {
      const Token keyword = tokens_.next();
      if (!starts_like_keyword(keyword.text))
        tokens_.fail(keyword.line,
                     "expected a section keyword, found " + quoted_text(keyword.text));
      if (!read_section(keyword)) break;
    }
    if (mesh_.dimension == 0) tokens_.fail(tokens_.line(), "missing Dimension keyword");
    check_index_range();
    return std::move(mesh_);
  }

 private:
  // Returns false at End.
  bool read_section(const Token& keyword) {
    const std::string name = lowercase(keyword.text);
    if (name == "end") return false;
    if (name == "meshversionformatted") {
      read_format_version(tokens_);
    } else if (name == "dimension") {
      read_dimension();
    } else if (name == "vertices") {
      require_dimension(keyword);
      read_vertices();
    } else if (name == "edges") {
      read_elements<2>("Edges", mesh_.edges, mesh_.edge_refs);
    } else if (name == "triangles") {
      read_elements<3>("Triangles", mesh_.triangles, mesh_.triangle_refs);
    } else if (name == "tetrahedra") {
      read_elements<4>("Tetrahedra", mesh_.tetrahedra, mesh_.tetrahedron_refs);
    } else {
      skip_section(tokens_, keyword, mesh_.dimension);
    }
    return true;
  }

  void read_dimension() {
    const long long dimension = tokens_.integer([] { return std::string("the dimension"); });
    if (dimension != 2 && dimension != 3)
      tokens_.fail(tokens_.line(),
                   "unknown dimension " + std::to_string(dimension) + " (expected 2 or 3)");
    mesh_.dimension = static_cast<int>(dimension);
  }

  void require_dimension(const Token& keyword) {
    if (mesh_.dimension == 0)
      tokens_.fail(keyword.line, "missing Dimension keyword before " + std::string(keyword.text));
  }

  void read_vertices() {
    const int count = tokens_.count("Vertices");
    mesh_.vertices.reserve(
        mesh_.vertices.size() +
        std::min(static_cast<std::size_t>(count), tokens_.entries_bound(mesh_.dimension + 1)));
    for (int i = 0; i < count; ++i) mesh_.vertices.push_back(read_vertex(i, count));
  }

  Vec3 read_vertex(int index, int count) {
    const auto describe = [&] { return entry_name("vertex", index, count, "Vertices"); };
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < mesh_.dimension; ++k) {
      p[k] = tokens_.real(describe);
      if (!std::isfinite(p[k]))
        tokens_.fail(tokens_.line(), "coordinate " + std::to_string(k + 1) + " of vertex " +
                                         std::to_string(index + 1) + " is not finite");
    }
    tokens_.integer(describe);  // reference tag: rvor keeps none for vertices
    return p;
  }

  template <std::size_t N>
  void read_elements(const std::string& section, std::vector<std::array<int, N>>& elements,
                     std::vector<int>& refs) {
    const int count = tokens_.count(section);
    const std::size_t expected =
        std::min(static_cast<std::size_t>(count), tokens_.entries_bound(static_cast<int>(N) + 1));
    elements.reserve(elements.size() + expected);
    refs.reserve(refs.size() + expected);
    for (int i = 0; i < count; ++i) {
      const auto describe = [&] { return entry_name("element", i, count, section); };
      std::array<int, N> element{};
      for (std::size_t k = 0; k < N; ++k) element[k] = read_vertex_index(section, describe);
      elements.push_back(element);
      refs.push_back(read_reference(describe));
    }
  }

  template <typename Describe>
  int read_vertex_index(const std::string& section, Describe describe) {
    const long long index = tokens_.integer(describe);
    if (index < 1)
      tokens_.fail(tokens_.line(), "vertex index " + std::to_string(index) + " in the " + section +
                                       " section is out of range (indices start at 1)");
    if (index > range_check_.largest) range_check_ = {index, tokens_.line(), section};
    return index > INT_MAX ? INT_MAX : static_cast<int>(index - 1);
  }

  template <typename Describe>
  int read_reference(Describe describe) {
    const long long ref = tokens_.integer(describe);
    if (ref < INT_MIN || ref > INT_MAX)
      tokens_.fail(tokens_.line(), "reference tag " + std::to_string(ref) + " does not fit an int");
    return static_cast<int>(ref);
  }

  void check_index_range() const {
    const auto vertex_count = static_cast<long long>(mesh_.vertices.size());
    if (range_check_.largest > vertex_count)
      tokens_.fail(range_check_.line, "vertex index " + std::to_string(range_check_.largest) +
                                          " in the " + range_check_.section +
                                          " section is out of range (the mesh has " +
                                          std::to_string(vertex_count) + " vertices)");
  }

  MeditTokens tokens_;
  MeditMesh mesh_{0, {}, {}, {}, {}, {}, {}, {}};
  IndexRangeCheck range_check_;
};

// Number of values of one solution field of Medit type `type` (1 scalar, 2 vector, 3 symmetric
// tensor, 4 full matrix); 0 for an unknown type.
int values_of_solution_type(long long type, int dimension) {
  switch (type) {
    case 1:
      return 1;
    case 2:
      return dimension;
    case 3:
      return dimension * (dimension + 1) / 2;
    case 4:
      return dimension * dimension;
    default:
      return 0;
  }
}

// The fields of a SolAtVertices section ("1 3": one field, a tensor) and where the tensor is.
struct SolutionLayout {
  std::vector<int> widths;  // values per field
  int tensor_field = -1;
};

class SolReader {
 public:
  SolReader(const std::string& path, int expected_vertices, int expected_dimension)
      : tokens_(path),
        expected_vertices_(expected_vertices),
        expected_dimension_(expected_dimension) {}

  detail::MeditSolTensors read() {
    bool found = false;
    while (!found && !tokens_.at_end()) {
      const Token keyword = tokens_.next();
      if (!starts_like_keyword(keyword.text))
        tokens_.fail(keyword.line,
                     "expected a section keyword, found " + quoted_text(keyword.text));
      found = read_section(keyword);
    }
    if (!found) tokens_.fail(tokens_.line(), "no SolAtVertices section");
    read_rest();
    return std::move(result_);
  }

 private:
  // After the tensors: other sections, up to End. A value here means the entries held more
  // values than Dimension and the solution types give them, so every tensor read was wrong.
  void read_rest() {
    while (!tokens_.at_end()) {
      const Token keyword = tokens_.next();
      if (!starts_like_keyword(keyword.text))
        tokens_.fail(keyword.line,
                     "unexpected value " + quoted_text(keyword.text) +
                         " after the SolAtVertices entries (do its entries hold more values "
                         "than Dimension " +
                         std::to_string(result_.dimension) + " and the solution types give?)");
      const std::string name = lowercase(keyword.text);
      if (name == "end") return;
      if (name == "solatvertices") tokens_.fail(keyword.line, "a second SolAtVertices section");
      skip_section(tokens_, keyword, result_.dimension);
    }
  }

  // Returns true once the SolAtVertices section is read.
  bool read_section(const Token& keyword) {
    const std::string name = lowercase(keyword.text);
    if (name == "end") tokens_.fail(keyword.line, "End before any SolAtVertices section");
    if (name == "meshversionformatted") {
      read_format_version(tokens_);
    } else if (name == "dimension") {
      read_dimension();
    } else if (name == "solatvertices") {
      if (result_.dimension == 0)
        tokens_.fail(keyword.line, "missing Dimension keyword before SolAtVertices");
      read_tensors();
      return true;
    } else {
      skip_section(tokens_, keyword, result_.dimension);
    }
    return false;
  }

  void read_dimension() {
    const long long dimension = tokens_.integer([] { return std::string("the dimension"); });
    if (dimension != 2 && dimension != 3)
      tokens_.fail(tokens_.line(),
                   "unknown dimension " + std::to_string(dimension) + " (expected 2 or 3)");
    // Before the tensors, which another dimension reads with the wrong number of values each.
    if (expected_dimension_ != 0 && dimension != expected_dimension_)
      tokens_.fail(tokens_.line(), "Dimension " + std::to_string(dimension) +
                                       ", but the mesh's Dimension is " +
                                       std::to_string(expected_dimension_));
    result_.dimension = static_cast<int>(dimension);
  }

  void read_tensors() {
    const int count = tokens_.count("SolAtVertices");
    if (expected_vertices_ >= 0 && count != expected_vertices_)
      tokens_.fail(tokens_.line(), "SolAtVertices has " + std::to_string(count) +
                                       " entries but the mesh has " +
                                       std::to_string(expected_vertices_) + " vertices");
    const SolutionLayout layout = read_layout();
    result_.tensors.reserve(std::min(static_cast<std::size_t>(count), tokens_.entries_bound(3)));
    for (int i = 0; i < count; ++i)
      result_.tensors.push_back(read_vertex_solution(layout, i, count));
  }

  // "NUMBER_OF_FIELDS TYPE..." (MMG writes "1 3"; several fields are accepted, the first tensor
  // is used).
  SolutionLayout read_layout() {
    const long long field_count =
        tokens_.integer([] { return std::string("the number of solution fields"); });
    if (field_count < 1 || field_count > 64)
      tokens_.fail(tokens_.line(), "invalid number of solution fields " +
                                       std::to_string(field_count) +
                                       " (expected a tensor (type 3))");
    SolutionLayout layout;
    std::string types;
    for (long long f = 0; f < field_count; ++f) {
      const long long type = tokens_.integer([] { return std::string("a solution type"); });
      const int width = values_of_solution_type(type, result_.dimension);
      if (width == 0)
        tokens_.fail(tokens_.line(), "unknown solution type " + std::to_string(type) +
                                         " (expected a tensor (type 3))");
      if (type == 3 && layout.tensor_field < 0) layout.tensor_field = static_cast<int>(f);
      layout.widths.push_back(width);
      types += (types.empty() ? "" : " ") + std::to_string(type);
    }
    if (layout.tensor_field < 0)
      tokens_.fail(tokens_.line(), "solution of type " + types + ": expected a tensor (type 3)");
    return layout;
  }

  Mat3 read_vertex_solution(const SolutionLayout& layout, int index, int count) {
    const auto describe = [&] { return entry_name("solution", index, count, "SolAtVertices"); };
    Mat3 tensor = Mat3::Identity();
    for (int f = 0; f < static_cast<int>(layout.widths.size()); ++f) {
      if (f == layout.tensor_field) {
        tensor = read_tensor(index, describe);
      } else {
        for (int k = 0; k < layout.widths[f]; ++k) tokens_.real(describe);
      }
    }
    return tensor;
  }

  template <typename Describe>
  Mat3 read_tensor(int index, Describe describe) {
    const int first_line = tokens_.peek().line;
    SolTensor values{};
    if (result_.dimension == 2) {
      for (int k = 0; k < 3; ++k) values[k] = tokens_.real(describe);
      values[3] = values[4] = 0.0;
      values[5] = 1.0;
    } else {
      for (double& value : values) value = tokens_.real(describe);
    }
    const Mat3 tensor = tensor_from_sol(values);
    require_spd(tensor, tokens_.path() + ":" + std::to_string(first_line) + ": tensor of vertex " +
                            std::to_string(index + 1) + " (1-based)");
    return tensor;
  }

  MeditTokens tokens_;
  int expected_vertices_;
  int expected_dimension_;  // 0: any
  detail::MeditSolTensors result_;
};

void require_writable_dimension(const std::string& path, int dimension) {
  if (dimension != 2 && dimension != 3)
    throw Error("cannot write " + path + ": dimension " + std::to_string(dimension) +
                " is not 2 or 3");
}

template <std::size_t N>
void check_elements(const std::string& path, const char* section,
                    const std::vector<std::array<int, N>>& elements, const std::vector<int>& refs,
                    std::size_t vertex_count) {
  if (!refs.empty() && refs.size() != elements.size())
    throw Error("cannot write " + path + ": " + section + " has " +
                std::to_string(elements.size()) + " elements but " + std::to_string(refs.size()) +
                " reference tags");
  for (std::size_t e = 0; e < elements.size(); ++e)
    for (int v : elements[e])
      if (v < 0 || static_cast<std::size_t>(v) >= vertex_count)
        throw Error("cannot write " + path + ": " + section + " element " + std::to_string(e) +
                    " (0-based) uses vertex " + std::to_string(v) + ", out of range 0.." +
                    std::to_string(vertex_count) + "-1");
}

template <std::size_t N>
void write_elements(std::ostream& out, const char* section,
                    const std::vector<std::array<int, N>>& elements, const std::vector<int>& refs) {
  if (elements.empty()) return;
  out << "\n" << section << "\n" << elements.size() << "\n";
  for (std::size_t e = 0; e < elements.size(); ++e) {
    for (int v : elements[e]) out << v + 1 << ' ';
    out << (refs.empty() ? 0 : refs[e]) << '\n';
  }
}

void write_vertices(std::ostream& out, const MeditMesh& mesh) {
  out << "\nVertices\n" << mesh.vertices.size() << "\n";
  for (const Vec3& p : mesh.vertices) {
    for (int k = 0; k < mesh.dimension; ++k) {
      out << exact_text(p[k]);
      out << ' ';
    }
    out << "0\n";
  }
}

}  // namespace

namespace detail {

MeditSolTensors read_medit_sol(const std::string& path, int expected_vertices,
                               int expected_dimension) {
  return SolReader(path, expected_vertices, expected_dimension).read();
}

}  // namespace detail

MeditMesh read_medit_mesh(const std::string& path) {
  return MeshReader(path).read();
}

void write_medit_mesh(const std::string& path, const MeditMesh& mesh) {
  require_writable_dimension(path, mesh.dimension);
  const std::size_t n = mesh.vertices.size();
  check_elements(path, "Edges", mesh.edges, mesh.edge_refs, n);
  check_elements(path, "Triangles", mesh.triangles, mesh.triangle_refs, n);
  check_elements(path, "Tetrahedra", mesh.tetrahedra, mesh.tetrahedron_refs, n);
  for (const Vec3& p : mesh.vertices)
    if (!p.allFinite()) throw Error("cannot write " + path + ": a vertex is not finite");
  write_file_atomically(path, [&](std::ostream& out) {
    out << "MeshVersionFormatted 2\n\nDimension " << mesh.dimension << "\n";
    write_vertices(out, mesh);
    write_elements(out, "Edges", mesh.edges, mesh.edge_refs);
    write_elements(out, "Triangles", mesh.triangles, mesh.triangle_refs);
    write_elements(out, "Tetrahedra", mesh.tetrahedra, mesh.tetrahedron_refs);
    out << "\nEnd\n";
  });
}

std::vector<Mat3> read_medit_sol_tensors(const std::string& path, int expected_vertices) {
  return detail::read_medit_sol(path, expected_vertices, 0).tensors;
}

void write_medit_sol_tensors(const std::string& path, int dimension,
                             const std::vector<Mat3>& tensors) {
  require_writable_dimension(path, dimension);
  write_file_atomically(path, [&](std::ostream& out) {
    out << "MeshVersionFormatted 2\n\nDimension " << dimension << "\n\nSolAtVertices\n"
        << tensors.size() << "\n1 3\n";
    const int values = dimension == 2 ? 3 : 6;
    for (const Mat3& G : tensors) {
      const SolTensor sol = tensor_to_sol(G);
      for (int k = 0; k < values; ++k) {
        out << exact_text(sol[k]);
        out << (k + 1 < values ? ' ' : '\n');
      }
    }
    out << "\nEnd\n";
  });
}

}  // namespace rvor
