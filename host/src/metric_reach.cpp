#include "rvor/metric_reach.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <Eigen/LU>

#include "rvor/metric.h"
#include "rvor/selling.h"

namespace rvor {

namespace {
constexpr std::size_t kSamples = 20000;
}  // namespace

MetricReach sampled_metric_reach(const Canvas& canvas) {
  const std::size_t stride = std::max<std::size_t>(1, canvas.slot_count() / kSamples);
  MetricReach reach;
  for (std::size_t slot = 0; slot < canvas.slot_count(); slot += stride) {
    if (!canvas.active[slot]) continue;
    const Mat3 G = canvas.metric_at(slot);
    const Eigen::VectorXd lambda = metric_eigenvalues(G, canvas.dimension);
    reach.max_anisotropy =
        std::max(reach.max_anisotropy, std::sqrt(lambda.maxCoeff() / lambda.minCoeff()));
    const SellingStencil stencil = canvas_selling_decomposition(canvas, slot, G.inverse());
    for (int i = 0; i < stencil.size; ++i)
      for (int component : stencil.offset[i])
        reach.longest_offset = std::max(reach.longest_offset, std::abs(component));
  }
  return reach;
}

}  // namespace rvor
