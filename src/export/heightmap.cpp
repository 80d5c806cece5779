// Height map: interval descent down each column, bisection at the top, libpng for the file.
#include "export/heightmap.h"

#include <png.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

#include "frep/interval.h"
#include "frep/op_grid.h"
#include "render/thread_pool.h"

namespace emboss {

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

class Column {
 public:
  Column(const Model& model, std::span<const std::uint32_t> cand, double x, double y, double tol)
      : box_(model, Interval(x), Interval(y), cand), point_(model, x, y, cand), tol_(tol) {}

  // Whether [lo, hi] is proven free of metal.
  bool empty(double lo, double hi) const { return lo >= hi || box_(Interval{lo, hi}).hi < 0.0; }

  // The highest z in [lo, hi] where the model is >= 0 (metal), or NaN.
  double top(double lo, double hi) {
    const Interval f = box_(Interval{lo, hi});
    if (f.hi < 0.0) return kNone;
    if (f.lo >= 0.0) return hi;
    if (hi - lo <= tol_) return leaf(lo, hi);
    const double mid = 0.5 * (lo + hi);
    const double up = top(mid, hi);
    return std::isnan(up) ? top(lo, mid) : up;
  }

 private:
  double at(double z) const { return point_(z); }

  double leaf(double lo, double hi) {
    constexpr int kSteps = 4;
    double above = hi;
    for (int s = 0; s <= kSteps; ++s) {
      const double z = hi - (hi - lo) * s / kSteps;
      if (at(z) >= 0.0) {
        if (s == 0) return hi;
        double in = z, out = above;
        for (int i = 0; i < 40 && out - in > 1e-5; ++i) {  // 10 nm: under a 16-bit step of any relief
          const double m = 0.5 * (in + out);
          (at(m) >= 0.0 ? in : out) = m;
        }
        return 0.5 * (in + out);
      }
      above = z;
    }
    return kNone;
  }

  // f down the column, the offsets under it summed once for each (Model::Line).
  const Model::Line<Interval> box_;
  const Model::Line<double> point_;
  double tol_;
};

}  // namespace

Result<HeightMap> heightMap(const Model& model, const HeightMapOptions& options) {
  const Box3 b = model.bounds();
  const double w = b.x1 - b.x0, h = b.y1 - b.y0;
  if (!(w > 0.0 && h > 0.0 && b.z1 > b.z0)) return fail("the model has empty bounds (nothing to map)");
  double pixel = options.pixel > 0.0 ? options.pixel : 0.1;
  pixel = std::max(pixel, std::max(w, h) / std::max(1, options.maxSide));
  HeightMap map;
  map.pixel = pixel;
  map.width = std::max(1, static_cast<int>(std::ceil(w / pixel)));
  map.height = std::max(1, static_cast<int>(std::ceil(h / pixel)));
  map.x0 = 0.5 * (b.x0 + b.x1) - 0.5 * (map.width - 1) * pixel;
  map.y1 = 0.5 * (b.y0 + b.y1) + 0.5 * (map.height - 1) * pixel;
  std::vector<double> z(static_cast<size_t>(map.width) * map.height, kNone);

  OpGrid grid;
  grid.sync(model);
  ThreadPool pool(options.threads);
  std::atomic<int> rowsDone{0};
  std::mutex progressMutex;
  int lastPercent = -1;
  const double tol = std::min(0.25 * pixel, 0.05);
  const double window = 0.5;  // mm either side of the last pixel's height
  pool.parallelFor2D(Rect{0, 0, 1, map.height}, 1, [&](const Rect& r) {
    std::vector<std::uint32_t> scratch;
    for (int row = r.y; row < r.y + r.h; ++row) {
      const double y = map.y1 - row * pixel;
      double prev = kNone;
      for (int col = 0; col < map.width; ++col) {
        const double x = map.x0 + col * pixel;
        Column column(model, grid.at(x, y, scratch), x, y, tol);
        // The face is continuous almost everywhere: look near the last pixel's height first, and
        // take what is found there once the column above it is proven empty.
        double top = kNone;
        if (!std::isnan(prev)) {
          const double lo = std::max(b.z0, prev - window), hi = std::min(b.z1, prev + window);
          top = column.top(lo, hi);
          if (std::isnan(top) || !column.empty(hi, b.z1)) top = kNone;
        }
        if (std::isnan(top)) top = column.top(b.z0, b.z1);
        z[static_cast<size_t>(row) * map.width + col] = prev = top;
      }
      const int done = ++rowsDone;
      if (options.progress) {
        std::lock_guard<std::mutex> lock(progressMutex);
        const int percent = done * 100 / map.height;
        if (percent != lastPercent) {
          lastPercent = percent;
          options.progress(static_cast<double>(done) / map.height);
        }
      }
    }
  });

  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : z)
    if (!std::isnan(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (!(lo <= hi)) return fail("no metal found on the plate (nothing to map)");
  if (hi - lo < 1e-6) hi = lo + 1e-6;
  map.zMin = lo;
  map.zMax = hi;
  map.values.resize(z.size());
  for (size_t i = 0; i < z.size(); ++i)
    map.values[i] = std::isnan(z[i]) ? 0 : static_cast<std::uint16_t>(1 + std::lround((z[i] - lo) / (hi - lo) * 65534.0));
  return map;
}

Result<std::string> heightMapPng(const HeightMap& map, const std::string& title) {
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return fail("libpng: cannot start a PNG");
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return fail("libpng: cannot write the height map");
  }
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, png_size_t n) {
        static_cast<std::string*>(png_get_io_ptr(p))->append(reinterpret_cast<const char*>(data), n);
      },
      nullptr);
  png_set_IHDR(png, info, map.width, map.height, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  const auto perMetre = static_cast<png_uint_32>(std::lround(1000.0 / map.pixel));
  png_set_pHYs(png, info, perMetre, perMetre, PNG_RESOLUTION_METER);
  auto fmt = [](double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return std::string(buf);
  };
  const std::string pixel = fmt(map.pixel), zMin = fmt(map.zMin), zMax = fmt(map.zMax);
  const std::string origin = fmt(map.x0) + " " + fmt(map.y1);
  const std::string comment = "Height of the front face: z_mm = " + zMin + " + (v - 1) * (" + zMax + " - " + zMin +
                              ") / 65534; v = 0: no metal. Pixel " + pixel + " mm; pixel (0,0) is centred at x,y = " +
                              origin + " mm; rows run toward -y.";
  std::string t = title.empty() ? "emboss height map" : title;
  png_text text[6] = {};
  const char* keys[6] = {"Title", "Comment", "emboss:pixel_mm", "emboss:z_min_mm", "emboss:z_max_mm", "emboss:origin_mm"};
  const std::string* values[6] = {&t, &comment, &pixel, &zMin, &zMax, &origin};
  for (int i = 0; i < 6; ++i) {
    text[i].compression = PNG_TEXT_COMPRESSION_NONE;
    text[i].key = const_cast<char*>(keys[i]);
    text[i].text = const_cast<char*>(values[i]->c_str());
  }
  png_set_text(png, info, text, 6);
  png_write_info(png, info);
  std::vector<png_byte> row(static_cast<size_t>(map.width) * 2);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const std::uint16_t v = map.values[static_cast<size_t>(y) * map.width + x];
      row[2 * x] = static_cast<png_byte>(v >> 8);  // PNG is big-endian
      row[2 * x + 1] = static_cast<png_byte>(v & 0xff);
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

}  // namespace emboss
