// Gray images and masks for the capture pipeline: luminance, box and Gaussian filters, bilinear sampling.
#pragma once

#include <cstdint>
#include <vector>

#include "render/image.h"

namespace emboss {

// Pixel coordinates: pixel (i, j) covers [i, i+1) x [j, j+1), its centre is (i + 0.5, j + 0.5),
// x right, y down. Everything in src/capture uses this convention.

// One float channel, row-major; values 0..255 for luminance.
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<float> v;

  GrayImage() = default;
  GrayImage(int w, int h, float fill = 0.0f) : width(w), height(h), v(static_cast<size_t>(w) * h, fill) {}
  float& at(int x, int y) { return v[static_cast<size_t>(y) * width + x]; }
  float at(int x, int y) const { return v[static_cast<size_t>(y) * width + x]; }
  // Bilinear at continuous coordinates (pixel centres at +0.5), clamped at the border.
  float sample(double x, double y) const;
};

// A binary image, 1 set and 0 clear, row-major.
struct Mask {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> v;

  Mask() = default;
  Mask(int w, int h) : width(w), height(h), v(static_cast<size_t>(w) * h, 0) {}
  std::uint8_t& at(int x, int y) { return v[static_cast<size_t>(y) * width + x]; }
  std::uint8_t at(int x, int y) const { return v[static_cast<size_t>(y) * width + x]; }
  // 0 outside the image.
  std::uint8_t get(int x, int y) const { return x < 0 || y < 0 || x >= width || y >= height ? 0 : at(x, y); }
  size_t count() const;
};

// Luminance 0..255 (Rec. 601 weights on the stored values; alpha ignored).
GrayImage toGray(const Image& image);
// The mean of each factor x factor block (the last partial blocks included).
GrayImage downscale(const GrayImage& g, int factor);
// Separable Gaussian, the border clamped.
GrayImage gaussianBlur(const GrayImage& g, double sigma);

// Summed-area table with one extra row and column of zeros: the sum over [x0, x1) x [y0, y1).
class IntegralImage {
 public:
  IntegralImage(int width, int height, const float* values);
  double sum(int x0, int y0, int x1, int y1) const;

 private:
  int w_ = 0, h_ = 0;
  std::vector<double> s_;
};

// 4-connected components of the set pixels: a label per pixel (0 clear, 1.. components) and each
// component's pixel count (index 0 unused).
struct Components {
  std::vector<int> label;
  std::vector<int> area;
};
Components connectedComponents(const Mask& m, bool eightConnected = false);

// The mask with every hole (a clear region not connected to the border) filled.
Mask fillHoles(const Mask& m);

}  // namespace emboss
