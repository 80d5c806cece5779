// Gray images and masks: the small image-processing toolbox the capture pipeline is built on.
#include "capture/gray.h"

#include <algorithm>
#include <cmath>

namespace emboss {

float GrayImage::sample(double x, double y) const {
  const double fx = std::clamp(x - 0.5, 0.0, width - 1.0), fy = std::clamp(y - 0.5, 0.0, height - 1.0);
  const int x0 = std::min(static_cast<int>(fx), width - 1), y0 = std::min(static_cast<int>(fy), height - 1);
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const float ax = static_cast<float>(fx - x0), ay = static_cast<float>(fy - y0);
  const float top = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * ax;
  const float bottom = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * ax;
  return top + (bottom - top) * ay;
}

size_t Mask::count() const { return static_cast<size_t>(std::count(v.begin(), v.end(), 1)); }

GrayImage toGray(const Image& image) {
  GrayImage g(image.width, image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      g.at(x, y) = 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2];
    }
  return g;
}

GrayImage downscale(const GrayImage& g, int factor) {
  if (factor <= 1) return g;
  GrayImage out((g.width + factor - 1) / factor, (g.height + factor - 1) / factor);
  std::vector<float> sum(out.v.size(), 0.0f), n(out.v.size(), 0.0f);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = static_cast<size_t>(y / factor) * out.width + x / factor;
      sum[i] += g.at(x, y);
      n[i] += 1.0f;
    }
  for (size_t i = 0; i < out.v.size(); ++i) out.v[i] = sum[i] / n[i];
  return out;
}

GrayImage gaussianBlur(const GrayImage& g, double sigma) {
  if (sigma <= 0) return g;
  const int r = std::max(1, static_cast<int>(std::ceil(3 * sigma)));
  std::vector<float> k(2 * r + 1);
  float total = 0;
  for (int i = -r; i <= r; ++i) total += k[i + r] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)));
  for (float& w : k) w /= total;
  GrayImage tmp(g.width, g.height), out(g.width, g.height);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i) s += k[i + r] * g.at(std::clamp(x + i, 0, g.width - 1), y);
      tmp.at(x, y) = s;
    }
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i) s += k[i + r] * tmp.at(x, std::clamp(y + i, 0, g.height - 1));
      out.at(x, y) = s;
    }
  return out;
}

IntegralImage::IntegralImage(int width, int height, const float* values)
    : w_(width), h_(height), s_(static_cast<size_t>(width + 1) * (height + 1), 0.0) {
  for (int y = 0; y < height; ++y) {
    double row = 0;
    for (int x = 0; x < width; ++x) {
      row += values[static_cast<size_t>(y) * width + x];
      s_[static_cast<size_t>(y + 1) * (w_ + 1) + x + 1] = s_[static_cast<size_t>(y) * (w_ + 1) + x + 1] + row;
    }
  }
}

double IntegralImage::sum(int x0, int y0, int x1, int y1) const {
  x0 = std::clamp(x0, 0, w_), x1 = std::clamp(x1, 0, w_), y0 = std::clamp(y0, 0, h_), y1 = std::clamp(y1, 0, h_);
  const size_t W = static_cast<size_t>(w_ + 1);
  return s_[y1 * W + x1] - s_[y0 * W + x1] - s_[y1 * W + x0] + s_[y0 * W + x0];
}

Components connectedComponents(const Mask& m, bool eightConnected) {
  Components c;
  c.label.assign(m.v.size(), 0);
  c.area.push_back(0);
  std::vector<int> stack;
  const int w = m.width, h = m.height;
  for (int start = 0; start < w * h; ++start) {
    if (!m.v[start] || c.label[start]) continue;
    const int id = static_cast<int>(c.area.size());
    int area = 0;
    stack.push_back(start);
    c.label[start] = id;
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      ++area;
      const int x = p % w, y = p / w;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) || (!eightConnected && dx != 0 && dy != 0)) continue;
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const int q = ny * w + nx;
          if (m.v[q] && !c.label[q]) {
            c.label[q] = id;
            stack.push_back(q);
          }
        }
    }
    c.area.push_back(area);
  }
  return c;
}

Mask fillHoles(const Mask& m) {
  // Flood the clear pixels from the border; whatever clear pixel it does not reach is a hole.
  const int w = m.width, h = m.height;
  std::vector<std::uint8_t> outside(m.v.size(), 0);
  std::vector<int> stack;
  auto seed = [&](int x, int y) {
    const int p = y * w + x;
    if (!m.v[p] && !outside[p]) outside[p] = 1, stack.push_back(p);
  };
  for (int x = 0; x < w; ++x) seed(x, 0), seed(x, h - 1);
  for (int y = 0; y < h; ++y) seed(0, y), seed(w - 1, y);
  while (!stack.empty()) {
    const int p = stack.back();
    stack.pop_back();
    const int x = p % w, y = p / w;
    if (x > 0) seed(x - 1, y);
    if (x + 1 < w) seed(x + 1, y);
    if (y > 0) seed(x, y - 1);
    if (y + 1 < h) seed(x, y + 1);
  }
  Mask out(w, h);
  for (size_t i = 0; i < out.v.size(); ++i) out.v[i] = outside[i] ? 0 : 1;
  return out;
}

}  // namespace emboss
