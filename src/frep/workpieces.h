// The built-in workpieces: the plate of equation (1), a disc (medallion) and a shallow bowl.
#pragma once

#include <memory>

#include "frep/workpiece.h"

namespace emboss {

// Adapts a class with `template <class T> T eval(const P3<T>&) const` to the Workpiece interface.
template <class Derived>
class WorkpieceOf : public Workpiece {
 public:
  double value(const P3<double>& p) const final { return self().eval(p); }
  Grad value(const P3<Grad>& p) const final { return self().eval(p); }
  Interval value(const P3<Interval>& p) const final { return self().eval(p); }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
};

// Equation (1): a sheet 2w x 2h x 2d, f = min(x + w, w - x, y + h, h - y, z + d, d - z).
class Plate final : public WorkpieceOf<Plate> {
 public:
  Plate(double w, double h, double d) : w_(w), h_(h), d_(d) {}
  template <class T>
  T eval(const P3<T>& p) const {
    return min(min(min(p.x + w_, w_ - p.x), min(p.y + h_, h_ - p.y)), min(p.z + d_, d_ - p.z));
  }
  Box3 bounds() const override { return {-w_, -h_, -d_, w_, h_, d_}; }
  double halfThickness() const override { return d_; }
  nlohmann::json toJson() const override { return {{"type", "plate"}, {"w", w_}, {"h", h_}, {"d", d_}}; }

 private:
  double w_, h_, d_;
};

// A medallion: a round sheet of radius r and thickness 2d, f = min(r - sqrt(x^2 + y^2), d - |z|).
class Disc final : public WorkpieceOf<Disc> {
 public:
  Disc(double r, double d) : r_(r), d_(d) {}
  template <class T>
  T eval(const P3<T>& p) const {
    return min(r_ - sqrt(sqr(p.x) + sqr(p.y)), min(p.z + d_, d_ - p.z));
  }
  Box3 bounds() const override { return {-r_, -r_, -d_, r_, r_, d_}; }
  double halfThickness() const override { return d_; }
  nlohmann::json toJson() const override { return {{"type", "disc"}, {"r", r_}, {"d", d_}}; }

 private:
  double r_, d_;
};

// A shallow bowl: a spherical shell of thickness 2d whose mid surface passes through the origin
// (its lowest point) and rises by `depth` at the rim radius r, opening toward +z:
// f = min(d - |(|P - C| - R)|, r - sqrt(x^2 + y^2)), C = (0, 0, R), R = (r^2 + depth^2) / (2 depth).
class Bowl final : public WorkpieceOf<Bowl> {
 public:
  Bowl(double r, double depth, double d) : r_(r), depth_(depth), d_(d), R_((r * r + depth * depth) / (2 * depth)) {}
  template <class T>
  T eval(const P3<T>& p) const {
    const T dc = sqrt(sqr(p.x) + sqr(p.y) + sqr(p.z - R_)) - R_;
    return min(d_ - abs(dc), r_ - sqrt(sqr(p.x) + sqr(p.y)));
  }
  Box3 bounds() const override { return {-r_, -r_, -d_, r_, r_, depth_ + d_ * 2}; }
  double halfThickness() const override { return d_; }
  nlohmann::json toJson() const override {
    return {{"type", "bowl"}, {"r", r_}, {"depth", depth_}, {"d", d_}};
  }

 private:
  double r_, depth_, d_, R_;
};

}  // namespace emboss
