// The kiosk's soak: KioskApp driven headless through many visitors, memory and descriptors watched.
#include "bench/soak.h"

#include <dirent.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "app/attract_library.h"
#include "app/kiosk_app.h"
#include "app/memory_display.h"
#include "bench/piece_generator.h"

namespace emboss {

namespace fs = std::filesystem;

namespace {
long statusKib(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(key);
  while (std::getline(in, line))
    if (line.compare(0, n, key) == 0) return std::strtol(line.c_str() + n, nullptr, 10);
  return -1;
}
}  // namespace

long residentKib() { return statusKib("VmRSS:"); }
long peakResidentKib() { return statusKib("VmHWM:"); }
// What the program holds on the heap (glibc: the arenas' blocks in use plus the mapped ones), or -1
// elsewhere: a leak raises it, fragmentation (resident memory the allocator keeps) does not.
double heapInUseMb() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd) / 1048576.0;
#else
  return -1.0;
#endif
}

long openFds() {
  DIR* d = ::opendir("/proc/self/fd");
  if (!d) return -1;
  long n = 0;
  while (const dirent* e = ::readdir(d))
    if (e->d_name[0] != '.') ++n;
  ::closedir(d);
  return n - 1;  // the directory stream's own
}

namespace {

constexpr double kFrame = 1.0 / 60.0;  // the fake clock's step while a visitor works

std::uintmax_t bytesOf(const fs::path& dir, bool journal) {
  std::uintmax_t n = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const bool isJournal = name.rfind("sessions.db", 0) == 0;
    if (isJournal == journal) n += it->is_regular_file(ec) ? it->file_size(ec) : 0;
  }
  return n;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

struct WindowStats {
  size_t count = 0;
  double median = 0, lowest = 0, highest = 0;  // KiB
};
WindowStats windowStats(const std::vector<double>& v) {
  if (v.empty()) return {};
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return {v.size(), median(v), *lo, *hi};
}

class Soak {
 public:
  Soak(const SoakOptions& o, std::FILE* out, fs::path sessions)
      : o_(o), out_(out), display_(o.width, o.height), pieces_(builtinAttractPieces()), rng_(o.seed) {
    config_.sessionsDir = std::move(sessions);
    config_.exportDir = config_.sessionsDir.parent_path() / "export";
    config_.threads = o.threads;
    config_.attractSpeed = 8;
    config_.retentionMb = 64;  // the journal and the files are pruned to 32 MB each, as a full card would be
    config_.tablet = config_.buttons = config_.camera = "none";
  }

