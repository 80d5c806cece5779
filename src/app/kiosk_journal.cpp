// The kiosk and its session journal: every change on the bench made durable as it is made, the
// unfinished session brought back at start, old sessions pruned (docs/sessions.md).
#include <chrono>
#include <cmath>

#include "app/kiosk_app.h"

namespace emboss {

namespace {

double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

void KioskApp::journalSync() {
  if (!journal()) return;
  const Model& m = bench_->model();
  const std::string metal(bench_->metal().name);
  const std::uint64_t made = bench_->strokesMade();
  if (m.revision() == journalRev_ && metal == journalState_.metal && made == journalState_.strokesMade) return;
  journalRev_ = m.revision();
  if (!journalOpen_) {
    if (m.operations().empty()) return;  // nothing made yet: no session
    Scene head = bench_->scene("Visitor session");
    head.operations.clear();
    journalId_ = journal_->begin(sceneToJson(head));
    journalOpen_ = true;
    setLogSession(journalId_);
    journaledIds_.clear();
    journalState_ = {};
  }
  const auto& ids = m.operationIds();
  size_t same = 0;
  while (same < ids.size() && same < journaledIds_.size() && ids[same] == journaledIds_[same]) ++same;
  if (same < ids.size()) {
    std::vector<std::string> ops;
    ops.reserve(ids.size() - same);
    for (size_t i = same; i < ids.size(); ++i) ops.push_back(operationToJson(m.operations()[i].op()));
    journal_->operations(same, std::move(ops));
  }
  journaledIds_ = ids;
  JournalState st{m.activeCount(), bench_->strokeSizes(), bench_->redoSizes(), metal, made};
  if (st.cursor != journalState_.cursor || st.strokes != journalState_.strokes || st.redo != journalState_.redo ||
      st.metal != journalState_.metal || st.strokesMade != journalState_.strokesMade) {
    journal_->state(st);
    journalState_ = std::move(st);
  }
}

void KioskApp::journalReport() {
  if (!journal()) return;
  const std::int64_t current = logSession();
  for (const auto& [session, n] : journal_->takeDurable()) {
    if (session != durableSession_) durableSession_ = session, durableLogged_ = 0;
    setLogSession(session);  // the writer may report a session that has just ended
    for (std::uint64_t k = durableLogged_ + 1; k <= n; ++k)
      if (log_) log_("<7>journal: stroke " + std::to_string(k) + " durable");
    durableLogged_ = std::max(durableLogged_, n);
  }
  setLogSession(current);
}

bool KioskApp::journalFlush(double seconds) {
  if (!journal()) return true;
  journalSync();
  const bool done = journal_->flush(seconds);
  journalReport();
  return done;
}

void KioskApp::restoreSession(double now) {
  if (!journal()) return;
  auto js = journal_->unfinished();
  if (!js) return;
  const std::string name = "session " + std::to_string(js->id);
  setLogSession(js->id);  // the lines below are about it
  if (js->dropped && log_)
    log_("<4>session: " + name + ": " + std::to_string(js->dropped) + " damaged records dropped (checksum); kept the " +
         std::to_string(js->records) + " before them");
  auto text = sceneWithOperations(js->head, js->operations);
  Result<Scene> scene = text ? parseScene(*text, "journal " + name, config_.sessionsDir) : Result<Scene>(fail(text.error()));
  if (!scene) {
    if (log_) log_("<3>session: " + name + " cannot be read back (" + scene.error() + "); kept in the journal as finished");
    journal_->endSession(js->id);
    setLogSession(0);
    return;
  }
  const double age = wallSeconds() - js->last;
  if (age > config_.idleSeconds || js->operations.empty()) {
    // The visitor has long gone: the session is closed and kept like every finished one.
    Result<Model> model = scene->makeModel();
    if (model) {
      for (size_t i = js->state.cursor; i < js->operations.size(); ++i) model->undo();
      if (model->activeCount() > 0) {
        scene->title = "Visitor session (closed at start)";
        sessions_->save(*scene, *model, nullptr, fileStamp());
      }
    }
    journal_->endSession(js->id);
    if (log_)
      log_("session: " + name + " was left unfinished " + std::to_string(int(std::round(age))) + " s ago; closed and kept (" +
           std::to_string(js->state.strokesMade) + " strokes, " + std::to_string(js->state.cursor) + " operations)");
    setLogSession(0);
    return;
  }
  if (!bench_->restore(scene->operations, js->state.cursor, js->state.strokes, js->state.redo, js->state.metal,
                       js->state.strokesMade) && log_)
    log_("<4>session: " + name + ": the model refused some operations");
  journal_->resume(js->id);
  journalOpen_ = true;
  journalId_ = js->id;
  journaledIds_ = bench_->model().operationIds();
  journalRev_ = bench_->model().revision();
  journalState_ = {bench_->model().activeCount(), bench_->strokeSizes(), bench_->redoSizes(), std::string(bench_->metal().name),
                   bench_->strokesMade()};
  durableSession_ = js->id;
  durableLogged_ = bench_->strokesMade();
  sessionStarted_ = now;
  states_.resumeVisitor(now);
  if (log_)
    log_("session: restored " + name + ": " + std::to_string(bench_->strokesMade()) + " strokes, " +
         std::to_string(bench_->model().operations().size()) + " operations (" + std::to_string(bench_->model().activeCount()) +
         " in effect)");
}

void KioskApp::pruneSessions(double now) {
  lastPrune_ = now;
  const double before = wallSeconds() - config_.retentionDays * 86400.0;
  const auto maxBytes = std::uintmax_t(config_.retentionMb * 1048576.0);
  size_t n = journal() ? journal_->prune(before, maxBytes / 2) : 0;
  n += sessions_->prune(before, maxBytes / 2);
  if (n && log_) log_("session: " + std::to_string(n) + " sessions beyond the retention (" + std::to_string(int(config_.retentionDays)) +
                      " days, " + std::to_string(int(config_.retentionMb)) + " MB) deleted");
}

}  // namespace emboss
