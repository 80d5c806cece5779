// The attract loop: pieces replayed operation by operation, then shown off with a slow turn.
#include "app/attract_player.h"

#include <algorithm>
#include <cmath>

#include "app/view_orbit.h"
#include "app/workbench.h"

namespace emboss {

double strokeSeconds(const Operation& op) {
  switch (op.kind) {
    case OpKind::Trace: {
      double len = 0;
      for (size_t i = 1; i < op.points.size(); ++i)
        len += std::hypot(op.points[i].x - op.points[i - 1].x, op.points[i].y - op.points[i - 1].y);
      return 0.02 + len / 45.0;  // a tracer moves ~45 mm/s
    }
    case OpKind::Punch: return 0.06;
    case OpKind::Press: return 0.08;
    case OpKind::Region: return 0.7;
    case OpKind::Patina: {
      double len = 0;
      for (size_t i = 1; i < op.points.size(); ++i)
        len += std::hypot(op.points[i].x - op.points[i - 1].x, op.points[i].y - op.points[i - 1].y);
      return 0.2 + len / 60.0;  // a brush moves ~60 mm/s
    }
    default: return 0.09;
  }
}

AttractPlayer::AttractPlayer(std::vector<AttractPiece> pieces, int width, int height, double speed)
    : pieces_(std::move(pieces)), w_(width), h_(height), speed_(speed > 0 ? speed : 1.0) {
  for (const auto& p : pieces_) {
    std::vector<double> t;
    double sum = 0;
    for (const auto& op : p.scene.operations) sum += strokeSeconds(op);
    // A piece takes 40..75 s to build at speed 1, whatever its number of operations.
    const double k = sum <= 0 ? 1.0 : std::clamp(sum, 40.0, 75.0) / sum / speed_;
    double at = 0;
    for (const auto& op : p.scene.operations) {
      at += strokeSeconds(op) * k;
      t.push_back(at);
    }
    times_.push_back(std::move(t));
  }
}

double AttractPlayer::buildSeconds(size_t i) const {
  return i < times_.size() && !times_[i].empty() ? times_[i].back() : 0.0;
}

const std::string& AttractPlayer::title() const {
  static const std::string none;
  if (pieces_.empty()) return none;
  const auto& p = pieces_[index_];
  return p.scene.title.empty() ? p.name : p.scene.title;
}

double AttractPlayer::progress() const {
  if (pieces_.empty() || pieces_[index_].scene.operations.empty()) return 1.0;
  return static_cast<double>(next_) / pieces_[index_].scene.operations.size();
}

ShadingParams AttractPlayer::shading() const {
  ShadingParams s;
  const Scene& sc = pieces_[index_].scene;
  s.metal = metalByName(sc.metal).value_or(metals()[0]);
  s.tinge = tingeByName(sc.tinge).value_or(tinges()[0]);
  s.frontZ = sc.workpiece->bounds().z1;
  return s;
}

void AttractPlayer::start(double now, size_t index, double doneFraction) {
  if (pieces_.empty()) return;
  load(index % pieces_.size(), now, doneFraction);
}

void AttractPlayer::load(size_t index, double now, double doneFraction) {
  index_ = index;
  const Scene& sc = pieces_[index_].scene;
  model_ = std::make_unique<Model>(sc.workpiece, sc.deformation);
  const size_t n = sc.operations.size();
  next_ = std::min(n, static_cast<size_t>(std::clamp(doneFraction, 0.0, 1.0) * n));
  for (size_t i = 0; i < next_; ++i) model_->add(sc.operations[i]);  // checked when the file was read
  home_ = benchCamera(sc.workpiece->bounds(), w_, h_, 0.8);
  camera_ = home_;
  phase_ = Phase::Build;
  phaseStart_ = now;
  buildStart_ = now - (next_ > 0 ? times_[index_][next_ - 1] : 0.0);
  changes_ = {};
  changes_.full = true;
}

void AttractPlayer::update(double now) {
  if (pieces_.empty()) return;
  const auto& ops = pieces_[index_].scene.operations;
  switch (phase_) {
    case Phase::Build: {
      const auto& t = times_[index_];
      while (next_ < ops.size() && now - buildStart_ >= t[next_]) {
        if (model_->add(ops[next_])) changes_.ops.push_back(model_->activeCount() - 1);
        ++next_;
      }
      if (next_ >= ops.size()) {
        phase_ = Phase::Show;
        phaseStart_ = now;
      }
      break;
    }
    case Phase::Show: {
      const double u = std::clamp((now - phaseStart_) / kShowSeconds, 0.0, 1.0);
      Orbit o = orbitOf(home_);
      // One slow swing to the right and back, tipping toward the raking light on the way.
      const double e = easeInOut(u);
      o.azimuthDeg += 26.0 * std::sin(2.0 * M_PI * e);
      o.elevationDeg -= 22.0 * std::sin(M_PI * e);
      camera_ = u >= 1.0 ? home_ : cameraAt(o, home_);
      changes_.camera = true;
      if (u >= 1.0) {
        phase_ = Phase::Rest;
        phaseStart_ = now;
      }
      break;
    }
    case Phase::Rest:
      if (now - phaseStart_ >= kRestSeconds) load((index_ + 1) % pieces_.size(), now, 0.0);
      break;
  }
}

ViewChanges AttractPlayer::takeChanges() {
  ViewChanges c;
  std::swap(c, changes_);
  return c;
}

}  // namespace emboss
