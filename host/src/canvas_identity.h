#pragma once
// How a propagator recognises the canvas it derived its stencils from (internal; the reference's
// stencils, the OpenCL engine's device canvas), so that it derives them again only for a canvas
// that differs (rvor/propagation.h).
#include <cstdint>
#include <optional>

#include "rvor/canvas.h"

namespace rvor {

// The canvas's content hash (Canvas::content_hash, which finalize() records) combined with what
// the call sees now: h, origin and dims, the convexity flag (which the exact start reads) and the
// activity and whole tensor of about 4096 evenly spread slots (so that a direct write not followed
// by finalize() shows if it touches one of them). None for a canvas without a content hash: it is
// never taken for another.
std::optional<std::uint64_t> canvas_identity(const Canvas& canvas);

}  // namespace rvor
