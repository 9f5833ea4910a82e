#include "rvor/input_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "rvor/error.h"

namespace rvor {

std::ifstream open_input_file(const std::string& path, const std::string& what) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw Error("cannot read " + what + " " + path + ": it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read " + what + " " + path + ": " + std::strerror(errno));
  return in;
}

}  // namespace rvor
