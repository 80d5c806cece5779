// The headless display: EGL on Mesa without any screen (surfaceless, else a pbuffer), drawing into
// an FBO; for CI, screenshots and kiosks whose picture is only recorded.
#pragma once

#include <memory>

#include "devices/display.h"
#include "gl/gl_presenter.h"
#include "util/result.h"

namespace emboss {

// A width x height headless display; name() is e.g. "headless (EGL surfaceless, llvmpipe)".
Result<std::unique_ptr<Display>> createHeadlessDisplay(int width, int height,
                                                       const GlPresenterSettings& settings = {});

}  // namespace emboss
