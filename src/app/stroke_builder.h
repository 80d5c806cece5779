// A stroke in progress: pen points on the sheet become the paper's operations while the pen moves.
#pragma once

#include <cstddef>
#include <vector>

#include "tools/tool_catalogue.h"

namespace emboss {

// Operations are made by strokeToOperations() (src/tools) from the whole stroke so far; those that
// can no longer change as the stroke goes on (all but the tail: the last one, the last two for the
// oval punch whose direction looks one strike ahead, none for a region until its contour closes;
// every strike of the flat punch, placed where the pen has already passed, once it has two)
// are handed out at once, so the metal moves under the pen. When the stroke ends, the operations
// of the whole stroke are computed once more: the result is exactly strokeToOperations(stroke).
class StrokeBuilder {
 public:
  void begin(const ToolSpec& tool, const Metal& metal);
  bool active() const { return active_; }
  const ToolSpec& tool() const { return tool_; }
  const std::vector<StrokePoint>& points() const { return points_; }

  // Adds a point; returns the operations that became final with it (to append to the model now).
  std::vector<Operation> add(const StrokePoint& p);

  struct Finish {
    size_t keep = 0;              // how many of the operations handed out so far stay
    std::vector<Operation> rest;  // then these complete the stroke
  };
  // Ends the stroke. Normally keep == handed out; were a handed-out operation ever to differ from
  // the final one, keep says how many to take back first.
  Finish end();
  size_t handedOut() const { return handed_.size(); }

 private:
  // How many of the stroke's operations so far are final (the same whatever the pen does next).
  size_t settled(const std::vector<Operation>& ops) const;

  bool active_ = false;
  ToolSpec tool_{};
  Metal metal_{};
  std::vector<StrokePoint> points_;
  std::vector<Operation> handed_;
  double sinceLast_ = 0;  // mm moved since the operations were last recomputed
};

// Field-by-field equality of the parameters that the operation's kind uses.
bool sameOperation(const Operation& a, const Operation& b);

}  // namespace emboss
