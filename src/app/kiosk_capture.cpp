// The kiosk's capture drawing: a still from the camera traced off the main loop, offered, embossed or
// put away; and the camera looked after while idle.
#include "app/kiosk_app.h"
#include "app/kiosk_app_detail.h"

namespace emboss {

using namespace kiosk_detail;

void KioskApp::captureNote(double now, const std::string& message, bool error) {
  capture_.message = message;
  capture_.messageIsError = error;
  capture_.messageUntil = now + kCaptureNoteSeconds;
  overlayChanged_ = true;
}

void KioskApp::startCapture(double now) {
  if (capture_.phase == CapturePhase::Running) return;
  if (!camera_) {
    captureNote(now, "No camera", true);
    if (log_) log_("capture: no camera (plug in a USB camera; the kiosk looks for one every few seconds)");
    return;
  }
  discardCapture("a new capture");
  bench_->finishStroke();
  const Box3 b = bench_->model().workpiecePtr()->bounds();
  const double plateW = b.x1 - b.x0, plateH = b.y1 - b.y0;
  CaptureOptions options;
  options.metal = std::string(bench_->metal().name);
  CameraSource* camera = camera_;
  // The still (about 0.2 s of streaming) and the tracing (0.1 to 0.5 s) run on their own thread;
  // the main loop goes on rendering and polls the result every step.
  capture_.job = std::async(std::launch::async, [camera, plateW, plateH, options]() -> Result<CaptureResult> {
    auto photo = camera->capture();
    if (!photo) return fail(photo.error());
    return captureDrawing(*photo, plateW, plateH, options);
  });
  capture_.phase = CapturePhase::Running;
  capture_.dropResult = false;
  capture_.started = now;
  overlayChanged_ = true;
  if (log_) log_("capture: taking a still with " + camera->name());
}

void KioskApp::pollCapture(double now) {
  if (capture_.phase != CapturePhase::Running || !capture_.job.valid()) return;
  if (capture_.job.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
  Result<CaptureResult> r = capture_.job.get();
  capture_.phase = CapturePhase::Idle;
  overlayChanged_ = true;
  const double secs = now - capture_.started;
  if (capture_.dropResult) {
    if (log_) log_("capture: the result came after the visitor left; dropped");
    return;
  }
  if (!r) {
    if (log_) log_("capture: " + r.error());
    // A camera gone is noticed at once rather than at the next check.
    if (camera_ && !camera_->present()) dropCamera();
    const bool noSheet = r.error().find("no sheet") != std::string::npos;
    const bool noDrawing = r.error().find("no drawing") != std::string::npos;
    captureNote(now, noSheet ? "No sheet of paper found: hold it flat under the camera" :
                noDrawing ? "No drawing found on the sheet" : "The camera did not give a picture", true);
    return;
  }
  if (r->operations.empty()) {
    captureNote(now, "No drawing found on the sheet", true);
    if (log_) log_("capture: the drawing gave no lines to emboss");
    return;
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, "capture: %zu lines, %zu operations, traced in %.1f s; offered (capture again: emboss, undo: put away)",
                r->polylines.size(), r->operations.size(), secs);
  if (log_) log_(buf);
  capture_.offer = std::move(*r);
  capture_.phase = CapturePhase::Offer;
  captureNote(now, "Your drawing: press capture again to emboss it, undo to put it away", false);
}

void KioskApp::acceptCapture(double now) {
  if (!capture_.offer) return;
  const size_t n = bench_->addStroke(capture_.offer->operations);
  lastCommitted_ = bench_->committed();  // not a pen event's latency
  capture_.offer.reset();
  capture_.phase = CapturePhase::Idle;
  captureNote(now, "Embossed: undo takes it back", false);
  if (log_) log_("capture: the drawing was embossed (" + std::to_string(n) + " operations, one undo takes them back)");
}

void KioskApp::discardCapture(const std::string& why) {
  if (capture_.phase == CapturePhase::Running) capture_.dropResult = true;
  if (!capture_.offer) return;
  capture_.offer.reset();
  capture_.phase = CapturePhase::Idle;
  overlayChanged_ = true;
  if (log_) log_("capture: the drawing on offer was put away (" + why + ")");
}

void KioskApp::checkCamera(double now) {
  if (!camera_ || capture_.phase == CapturePhase::Running || now - lastCameraCheck_ < kCameraCheckSeconds) return;
  lastCameraCheck_ = now;
  if (!camera_->present()) dropCamera();
}

void KioskApp::dropCamera() {
  if (log_) log_("camera: '" + camera_->name() + "' is gone; capture drawing is off until a camera is back");
  camera_ = nullptr;
  cameraLost_ = true;
}

}  // namespace emboss
