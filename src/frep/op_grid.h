// A regular grid over the plate's plane that lists, per cell, the operations whose support meets it.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "frep/model.h"

namespace emboss {

// The paper's "regular grid over the model", over exact supports. Each cell keeps the ascending
// indices of the operations whose support rectangle overlaps it; a lookup returns those below the
// model's active count, so undo and redo cost nothing. sync() follows the model incrementally: an
// appended operation is inserted into the cells under its support only; operations dropped or
// replaced (an add after an undo) are removed from theirs. Not thread-safe against sync(); lookups
// are const and may run concurrently.
class OpGrid {
 public:
  // Which operations a grid lists (all when none is given): a grid of one kind, the patina strokes
  // say, answers a lookup without the others that share its cells.
  using Filter = bool (*)(const Operation&);
  // cellSize <= 0 picks one from the workpiece size (about 256 cells across the longer side).
  explicit OpGrid(double cellSize = 0.0, Filter keep = nullptr) : requestedCell_(cellSize), keep_(keep) {}

  // Brings the grid up to date with the model. Returns the number of operations (re)inserted (of
  // those the filter keeps).
  size_t sync(const Model& model);
  // The operations that may affect (x, y): ascending, active only. Exact superset of those whose
  // support contains the point (of those the filter keeps; no other).
  std::span<const std::uint32_t> at(double x, double y, std::vector<std::uint32_t>& scratch) const;
  // The operations whose support may meet the box, ascending, active only, without duplicates;
  // only those at index `from` or after (the rest of a pile left out before the sort).
  std::span<const std::uint32_t> in(const Box2& box, std::vector<std::uint32_t>& scratch, std::uint32_t from = 0) const;

  // Cells at least this wide (mm; 0: none): the next sync() builds the grid again when it changes.
  // The sheet model's renderer asks for one (Renderer::sync()): its offsets come from the
  // displacement field, and a grid of 256 cells across a small workpiece made a stroke's insert
  // and removal touch a thousand cells and more.
  void setMinCellSize(double mm);
  double cellSize() const { return cell_; }
  size_t cellCount() const { return cells_.size(); }
  // Mean list length over the cells that hold anything (for --stats).
  double meanListLength() const;
  // The bytes the index holds: its cells and their lists' storage (capacity, not size).
  size_t memoryBytes() const;

 private:
  void build(const Model& model);
  void newCells(size_t n);
  void insert(std::uint32_t index, const Box2& support);
  void remove(std::uint32_t index, const Box2& support);
  bool cellRange(const Box2& b, int& cx0, int& cy0, int& cx1, int& cy1) const;

  double requestedCell_;
  Filter keep_;
  double minCell_ = 0.0;
  double cell_ = 1.0;
  double x0_ = 0, y0_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<std::uint32_t>> cells_;
  std::vector<std::uint64_t> ids_;     // ids of the operations indexed, by index
  std::vector<Box2> supports_;         // their supports, to remove them again
  size_t activeCount_ = 0;
  std::shared_ptr<const Workpiece> workpiece_;  // held: its address is never another workpiece's
  const Model* model_ = nullptr;
};

}  // namespace emboss
