// The OSMesa display: OSMesaCreateContextExt, OSMesaMakeCurrent into a client buffer, and the GL
// presenter with GLSL 1.20 shaders; every GL call goes through OSMesaGetProcAddress.
#include "display/display_osmesa.h"

#include <GL/osmesa.h>

#include <cstdint>
#include <string>
#include <vector>

namespace emboss {
namespace {

struct OsmesaContextDeleter {
  void operator()(osmesa_context* context) const { OSMesaDestroyContext(context); }
};
using OsmesaContextPtr = std::unique_ptr<osmesa_context, OsmesaContextDeleter>;

class OsmesaDisplay final : public Display {
 public:
  OsmesaDisplay(OsmesaContextPtr context, int width, int height)
      : context_(std::move(context)), width_(width), height_(height),
        buffer_(static_cast<std::size_t>(width) * height * 4, 0) {}
  ~OsmesaDisplay() override {
    if (makeCurrent()) presenter_.reset();  // the presenter frees its GL objects in this context
    OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
  }

  // OSMesa binds Mesa's per-thread GL dispatch behind EGL's back; bind every time (it is cheap)
  // and tell EGL displays on this thread to bind again before their next frame.
  bool makeCurrent() {
    noteForeignGlBinding();
    return OSMesaMakeCurrent(context_.get(), buffer_.data(), GL_UNSIGNED_BYTE, width_, height_) == GL_TRUE;
  }

  Status start(const GlPresenterSettings& settings) {
    if (!makeCurrent()) return fail("osmesa: OSMesaMakeCurrent failed for a " + std::to_string(width_) + "x" +
                                    std::to_string(height_) + " buffer");
    auto loader = [](const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); };
    auto presenter = GlPresenter::create(loader, GlFlavor::kDesktop, width_, height_, false, settings);
    if (!presenter) return fail("osmesa: " + presenter.error());
    presenter_ = std::move(*presenter);
    name_ = "osmesa (software GL, " + presenter_->renderer() + ")";
    return Ok{};
  }

  std::string name() const override { return name_; }
  int width() const override { return width_; }
  int height() const override { return height_; }

  bool present(const Image& frame, std::span<const Rect> dirty, const Overlay& overlay) override {
    if (!makeCurrent()) return false;
    return presenter_->draw(frame, dirty, overlay);
  }

  Image screenshot() override {
    if (!makeCurrent()) return Image();
    return presenter_->screenshot();
  }

 private:
  OsmesaContextPtr context_;
  int width_, height_;
  std::vector<std::uint8_t> buffer_;  // the "screen" OSMesa renders into (rows bottom up)
  std::unique_ptr<GlPresenter> presenter_;
  std::string name_;
};

}  // namespace

Result<std::unique_ptr<Display>> createOsmesaDisplay(int width, int height, const GlPresenterSettings& settings) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
    return fail("osmesa: bad size " + std::to_string(width) + "x" + std::to_string(height));
  }
  OsmesaContextPtr context(OSMesaCreateContextExt(OSMESA_RGBA, 0, 0, 0, nullptr));
  if (!context) return fail("osmesa: OSMesaCreateContextExt failed (is libosmesa6 installed and working?)");
  auto display = std::make_unique<OsmesaDisplay>(std::move(context), width, height);
  if (Status s = display->start(settings); !s) return fail(s.error());
  return std::unique_ptr<Display>(std::move(display));
}

}  // namespace emboss