  SoakResult run() {
    open();
    const size_t every = o_.reportEvery ? o_.reportEvery : std::max<size_t>(1, o_.strokes / 20);
    const size_t warmup = o_.warmup ? o_.warmup : o_.strokes / 10;
    std::fprintf(out_, "soak: %zu strokes, %dx%d, %d render thread%s; baseline after %zu strokes\n\n", o_.strokes, o_.width,
                 o_.height, o_.threads, o_.threads == 1 ? "" : "s", warmup);
    std::fprintf(out_, "| strokes | visitors | restores | resets | attract cycles | attract pieces | RSS MB | RSS when a visitor left, median | RSS since the last row, lowest .. highest | heap in use since the last row, lowest .. highest | peak RSS MB | fds | journal MB | session files MB | s |\n");
    std::fprintf(out_, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    row();
    size_t nextRow = every;
    long baseFd = -1;
    // (strokes, resident KiB) read in the same state after every visitor after the warm-up: the
    // session has just ended, the sheet is blank, the heap trimmed, attract mode not yet played.
    std::vector<std::pair<size_t, long>> rss;
    while (strokes_ < o_.strokes) {
      visitor();
      if (strokes_ >= warmup && baseFd < 0) {
        baseFd = openFds();
        if (warmup > 0 && strokes_ < nextRow) row();
      }
      if (strokes_ >= warmup) rss.emplace_back(strokes_, settledKib_);
      // Every visitor's readings go into the row's ranges: the one in the settled state, and the
      // one after attract mode played (resident memory swings by tens of MB with what was shown).
      for (const double mb : {settledKib_ / 1024.0, residentKib() / 1024.0})
        rowRss_ = {std::min(rowRss_.first, mb), std::max(rowRss_.second, mb)};
      const double heapMb = heapInUseMb();
      rowHeap_ = {std::min(rowHeap_.first, heapMb), std::max(rowHeap_.second, heapMb)};
      rowSettled_.push_back(settledKib_ / 1024.0);
      if (strokes_ >= nextRow || strokes_ >= o_.strokes) {
        row();
        while (nextRow <= strokes_) nextRow += every;
      }
    }
    const long endFd = openFds();
    if (baseFd < 0) baseFd = endFd;
    // The verdict: the median of the settled readings of the first report window after the warm-up
    // against that of the last window. A leak lifts every reading, so the median; a transient (a
    // large piece being shown, the allocator keeping a few pages) moves a few readings, not it.
    const auto window = [&](bool first) {
      std::vector<double> v;
      const size_t from = rss.empty() ? 0 : first ? rss.front().first : (strokes_ > every ? strokes_ - every : 0);
      const size_t to = rss.empty() ? 0 : first ? rss.front().first + every : strokes_;
      for (const auto& [n, kib] : rss)
        if (n >= from && n <= to) v.push_back(static_cast<double>(kib));
      return v;
    };
    const WindowStats firstW = windowStats(window(true)), lastW = windowStats(window(false));
    SoakResult r;
    r.settledGrowthMb = (lastW.median - firstW.median) / 1024.0;
    r.settledLowestGrowthMb = (lastW.lowest - firstW.lowest) / 1024.0;
    r.fdGrowth = endFd - baseFd;
    const bool memOk = firstW.count > 0 && lastW.count > 0 && r.settledGrowthMb < kSoakMaxRssGrowthMb;
    const bool fdOk = r.fdGrowth <= kSoakMaxFdGrowth;
    const bool restoredOk = restoreMismatches_ == 0;
    r.pass = memOk && fdOk && restoredOk;
    std::fprintf(out_, "\nresident memory when a visitor has left (the session ended, the sheet blank, the heap trimmed), "
                 "median (lowest .. highest) of %zu readings in the first %zu strokes after the warm-up: %.1f (%.1f .. %.1f) MB; "
                 "of %zu in the last %zu: %.1f (%.1f .. %.1f) MB: growth %+.2f MB (lowest %+.2f) (limit < %.0f MB): %s\n",
                 firstW.count, every, firstW.median / 1024.0, firstW.lowest / 1024.0, firstW.highest / 1024.0, lastW.count, every,
                 lastW.median / 1024.0, lastW.lowest / 1024.0, lastW.highest / 1024.0, r.settledGrowthMb, r.settledLowestGrowthMb,
                 kSoakMaxRssGrowthMb, memOk ? "PASS" : "FAIL");
    std::fprintf(out_, "file descriptors: %ld after the warm-up, %ld at the end: growth %+ld (limit %ld): %s\n", baseFd, endFd,
                 r.fdGrowth, kSoakMaxFdGrowth, fdOk ? "PASS" : "FAIL");
    std::fprintf(out_, "restores: %zu, each with every stroke back: %s\n", restores_,
                 restoredOk ? "PASS" : ("FAIL (" + std::to_string(restoreMismatches_) + " differed)").c_str());
    std::fprintf(out_, "soak: %s\n", r.pass ? "PASS" : "FAIL");
    app_.reset();
    return r;
  }

 private:
  void open() {
    app_.reset();
    app_ = std::make_unique<KioskApp>(config_, pieces_, display_, [](const std::string&) {}, [this] { return t_; });
    app_->setPen(&pen_, PenMapping::Tablet);
    app_->addButtons(&buttons_);
    lastPiece_ = app_->attract().pieceIndex();
  }

  void step(double dt) {
    t_ += dt;
    app_->step();
    if (app_->attract().pieceIndex() != lastPiece_) lastPiece_ = app_->attract().pieceIndex(), ++piecesPlayed_;
  }
  void settle() {
    for (int i = 0; i < 40 && app_->busy(); ++i) step(kFrame);
  }

  // One stroke: the tip down, a short drag across the sheet, the tip up.
  void stroke() {
    const double x = rng_.uniform(0.15, 0.85), y = rng_.uniform(0.15, 0.85);
    const double dx = rng_.uniform(-0.03, 0.03), dy = rng_.uniform(-0.03, 0.03);
    const int n = 1 + rng_.below(4);
    for (int i = 0; i <= n; ++i)
      pen_.queued.push_back({t_ + i * 0.01, x + dx * i, y + dy * i, rng_.uniform(0.3, 1.0), true, true, false, false});
    pen_.queued.push_back({t_ + (n + 1) * 0.01, x + dx * n, y + dy * n, 0.0, false, true, false, false});
    step(kFrame);
    settle();
    ++strokes_;
  }

  void tap(Action a) {
    buttons_.tap(a, t_);
    step(kFrame);
    settle();
  }

  // A visitor: strokes with undo and redo, a tool or metal now and then, maybe a new sheet; the
  // kiosk killed and restarted mid-session now and then (the journal brings the session back);
  // then the visitor leaves (the idle timeout, or staff reset from embossctl) and attract plays.
  void visitor() {
    ++visitors_;
    const size_t n = 20 + size_t(rng_.below(180));
    const bool crash = o_.restartEvery > 0 && visitors_ % o_.restartEvery == o_.restartEvery / 2;
    for (size_t i = 0; i < n && strokes_ < o_.strokes; ++i) {
      stroke();
      if (rng_.chance(0.15)) tap(Action::Undo);
      if (rng_.chance(0.05)) tap(Action::Redo);
      if (rng_.chance(0.03)) tap(Action::NextTool);
      if (rng_.chance(0.01)) tap(Action::NextMetal);
      if (rng_.chance(0.005)) tap(Action::NewSheet);
      if (crash && i == n / 2) restart();
    }
    if (visitors_ % 5 == 0) {
      app_->staffCommand(R"({"cmd":"reset"})");
      ++resets_;
    } else {
      pen_.queued.push_back({t_, 0.5, 0.5, 0, false, false, false, false});  // the pen put down
      step(config_.idleSeconds + 0.5);
      step(config_.countdownSeconds + 0.5);
    }
    for (int i = 0; i < 4 && app_->mode() != KioskMode::Attract; ++i) step(1.0);
    if (o_.leakKibPerVisitor > 0) {  // on purpose (SoakOptions::leakKibPerVisitor)
      leaked_.emplace_back(o_.leakKibPerVisitor * 1024, char(visitors_));
    }
    app_->journalFlush(10.0);     // the session's last records written: the writer thread idle
    settledKib_ = residentKib();  // the same state every time: the session ended, the heap trimmed
    // Now and then the attract loop plays before the next visitor comes (the kiosk caps its steps at 0.25 s).
    if (o_.attractEvery > 0 && visitors_ % o_.attractEvery == 0) {
      for (double played = 0; played < o_.attractSeconds; played += 0.2) step(0.2);
      ++attractCycles_;
    }
    settle();
  }

  // The kiosk stops without ending the session (a crash, a watchdog restart) and starts again.
  void restart() {
    app_->journalFlush(10.0);
    const std::uint64_t made = app_->bench().strokesMade();
    const size_t active = app_->bench().model().activeCount();
    open();
    ++restores_;
    if (app_->bench().strokesMade() != made || app_->bench().model().activeCount() != active) ++restoreMismatches_;
  }

  void row() {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    const auto range = [](const std::pair<double, double>& r) {
      char b[48];
      if (r.first > r.second) return std::string("-");
      std::snprintf(b, sizeof b, "%.1f .. %.1f", r.first, r.second);
      return std::string(b);
    };
    char settled[24] = "-";
    if (!rowSettled_.empty()) std::snprintf(settled, sizeof settled, "%.1f", median(rowSettled_));
    std::fprintf(out_, "| %zu | %zu | %zu | %zu | %zu | %zu | %.1f | %s | %s | %s | %.1f | %ld | %.1f | %.1f | %.0f |\n", strokes_,
                 visitors_, restores_, resets_, attractCycles_, piecesPlayed_, residentKib() / 1024.0, settled, range(rowRss_).c_str(),
                 range(rowHeap_).c_str(), peakResidentKib() / 1024.0, openFds(), bytesOf(config_.sessionsDir, true) / 1048576.0,
                 bytesOf(config_.sessionsDir, false) / 1048576.0, s);
    std::fflush(out_);
    rowRss_ = rowHeap_ = {1e300, -1e300};
    rowSettled_.clear();
  }

  SoakOptions o_;
  std::FILE* out_;
  KioskConfig config_;
  MemoryDisplay display_;
  std::vector<AttractPiece> pieces_;
  PieceRandom rng_;
  QueuedPen pen_;
  QueuedButtons buttons_;
  std::unique_ptr<KioskApp> app_;
  double t_ = 1000.0;
  size_t strokes_ = 0, visitors_ = 0, attractCycles_ = 0, restores_ = 0, resets_ = 0, piecesPlayed_ = 0, restoreMismatches_ = 0;
  size_t lastPiece_ = 0;
  std::pair<double, double> rowRss_{1e300, -1e300}, rowHeap_{1e300, -1e300};  // MB, over the visitors since the last row
  std::vector<double> rowSettled_;  // MB, the settled readings since the last row
  long settledKib_ = 0;             // the last visitor's settled reading
  std::vector<std::string> leaked_;  // SoakOptions::leakKibPerVisitor
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

}  // namespace

SoakResult runSoak(const SoakOptions& options, std::FILE* out) {
  fs::path dir = options.dir;
  const bool temporary = dir.empty();
  if (temporary) {
    std::string tmpl = (fs::temp_directory_path() / "emboss-soak-XXXXXX").string();
    if (!::mkdtemp(tmpl.data())) {
      std::fprintf(out, "soak: cannot make a temporary folder\n");
      return {};
    }
    dir = tmpl;
  }
  SoakResult r;
  {
    Soak soak(options, out, dir / "sessions");
    r = soak.run();
  }
  if (temporary) {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  return r;
}

}  // namespace emboss
