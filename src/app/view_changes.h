// What changed in a view since the last frame: the renderer's to-do list, kept by the bench and the attract player.
#pragma once

#include <cstddef>
#include <vector>

namespace emboss {

struct ViewChanges {
  bool full = false;         // trace everything again (a new sheet, another metal, another model)
  bool camera = false;       // the camera moved (implies full)
  std::vector<size_t> ops;   // operations added, undone or redone (indices into the model's list)

  bool any() const { return full || camera || !ops.empty(); }
  void merge(const ViewChanges& o) {
    full = full || o.full;
    camera = camera || o.camera;
    ops.insert(ops.end(), o.ops.begin(), o.ops.end());
  }
};

}  // namespace emboss
