#include "rvor/error.h"
#include "rvor/propagation.h"

namespace rvor {

std::unique_ptr<Propagator> make_propagator(const std::string& device) {
  if (device == "cpu") return make_reference_propagator();
  throw Error("unknown device '" + device + "': use --device cpu");
}

}  // namespace rvor
