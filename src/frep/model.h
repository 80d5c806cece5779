// The model: a workpiece modified by an ordered list of operations, with multilevel undo and redo.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "frep/operation.h"
#include "frep/workpiece.h"
#include "util/result.h"

namespace emboss {

// The list is a stack with a cursor: operations [0, activeCount()) are in effect, the rest are
// the redo tail. Adding an operation drops the redo tail. Evaluation is const and thread-safe;
// edits (add, undo, redo) must not run concurrently with evaluation (the renderer's owner
// serialises them, as Embree's commit does).
class Model {
 public:
  Model(std::shared_ptr<const Workpiece> workpiece, Deformation deformation);

  const Workpiece& workpiece() const { return *workpiece_; }
  std::shared_ptr<const Workpiece> workpiecePtr() const { return workpiece_; }
  Deformation deformation() const { return deformation_; }

  // Appends an operation after checking its parameters; drops the redo tail.
  Status add(Operation op);
  bool canUndo() const { return cursor_ > 0; }
  bool canRedo() const { return cursor_ < ops_.size(); }
  bool undo();
  bool redo();
  // Removes every operation (a new sheet).
  void clear();

  size_t activeCount() const { return cursor_; }
  // Every operation, the redo tail included (index < activeCount() are in effect).
  const std::vector<PreparedOp>& operations() const { return ops_; }
  // Increases at every edit; lets caches notice a change.
  std::uint64_t revision() const { return revision_; }
  // A number unique to each operation ever added to any model in this process (never reused),
  // parallel to operations(): an index whose id changed holds a different operation than before.
  const std::vector<std::uint64_t>& operationIds() const { return ids_; }

  // f at p with every active operation (the naive, exact evaluation).
  template <class T>
  T evaluate(const P3<T>& p) const;
  // f at p with only the listed operations (ascending indices, all < activeCount()). Exact when
  // the list holds every active operation whose support contains (p.x, p.y): the others change
  // nothing there.
  template <class T>
  T evaluate(const P3<T>& p, std::span<const std::uint32_t> candidates) const;

  // Batches: one value (or value and gradient) per point.
  void evaluate(std::span<const P3<double>> points, std::span<double> out) const;
  void evaluateGradient(std::span<const P3<double>> points, std::span<Grad> out) const;

  // f along the vertical line through (x, y) with the listed operations (as evaluate(p,
  // candidates), whose rule the list follows; the line reads it, so it must outlive the line).
  // Under the sheet model every offset moves space along z by a function of (x, y) alone: their
  // sum, and the shift each set operation sees, are found once for the line, and a value at a z
  // after that costs the workpiece and the set operations alone. The same bits as evaluate() at
  // every z. (A column searched for its faces: a flat tool's fit, a height map's pixel.)
  template <class T>
  class Line {
   public:
    Line(const Model& model, const T& x, const T& y, std::span<const std::uint32_t> candidates);
    T operator()(const T& z) const;

   private:
    const Model* model_;
    T x_, y_;
    std::span<const std::uint32_t> candidates_;
    bool sheet_;
    T total_{0.0};  // the offsets' sum (the sheet model)
    struct SetStep {
      std::uint32_t op;
      T shift;  // the offsets after it
    };
    std::vector<SetStep> sets_;
  };

  // The sum of the active offsets at (x, y): the sheet's displacement D (sheet model) in mm.
  template <class T>
  T displacement(const T& x, const T& y, const T& z, std::span<const std::uint32_t> candidates) const;

  // A box that holds the model: the workpiece's bounds grown by the largest reach of the operations.
  Box3 bounds() const;

 private:
  template <class T, class Indices>
  T evaluateWith(const P3<T>& p, const Indices& indices) const;

  std::shared_ptr<const Workpiece> workpiece_;
  Deformation deformation_;
  std::vector<PreparedOp> ops_;
  std::vector<std::uint64_t> ids_;
  size_t cursor_ = 0;
  std::uint64_t revision_ = 0;
};

extern template double Model::evaluate(const P3<double>&) const;
extern template Grad Model::evaluate(const P3<Grad>&) const;
extern template Interval Model::evaluate(const P3<Interval>&) const;
extern template double Model::evaluate(const P3<double>&, std::span<const std::uint32_t>) const;
extern template Grad Model::evaluate(const P3<Grad>&, std::span<const std::uint32_t>) const;
extern template Interval Model::evaluate(const P3<Interval>&, std::span<const std::uint32_t>) const;
extern template class Model::Line<double>;
extern template class Model::Line<Interval>;

}  // namespace emboss
