// The ray tracer: exact root finding on the model's function, tiles on the fixed thread pool.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

#include "frep/model.h"
#include "frep/op_grid.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/shading.h"
#include "render/thread_pool.h"

namespace emboss {

struct RenderStats {
  std::uint64_t rays = 0;
  std::uint64_t hits = 0;
  std::uint64_t steps = 0;        // root-finder steps (interval tests and sign tests) over all rays
  std::uint64_t evaluations = 0;  // function evaluations (point, gradient and interval)
  std::uint64_t opsVisited = 0;   // operations visited over all evaluations
  double meanStepsPerRay() const { return rays ? static_cast<double>(steps) / rays : 0.0; }
  double meanOpsPerEvaluation() const { return evaluations ? static_cast<double>(opsVisited) / evaluations : 0.0; }
  RenderStats& operator+=(const RenderStats& o) {
    rays += o.rays, hits += o.hits, steps += o.steps, evaluations += o.evaluations, opsVisited += o.opsVisited;
    return *this;
  }
};

struct RenderOptions {
  bool naive = false;  // no index: every active operation at every point (for comparison)
  int tileSize = 32;
};

// Root finding (docs/rendering.md): the ray is cut into steps of fixed length h aligned to a grid
// along the ray that depends on nothing but the camera, so a pixel's result never depends on the
// model's bounds, the tile or the thread. Spans of 8 steps and then single steps are skipped when
// the interval bound of f over their box excludes zero (no Lipschitz constant is assumed: the
// offsets and blends are not distance fields). In a step whose bound contains zero, a sign change
// of f between its ends is bisected to the surface; without one, the step is split up to three
// times more so thin features are not missed. Normals come from the exact gradient (forward-mode
// differentiation of the same kernels).
class Renderer {
 public:
  explicit Renderer(ThreadPool& pool) : pool_(pool) {}

  // Brings the spatial index up to date with the model (call after edits, never during a render).
  void sync(const Model& model);
  void setCamera(const Camera& camera) { camera_ = camera; }
  void setShading(const ShadingParams& shading) { shading_ = shading; }
  void setOptions(const RenderOptions& options) { options_ = options; }

  // Traces every pixel of `rect` into `image` (sized to the camera). Returns false if cancelled.
  bool render(Image& image, const Rect& rect, RenderStats* stats = nullptr, const std::atomic_bool* cancel = nullptr);
  bool renderFull(Image& image, RenderStats* stats = nullptr, const std::atomic_bool* cancel = nullptr);

  // The pixels whose rays can see a change made by operation `index` of the model (appended or
  // undone): the projection of its support, from the lowest to the highest the surface can reach,
  // grown by the root finder's span so that no ray outside it examines a different function.
  Rect dirtyRect(const Model& model, size_t index) const;

  const OpGrid& grid() const { return grid_; }
  double stepLength() const { return step_; }

 private:
  std::optional<glm::dvec3> traceColor(int px, int py, RenderStats& st, std::vector<std::uint32_t>& scratch) const;

  ThreadPool& pool_;
  const Model* model_ = nullptr;
  OpGrid grid_;
  std::optional<Camera> camera_;
  ShadingParams shading_{};
  RenderOptions options_{};
  double step_ = 0.25;
  Box3 bounds_{};
  std::vector<std::uint32_t> all_;  // 0..active-1, for the naive mode
};

}  // namespace emboss
