// `emboss bench --kiosk RECORDING`: what a visitor feels, measured on the kiosk program itself.
#pragma once

#include <functional>
#include <string>

namespace emboss::cli {

struct KioskBenchOptions {
  std::string recording;  // an evemu recording of a real tablet (its .desc beside it or inside)
  int loops = 5;          // the recording played this many times in a row, at its own pace
  int threads = 0;        // the kiosk's render threads (0: one per core)
  bool quick = false;     // shorter idle and attract windows (a smoke test)
  int width = 1280, height = 800;  // the size of the full frames of the sheet the recording left
  // A frame of the bench's baseline (its ms), run before each of those full frames; empty: none.
  std::function<double()> baselineFrame;
  // Where to keep the sheet the recording left: KEEP.json (the session the kiosk saved) and
  // KEEP.png (the full frame that was timed). Empty: nowhere (it goes with the bench's folder).
  std::string keepSheet;
};

// Runs emboss-kiosk (beside this program, else on PATH) headless, twice, and returns the table's
// Markdown: stroke-to-screen latency over the looped recording replayed at its own pace, the
// kiosk's CPU while it then stands idle (screen unchanged), a full frame of the sheet the
// recording left (the session the kiosk saved; kept where keepSheet says), attract mode's frames a
// second; each against the target. On failure returns the reason in `error` and an empty
// string.
std::string kioskBench(const KioskBenchOptions& options, std::string& error);

}  // namespace emboss::cli
