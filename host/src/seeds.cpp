#include "rvor/seeds.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <sstream>

#include "rvor/atomic_file.h"
#include "rvor/error.h"
#include "rvor/input_file.h"
#include "rvor/spec_text.h"

namespace rvor {

namespace {

// Six significant digits, in exponent form where needed: "1e-300", not std::to_string's "0.000000".
std::string format_number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

std::string format_point(const Vec3& p) {
  return "(" + format_number(p.x()) + ", " + format_number(p.y()) + ", " + format_number(p.z()) +
         ")";
}

// The number fields of a line: split at its commas, or at its semicolons, where it has any, else
// at its blanks. One kind of separator per line, spaced alike: a decimal comma read as a
// separator would give a point of other coordinates ("0.5 0,5", "1;2,5" and "0.5, 0,5" as
// (0.5, 0, 5), (1, 2, 5) and (0.5, 0, 5)), so such lines are refused (nullopt), as are empty
// fields ("1,,2", ",1,2").
std::optional<std::vector<std::string>> number_fields(const std::string& line) {
  constexpr const char* kBlanks = " \t";
  std::vector<std::string> fields;
  const bool commas = line.find(',') != std::string::npos;
  const bool semicolons = line.find(';') != std::string::npos;
  if (!commas && !semicolons) {
    std::istringstream in(line);
    for (std::string token; in >> token;) fields.push_back(token);
    return fields;
  }
  if (commas && semicolons) return std::nullopt;
  std::optional<bool> blank_after;  // whether a blank follows each separator, alike on the line
  for (const std::string& field : split_at(line, commas ? ',' : ';')) {
    const std::size_t first = field.find_first_not_of(kBlanks);
    if (first == std::string::npos) return std::nullopt;
    const std::size_t last = field.find_last_not_of(kBlanks);
    const std::string number = field.substr(first, last - first + 1);
    if (number.find_first_of(kBlanks) != std::string::npos) return std::nullopt;
    if (!fields.empty()) {
      const bool blank = first != 0;
      if (blank_after && *blank_after != blank) return std::nullopt;
      blank_after = blank;
    }
    fields.push_back(number);
  }
  return fields;
}

// Parses 2 or 3 numbers (number_fields); nothing else may follow. Returns how many, 0 on a
// malformed line.
int parse_point(const std::string& line, Vec3& point) {
  const std::optional<std::vector<std::string>> fields = number_fields(line);
  if (!fields || (fields->size() != 2 && fields->size() != 3)) return 0;
  double values[3] = {0, 0, 0};
  for (std::size_t i = 0; i < fields->size(); ++i) {
    const std::optional<double> value = parse_decimal((*fields)[i]);
    if (!value) return 0;
    values[i] = *value;
  }
  point = Vec3(values[0], values[1], values[2]);
  return static_cast<int>(fields->size());
}

struct PointFile {
  std::vector<Vec3> points;
  std::vector<int> lines;  // each point's line, for messages
  int columns = 0;         // coordinates per line, the same on every line
};

PointFile read_point_file(const std::string& path) {
  InputFile in = open_input_file(path, "point file");
  PointFile file;
  std::string line;
  for (int number = 1; read_input_line(in, line, path, number); ++number) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    Vec3 point;
    const int columns = parse_point(line, point);
    if (columns == 0)
      throw Error(where +
                  "expected 2 or 3 finite numbers (within double's range) per line, separated by "
                  "blanks, by commas or by semicolons, one kind spaced alike (a decimal comma?), "
                  "got " +
                  quoted_text(line));
    if (file.columns != 0 && columns != file.columns)
      throw Error(where + std::to_string(columns) + " coordinates, but the lines before have " +
                  std::to_string(file.columns));
    file.columns = columns;
    file.points.push_back(point);
    file.lines.push_back(number);
  }
  if (in.bad())
    throw Error(path + ": read error after line " +
                std::to_string(file.lines.empty() ? 0 : file.lines.back()));
  if (file.points.empty()) throw Error(path + ": no points in file");
  return file;
}

// The active slots of a canvas in slot order, by rank, without listing them (a list takes 8 bytes
// per active voxel: 1 GB at 512^3 to draw a few seeds): the actives before each brick.
class ActiveSlotRanks {
 public:
  explicit ActiveSlotRanks(const Canvas& canvas)
      : canvas_(canvas), before_(canvas.brick_count() + 1) {
    const auto volume = static_cast<std::size_t>(canvas.brick_volume());
    for (std::size_t brick = 0; brick < canvas.brick_count(); ++brick) {
      const auto first = canvas.active.begin() + static_cast<std::ptrdiff_t>(brick * volume);
      before_[brick + 1] = before_[brick] + static_cast<std::size_t>(std::count_if(
                                                first, first + static_cast<std::ptrdiff_t>(volume),
                                                [](std::uint8_t a) { return a != 0; }));
    }
  }
  std::size_t size() const { return before_.back(); }
  // The slot of the active voxel of that rank (rank < size()).
  std::size_t slot_of(std::size_t rank) const {
    const std::size_t brick =
        static_cast<std::size_t>(std::upper_bound(before_.begin(), before_.end(), rank) -
                                 before_.begin()) -
        1;
    std::size_t left = rank - before_[brick];
    std::size_t slot = brick * static_cast<std::size_t>(canvas_.brick_volume());
    for (;; ++slot)
      if (canvas_.active[slot] && left-- == 0) return slot;
  }

 private:
  const Canvas& canvas_;
  std::vector<std::size_t> before_;
};

}  // namespace

std::vector<Vec3> read_xyz(const std::string& path) {
  return read_point_file(path).points;
}

