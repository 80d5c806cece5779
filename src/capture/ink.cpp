// Ink on paper: Sauvola's local threshold and a local white level from integral images.
#include "capture/ink.h"

#include <algorithm>
#include <cmath>

namespace emboss {

Mask inkMask(const GrayImage& paper, const InkOptions& options) {
  const int w = paper.width, h = paper.height, r = options.window / 2;
  std::vector<float> sq(paper.v.size());
  for (size_t i = 0; i < sq.size(); ++i) sq[i] = paper.v[i] * paper.v[i];
  const IntegralImage sum(w, h, paper.v.data()), sum2(w, h, sq.data());
  Mask ink(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1), y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
      const double n = double(x1 - x0) * (y1 - y0);
      const double m = sum.sum(x0, y0, x1, y1) / n;
      const double var = std::max(0.0, sum2.sum(x0, y0, x1, y1) / n - m * m);
      const double t = std::min(m * (1 + options.k * (std::sqrt(var) / options.range - 1)), m - options.minStep);
      ink.at(x, y) = paper.at(x, y) < t;
    }
  return ink;
}

GrayImage paperWhite(const GrayImage& paper, const Mask& ink, int radius) {
  const int w = paper.width, h = paper.height, r = radius;
  std::vector<float> val(paper.v.size()), one(paper.v.size());
  for (size_t i = 0; i < val.size(); ++i) {
    one[i] = ink.v[i] ? 0.0f : 1.0f;
    val[i] = one[i] * paper.v[i];
  }
  const IntegralImage sumV(w, h, val.data()), sumN(w, h, one.data()), sumAll(w, h, paper.v.data());
  GrayImage white(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x0 = x - r, x1 = x + r + 1, y0 = y - r, y1 = y + r + 1;
      const double n = sumN.sum(x0, y0, x1, y1);
      // Mostly ink around here (a filled area): the plain mean is the best guess left.
      white.at(x, y) = n >= 8 ? static_cast<float>(sumV.sum(x0, y0, x1, y1) / n)
                              : static_cast<float>(sumAll.sum(x0, y0, x1, y1) / (double(std::min(w, x1) - std::max(0, x0)) * (std::min(h, y1) - std::max(0, y0))));
    }
  return white;
}

}  // namespace emboss
