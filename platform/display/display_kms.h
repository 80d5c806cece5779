// The KMS display: fullscreen GLES on a bare DRM/KMS card through GBM and EGL (like kmscube), with
// page flips on vblank; the kiosk's display on the board. Also probing and waiting for a screen.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "devices/display.h"
#include "gl/gl_presenter.h"
#include "util/result.h"

namespace emboss {

// A connected output found without touching it.
struct KmsOutput {
  std::string card;       // "/dev/dri/card1"
  std::string driver;     // "vc4"
  std::string connector;  // "HDMI-A-1"
  int width = 0, height = 0, refreshHz = 0;  // its preferred mode
};

// The first card with a connected connector and a mode. Fails with a message that says what is
// missing: "kms: no /dev/dri/card* (no GPU driver loaded)", "kms: card0 has no connected connector
// (...)", "kms: cannot open /dev/dri/card0: Permission denied (...)".
Result<KmsOutput> probeKmsOutput();

// Takes over that output at its preferred mode. The display's size is the mode's; name() is e.g.
// "kms (card1 HDMI-A-1 1920x1080@60, V3D 4.2)". present() waits for the page flip (vsync) and
// returns false once the connector is unplugged or the card stops flipping.
Result<std::unique_ptr<Display>> createKmsDisplay(const GlPresenterSettings& settings = {});

// For the kiosk's start-up and after a lost output: tries createKmsDisplay() at once and then once
// a second until it succeeds or `timeout` has passed. Before each wait `keepWaiting(lastError)` is
// called when given (show the message, check for SIGTERM); returning false gives up early.
Result<std::unique_ptr<Display>> waitForKmsDisplay(
    std::chrono::milliseconds timeout, const GlPresenterSettings& settings = {},
    const std::function<bool(const std::string& lastError)>& keepWaiting = {});

}  // namespace emboss
