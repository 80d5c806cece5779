// A staff export of the visitors' sessions (docs/sessions.md), run on a thread of its own so that the
// kiosk's main loop goes on; the staff screen and embossctl both start it here and watch its progress.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/session_store.h"
#include "export/take_home.h"
#include "render/image.h"

namespace emboss {

struct ExportRequest {
  std::filesystem::path dest;    // the stick's mount point
  double sinceUnix = 0;          // sessions saved since then only (0: all)
  bool allowAnyDir = false;      // a folder on the kiosk's own disk too (tests)
  std::string stamp;             // names the export's folder (sanitized here)
  std::optional<std::string> currentJson;  // the session in progress, if any
  std::optional<Image> currentPicture;     // ... and its picture as last shown
  TakeHomeSet takeHome;                    // take-home files made beside each session
  std::function<std::unique_ptr<TextPainter>()> textFactory;  // the postcard's caption (none: no words)
};

// Thread-safe: the main loop starts it and reads takeUpdates() and result(); the export's thread writes.
class SessionExport {
 public:
  // Checks the destination (a mounted file system other than the root's, unless allowAnyDir) and
  // starts copying from `sessionsDir`. A refusal is returned at once, with the reason.
  static Result<std::unique_ptr<SessionExport>> start(std::filesystem::path sessionsDir, ExportRequest request);
  ~SessionExport();  // stops the copying between two files (the kiosk is stopping) and waits for it
  SessionExport(const SessionExport&) = delete;
  SessionExport& operator=(const SessionExport&) = delete;

  // Stops the copying between two files and waits for it: done() is then true, and result() says
  // how far it got.
  void stop();
  const std::filesystem::path& dest() const { return request_.dest; }
  // Every progress report since the last call, in order (none is lost between two main-loop steps,
  // however fast the copying goes).
  std::vector<SessionStore::ExportProgress> takeUpdates();
  bool done() const { return done_.load(); }
  // Once done(): the summary, or why the export failed.
  const Result<SessionStore::ExportSummary>& result() const { return result_; }

 private:
  SessionExport(std::filesystem::path sessionsDir, ExportRequest request);
  void run();

  std::filesystem::path sessionsDir_;
  ExportRequest request_;
  mutable std::mutex m_;
  std::vector<SessionStore::ExportProgress> updates_;
  Result<SessionStore::ExportSummary> result_ = fail("the export has not finished");
  std::atomic<bool> done_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace emboss
