// Workpieces: the function of the untouched piece of metal, before any operation (equation (1)).
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "frep/box.h"
#include "frep/scalar.h"

namespace emboss {

// A workpiece is an F-rep function: f >= 0 inside, 0 on the surface, < 0 outside; lengths in mm,
// the front face looks at +z. Implementations are immutable after construction and thread-safe
// for concurrent evaluation; evaluation neither allocates nor throws.
class Workpiece {
 public:
  virtual ~Workpiece() = default;
  virtual double value(const P3<double>& p) const = 0;
  virtual Grad value(const P3<Grad>& p) const = 0;
  // Bounds of f over a box (conservative: contains every value f takes there).
  virtual Interval value(const P3<Interval>& p) const = 0;
  // A box outside which f < 0 (the piece lies inside it).
  virtual Box3 bounds() const = 0;
  // Half the sheet's thickness, d (mm): the sheet model keeps this thickness.
  virtual double halfThickness() const = 0;
  // The scene-file description ({"type": ...}).
  virtual nlohmann::json toJson() const = 0;
};

}  // namespace emboss
