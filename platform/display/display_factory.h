// Choosing the display back end by name: auto (kms, x11, headless, osmesa in that order), kms,
// x11, headless or osmesa.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "devices/display.h"
#include "gl/gl_presenter.h"
#include "util/result.h"

namespace emboss {

// The kinds createDisplay() accepts, "auto" first.
const std::vector<std::string>& displayKinds();

// Starts the display `kind`. "auto" tries kms, x11, headless, osmesa and returns the first that
// starts. kms takes its size from the screen's preferred mode, x11 opens a width x height window,
// headless and osmesa are width x height. When `log` is given, one line per attempt is appended,
// e.g. "kms: no /dev/dri/card* (no GPU driver loaded)\nx11: $DISPLAY not set (...)\n
// headless: started headless (EGL surfaceless, llvmpipe) 1280x800\n". On failure the error has
// every attempt's reason.
Result<std::unique_ptr<Display>> createDisplay(const std::string& kind, int width, int height, std::string* log,
                                               const GlPresenterSettings& settings = {});

}  // namespace emboss
