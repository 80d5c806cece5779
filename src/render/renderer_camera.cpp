// The renderer's camera: the kept hits and backdrops of the last cameras, and picking a point of
// the model under an image point.
#include <algorithm>
#include <cstddef>

#include "render/renderer_internal.h"

namespace emboss {

using namespace render_internal;

namespace {

bool sameCamera(const Camera& a, const Camera& b) {
  return a.width() == b.width() && a.height() == b.height() && a.spec() == b.spec();
}

// Moves the first of `items` that `matches` to the front, the others keeping their order behind
// it, or when none does the last one (used longest ago): whether one matched.
template <class T, size_t N, class Match>
bool toFront(T (&items)[N], Match matches) {
  T* it = std::find_if(items, items + N, matches);
  const bool found = it != items + N;
  if (!found) it = items + N - 1;
  std::rotate(items, it, it + 1);
  return found;
}

}  // namespace

bool Renderer::pick(const Model& model, const Camera& camera, double sx, double sy, std::optional<glm::dvec3>& hit) const {
  if (model_ != &model || model.revision() != syncedRevision_ || model.workpiecePtr() != syncedWorkpiece_ || fieldPending() ||
      !camera_ || !sameCamera(*camera_, camera))
    return false;
  RenderStats st;
  std::vector<std::uint32_t> scratch;
  const std::optional<Hit> h = usesField() ? traceField(sx, sy, st, scratch) : traceExact(sx, sy, st, scratch);
  hit = h ? std::optional<glm::dvec3>(h->p) : std::nullopt;
  return true;
}

void Renderer::setCamera(const Camera& camera) {
  camera_ = camera;
  ++cameraGeneration_;
  // The kept hits: this camera's if it is one of the last three, else none yet (in the place of
  // the one used longest ago).
  if (!toFront(hitCaches_, [&](const HitCache& h) { return h.camera && sameCamera(*h.camera, camera); })) {
    hitCaches_[0].camera = camera;
    hitCaches_[0].t.resize(static_cast<size_t>(camera.width()) * camera.height());
    hitCaches_[0].sampled.clear();
    hitCaches_[0].blank = true;
  }
  // The backdrop depends on the pixel and the picture's size alone: computed once per size, the
  // last three sizes kept.
  const int w = camera.width(), h = camera.height();
  if (toFront(backdrops_, [&](const Backdrop& k) { return k.w == w && k.h == h && !k.bytes.empty(); })) return;
  Backdrop& b = backdrops_[0];
  ++backdropsMade_;
  b.w = w, b.h = h;
  b.bytes.assign(static_cast<size_t>(w) * h * 3, 0);
  std::uint8_t* const bytes = b.bytes.data();
  pool_.parallelFor2D(Rect{0, 0, w, h}, 64, [&](const Rect& t) {
    for (int y = t.y; y < t.y + t.h; ++y)
      for (int x = t.x; x < t.x + t.w; ++x) {
        const auto rgb = toSrgb8Fast(backdrop(x, y, w, h));
        std::copy(rgb.begin(), rgb.end(), &bytes[(static_cast<size_t>(y) * w + x) * 3]);
      }
  });
}

}  // namespace emboss
