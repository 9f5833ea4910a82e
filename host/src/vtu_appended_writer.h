#pragma once
// VTK XML unstructured grids with raw appended binary data (UInt64 block headers), shared by the
// canvas and dual writers: arrays are declared in the XML with their offsets, then written after
// the `_` marker of the AppendedData section. The declared vectors must outlive write().
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "rvor/atomic_file.h"

namespace rvor::vtu {

// Writes a vector's bytes; the vector must outlive the function.
template <typename T>
std::function<void(std::ostream&)> whole_array(const std::vector<T>& data) {
  return [&data](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(data.data()),
              static_cast<std::streamsize>(data.size() * sizeof(T)));
  };
}

class AppendedWriter {
 public:
  template <typename T>
  std::string declare(const std::string& type, const std::string& name, int components,
                      const std::vector<T>& data) {
    return declare_streamed(type, name, components, data.size() * sizeof(T), whole_array(data));
  }
  // An array of `size` bytes that `write_values` writes when the file is written: arrays made on
  // the fly, never held whole (a canvas's cells: ~45 bytes per voxel).
  std::string declare_streamed(const std::string& type, const std::string& name, int components,
                               std::size_t size, std::function<void(std::ostream&)> write_values) {
    std::string xml = "<DataArray type=\"" + type + "\"";
    if (!name.empty()) xml += " Name=\"" + name + "\"";
    xml += " NumberOfComponents=\"" + std::to_string(components) +
           "\" format=\"appended\" offset=\"" + std::to_string(offset_) + "\"/>\n";
    blocks_.push_back({size, std::move(write_values)});
    offset_ += sizeof(uint64_t) + size;
    return xml;
  }
  void write(std::ostream& out) const {
    for (const auto& [size, write_values] : blocks_) {
      const uint64_t header = size;
      out.write(reinterpret_cast<const char*>(&header), sizeof header);
      write_values(out);
    }
  }

 private:
  uint64_t offset_ = 0;
  std::vector<std::pair<std::size_t, std::function<void(std::ostream&)>>> blocks_;
};

// Values written to a stream in chunks (streamed() below).
template <typename T>
class ChunkedWriter {
 public:
  explicit ChunkedWriter(std::ostream& out) : out_(out) { chunk_.reserve(std::size_t{1} << 16); }
  void push(T value) {
    chunk_.push_back(value);
    if (chunk_.size() == chunk_.capacity()) finish();
  }
  // Writes what is pushed and not yet written; call it after the last push.
  void finish() {
    out_.write(reinterpret_cast<const char*>(chunk_.data()),
               static_cast<std::streamsize>(chunk_.size() * sizeof(T)));
    chunk_.clear();
  }

 private:
  std::ostream& out_;
  std::vector<T> chunk_;
};

// An array for declare_streamed(), made as it is written: `values(push)` calls push(value) for
// each of its values in order, and they reach the stream in chunks.
template <typename T, typename Values>
std::function<void(std::ostream&)> streamed(Values values) {
  return [values](std::ostream& out) {
    ChunkedWriter<T> writer(out);
    values([&writer](T value) { writer.push(value); });
    writer.finish();
  };
}

// The XML up to and including <Points>' opening tag of a one-piece unstructured grid.
inline std::string grid_header(std::size_t points, std::size_t cells) {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
         "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece "
         "NumberOfPoints=\"" +
         std::to_string(points) + "\" NumberOfCells=\"" + std::to_string(cells) + "\">\n<Points>\n";
}

// The VTK name of a value type: the index types that connectivity and offsets may take, and the
// coordinate types of points.
template <typename T>
constexpr const char* vtk_type_name() {
  static_assert(std::is_same_v<T, int32_t> || std::is_same_v<T, int64_t> ||
                    std::is_same_v<T, float> || std::is_same_v<T, double>,
                "no VTK type name for this type");
  if constexpr (std::is_same_v<T, int32_t>) return "Int32";
  if constexpr (std::is_same_v<T, int64_t>) return "Int64";
  if constexpr (std::is_same_v<T, float>) return "Float32";
  return "Float64";
}

// The XML from the file header through </Cells>: points (3 coordinates each, float or double) and
// `cells` cells whose connectivity (`connectivity_entries` indices), offsets and types the
// functions write when the file is written (AppendedWriter::declare_streamed). Cell and point data
// sections follow.
template <typename Index, typename Real>
std::string grid_geometry_streamed(AppendedWriter& appended, const std::vector<Real>& points,
                                   std::size_t cells, std::size_t connectivity_entries,
                                   std::function<void(std::ostream&)> connectivity,
                                   std::function<void(std::ostream&)> offsets,
                                   std::function<void(std::ostream&)> types) {
  std::string xml = grid_header(points.size() / 3, cells);
  xml += appended.declare(vtk_type_name<Real>(), "", 3, points);
  xml += "</Points>\n<Cells>\n";
  xml += appended.declare_streamed(vtk_type_name<Index>(), "connectivity", 1,
                                   connectivity_entries * sizeof(Index), std::move(connectivity));
  xml += appended.declare_streamed(vtk_type_name<Index>(), "offsets", 1, cells * sizeof(Index),
                                   std::move(offsets));
  xml += appended.declare_streamed("UInt8", "types", 1, cells, std::move(types));
  return xml + "</Cells>\n";
}

// grid_geometry_streamed of arrays held whole.
template <typename Index, typename Real>
std::string grid_geometry(AppendedWriter& appended, const std::vector<Real>& points,
                          const std::vector<Index>& connectivity, const std::vector<Index>& offsets,
                          const std::vector<uint8_t>& types) {
  return grid_geometry_streamed<Index>(appended, points, types.size(), connectivity.size(),
                                       whole_array(connectivity), whole_array(offsets),
                                       whole_array(types));
}

// Closes the piece (`xml` ends after the last data section) and writes the file atomically.
inline void publish(const std::string& path, std::string xml, const AppendedWriter& appended) {
  xml += "</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        out << xml;
        appended.write(out);
        out << "\n</AppendedData>\n</VTKFile>\n";
      },
      /*binary=*/true);
}

}  // namespace rvor::vtu
