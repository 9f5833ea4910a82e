#include <cstdlib>

#include "rvor/devices.h"
#include "rvor/error.h"
#include "rvor/opencl_propagator.h"
#include "rvor/propagation.h"

namespace rvor {

std::unique_ptr<Propagator> make_propagator(const std::string& device) {
  if (device == "cpu") return make_reference_propagator();
  return make_opencl_propagator(device);
}

std::unique_ptr<Propagator> make_default_propagator() {
  return with_default_device([](const std::string& name) { return make_propagator(name); });
}

bool device_name_from_environment() {
  const char* value = std::getenv("RVOR_DEVICE");
  return value && *value;
}

std::string default_device_name() {
  return device_name_from_environment() ? std::getenv("RVOR_DEVICE") : "auto";
}

}  // namespace rvor
