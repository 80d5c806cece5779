// The OSMesa display: Mesa's software GL into a buffer in memory, the fallback when EGL is not
// there at all (old images, odd containers). Same presenter, desktop-GL shaders.
#pragma once

#include <memory>

#include "devices/display.h"
#include "gl/gl_presenter.h"
#include "util/result.h"

namespace emboss {

// A width x height OSMesa display; name() is e.g. "osmesa (software GL, llvmpipe)".
Result<std::unique_ptr<Display>> createOsmesaDisplay(int width, int height,
                                                     const GlPresenterSettings& settings = {});

}  // namespace emboss