std::vector<Vec3> read_xyz(const std::string& path, int dimension) {
  return read_xyz_with_lines(path, dimension).points;
}

XyzPoints read_xyz_with_lines(const std::string& path, int dimension) {
  if (dimension != 2 && dimension != 3)
    throw Error("reading " + path + ": dimension must be 2 or 3, not " + std::to_string(dimension));
  PointFile file = read_point_file(path);
  if (dimension == 3 && file.columns != 3)
    throw Error(path + ": 2 coordinates per point, but the domain is 3D (give x y z)");
  if (dimension == 2)
    for (std::size_t n = 0; n < file.points.size(); ++n)
      if (file.points[n].z() != 0.0)
        throw Error(path + ":" + std::to_string(file.lines[n]) + ": z = " +
                    format_number(file.points[n].z()) + ", but the domain is 2D (z must be 0)");
  return {std::move(file.points), std::move(file.lines)};
}

void write_xyz(const std::string& path, const std::vector<Vec3>& points, int dimension) {
  if (dimension != 2 && dimension != 3)
    throw Error("cannot write " + path + ": dimension must be 2 or 3, not " +
                std::to_string(dimension));
  // read_xyz refuses them: a file it cannot read back is not written.
  for (std::size_t n = 0; n < points.size(); ++n)
    if (!points[n].head(dimension).allFinite())
      throw Error("cannot write " + path + ": point " + std::to_string(n) + " at " +
                  format_point(points[n]) + " is not finite");
  write_file_atomically(path, [&](std::ostream& out) {
    for (const Vec3& p : points) {
      out << exact_text(p.x()) << " " << exact_text(p.y());
      if (dimension == 3) out << " " << exact_text(p.z());
      out << "\n";
    }
  });
}

void validate_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds,
                    std::size_t first_unchecked) {
  validate_seeds(canvas, seeds, first_unchecked,
                 [](std::size_t n) { return "seed " + std::to_string(n); });
}

void validate_seeds(const Canvas& canvas, const std::vector<Vec3>& seeds,
                    std::size_t first_unchecked,
                    const std::function<std::string(std::size_t)>& name) {
  canvas.require_consistent();  // the seeds are looked up in its bricks, and then solved on it
  if (canvas.active_voxel_count == 0) throw Error(kEmptyCanvasMessage);
  if (seeds.empty()) throw Error("no seeds given");
  // More seeds than voxels leave some without a cell, and the seed blocks' claims cost the square
  // of the seeds around a voxel (20 000 seeds on a 32^2 canvas ran for minutes).
  if (seeds.size() > canvas.active_voxel_count)
    throw Error(std::to_string(seeds.size()) + " seeds on a canvas of " +
                std::to_string(canvas.active_voxel_count) + " active voxels: at least " +
                std::to_string(seeds.size() - canvas.active_voxel_count) +
                " would share a voxel and own none; raise the resolution or give fewer seeds");
  for (std::size_t n = first_unchecked; n < seeds.size(); ++n) {
    const Vec3& s = seeds[n];
    if (!s.allFinite()) throw Error(name(n) + " has a coordinate that is not finite");
    if (canvas.slot_of(canvas.voxel_containing(s)) < 0)
      throw Error(name(n) + " at " + format_point(s) +
                  " is outside the domain (its voxel is not an active canvas voxel: the canvas "
                  "holds the voxels whose centres lie in the domain, so a point within half a "
                  "voxel of its boundary can fall outside)");
  }
}

std::vector<Vec3> random_seeds(const Canvas& canvas, std::size_t count, std::uint64_t rng_seed) {
  if (canvas.active_voxel_count == 0) throw Error("cannot draw seeds on an empty canvas");
  if (count > canvas.active_voxel_count)
    throw Error("cannot draw " + std::to_string(count) + " seeds on a canvas of " +
                std::to_string(canvas.active_voxel_count) +
                " active voxels: seeds sharing a voxel have empty cells");
  const ActiveSlotRanks ranks(canvas);
  std::mt19937_64 random(rng_seed);
  std::uniform_int_distribution<std::size_t> pick(0, ranks.size() - 1);
  std::uniform_real_distribution<double> jitter(-0.49, 0.49);
  // Distinct voxels (two seeds in one voxel leave one an empty cell): a voxel drawn again is drawn
  // anew, which leaves the draws before the first repeat as they were. Past half the canvas,
  // repeats would be most draws: a shuffle's first `count` voxels instead.
  const bool shuffled = 2 * count > ranks.size();
  std::vector<std::size_t> shuffled_slots;
  if (shuffled) {
    shuffled_slots.reserve(ranks.size());
    for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
      if (canvas.active[slot]) shuffled_slots.push_back(slot);
    std::shuffle(shuffled_slots.begin(), shuffled_slots.end(), random);
  }
  std::vector<bool> taken(shuffled ? 0 : ranks.size(), false);
  std::vector<Vec3> seeds;
  seeds.reserve(count);
  for (std::size_t n = 0; n < count; ++n) {
    // Drawn one statement at a time: the order of a call's arguments is the compiler's choice.
    const double z = canvas.dimension == 3 ? jitter(random) : 0.0;
    const double y = jitter(random);
    const double x = jitter(random);
    const Vec3 offset(x, y, z);
    std::size_t slot = 0;
    if (shuffled) {
      slot = shuffled_slots[n];
    } else {
      std::size_t rank = 0;
      do rank = pick(random);
      while (taken[rank]);
      taken[rank] = true;
      slot = ranks.slot_of(rank);
    }
    seeds.push_back(canvas.world_of(slot) + canvas.voxel_size * offset);
  }
  return seeds;
}

}  // namespace rvor
