// The stroke in progress: settled operations are handed out while the pen still moves.
#include "app/stroke_builder.h"

#include <algorithm>
#include <cmath>

namespace emboss {

namespace {

bool same(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
bool same(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y) return false;
  return true;
}
bool same(const TraceJoin& a, const TraceJoin& b) { return a.r == b.r && a.dir.x == b.dir.x && a.dir.y == b.dir.y; }
bool same(const ToolShape& a, const ToolShape& b) {
  return a.type == b.type && same(a.center, b.center) && same(a.end, b.end) && a.r == b.r && same(a.half, b.half);
}

}  // namespace

bool sameOperation(const Operation& a, const Operation& b) {
  if (a.kind != b.kind) return false;
  switch (a.kind) {
    case OpKind::Trace:
      return a.side == b.side && a.a == b.a && same(a.points, b.points) && same(a.joinStart, b.joinStart) && same(a.joinEnd, b.joinEnd);
    case OpKind::Punch: return a.side == b.side && a.a == b.a && a.p == b.p && a.q == b.q && same(a.at, b.at);
    case OpKind::Press: return a.side == b.side && a.a == b.a && a.p == b.p && a.q == b.q && same(a.points, b.points);
    case OpKind::Region:
      return a.side == b.side && same(a.points, b.points) && a.height == b.height && a.falloff == b.falloff;
    case OpKind::Subtract: return same(a.tool, b.tool);
    case OpKind::BlendUnion:
    case OpKind::BlendSubtract: return same(a.tool, b.tool) && a.a1 == b.a1 && a.a2 == b.a2 && a.a3 == b.a3;
    case OpKind::Patina: return a.tinge == b.tinge && a.a == b.a && a.strength == b.strength && same(a.points, b.points);
  }
  return false;
}

void StrokeBuilder::begin(const ToolSpec& tool, const Metal& metal) {
  active_ = true;
  tool_ = tool;
  metal_ = metal;
  points_.clear();
  handed_.clear();
  sinceLast_ = 0;
}

size_t StrokeBuilder::settled(const std::vector<Operation>& ops) const {
  const size_t count = ops.size();
  switch (tool_.kind) {
    case ToolKind::RegionRaiser:
    case ToolKind::PatinaBrush: return 0;
    case ToolKind::OvalPunch: return count >= 2 ? count - 2 : 0;
    // Its strikes are final once placed; the first turns along the stroke once a second is there.
    case ToolKind::FlatPunch: return count >= 2 ? count : 0;
    case ToolKind::Tracer:
      // A piece's end joint bisects the turn into the next piece's first segment, which is settled
      // once that piece has a point after it (before, it may still end at the pen).
      if (count >= 2 && ops.back().points.size() < 3) return count - 2;
      return count >= 1 ? count - 1 : 0;
    default: return count >= 1 ? count - 1 : 0;
  }
}

std::vector<Operation> StrokeBuilder::add(const StrokePoint& p) {
  std::vector<Operation> out;
  if (!active_) return out;
  if (!points_.empty()) sinceLast_ += std::hypot(p.x - points_.back().x, p.y - points_.back().y);
  points_.push_back(p);
  if (tool_.kind == ToolKind::RegionRaiser || tool_.kind == ToolKind::PatinaBrush) return out;
  // Recomputing the whole stroke costs O(points); doing it only every quarter millimetre keeps
  // long strokes cheap without delaying a strike by more than that.
  if (points_.size() > 1 && sinceLast_ < 0.25) return out;
  sinceLast_ = 0;
  const auto ops = strokeToOperations(tool_, metal_, points_);
  const size_t n = settled(ops);
  for (size_t i = handed_.size(); i < n; ++i) {
    handed_.push_back(ops[i]);
    out.push_back(ops[i]);
  }
  return out;
}

StrokeBuilder::Finish StrokeBuilder::end() {
  Finish f;
  if (!active_) return f;
  active_ = false;
  const auto ops = strokeToOperations(tool_, metal_, points_);
  size_t keep = 0;
  while (keep < handed_.size() && keep < ops.size() && sameOperation(handed_[keep], ops[keep])) ++keep;
  f.keep = keep;
  f.rest.assign(ops.begin() + static_cast<std::ptrdiff_t>(keep), ops.end());
  handed_.clear();
  points_.clear();
  return f;
}

}  // namespace emboss
