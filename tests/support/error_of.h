#pragma once
// The message of an expected rvor::Error, for tests that check what it says.
#include <functional>
#include <string>

#include "rvor/error.h"

namespace rvor::test {

// The message of the rvor::Error `action` throws, or "" when it throws none.
inline std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

}  // namespace rvor::test
