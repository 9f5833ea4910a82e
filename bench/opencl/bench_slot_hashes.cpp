// The per-slot hashes on the host (host/src/slot_hash.h): an insertion's digest of the caller's
// field (its hash and insertable check, on slot_threads() threads beside the device's rounds), a
// canvas's content hash (Canvas::finalize) and the identity every solve and insertion compares
// (canvas_identity). Slots per second; the 256^3 sizes of the standard bench cases.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <optional>
#include <vector>

#include "canvas_identity.h"
#include "field_transfer.h"
#include "rvor/canvas.h"

namespace {

constexpr int kEdge = 256;

// Tensors per slot, or one for all (`uniform`: the canvas's uniform form).
rvor::Canvas box_canvas(bool uniform = false) {
  std::vector<rvor::VoxelIndex> origins;
  for (int k = 0; k < kEdge; k += rvor::Canvas::kBrickEdge)
    for (int j = 0; j < kEdge; j += rvor::Canvas::kBrickEdge)
      for (int i = 0; i < kEdge; i += rvor::Canvas::kBrickEdge) origins.push_back({i, j, k});
  rvor::Canvas canvas;
  canvas.allocate(3, 2.0 / kEdge, rvor::Vec3::Constant(-1), {kEdge, kEdge, kEdge}, origins,
                  uniform ? std::optional<rvor::Mat3>(rvor::Mat3::Identity()) : std::nullopt);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    canvas.active[slot] = 1;
    if (uniform) continue;
    float* metric = canvas.mutable_metric(slot);
    metric[0] = metric[2] = metric[5] = 1.0f + static_cast<float>(slot % 977) * 1e-3f;
  }
  canvas.finalize();
  return canvas;
}

void BM_FieldDigest(benchmark::State& state) {
  rvor::VoronoiField field;
  const std::size_t slots = std::size_t{kEdge} * kEdge * kEdge;
  field.distance.resize(slots);
  field.label.resize(slots);
  for (std::size_t slot = 0; slot < slots; ++slot) {
    field.distance[slot] = 1e-3f * static_cast<float>(slot % 9973);
    field.label[slot] = static_cast<std::int32_t>(slot % 1000);
  }
  for (auto _ : state) benchmark::DoNotOptimize(rvor::opencl::digest_field(field, 1000));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * slots));
}

// state.range(0): 1 for the uniform form.
void BM_CanvasContentHash(benchmark::State& state) {
  rvor::Canvas canvas = box_canvas(state.range(0) == 1);
  for (auto _ : state) {
    canvas.finalize();
    benchmark::DoNotOptimize(canvas.content_hash());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * canvas.slot_count()));
}

void BM_CanvasIdentity(benchmark::State& state) {
  const rvor::Canvas canvas = box_canvas();
  for (auto _ : state) benchmark::DoNotOptimize(rvor::canvas_identity(canvas));
}

// As an insertion meets it: after the caller's field has streamed through the caches.
void BM_CanvasIdentityCold(benchmark::State& state) {
  const rvor::Canvas canvas = box_canvas();
  std::vector<std::uint64_t> evictor(std::size_t{1} << 25, 1);  // 256 MiB
  std::uint64_t sink = 0;
  for (auto _ : state) {
    state.PauseTiming();
    for (std::uint64_t& word : evictor) sink += word++;
    state.ResumeTiming();
    benchmark::DoNotOptimize(rvor::canvas_identity(canvas));
  }
  benchmark::DoNotOptimize(sink);
}

BENCHMARK(BM_FieldDigest)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CanvasContentHash)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CanvasIdentity)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CanvasIdentityCold)->Unit(benchmark::kMicrosecond)->Iterations(20);

}  // namespace
