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
  const std::string device = default_device_name();
  const char* environment = std::getenv("RVOR_DEVICE");
  if (!environment || !*environment) return make_propagator(device);
  try {
    return make_propagator(device);
  } catch (const Error& error) {
    throw Error("RVOR_DEVICE=" + device + ": " + error.what());
  }
}

std::string default_device_name() {
  const char* value = std::getenv("RVOR_DEVICE");
  return value && *value ? value : "auto";
}

}  // namespace rvor
