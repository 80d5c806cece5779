// The patina at a hit: the strokes' amounts, from the lattice (patina_cache.h) for the strokes it
// keeps and worked out at the hit for the rest (docs/rendering.md, "The patina's lattice").
#include <algorithm>
#include <unordered_map>

#include "render/renderer_internal.h"

namespace emboss {

using namespace render_internal;

// The kept strokes' lattice does not reach past a cell beyond a stroke's support: a change of a
// stroke changes the hits within a cell's diagonal of its support, which dirtySpansOfRays() grows
// by more (the cavity term's reach).
static_assert(PatinaCache::kSpacing * 1.5 <= kCavityReach);

void Renderer::syncPatina(const Model& model, bool followed) {
  hasPatina_ = false, patinaExact_ = false;
  std::vector<std::pair<std::uint64_t, Box2>> kept;
  const auto& ops = model.operations();
  const auto& ids = model.operationIds();
  patinaLattice_ = options_.patinaLattice && usesField();
  for (size_t i = 0; i < model.activeCount(); ++i) {
    const Operation& o = ops[i].op();
    if (!o.isPatina()) continue;
    hasPatina_ = true;
    if (patinaLattice_ && PatinaCache::kept(o)) kept.emplace_back(ids[i], ops[i].support());
    else patinaExact_ = true;
  }
  if (!patinaLattice_ || kept.empty()) {
    // Nothing on the lattice: its blocks are let go.
    patinaCache_.clear();
    patinaKept_.clear();
    return;
  }
  // The lattice over the workpiece and a node beyond it (a hit off it works every stroke out).
  const Box3 wb = model.workpiece().bounds();
  const double m = PatinaCache::kSpacing;
  const bool same = patinaCache_.configure(Box2{wb.x0 - m, wb.y0 - m, wb.x1 + m, wb.y1 + m});
  if (same && followed) {
    // The blocks under the strokes that came or went (undone, redone, a stroke in the making
    // replaced at each pen event) are forgotten; the rest hold the same values.
    std::unordered_map<std::uint64_t, Box2> before(patinaKept_.begin(), patinaKept_.end());
    for (const auto& [id, support] : kept)
      if (before.erase(id) == 0) patinaCache_.invalidate(support);
    for (const auto& [id, support] : before) patinaCache_.invalidate(support);
  } else {
    patinaCache_.clear();
  }
  patinaKept_ = std::move(kept);
}

bool Renderer::patinaBlock(int i0, int j0, float* values) const {
  constexpr int n = PatinaCache::kBlockNodes;
  const Box2 box{patinaCache_.nodeX(i0), patinaCache_.nodeY(j0), patinaCache_.nodeX(i0 + n - 1),
                 patinaCache_.nodeY(j0 + n - 1)};
  thread_local std::vector<std::uint32_t> scratch;
  thread_local std::vector<const PreparedOp*> strokes;
  strokes.clear();
  const size_t active = model_->activeCount();
  for (std::uint32_t k : patinaGrid_.in(box, scratch)) {
    const PreparedOp& op = model_->operations()[k];
    if (k < active && PatinaCache::kept(op.op()) && op.support().overlaps(box)) strokes.push_back(&op);
  }
  if (strokes.empty()) return false;
  // A node's amounts from the strokes over it in the model's order (as a hit's: 1 - prod(1 -
  // amount) per tinge); a stroke whose support misses the node gives 0 there exactly, so a node
  // two blocks share has the same bits in both.
  for (int j = 0; j < n; ++j) {
    const double y = patinaCache_.nodeY(j0 + j);
    for (int i = 0; i < n; ++i) {
      const double x = patinaCache_.nodeX(i0 + i);
      std::array<double, PatinaCache::kTinges + 1> bare{1.0, 1.0, 1.0, 1.0, 1.0};
      for (const PreparedOp* op : strokes) bare[static_cast<size_t>(op->op().tinge)] *= 1.0 - op->patinaAt(x, y);
      float* v = values + (static_cast<size_t>(j) * n + i) * PatinaCache::kTinges;
      for (int t = 0; t < PatinaCache::kTinges; ++t) v[t] = static_cast<float>(1.0 - bare[static_cast<size_t>(t) + 1]);
    }
  }
  return true;
}

Patina Renderer::patinaAt(double x, double y, std::vector<std::uint32_t>& scratch) const {
  // The strokes of each tinge build up: 1 - prod(1 - amount), in any order; the lattice's strokes
  // first, as one.
  Patina patina{};
  std::array<double, 5> bare{1.0, 1.0, 1.0, 1.0, 1.0};
  const bool lattice = patinaLattice_ && !patinaKept_.empty() && patinaCache_.covers(x, y);
  if (lattice) {
    double a[PatinaCache::kTinges];
    patinaCache_.at(x, y, [&](int i0, int j0, float* values) { return patinaBlock(i0, j0, values); }, a);
    for (int t = 0; t < PatinaCache::kTinges; ++t) bare[static_cast<size_t>(t) + 1] = 1.0 - a[t];
    if (!patinaExact_) {
      for (size_t t = 1; t < bare.size(); ++t) patina.amount[t] = 1.0 - bare[t];
      return patina;
    }
  }
  const size_t active = model_->activeCount();
  for (std::uint32_t j : patinaGrid_.at(x, y, scratch)) {
    if (j >= active) continue;
    const PreparedOp& op = model_->operations()[j];
    if (lattice && PatinaCache::kept(op.op())) continue;
    bare[static_cast<size_t>(op.op().tinge)] *= 1.0 - op.patinaAt(x, y);
  }
  for (size_t t = 1; t < bare.size(); ++t) patina.amount[t] = 1.0 - bare[t];
  return patina;
}

}  // namespace emboss
