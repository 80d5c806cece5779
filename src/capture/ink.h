// Ink on paper: an adaptive (Sauvola) threshold and the paper's white level, both robust to uneven light.
#pragma once

#include "capture/gray.h"

namespace emboss {

struct InkOptions {
  int window = 31;        // odd; the local neighbourhood in pixels (several stroke widths)
  double k = 0.25;        // Sauvola's k: how much darker than the local mean ink must be, in flat areas
  double range = 128.0;   // Sauvola's R: the dynamic range of the standard deviation
  double minStep = 12.0;  // ink is at least this many gray levels below the local mean (noise guard)
};

// Ink where g < m (1 + k (s / R - 1)) and g < m - minStep, m and s the local mean and standard
// deviation over window x window (integral images; O(1) a pixel).
Mask inkMask(const GrayImage& paper, const InkOptions& options);

// The paper's own brightness under the local light: the mean of the non-ink pixels within `radius`
// of each pixel (a square), so that gray / white is about 1 on paper and low on ink.
GrayImage paperWhite(const GrayImage& paper, const Mask& ink, int radius);

}  // namespace emboss
