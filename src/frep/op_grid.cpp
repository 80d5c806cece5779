// The operation grid: construction, incremental updates and lookups.
#include "frep/op_grid.h"

#include <algorithm>
#include <cmath>

namespace emboss {

void OpGrid::build(const Model& model) {
  const Box3 b = model.workpiece().bounds();
  const double sx = b.x1 - b.x0, sy = b.y1 - b.y0;
  cell_ = requestedCell_ > 0 ? requestedCell_ : std::max(std::max(sx, sy) / 256.0, minCell_);
  if (!(cell_ > 0)) cell_ = 1.0;
  // A margin of cells around the workpiece keeps tools at the rim in their own cells.
  x0_ = b.x0 - 8 * cell_;
  y0_ = b.y0 - 8 * cell_;
  nx_ = static_cast<int>(std::ceil(sx / cell_)) + 16;
  ny_ = static_cast<int>(std::ceil(sy / cell_)) + 16;
  newCells(static_cast<size_t>(nx_) * ny_);
  ids_.clear();
  supports_.clear();
  workpiece_ = model.workpiecePtr();
}

void OpGrid::setMinCellSize(double mm) {
  if (mm == minCell_) return;
  minCell_ = mm;
  cells_.clear();  // (sync() builds it again)
}

void OpGrid::newCells(size_t n) {
  // A new vector of empty lists, so that what the old lists held goes back to the allocator:
  // assigning empty lists over them would keep their storage.
  std::vector<std::vector<std::uint32_t>>(n).swap(cells_);
}

bool OpGrid::cellRange(const Box2& b, int& cx0, int& cy0, int& cx1, int& cy1) const {
  if (b.empty()) return false;
  // Supports beyond the grid are clamped to its border cells: lookups there clamp the same way.
  auto clampX = [&](double x) { return std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1); };
  auto clampY = [&](double y) { return std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1); };
  cx0 = clampX(b.x0), cx1 = clampX(b.x1), cy0 = clampY(b.y0), cy1 = clampY(b.y1);
  return true;
}

void OpGrid::insert(std::uint32_t index, const Box2& support) {
  int cx0, cy0, cx1, cy1;
  if (!cellRange(support, cx0, cy0, cx1, cy1)) return;
  for (int cy = cy0; cy <= cy1; ++cy)
    for (int cx = cx0; cx <= cx1; ++cx) {
      auto& list = cells_[static_cast<size_t>(cy) * nx_ + cx];
      // Appends keep the lists ascending; an insert below the end happens only after a removal.
      if (list.empty() || list.back() < index)
        list.push_back(index);
      else
        list.insert(std::lower_bound(list.begin(), list.end(), index), index);
    }
}

void OpGrid::remove(std::uint32_t index, const Box2& support) {
  int cx0, cy0, cx1, cy1;
  if (!cellRange(support, cx0, cy0, cx1, cy1)) return;
  for (int cy = cy0; cy <= cy1; ++cy)
    for (int cx = cx0; cx <= cx1; ++cx) {
      auto& list = cells_[static_cast<size_t>(cy) * nx_ + cx];
      auto it = std::lower_bound(list.begin(), list.end(), index);
      if (it != list.end() && *it == index) list.erase(it);
    }
}

size_t OpGrid::sync(const Model& model) {
  if (workpiece_.get() != &model.workpiece() || model_ != &model || cells_.empty()) build(model);
  model_ = &model;
  const auto& ops = model.operations();
  const auto& ids = model.operationIds();
  // The first index where the model differs from what is indexed.
  size_t k = 0;
  while (k < ids_.size() && k < ids.size() && ids_[k] == ids[k]) ++k;
  if (k == 0 && !ids_.empty()) {
    // Nothing is kept (a new sheet, a new visitor, the next attract piece): new empty lists at
    // once, and the id and support lists' storage given back too.
    newCells(cells_.size());
    std::vector<std::uint64_t>().swap(ids_);
    std::vector<Box2>().swap(supports_);
  } else {
    for (size_t i = ids_.size(); i-- > k;) remove(static_cast<std::uint32_t>(i), supports_[i]);
  }
  ids_.resize(k);
  supports_.resize(k);
  size_t inserted = 0;
  for (size_t i = k; i < ops.size(); ++i) {
    // One the filter leaves out is kept with an empty support: in no cell, never removed from one.
    const bool kept = !keep_ || keep_(ops[i].op());
    const Box2 support = kept ? ops[i].support() : Box2{};
    insert(static_cast<std::uint32_t>(i), support);
    ids_.push_back(ids[i]);
    supports_.push_back(support);
    if (kept) ++inserted;
  }
  activeCount_ = model.activeCount();
  return inserted;
}

std::span<const std::uint32_t> OpGrid::at(double x, double y, std::vector<std::uint32_t>&) const {
  if (cells_.empty()) return {};
  const int cx = std::clamp(static_cast<int>(std::floor((x - x0_) / cell_)), 0, nx_ - 1);
  const int cy = std::clamp(static_cast<int>(std::floor((y - y0_) / cell_)), 0, ny_ - 1);
  const auto& list = cells_[static_cast<size_t>(cy) * nx_ + cx];
  // Active operations are a prefix of every ascending list.
  const auto end = std::lower_bound(list.begin(), list.end(), static_cast<std::uint32_t>(activeCount_));
  return {list.data(), static_cast<size_t>(end - list.begin())};
}

std::span<const std::uint32_t> OpGrid::in(const Box2& box, std::vector<std::uint32_t>& scratch, std::uint32_t from) const {
  int cx0, cy0, cx1, cy1;
  if (cells_.empty() || !cellRange(box, cx0, cy0, cx1, cy1)) return {};
  if (cx0 == cx1 && cy0 == cy1) {
    const std::span<const std::uint32_t> all = at(box.x0, box.y0, scratch);
    return all.subspan(static_cast<size_t>(std::lower_bound(all.begin(), all.end(), from) - all.begin()));
  }
  scratch.clear();
  for (int cy = cy0; cy <= cy1; ++cy)
    for (int cx = cx0; cx <= cx1; ++cx) {
      const auto& list = cells_[static_cast<size_t>(cy) * nx_ + cx];
      for (auto it = std::lower_bound(list.begin(), list.end(), from); it != list.end() && *it < activeCount_; ++it)
        scratch.push_back(*it);
    }
  std::sort(scratch.begin(), scratch.end());
  scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
  return scratch;
}

size_t OpGrid::memoryBytes() const {
  size_t n = cells_.capacity() * sizeof(cells_[0]) + ids_.capacity() * sizeof(ids_[0]) + supports_.capacity() * sizeof(supports_[0]);
  for (const auto& c : cells_) n += c.capacity() * sizeof(std::uint32_t);
  return n;
}

double OpGrid::meanListLength() const {
  size_t n = 0, sum = 0;
  for (const auto& c : cells_)
    if (!c.empty()) ++n, sum += c.size();
  return n ? static_cast<double>(sum) / n : 0.0;
}

}  // namespace emboss
