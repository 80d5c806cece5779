// The staff export on a thread of its own: the destination checked, the sessions copied, progress kept.
#include "app/session_export.h"

#include "staff/staff_protocol.h"

namespace emboss {

namespace fs = std::filesystem;

Result<std::unique_ptr<SessionExport>> SessionExport::start(fs::path sessionsDir, ExportRequest request) {
  if (Status s = checkExportDestination(request.dest, request.allowAnyDir); !s) return fail(s.error());
  std::unique_ptr<SessionExport> e(new SessionExport(std::move(sessionsDir), std::move(request)));
  e->thread_ = std::thread([p = e.get()] { p->run(); });
  return e;
}

SessionExport::SessionExport(fs::path sessionsDir, ExportRequest request)
    : sessionsDir_(std::move(sessionsDir)), request_(std::move(request)) {}

SessionExport::~SessionExport() { stop(); }

void SessionExport::stop() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

std::vector<SessionStore::ExportProgress> SessionExport::takeUpdates() {
  std::lock_guard lock(m_);
  std::vector<SessionStore::ExportProgress> out;
  out.swap(updates_);
  return out;
}

void SessionExport::run() {
  // A store of its own over the same folder: exportAll only reads the saved files.
  const SessionStore store(sessionsDir_, {});
  std::optional<SessionStore::Extra> current;
  if (request_.currentJson)
    current = SessionStore::Extra{*request_.currentJson, request_.currentPicture ? &*request_.currentPicture : nullptr};
  ExportTakeHome hook;
  std::unique_ptr<TextPainter> painter;
  if (request_.takeHome.any()) {
    if (request_.takeHome.postcard && request_.textFactory) painter = request_.textFactory();
    hook.allowance = request_.takeHome.allowance();
    hook.make = [this, &painter](const fs::path& scene) -> Result<std::pair<size_t, std::uintmax_t>> {
      auto w = writeTakeHomeFiles(scene, request_.takeHome, painter.get(), 1);
      if (!w) return fail(w.error());
      return std::make_pair(w->files, w->bytes);
    };
  }
  auto r = store.exportAll(request_.dest, sanitizeName(request_.stamp), current, {}, request_.sinceUnix,
                           [this](const SessionStore::ExportProgress& p) {
                             std::lock_guard lock(m_);
                             updates_.push_back(p);
                           },
                           &stop_, hook);
  {
    std::lock_guard lock(m_);
    result_ = std::move(r);
  }
  done_.store(true);
}

}  // namespace emboss
