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

namespace {

// The file buffer throws where the system's read fails (EIO, or /proc/self/mem), with a message
// that names no file.
// `peek`: the byte is left to be read next.
int next_byte(std::streambuf& buffer, const std::string& path, long number, bool peek = false) {
  try {
    return peek ? buffer.sgetc() : buffer.sbumpc();
  } catch (const std::ios_base::failure& failure) {
    throw Error("cannot read " + path + " at line " + std::to_string(number) + ": " +
                (errno != 0 ? std::strerror(errno) : failure.what()));
  }
}

}  // namespace

bool read_input_line(std::istream& in, std::string& line, const std::string& path, long number) {
  line.clear();
  errno = 0;  // next_byte's message reads it: only a failed read sets it in the loop
  std::streambuf* buffer = in.rdbuf();
  for (;;) {
    const int c = next_byte(*buffer, path, number);
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return !line.empty();
    }
    if (c == '\n') return true;
    if (c == '\r') {  // CRLF, or CR alone: the line ends of classic Mac OS files
      if (next_byte(*buffer, path, number, true) == '\n') buffer->sbumpc();
      return true;
    }
    if (line.size() == kMaxInputLineBytes)
      throw Error(path + ":" + std::to_string(number) + ": a line longer than " +
                  std::to_string(kMaxInputLineBytes >> 20) +
                  " MiB (a binary file, or not the file meant?)");
    line.push_back(static_cast<char>(c));
  }
}

}  // namespace rvor
