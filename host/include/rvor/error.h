#pragma once
// Errors raised at the library boundary. Every message says what is wrong and where
// (file:line, seed index, world position, OpenCL call), so the CLI can print it as one line.
#include <stdexcept>
#include <string>

namespace rvor {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rvor
