// The display factory: one kind by name, or the first that starts of kms, x11, headless, osmesa.
#include "display/display_factory.h"

#include "display/display_headless.h"
#include "display/display_kms.h"
#include "display/display_osmesa.h"
#include "display/display_x11.h"

namespace emboss {
namespace {

Result<std::unique_ptr<Display>> createOne(const std::string& kind, int width, int height,
                                           const GlPresenterSettings& settings) {
  if (kind == "kms") return createKmsDisplay(settings);
  if (kind == "x11") return createX11Display(width, height, settings);
  if (kind == "headless") return createHeadlessDisplay(width, height, settings);
  if (kind == "osmesa") return createOsmesaDisplay(width, height, settings);
  return fail("display: unknown kind '" + kind + "' (use auto, kms, x11, headless or osmesa)");
}

}  // namespace

const std::vector<std::string>& displayKinds() {
  static const std::vector<std::string> kinds = {"auto", "kms", "x11", "headless", "osmesa"};
  return kinds;
}

Result<std::unique_ptr<Display>> createDisplay(const std::string& kind, int width, int height, std::string* log,
                                               const GlPresenterSettings& settings) {
  const std::vector<std::string> order =
      kind == "auto" ? std::vector<std::string>{"kms", "x11", "headless", "osmesa"} : std::vector<std::string>{kind};
  std::string reasons;
  for (const std::string& k : order) {
    auto display = createOne(k, width, height, settings);
    if (display) {
      if (log != nullptr) {
        *log += k + ": started " + (*display)->name() + " " + std::to_string((*display)->width()) + "x" +
                std::to_string((*display)->height()) + "\n";
      }
      return display;
    }
    if (log != nullptr) *log += display.error() + "\n";
    reasons += (reasons.empty() ? "" : "; ") + display.error();
  }
  if (kind == "auto") return fail("display: no back end started: " + reasons);
  return fail(reasons);
}

}  // namespace emboss
