#pragma once
// Errors raised at the library boundary. Every message says what is wrong and where
// (file:line, seed index, world position, OpenCL call), so the CLI can print it as one line.
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rvor {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The rvor::Error a std::bad_alloc becomes at the library's entry points, so that their callers
// catch one type with a message: "out of memory <doing> (std::bad_alloc): ...". (The budgets check
// the large arrays beforehand, rvor/memory_budget.h; this is what they could not foresee.)
inline Error out_of_memory_error(std::string_view doing) {
  return Error("out of memory " + std::string(doing) +
               " (std::bad_alloc): the process may not allocate more; lower the resolution or the "
               "seed count, or free memory");
}

// Runs `body`; a std::bad_alloc from it leaves as out_of_memory_error(doing).
template <typename Body>
auto naming_out_of_memory(std::string_view doing, Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    throw out_of_memory_error(doing);
  }
}

}  // namespace rvor
