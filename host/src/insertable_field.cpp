// The check of a field that insert() starts from (rvor/propagation.h).
#include <cmath>
#include <string>

#include "rvor/error.h"
#include "rvor/propagation.h"

namespace rvor {

namespace {

std::string label_range(std::size_t solved_seeds) {
  return solved_seeds == 0 ? "-1 only, no seed was solved"
                           : "-1 to " + std::to_string(solved_seeds - 1);
}

// What makes a slot fail insertable_slot.
std::string slot_fault(float distance, std::int32_t label, std::size_t solved_seeds) {
  if (label < -1 || (label >= 0 && static_cast<std::size_t>(label) >= solved_seeds))
    return "label " + std::to_string(label) + " (labels " + label_range(solved_seeds) + ")";
  if (std::isnan(distance)) return "distance NaN";
  if (distance < 0.0f) return "distance " + std::to_string(distance) + " (below 0)";
  if (label < 0 && std::isfinite(distance))
    return "distance " + std::to_string(distance) + " without a label";
  return "label " + std::to_string(label) + " without a distance";
}

}  // namespace

void require_insertable_field(const Canvas& canvas, const VoronoiField& field,
                              std::size_t solved_seeds, const std::string& what) {
  require_field_for(canvas, field, what);
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (insertable_slot(field.distance[slot], field.label[slot], solved_seeds)) continue;
    const std::string fault = slot_fault(field.distance[slot], field.label[slot], solved_seeds);
    const VoxelIndex v = canvas.voxel_of(slot);
    throw Error(what + ": the field is not one solved for the first " +
                std::to_string(solved_seeds) + " seeds: slot " + std::to_string(slot) + " (voxel " +
                std::to_string(v.i) + ", " + std::to_string(v.j) + ", " + std::to_string(v.k) +
                ") has " + fault + "; pass the field that solve() or insert() returned");
  }
}

void require_first_new(std::size_t first_new, std::size_t seed_count) {
  if (first_new > seed_count)
    throw Error("insert(): first_new " + std::to_string(first_new) + " is past the last of the " +
                std::to_string(seed_count) + " seeds");
}

void require_solved_for_these_seeds(std::size_t solved_seeds, std::size_t unchanged,
                                    std::size_t first_new) {
  if (solved_seeds != first_new)
    throw Error("insert(): the field is this propagator's solve of " +
                std::to_string(solved_seeds) +
                " seeds, not of first_new = " + std::to_string(first_new));
  if (unchanged < first_new)
    throw Error("insert(): the field is this propagator's solve of other seeds: seed " +
                std::to_string(unchanged) + " is not the one it was solved with");
}

}  // namespace rvor
