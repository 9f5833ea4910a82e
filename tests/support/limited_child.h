#pragma once
// Running a piece of a test in a forked process under an address-space limit, to reach the
// allocation failures that budgets and estimates cannot foresee.
#include <sys/resource.h>

#include <functional>

namespace rvor::test {

// The exit code of `child` run in a forked process under an address-space limit of `limit` bytes
// above what the process maps now (none: 0), or 128 + the signal that killed it; 255 where no
// limit could be set; 2 where `child` threw.
int exit_code_in_a_child(rlim_t limit_above_now, const std::function<bool()>& child);

}  // namespace rvor::test
