#pragma once
// VTK XML unstructured grids with raw appended binary data (UInt64 block headers), shared by the
// canvas and dual writers: arrays are declared in the XML with their offsets, then written after
// the `_` marker of the AppendedData section. The declared vectors must outlive write().
#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "rvor/atomic_file.h"

namespace rvor::vtu {

class AppendedWriter {
 public:
  template <typename T>
  std::string declare(const std::string& type, const std::string& name, int components,
                      const std::vector<T>& data) {
    std::string xml = "<DataArray type=\"" + type + "\"";
    if (!name.empty()) xml += " Name=\"" + name + "\"";
    xml += " NumberOfComponents=\"" + std::to_string(components) +
           "\" format=\"appended\" offset=\"" + std::to_string(offset_) + "\"/>\n";
    blocks_.push_back({reinterpret_cast<const char*>(data.data()), data.size() * sizeof(T)});
    offset_ += sizeof(uint64_t) + data.size() * sizeof(T);
    return xml;
  }
  void write(std::ostream& out) const {
    for (const auto& [bytes, size] : blocks_) {
      const uint64_t header = size;
      out.write(reinterpret_cast<const char*>(&header), sizeof header);
      out.write(bytes, static_cast<std::streamsize>(size));
    }
  }

 private:
  uint64_t offset_ = 0;
  std::vector<std::pair<const char*, std::size_t>> blocks_;
};

// The XML up to and including <Points>' opening tag of a one-piece unstructured grid.
inline std::string grid_header(std::size_t points, std::size_t cells) {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
         "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece "
         "NumberOfPoints=\"" +
         std::to_string(points) + "\" NumberOfCells=\"" + std::to_string(cells) + "\">\n<Points>\n";
}

// The VTK name of the index types that connectivity and offsets may take.
template <typename Index>
const char* index_type_name();
template <>
inline const char* index_type_name<int32_t>() {
  return "Int32";
}
template <>
inline const char* index_type_name<int64_t>() {
  return "Int64";
}

// The XML from the file header through </Cells>: points (3 floats each) and cells, declared in
// `appended`. Cell and point data sections follow.
template <typename Index>
std::string grid_geometry(AppendedWriter& appended, const std::vector<float>& points,
                          const std::vector<Index>& connectivity, const std::vector<Index>& offsets,
                          const std::vector<uint8_t>& types) {
  std::string xml = grid_header(points.size() / 3, types.size());
  xml += appended.declare("Float32", "", 3, points);
  xml += "</Points>\n<Cells>\n";
  xml += appended.declare(index_type_name<Index>(), "connectivity", 1, connectivity);
  xml += appended.declare(index_type_name<Index>(), "offsets", 1, offsets);
  xml += appended.declare("UInt8", "types", 1, types);
  return xml + "</Cells>\n";
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
