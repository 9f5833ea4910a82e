#pragma once
// OpenCL C sources of kernels/, embedded at build time.
#include <map>
#include <string>

namespace rvor {
const std::map<std::string, std::string>& embedded_kernel_sources();
// Throws std::runtime_error when no kernel file of that name was embedded.
const std::string& embedded_kernel_source(const std::string& name);
}  // namespace rvor
