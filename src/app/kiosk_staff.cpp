// The kiosk's staff screen: its menu (resume, export, reset, capture) and its diagnostics lines.
#include <cmath>

#include "app/kiosk_app.h"
#include "app/kiosk_app_detail.h"
#include "staff/staff_protocol.h"

#include <chrono>

#include <nlohmann/json.hpp>

namespace emboss {

namespace fs = std::filesystem;
using namespace kiosk_detail;

namespace kiosk_detail {

// Splits text at spaces into lines of at most n characters (a longer word is cut).
std::vector<std::string> wrapWords(const std::string& text, size_t n) {
  std::vector<std::string> out;
  std::string line;
  size_t i = 0;
  while (i < text.size()) {
    const size_t sp = text.find(' ', i);
    std::string word = text.substr(i, sp == std::string::npos ? std::string::npos : sp - i);
    i = sp == std::string::npos ? text.size() : sp + 1;
    while (word.size() > n) {
      if (!line.empty()) out.push_back(line), line.clear();
      out.push_back(word.substr(0, n));
      word.erase(0, n);
    }
    if (!line.empty() && line.size() + 1 + word.size() > n) out.push_back(line), line.clear();
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) out.push_back(line);
  return out;
}

}  // namespace kiosk_detail

void KioskApp::staffActivate(size_t index) {
  const double now = clock_();
  states_.penTouch(now);  // staff activity
  switch (index) {
    case 0:
      states_.leaveStaff(now);
      handleEvents(now);
      break;
    case 1: {
      ExportRequest r;
      r.dest = config_.exportDir;
      r.allowAnyDir = config_.exportAnyDir;
      if (Status st = startExport(std::move(r)); !st) {
        staff_.message = st.error();
        staff_.messageIsError = true;
        if (log_) log_("staff: " + staff_.message);
      }
      break;
    }
    case 2: {
      const bool hadVisitor = states_.modeBeforeStaff() != KioskMode::Attract;
      states_.resetToAttract(now);
      handleEvents(now);  // saves the visitor's session and restarts attract
      if (!hadVisitor) {
        bench_->resetForVisitor(now);
        startAttract(now, 0, 0.0);
      }
      staff_.message = "The exhibit was reset";
      staff_.messageIsError = false;
      if (log_) log_("staff: the exhibit was reset");
      break;
    }
    case 3:
      // Capture a drawing for the bench: back to it (a fresh visitor's sheet when staff mode was
      // entered from attract mode), and the still is taken there, where its guide will show.
      if (!camera_) {
        staff_.message = "No camera: plug in a USB camera (capture drawing is off until then)";
        staff_.messageIsError = true;
        if (log_) log_("staff: capture: no camera");
        break;
      }
      states_.leaveStaff(now);
      handleEvents(now);
      if (states_.mode() == KioskMode::Attract) {
        states_.penTouch(now);
        handleEvents(now);
      }
      startCapture(now);
      break;
    default: break;
  }
}

void KioskApp::updateStaffView(double now) {
  staff_.menu.assign(std::begin(kStaffMenu), std::end(kStaffMenu));
  auto& L = staff_.lines;
  L.clear();
  L.push_back("Display: " + display_->name() + " " + std::to_string(display_->width()) + "x" + std::to_string(display_->height()));
  L.push_back("Pen: " + (pen_ ? pen_->name() : std::string("none")));
  std::string b;
  for (auto* s : buttons_) b += (b.empty() ? "" : ", ") + s->name();
  L.push_back("Buttons: " + (b.empty() ? std::string("none") : b));
  L.push_back("Camera: " + (camera_ ? (capture_.phase == CapturePhase::Running ? std::string("taking a still") : camera_->name())
                                    : std::string("none (capture drawing is off)")));
  for (const auto& [k, v] : deviceNotes_) L.push_back(k + ": " + v);
  std::string rates;
  for (KioskMode m : {KioskMode::Attract, KioskMode::Visitor})
    if (fps(m).seconds() > 0.5) rates += (rates.empty() ? "" : ", ") + std::string(kioskModeName(m)) + fmt(" %.1f fps", fps(m).meanFps());
  L.push_back("Frame rate: " + (rates.empty() ? std::string("not measured yet") : rates));
  if (latency_.count())
    L.push_back(fmt("Stroke to screen: mean %.0f ms", latency_.meanMs()) + fmt(", 95%% %.0f ms", latency_.percentileMs(95)) +
                " (" + std::to_string(latency_.count()) + " updates)");
  else
    L.push_back("Stroke to screen: no strokes yet");
  const auto& c = composer_->counters();
  L.push_back("Tracing: " + std::to_string(c.dirtyRects) + " dirty updates, " + std::to_string(c.previews) + " previews, " +
              std::to_string(c.bands) + " bands");
  L.push_back("Sessions: " + std::to_string(sessions_->list().size()) + " saved, " + std::to_string(sessions_->pendingCount()) +
              " waiting to be written");
  L.push_back("Sessions folder: " + sessions_->dir().string());
  // The journal: a full or read-only disk shows here (the kiosk goes on; what is made waits in memory).
  if (!journal_ || !journal_->ok()) L.push_back("Journal: OFF - sessions are only saved when they end");
  else if (const std::string e = journal_->lastError(); !e.empty())
    L.push_back("Journal: CANNOT WRITE (" + e + "); " + std::to_string(journal_->queued()) + " changes wait in memory");
  else L.push_back("Journal: every stroke on the disk");
  std::error_code ec;
  const auto sp = fs::space(sessions_->dir(), ec);
  if (!ec) L.push_back(fmt("Free space for sessions: %.0f MiB", sp.available / 1048576.0));
  L.push_back("Export folder: " + config_.exportDir.string() + (fs::is_directory(config_.exportDir, ec) ? "" : " (not there)"));
  const int up = static_cast<int>(now - started_);
  char buf[64];
  std::snprintf(buf, sizeof buf, "Up %d:%02d:%02d", up / 3600, up / 60 % 60, up % 60);
  L.push_back(buf);
  // Long lines (a tablet's reason, a deep folder) are wrapped to fit beside the menu.
  std::vector<std::string> wrapped;
  for (const auto& line : L) {
    const auto parts = wrapWords(line, kStaffLineChars);
    for (size_t k = 0; k < parts.size(); ++k) wrapped.push_back(k ? "  " + parts[k] : parts[k]);
  }
  L = std::move(wrapped);
}

namespace {

double unixNow() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

std::string answer(nlohmann::json j) {
  if (!j.contains("ok")) j["ok"] = true;
  return j.dump();
}

std::string refusal(const std::string& message) { return nlohmann::json{{"ok", false}, {"error", message}}.dump(); }

}  // namespace

std::optional<std::string> KioskApp::staffCommand(const std::string& line) {
  using nlohmann::json;
  auto req = parseStaffRequest(line);
  if (!req) return refusal(req.error());
  const double now = clock_();
  switch (req->command) {
    case StaffRequest::Command::Status: {
      json j;
      j["state"] = kioskModeName(states_.mode());
      j["devices"] = deviceNotes_;
      json fps = json::object();
      for (KioskMode m : {KioskMode::Attract, KioskMode::Visitor, KioskMode::StillThere, KioskMode::Staff})
        if (this->fps(m).seconds() > 0.5) fps[kioskModeName(m)] = this->fps(m).meanFps();
      j["fps"] = fps;
      j["latency_ms"] = {{"count", latency_.count()}, {"mean", latency_.meanMs()}, {"p95", latency_.percentileMs(95)}};
      j["sessions"] = {{"saved", sessions_->list().size()}, {"waiting", sessions_->pendingCount()},
                       {"folder", sessions_->dir().string()},
                       {"journal", journal() ? (journal_->lastError().empty() ? "ok" : "cannot write: " + journal_->lastError()) : "off"},
                       {"journal_queued", journal() ? journal_->queued() : 0}};
      std::error_code ec;
      const auto sp = std::filesystem::space(sessions_->dir(), ec);
      if (!ec) j["disk"] = {{"free_mib", double(sp.available) / 1048576.0}, {"size_mib", double(sp.capacity) / 1048576.0}};
      j["operations_on_bench"] = bench_->model().activeCount();
      j["exporting"] = exporting();
      return answer(j);
    }
    case StaffRequest::Command::Sessions: {
      json list = json::array();
      if (journal())
        for (const auto& s : journal_->list())
          list.push_back({{"id", s.id}, {"started", s.started}, {"ended", s.ended}, {"operations", s.operations}});
      json files = json::array();
      for (const auto& f : sessions_->list()) files.push_back(f.filename().string());
      return answer({{"journal", list}, {"files", files}});
    }
    case StaffRequest::Command::Reset: {
      const bool hadVisitor = states_.mode() == KioskMode::Visitor || states_.mode() == KioskMode::StillThere ||
                              (states_.mode() == KioskMode::Staff && states_.modeBeforeStaff() != KioskMode::Attract);
      states_.resetToAttract(now);
      handleEvents(now);  // saves the visitor's session and restarts attract
      if (log_) log_(std::string("staff: the exhibit was reset from embossctl") + (hadVisitor ? " (the visitor's session was saved)" : ""));
      return answer({{"reset", true}, {"session_ended", hadVisitor}});
    }
    case StaffRequest::Command::Wipe: {
      const double before = unixNow() - req->olderThanDays * 86400.0;
      size_t n = journal() ? journal_->prune(before, ~std::uintmax_t(0)) : 0;
      n += sessions_->prune(before, ~std::uintmax_t(0));
      if (log_) log_("staff: wiped " + std::to_string(n) + " sessions finished more than " + fmt("%g", req->olderThanDays) + " days ago");
      return answer({{"wiped", n}});
    }
    case StaffRequest::Command::Export: {
      ExportRequest r;
      r.dest = req->dest;
      r.sinceUnix = req->sinceUnix;
      r.allowAnyDir = req->allowAnyDir;
      if (Status st = startExport(std::move(r)); !st) return refusal(st.error());
      exportForSocket_ = true;
      exportProgressLines_ = req->progress;
      return std::nullopt;
    }
  }
  return refusal("unknown command");
}

std::string KioskApp::statusLine() const {
  std::string s = kioskModeName(states_.mode());
  if (s == "attract") s += " mode";
  if (exporting()) s += ", exporting";
  if (displayLost_) s += ", no display";
  if (journal_ && !journal_->ok()) s += ", sessions not journalled";
  else if (journal_ && !journal_->lastError().empty()) s += ", cannot write sessions: " + journal_->lastError();
  return s;
}

Status KioskApp::startExport(ExportRequest request) {
  if (export_) return fail("An export is already under way (to " + export_->dest().string() + ")");
  sessions_->retryPending();
  // What the thread needs, copied: it never touches the bench, the composer or the store's state.
  if (bench_->model().activeCount() > 0) {
    request.currentJson = sceneToJson(bench_->scene("Visitor session in progress"), &bench_->model());
    if (benchShown_) request.currentPicture = composer_->frame();
  }
  request.stamp = fileStamp();
  request.takeHome = config_.takeHome;
  request.textFactory = textFactory_;
  const std::string dest = request.dest.string();
  auto started = SessionExport::start(sessions_->dir(), std::move(request));
  if (!started) return fail(started.error());
  export_ = std::move(*started);
  exportForSocket_ = exportProgressLines_ = false;
  exportLines_.clear();
  exportAnswer_.reset();
  exportShown_ = {};
  staff_.message = "Exporting to " + dest + " ...";
  staff_.messageIsError = false;
  overlayChanged_ = true;
  if (log_) log_("staff: exporting to " + dest);
  return Ok{};
}

void KioskApp::pollExport() {
  if (!export_) return;
  const bool finished = export_->done();  // read first: the updates taken after it are the last ones
  for (const SessionStore::ExportProgress& p : export_->takeUpdates()) {
    if (p.sessions == exportShown_.sessions && p.sessionsDone == exportShown_.sessionsDone && p.bytes == exportShown_.bytes)
      continue;
    const StaffProgress sp{p.sessionsDone, p.sessions, p.bytes};
    exportShown_ = p;
    staff_.message = "Exporting to " + export_->dest().string() + ": " + staffProgressText(sp);
    staff_.messageIsError = false;
    overlayChanged_ = true;
    if (exportForSocket_ && exportProgressLines_) exportLines_.push_back(staffProgressLine(sp));
  }
  if (!finished) return;
  const auto& r = export_->result();
  if (r) {
    staff_.message = "Exported " + std::to_string(r->files) + " files (" + std::to_string(r->bytes / 1024) + " KiB) to " +
                     r->folder.string();
    if (!r->warnings.empty())
      staff_.message += "; " + std::to_string(r->warnings.size()) + " take-home file(s) not made: " + r->warnings.front();
    staff_.messageIsError = false;
    if (exportForSocket_)
      exportAnswer_ = answer({{"folder", r->folder.string()}, {"files", r->files}, {"bytes", r->bytes}, {"warnings", r->warnings}});
    if (log_)
      for (const auto& w : r->warnings) log_("<4>staff: take-home file not made: " + w);
  } else {
    staff_.message = r.error();
    staff_.messageIsError = true;
    if (exportForSocket_) exportAnswer_ = refusal(r.error());
  }
  overlayChanged_ = true;
  if (log_) log_(std::string(r ? "" : "<3>") + "staff: " + staff_.message);
  export_.reset();
}

StaffPending KioskApp::staffPoll() {
  StaffPending p;
  p.progress.swap(exportLines_);
  if (exportAnswer_) {
    p.answer = std::move(exportAnswer_);
    exportAnswer_.reset();
    exportForSocket_ = false;
  }
  return p;
}

}  // namespace emboss
