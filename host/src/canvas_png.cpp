#include "rvor/canvas_png.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <cairo.h>

#include "rvor/atomic_file.h"
#include "rvor/curved_dual.h"
#include "rvor/dual.h"
#include "rvor/error.h"

namespace rvor {

namespace {

// A well-spread hue per label (golden-ratio steps), as RGB in [0, 1].
void label_colour(int label, double& r, double& g, double& b) {
  const double hue = std::fmod(0.618033988749895 * label, 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
  const int sector = static_cast<int>(hue);
  const double rgb[6][3] = {{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}};
  r = 0.35 + 0.55 * rgb[sector][0];
  g = 0.35 + 0.55 * rgb[sector][1];
  b = 0.35 + 0.55 * rgb[sector][2];
}

// Pixel bytes of the labelled canvas (cairo's native-endian ARGB32), y pointing up.
void paint_cells(const Canvas& canvas, const VoronoiField& field, int scale, unsigned char* data,
                 int stride, double band) {
  const int height = canvas.dims[1] * scale;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot) {
    if (!canvas.active[slot] || field.label[slot] < 0) continue;
    const VoxelIndex v = canvas.voxel_of(slot);
    double r, g, b;
    label_colour(field.label[slot], r, g, b);
    // Alternating iso-distance bands: the shapes of the metric's unit balls.
    const double shade = static_cast<int>(field.distance[slot] / band) % 2 == 0 ? 1.0 : 0.88;
    const uint32_t pixel = 0xFF000000u | (static_cast<uint32_t>(255 * r * shade) << 16) |
                           (static_cast<uint32_t>(255 * g * shade) << 8) |
                           static_cast<uint32_t>(255 * b * shade);
    for (int dy = 0; dy < scale; ++dy) {
      auto* row = reinterpret_cast<uint32_t*>(data + (height - 1 - (v.j * scale + dy)) * stride);
      std::fill(row + v.i * scale, row + (v.i + 1) * scale, pixel);
    }
  }
}

void draw_dual(cairo_t* cr, const Canvas& canvas, const StraightDual& dual, int scale) {
  const double height = canvas.dims[1] * scale;
  auto to_pixel = [&](const Vec3& p) {
    const Vec3 c = canvas.index_coordinates(p);
    return std::pair<double, double>((c.x() + 0.5) * scale, height - (c.y() + 0.5) * scale);
  };
  cairo_set_line_width(cr, std::max(1.0, scale * 0.35));
  cairo_set_source_rgba(cr, 0.05, 0.05, 0.05, 0.85);
  for (const auto& edge : dual.edges) {
    const auto [x0, y0] = to_pixel(dual.vertices[edge[0]]);
    const auto [x1, y1] = to_pixel(dual.vertices[edge[1]]);
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
  }
  cairo_stroke(cr);
}

// Thinner than the straight edges and in red, so that both stay visible where they coincide.
void draw_curved_edges(cairo_t* cr, const Canvas& canvas, const CurvedDual& curved, int scale) {
  const double height = canvas.dims[1] * scale;
  cairo_set_line_width(cr, std::max(1.0, scale * 0.2));
  cairo_set_source_rgba(cr, 0.8, 0.05, 0.05, 0.9);
  for (const CurvedEdge& edge : curved.edges)
    for (std::size_t p = 0; p < edge.points.size(); ++p) {
      const Vec3 c = canvas.index_coordinates(edge.points[p]);
      const double x = (c.x() + 0.5) * scale, y = height - (c.y() + 0.5) * scale;
      if (p == 0)
        cairo_move_to(cr, x, y);
      else
        cairo_line_to(cr, x, y);
    }
  cairo_stroke(cr);
}

void draw_seeds(cairo_t* cr, const Canvas& canvas, const std::vector<Vec3>& seeds, int scale) {
  const double height = canvas.dims[1] * scale;
  cairo_set_source_rgb(cr, 0, 0, 0);
  for (const Vec3& s : seeds) {
    const Vec3 c = canvas.index_coordinates(s);
    cairo_arc(cr, (c.x() + 0.5) * scale, height - (c.y() + 0.5) * scale, std::max(1.5, scale * 0.8),
              0, 2 * M_PI);
    cairo_fill(cr);
  }
}

// Pixels per voxel side: as asked, or about 1024 pixels along the longest side, at least one.
int png_scale(const Canvas& canvas, int pixels_per_voxel) {
  const int longest = std::max(canvas.dims[0], canvas.dims[1]);
  return pixels_per_voxel > 0 ? pixels_per_voxel : std::max(1, 1024 / longest);
}

}  // namespace

std::array<long long, 2> canvas_png_size(const Canvas& canvas, int pixels_per_voxel) {
  const long long scale = png_scale(canvas, pixels_per_voxel);
  return {canvas.dims[0] * scale, canvas.dims[1] * scale};
}

void require_drawable_png(const Canvas& canvas, int pixels_per_voxel, const std::string& where) {
  const std::array<long long, 2> size = canvas_png_size(canvas, pixels_per_voxel);
  if (std::max(size[0], size[1]) <= kLargestPngSide) return;
  throw Error(where + ": a picture of this " + std::to_string(canvas.dims[0]) + "x" +
              std::to_string(canvas.dims[1]) + "-voxel canvas would be " + std::to_string(size[0]) +
              "x" + std::to_string(size[1]) + " pixels, and cairo draws at most " +
              std::to_string(kLargestPngSide) + " a side");
}

void write_canvas_png(const std::string& path, const Canvas& canvas, const VoronoiField& field,
                      const std::vector<Vec3>& seeds, const StraightDual* dual,
                      const CurvedDual* curved, int pixels_per_voxel) {
  if (canvas.dimension != 2)
    throw Error("a PNG picture needs a 2D canvas (--png is for rect domains)");
  require_field_for(canvas, field, "cannot write " + path);
  if (dual) require_consistent_dual(*dual, "cannot write " + path);
  require_drawable_png(canvas, pixels_per_voxel, "cannot write " + path);
  const std::array<long long, 2> size = canvas_png_size(canvas, pixels_per_voxel);
  const int scale = png_scale(canvas, pixels_per_voxel);
  const int width = static_cast<int>(size[0]), height = static_cast<int>(size[1]);
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS)
    throw Error("cannot write " + path + ": cairo could not allocate a " + std::to_string(width) +
                "x" + std::to_string(height) + " picture");
  cairo_surface_flush(surface);
  double max_distance = 0;
  for (std::size_t slot = 0; slot < canvas.slot_count(); ++slot)
    if (canvas.active[slot] && std::isfinite(field.distance[slot]))
      max_distance = std::max(max_distance, static_cast<double>(field.distance[slot]));
  paint_cells(canvas, field, scale, cairo_image_surface_get_data(surface),
              cairo_image_surface_get_stride(surface), std::max(max_distance / 12, 1e-12));
  cairo_surface_mark_dirty(surface);
  cairo_t* cr = cairo_create(surface);
  if (dual) draw_dual(cr, canvas, *dual, scale);
  if (curved) draw_curved_edges(cr, canvas, *curved, scale);
  draw_seeds(cr, canvas, seeds, scale);
  cairo_destroy(cr);
  const std::string temporary = temporary_path_for(path);
  const cairo_status_t status = cairo_surface_write_to_png(surface, temporary.c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS)
    throw Error("cannot write " + path + ": " + cairo_status_to_string(status));
  publish_temporary(temporary, path);
}

}  // namespace rvor
