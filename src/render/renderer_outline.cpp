// Outline sheets (2D vm workpieces): the column map and the outline's program specialised per
// column block (renderer.h, docs/rendering.md "Outline sheets").
#include <array>

#include "render/renderer_internal.h"
#include "util/portable_math.h"


namespace emboss {

using namespace render_internal;

Renderer::ColumnMap::Column Renderer::ColumnMap::block(int i, int j) const {
  // Beyond the workpiece's bounds W < 0.
  if (i < 0 || j < 0 || i >= nx || j >= ny) return {-std::numeric_limits<float>::infinity(), -1.0f};
  const size_t k = static_cast<size_t>(j) * nx + i;
  return {lo[k], hi[k]};
}

Renderer::ColumnMap::Column Renderer::ColumnMap::at(double x, double y) const {
  const WalkSheet::Columns::Bounds b = view().at(x, y);
  return {b.lo, b.hi};
}

const VmProgram& Renderer::ColumnMap::tapeAt(double x, double y) const {
  const int i = floorToInt((x - x0) * inv), j = floorToInt((y - y0) * inv);
  if (i < 0 || j < 0 || i >= nx || j >= ny) return vm->program();
  if (const std::int32_t b = blockTapeOf[static_cast<size_t>(j) * nx + i]; b >= 0) return blockTape[static_cast<size_t>(b)];
  return leafTape[static_cast<size_t>(j / kLeaf) * leavesX + i / kLeaf];
}

Renderer::ColumnMap::Blocks Renderer::ColumnMap::under(const Box2& xy) const {
  return {floorToInt((xy.x0 - x0) * inv), floorToInt((xy.y0 - y0) * inv),
          floorToInt((xy.x1 - x0) * inv), floorToInt((xy.y1 - y0) * inv)};
}

Interval Renderer::ColumnMap::valueOver(const P3<Interval>& p) const {
  // (Named, not structured bindings: the lambda below reads them.)
  const Blocks box = under(Box2{p.x.lo, p.y.lo, p.x.hi, p.y.hi});
  const int i0 = box.i0, j0 = box.j0, i1 = box.i1, j1 = box.j1;
  if (i0 < 0 || j0 < 0 || i1 >= nx || j1 >= ny) return vm->value(vm->program(), p);
  if (i0 == i1 && j0 == j1)
    if (const std::int32_t b = blockTapeOf[static_cast<size_t>(j0) * nx + i0]; b >= 0) return vm->value(blockTape[static_cast<size_t>(b)], p);
  // Cut along the edges of the cells (leaves, else regions) the box meets, when there are at most
  // 2 x 2 of them. The first part starts at the box's own low end and the last ends at its high
  // end, so the parts cover the box whatever the rounding that put an end in a cell; each end
  // lies within the hair its cell's tape was specialised beyond the cell.
  auto cut = [&](int cell, const std::vector<VmProgram>& tapes, int cellsX) -> std::optional<Interval> {
    const int a0 = i0 / cell, a1 = i1 / cell, b0 = j0 / cell, b1 = j1 / cell;
    if (a1 - a0 > 1 || b1 - b0 > 1) return std::nullopt;
    const double w = cell * size;
    std::optional<Interval> hull;
    for (int b = b0; b <= b1; ++b)
      for (int a = a0; a <= a1; ++a) {
        const Interval x(a == a0 ? p.x.lo : x0 + a * w, a == a1 ? p.x.hi : x0 + (a + 1) * w);
        const Interval y(b == b0 ? p.y.lo : y0 + b * w, b == b1 ? p.y.hi : y0 + (b + 1) * w);
        const Interval v = vm->value(tapes[static_cast<size_t>(b) * cellsX + a], P3<Interval>{x, y, p.z});
        hull = hull ? Interval(std::min(hull->lo, v.lo), std::max(hull->hi, v.hi)) : v;
      }
    return hull;
  };
  if (const auto v = cut(kLeaf, leafTape, leavesX)) return *v;
  if (const auto v = cut(kLeaf * kRegion, regionTape, regionsX)) return *v;
  return vm->value(vm->program(), p);
}

bool Renderer::ColumnMap::anyOutside(const Box2& xy) const {
  const auto [i0, j0, i1, j1] = under(xy);
  if (i0 < 0 || j0 < 0 || i1 >= nx || j1 >= ny) return true;
  for (int lj = j0 / kLeaf; lj <= j1 / kLeaf; ++lj)
    for (int li = i0 / kLeaf; li <= i1 / kLeaf; ++li)
      if (leafOutside[static_cast<size_t>(lj) * leavesX + li]) return true;
  return false;
}

size_t Renderer::ColumnMap::memoryBytes() const {
  size_t n = (lo.size() + hi.size() + subLo.size() + subHi.size()) * sizeof(float) +
             blockTapeOf.size() * sizeof(std::int32_t) + leafOutside.size() + leafInside.size();
  for (const auto* tapes : {&leafTape, &regionTape, &blockTape})
    for (const VmProgram& t : *tapes) n += sizeof t + t.memoryBytes();
  return n;
}

double Renderer::workpieceValue(const P3<double>& p) const {
  if (workpieceKind_ == 4 && options_.specialisedOutline) return columns_.vm->value(columns_.tapeAt(p.x, p.y), p);
  return model_->workpiece().value(p);
}

Grad Renderer::workpieceValue(const P3<Grad>& p) const {
  if (workpieceKind_ == 4 && options_.specialisedOutline) return columns_.vm->value(columns_.tapeAt(p.x.v, p.y.v), p);
  return model_->workpiece().value(p);
}

Interval Renderer::workpieceValue(const P3<Interval>& p) const {
  if (workpieceKind_ == 4 && options_.specialisedOutline) return columns_.valueOver(p);
  return model_->workpiece().value(p);
}

// The documented form of a 2D vm workpiece is W = min(O(x, y), d - |z|), so W over a column box
// at z = 0 bounds min(O, d): proven outside where its high end is negative, the slab where the
// slab is below its low end. Each region specialises the program to its box, each of its leaves
// the region's tape to its own; the blocks' bounds are computed through their leaf's tape.
void Renderer::buildColumns() {
  ColumnMap& c = columns_;
  c.vm = dynamic_cast<const VmWorkpiece*>(fieldWorkpiece_.get());
  const VmWorkpiece& w = *c.vm;
  const Box2 dom = field_.domain();
  c.size = 2.0 * field_.spacing();
  c.inv = 1.0 / c.size;
  c.x0 = dom.x0, c.y0 = dom.y0;
  c.nx = static_cast<int>(std::ceil((dom.x1 - dom.x0) * c.inv));
  c.ny = static_cast<int>(std::ceil((dom.y1 - dom.y0) * c.inv));
  constexpr int kLeaf = ColumnMap::kLeaf, kRegion = ColumnMap::kRegion;
  c.leavesX = (c.nx + kLeaf - 1) / kLeaf;
  c.leavesY = (c.ny + kLeaf - 1) / kLeaf;
  c.regionsX = (c.leavesX + kRegion - 1) / kRegion;
  c.regionsY = (c.leavesY + kRegion - 1) / kRegion;
  c.halfThickness = w.halfThickness();
  c.lo.assign(static_cast<size_t>(c.nx) * c.ny, 0.0f);
  c.hi.assign(c.lo.size(), 0.0f);
  c.leafTape.assign(static_cast<size_t>(c.leavesX) * c.leavesY, VmProgram());
  c.regionTape.assign(static_cast<size_t>(c.regionsX) * c.regionsY, VmProgram());
  const double d = c.halfThickness;
  constexpr float inf = std::numeric_limits<float>::infinity();
  // A tape serves every point whose block a lookup finds; a point on a block's edge may round
  // into the next block, so each is specialised over its box grown by a hair.
  const double hair = 1e-6 * c.size, toModel = 1.0 / w.scale();
  auto specialise = [&](const VmProgram& from, int i0, int j0, int i1, int j1) {
    return from.specialised(Interval((c.x0 + i0 * c.size - hair) * toModel, (c.x0 + i1 * c.size + hair) * toModel),
                            Interval((c.y0 + j0 * c.size - hair) * toModel, (c.y0 + j1 * c.size + hair) * toModel),
                            Interval(0.0));
  };
  // O over a box, then min(O, d) (what W is at z' = 0) with a margin for the rounding.
  auto boundsOver = [&](const VmProgram& tape, const Interval& x, const Interval& y) {
    const Interval o = w.outline(tape, x, y);
    const Interval v = min(o, Interval(d));
    const double m = 1e-9 * (1.0 + std::abs(o.lo) + std::abs(v.hi));
    float lo = std::nextafter(static_cast<float>(v.lo - m), -inf);
    float hi = std::nextafter(static_cast<float>(v.hi + m), inf);
    if (hi < 0.0f) lo = -inf;                          // outside: the slab never applies
    if (o.lo >= d + m) lo = static_cast<float>(2 * d);  // inside: the slab always applies
    return ColumnMap::Column{lo, hi};
  };
  // The same over blocks i0..i1 - 1, j0..j1 - 1.
  auto bounds = [&](const VmProgram& tape, int i0, int j0, int i1, int j1) {
    return boundsOver(tape, Interval(c.x0 + i0 * c.size, c.x0 + i1 * c.size), Interval(c.y0 + j0 * c.size, c.y0 + j1 * c.size));
  };
  auto decided = [&](const ColumnMap::Column& b) { return b.hi < 0.0f || b.lo >= static_cast<float>(d); };
  // A block's sub-cells (WalkSheet::Columns): each over its box grown by the hair, which holds
  // every point Columns::at() finds in it whatever the rounding.
  constexpr int kSub = WalkSheet::Columns::kSub;
  using SubBounds = std::array<ColumnMap::Column, kSub * kSub>;
  // Found by quarters: a square of sub-cells whose bounds decide W gives them to all its
  // sub-cells, any other is cut in four. A square's bounds are intersected with those of the
  // square it was cut from (the block's at the top), which hold there too.
  auto subBounds = [&](const VmProgram& tape, int i, int j, const ColumnMap::Column& block) {
    SubBounds out;
    const double s = c.size / kSub;
    auto square = [&](auto& self, int si, int sj, int n, const ColumnMap::Column& outer) -> void {
      const double xa = c.x0 + i * c.size + si * s, ya = c.y0 + j * c.size + sj * s;
      ColumnMap::Column b = boundsOver(tape, Interval(xa - hair, xa + n * s + hair), Interval(ya - hair, ya + n * s + hair));
      b.lo = std::max(b.lo, outer.lo), b.hi = std::min(b.hi, outer.hi);
      if (b.hi < 0.0f) b.lo = -inf;
      if (n == 1 || decided(b)) {
        for (int y = sj; y < sj + n; ++y)
          for (int x = si; x < si + n; ++x) out[static_cast<size_t>(y) * kSub + x] = b;
        return;
      }
      const int h = n / 2;
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) self(self, si + x * h, sj + y * h, h, b);
    };
    const int h = kSub / 2;
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) square(square, x * h, y * h, h, block);
    return out;
  };
  c.blockTapeOf.assign(c.lo.size(), -1);
  c.leafOutside.assign(c.leafTape.size(), 0);
  c.leafInside.assign(c.leafTape.size(), 0);
  c.blockTape.clear();
  // Each region's block tapes and sub-cells, gathered after.
  struct BlockTape {
    size_t k;
    VmProgram tape;
    SubBounds sub;
  };
  std::vector<std::vector<BlockTape>> regionBlocks(static_cast<size_t>(c.regionsX) * c.regionsY);
  const Rect regions{0, 0, c.regionsX, c.regionsY};
  pool_.parallelFor2D(regions, 1, [&](const Rect& t) {
    const int ra = t.x, rb = t.y;
    const int li0 = ra * kRegion, lj0 = rb * kRegion;
    const int li1 = std::min(li0 + kRegion, c.leavesX), lj1 = std::min(lj0 + kRegion, c.leavesY);
    // The region's tape is specialised from the whole program (nodes kept until its leaves are done).
    VmProgram region = w.program().specialised(
        Interval((c.x0 + li0 * kLeaf * c.size - hair) * toModel, (c.x0 + std::min(li1 * kLeaf, c.nx) * c.size + hair) * toModel),
        Interval((c.y0 + lj0 * kLeaf * c.size - hair) * toModel, (c.y0 + std::min(lj1 * kLeaf, c.ny) * c.size + hair) * toModel),
        Interval(0.0));
    for (int lb = lj0; lb < lj1; ++lb)
      for (int la = li0; la < li1; ++la) {
        const int i0 = la * kLeaf, j0 = lb * kLeaf;
        const int i1 = std::min(i0 + kLeaf, c.nx), j1 = std::min(j0 + kLeaf, c.ny);
        VmProgram& leaf = c.leafTape[static_cast<size_t>(lb) * c.leavesX + la];
        leaf = specialise(region, i0, j0, i1, j1);
        const ColumnMap::Column b = bounds(leaf, i0, j0, i1, j1);
        for (int j = j0; j < j1; ++j)
          for (int i = i0; i < i1; ++i) {
            const ColumnMap::Column col = decided(b) ? b : bounds(leaf, i, j, i + 1, j + 1);
            const size_t k = static_cast<size_t>(j) * c.nx + i;
            c.lo[k] = col.lo, c.hi[k] = col.hi;
            (col.hi < 0.0f ? c.leafOutside : c.leafInside)[static_cast<size_t>(lb) * c.leavesX + la] = 1;
            if (!decided(col)) {
              VmProgram block = specialise(leaf, i, j, i + 1, j + 1);
              block.dropNodes();
              SubBounds sub = subBounds(block, i, j, col);
              regionBlocks[static_cast<size_t>(rb) * c.regionsX + ra].push_back(BlockTape{k, std::move(block), sub});
            }
          }
        leaf.dropNodes();
      }
    region.dropNodes();
    c.regionTape[static_cast<size_t>(rb) * c.regionsX + ra] = std::move(region);
  });
  outlineMaskKey_.clear();  // the mask follows the new map
  c.subLo.clear(), c.subHi.clear();
  for (auto& blocks : regionBlocks)
    for (BlockTape& b : blocks) {
      c.blockTapeOf[b.k] = static_cast<std::int32_t>(c.blockTape.size());
      c.blockTape.push_back(std::move(b.tape));
      for (const ColumnMap::Column& s : b.sub) c.subLo.push_back(s.lo), c.subHi.push_back(s.hi);
    }
}

