// The pace at which the kiosk's main loop polls an input source that has no descriptor to wait on.
#pragma once

namespace emboss {

// Seconds between two polls of a source without a descriptor (a pen behind hidapi, the keyboard of
// an X11 window): the loop's turn while it waits.
inline constexpr double kPollPaceS = 0.005;

}  // namespace emboss