void Renderer::updateOutlineMask() {
  if (workpieceKind_ != 4 || !options_.cullOutsideClip || !camera_) {
    outlineMask_.clear(), outlineMaskKey_.clear();
    return;
  }
  std::vector<double> key{static_cast<double>(cameraGeneration_), fieldClip_.x0, fieldClip_.y0, fieldClip_.z0,
                          fieldClip_.x1, fieldClip_.y1, fieldClip_.z1};
  for (const SetOp& s : setOps_)
    for (double v : {s.support.x0, s.support.y0, s.zlo, s.support.x1, s.support.y1, s.zhi}) key.push_back(v);
  if (key == outlineMaskKey_ && !outlineMask_.empty()) return;
  outlineMaskKey_ = std::move(key);
  const int w = camera_->width(), h = camera_->height();
  maskTilesX_ = (w + kMaskTile - 1) / kMaskTile, maskTilesY_ = (h + kMaskTile - 1) / kMaskTile;
  outlineMask_.assign(static_cast<size_t>(maskTilesX_) * maskTilesY_, 0);
  // A ray is tested where its image point lies (findHit(): up to the rectangle's far edge
  // included); a tile is marked when the rectangle reaches into it.
  auto mark = [&](const Box3& b) {
    const Rect r = projectBox(b);
    if (r.empty()) return;
    const int tx0 = std::max(0, r.x / kMaskTile), ty0 = std::max(0, r.y / kMaskTile);
    const int tx1 = std::min(maskTilesX_ - 1, (r.x + r.w) / kMaskTile), ty1 = std::min(maskTilesY_ - 1, (r.y + r.h) / kMaskTile);
    for (int ty = ty0; ty <= ty1; ++ty)
      std::fill_n(&outlineMask_[static_cast<size_t>(ty) * maskTilesX_ + tx0], tx1 - tx0 + 1, std::uint8_t{1});
  };
  const ColumnMap& c = columns_;
  const double leaf = ColumnMap::kLeaf * c.size, hair = 1e-6 * (1.0 + std::abs(c.x0) + std::abs(c.y0)) + 1e-9;
  for (int lb = 0; lb < c.leavesY; ++lb)
    for (int la = 0; la < c.leavesX; ++la)
      if (c.leafInside[static_cast<size_t>(lb) * c.leavesX + la])
        mark(Box3{c.x0 + la * leaf - hair, c.y0 + lb * leaf - hair, fieldClip_.z0, c.x0 + (la + 1) * leaf + hair,
                  c.y0 + (lb + 1) * leaf + hair, fieldClip_.z1});
  for (const SetOp& s : setOps_) mark(Box3{s.support.x0, s.support.y0, s.zlo, s.support.x1, s.support.y1, s.zhi});
}

}  // namespace emboss
