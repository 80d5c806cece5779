// `emboss bench --kiosk`: the kiosk program run headless in a child process, as on the board, with a
// real tablet recording replayed at its own pace; its own --stats read back.
#include "cli/bench_kiosk.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "bench/host_cpu.h"
#include "input/evemu.h"
#include "render/image.h"
#include "render/renderer.h"
#include "render/shading.h"
#include "scene/scene.h"

extern char** environ;

namespace emboss::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// emboss-kiosk beside this program (the build tree, /usr/bin), else whatever PATH finds.
std::string kioskProgram() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = self.parent_path() / "emboss-kiosk";
    if (fs::is_regular_file(beside, ec)) return beside.string();
  }
  return "emboss-kiosk";
}

// The recording played `loops` times, a second apart, each at its own pace: the header once (the
// device's description when it is inside), the events' times shifted loop by loop. Beside it, the
// recording's .desc under the new name when the description is not inside. Returns the events'
// span of one loop in seconds, or a negative value with `error` set.
double writeLoopedRecording(const fs::path& from, int loops, const fs::path& to, std::string& error) {
  std::ifstream in(from);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in && !in.eof()) {
    error = "cannot read the recording " + from.string();
    return -1;
  }
  // Read as the kiosk reads it (malformed lines fail with their number); its description is
  // inside when it has axis ranges of its own, as loadEvemu() decides.
  const auto recording = parseEvemu(text);
  if (!recording) {
    error = from.string() + ": " + recording.error();
    return -1;
  }
  if (recording->events.size() < 2) {
    error = from.string() + " holds no events";
    return -1;
  }
  const bool described = recording->device.hasAxes();
  std::vector<std::string> header;
  std::vector<std::pair<double, std::string>> events;  // time, the rest of the line after it
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("E:", 0) == 0) {
      char* rest = nullptr;
      const double t = std::strtod(line.c_str() + 2, &rest);
      events.emplace_back(t, std::string(rest));
    } else if (events.empty()) {
      header.push_back(line);
    }
  }
  const double t0 = events.front().first, span = events.back().first - t0;
  std::ofstream out(to);
  for (const auto& h : header) out << h << '\n';
  char buf[64];
  for (int k = 0; k < loops; ++k)
    for (const auto& [t, rest] : events) {
      std::snprintf(buf, sizeof buf, "E: %.6f", t + k * (span + 1.0));
      out << buf << rest << '\n';
    }
  if (!out) {
    error = "cannot write " + to.string();
    return -1;
  }
  if (!described) {
    auto desc = findEvemuDesc(from);
    if (!desc) {
      error = desc.error();
      return -1;
    }
    std::error_code ec;
    fs::copy_file(*desc, fs::path(to).replace_extension(".desc"), fs::copy_options::overwrite_existing, ec);
    if (ec) {
      error = "cannot copy " + desc->string() + ": " + ec.message();
      return -1;
    }
  }
  return span;
}

struct Child {
  pid_t pid = -1;
  int out = -1;  // its stdout
  bool exited = false;
  int status = 0;
};

// Whether the child has exited yet (reaped then, its status kept).
bool exitedYet(Child& c) {
  if (!c.exited && waitpid(c.pid, &c.status, WNOHANG) == c.pid) c.exited = true;
  return c.exited;
}

// Starts `argv` with its stdout on a pipe, its stderr into `log`, its sessions under `state`.
// posix_spawnp: nothing runs in a forked copy of this threaded process before the exec.
Child start(const std::vector<std::string>& argv, const fs::path& log, const fs::path& state) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<std::string> envStrings;
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "STATE_DIRECTORY=", 16) != 0) envStrings.emplace_back(*e);
  envStrings.push_back("STATE_DIRECTORY=" + state.string());
  std::vector<char*> env;
  for (auto& e : envStrings) env.push_back(e.data());
  env.push_back(nullptr);
  int fds[2];
  if (pipe(fds) != 0) return {};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  if (rc != 0) {
    close(fds[0]);
    errno = rc;
    return {};
  }
  return {pid, fds[0]};
}

// Reads the child's stdout to its end and waits for it; false unless it exited 0.
bool finish(Child& c, std::string& out) {
  char buf[4096];
  for (ssize_t n; (n = read(c.out, buf, sizeof buf)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    out.append(buf, static_cast<size_t>(n));
  }
  close(c.out);
  while (!c.exited && waitpid(c.pid, &c.status, 0) < 0 && errno == EINTR) {}
  c.exited = true;
  return WIFEXITED(c.status) && WEXITSTATUS(c.status) == 0;
}

// CPU seconds (user + system) the process has used, from /proc/PID/stat; negative if unknown.
double cpuSeconds(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t close = text.rfind(')');  // the command's name may hold spaces
  if (close == std::string::npos) return -1;
  std::istringstream s(text.substr(close + 2));
  std::string field;
  unsigned long long utime = 0, stime = 0;
  for (int i = 3; i <= 15 && s >> field; ++i) {
    if (i == 14) utime = std::stoull(field);
    if (i == 15) stime = std::stoull(field);
  }
  return static_cast<double>(utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

std::string lineWith(const std::string& text, const std::string& prefix) {
  const size_t at = text.find(prefix);
  if (at == std::string::npos) return {};
  return text.substr(at, text.find('\n', at) - at);
}

std::string tail(const fs::path& log) {
  std::ifstream f(log);
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return text.size() > 600 ? text.substr(text.size() - 600) : text;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// The full frames of the newest session saved under `sessions`.
struct SheetFrames {
  size_t operations = 0, setOperations = 0, patina = 0;
  int frames = 0;
  double ms = 0, baselineMs = 0;  // medians
  std::string kept;               // what was kept of it (KioskBenchOptions::keepSheet), or why not
};

double medianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

bool sheetFrames(const fs::path& sessions, const KioskBenchOptions& o, SheetFrames& out, std::string& error) {
  std::error_code ec;
  fs::path newest;  // (session-YYYYMMDD-HHMMSS.json: the names sort by time)
  for (const auto& e : fs::directory_iterator(sessions, ec))
    if (e.path().extension() == ".json" && e.path().filename().string().rfind("session-", 0) == 0 &&
        (newest.empty() || e.path().filename() > newest.filename()))
      newest = e.path();
  if (newest.empty()) {
    error = "the kiosk saved no session under " + sessions.string();
    return false;
  }
  auto scene = loadScene(newest);
  if (!scene) {
    error = "the session the kiosk saved does not load: " + scene.error();
    return false;
  }
  auto model = scene->makeModel();
  if (!model) {
    error = "the session the kiosk saved does not load: " + model.error();
    return false;
  }
  out.operations = model->activeCount();
  for (size_t i = 0; i < out.operations; ++i) {
    const Operation& op = model->operations()[i].op();
    out.setOperations += op.isOffset() || op.isPatina() ? 0 : 1;
    out.patina += op.isPatina() ? 1 : 0;
  }
  ThreadPool pool(o.threads);
  Renderer r(pool);
  r.setCamera(Camera(scene->camera, o.width, o.height));
  r.setShading(sheetShading(scene->metal, scene->tinge, model->workpiece().bounds().z1));
  r.sync(*model);
  Image image;
  std::vector<double> wall, base;
  out.frames = o.quick ? 2 : 3;
  for (int i = 0; i < out.frames; ++i) {
    if (o.baselineFrame) base.push_back(o.baselineFrame());
    const auto t = Clock::now();
    r.renderFull(image);
    wall.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());
  }
  out.ms = medianOf(wall), out.baselineMs = medianOf(base);
  if (!o.keepSheet.empty()) {
    // A figure to look at and to time again: the scene and the picture it was timed on.
    const fs::path json = o.keepSheet + ".json", png = o.keepSheet + ".png";
    fs::copy_file(newest, json, fs::copy_options::overwrite_existing, ec);
    if (ec)
      out.kept = "could not be kept (" + json.filename().string() + ": " + ec.message() + ")";
    else if (const Status written = writePng(image, png); !written)
      out.kept = "could not be kept (" + written.error() + ")";
    else
      out.kept = "kept as " + json.filename().string() + " (the session the kiosk saved) and " + png.filename().string() +
                 " (the full frame timed)";
  }
  return true;
}

}  // namespace

std::string kioskBench(const KioskBenchOptions& o, std::string& error) {
  std::error_code ec;
  std::string pattern = (fs::temp_directory_path(ec) / "emboss-bench-kiosk.XXXXXX").string();
  if (ec || !mkdtemp(pattern.data())) {
    error = "cannot make a temporary folder (" + pattern + "): " + std::strerror(errno);
    return {};
  }
  const fs::path dir(pattern);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{dir};
  const std::string kiosk = kioskProgram();
  const int loops = std::max(1, o.loops);
  const fs::path recording = dir / fs::path(o.recording).filename().replace_extension(".events");
  const double span = writeLoopedRecording(o.recording, loops, recording, error);
  if (span < 0) return {};
  {
    std::ofstream conf(dir / "kiosk.conf");
    conf << "# The visitor stays: no attract mode after the recording.\nidle_seconds = 600\n";
  }
  const std::string threads = "--threads=" + std::to_string(o.threads);

  // 1. The recording at its own pace, then the kiosk left idle: latency, then CPU while idle.
  const double played = loops * (span + 1.0), settle = 3.0, idleWindow = o.quick ? 3.0 : 10.0;
  const double runFor = played + settle + idleWindow + 1.0;
  std::fprintf(stderr, "emboss bench: kiosk: %s played %d times (%.1f s each), then %.0f s idle...\n",
               fs::path(o.recording).filename().c_str(), loops, span, idleWindow);
  const auto t0 = Clock::now();
  const std::optional<HostCpuTimes> hostBefore = readHostCpuTimes();
  Child c = start({kiosk, "--config", (dir / "kiosk.conf").string(), "--display=headless", "--tablet=evemu:" + recording.string(),
                   threads, "--run-for=" + fmt("%.1f", runFor), "--stats"},
                  dir / "kiosk.log", dir / "state");
  if (c.pid < 0) {
    error = std::string("cannot start ") + kiosk + ": " + std::strerror(errno);
    return {};
  }
  // Waits until `s` seconds after the start, or until the kiosk has exited (it failed to start).
  auto sleepUntil = [&](double s) {
    const Clock::time_point until = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
    for (Clock::time_point now = Clock::now(); now < until && !exitedYet(c); now = Clock::now())
      std::this_thread::sleep_for(std::min<Clock::duration>(until - now, std::chrono::milliseconds(100)));
  };
  sleepUntil(played + settle);
  const double cpu0 = cpuSeconds(c.pid);
  const auto w0 = Clock::now();
  sleepUntil(played + settle + idleWindow);
  const double cpu1 = cpuSeconds(c.pid);
  const double wall = std::chrono::duration<double>(Clock::now() - w0).count();
  std::string out;
  if (!finish(c, out)) {
    error = kiosk + " failed: " + tail(dir / "kiosk.log");
    return {};
  }
  const std::string latency = lineWith(out, "stats: stroke-to-screen latency:");
  size_t updates = 0;
  double mean = 0, median = 0, p95 = 0, p99 = 0, max = 0;
  if (std::sscanf(latency.c_str(),
                  "stats: stroke-to-screen latency: %zu updates, mean %lf ms, median %lf ms, 95%% %lf ms, 99%% %lf ms, max %lf ms",
                  &updates, &mean, &median, &p95, &p99, &max) != 6) {
    error = kiosk + " printed no latency (" + (latency.empty() ? out.substr(0, 300) : latency) + ")";
    return {};
  }
  const double idlePercent = cpu0 >= 0 && cpu1 >= 0 && wall > 0 ? 100.0 * (cpu1 - cpu0) / wall : -1.0;

  // 1b. The sheet the recording left, as the kiosk saved it when it stopped: full frames of it,
  // each after a frame of the baseline, as the bench's own pieces are timed. A visitor's piece is
  // not the generator's: the set operations and the patina strokes pile up where the pen works.
  SheetFrames sheet;
  std::string noSheet;  // why there is none (a recording that made no stroke)
  if (!sheetFrames(dir / "state" / "sessions", o, sheet, noSheet)) sheet.frames = 0;

  // 2. Attract mode alone.
  const double attractFor = o.quick ? 4.0 : 12.0;
  std::fprintf(stderr, "emboss bench: kiosk: attract mode for %.0f s...\n", attractFor);
  c = start({kiosk, "--display=headless", "--attract", threads, "--run-for=" + fmt("%.1f", attractFor), "--stats"},
            dir / "attract.log", dir / "state");
  out.clear();
  if (c.pid < 0 || !finish(c, out)) {
    error = kiosk + " --attract failed: " + tail(dir / "attract.log");
    return {};
  }
  const std::string attract = lineWith(out, "stats: attract:");
  size_t frames = 0, intervals = 0;
  double seconds = 0, meanFps = 0, pace = 0, paceSeconds = 0;
  if (std::sscanf(attract.c_str(), "stats: attract: %zu frames in %lf s = %lf fps; %lf fps from its first frame on (%zu intervals in %lf s)",
                  &frames, &seconds, &meanFps, &pace, &intervals, &paceSeconds) != 6) {
    error = kiosk + " --attract printed no frame rate (" + (attract.empty() ? out.substr(0, 300) : attract) + ")";
    return {};
  }

  auto met = [](bool ok) { return std::string(ok ? "yes" : "**no**"); };
  std::string t = "\nThe kiosk (" + kiosk + ", headless, " +
                  (o.threads > 0 ? std::to_string(o.threads) + " render threads" : std::string("one render thread per core")) +
                  "), run in a child process; the recording " + fs::path(o.recording).filename().string() + " played " +
                  std::to_string(loops) + " times, a second apart, at its own pace (" + fmt("%.1f", span) + " s each).\n\n";
  t += "| kiosk | measured | target | met |\n|---|---|---|---|\n";
  t += "| stroke-to-screen latency (every pen event that changed the picture, to the frame presented) | " +
       std::to_string(updates) + " updates: mean " + fmt("%.1f", mean) + " ms, median " + fmt("%.1f", median) + ", 95 % " +
       fmt("%.1f", p95) + ", 99 % " + fmt("%.1f", p99) + ", max " + fmt("%.1f", max) + " ms | 99 % <= 16 ms, >= 100 updates | " +
       met(p99 <= 16.0 && updates >= 100) + (updates < 100 ? " (too few updates: play it more times)" : "") + " |\n";
  t += "| CPU while the visitor stands idle (screen unchanged), " + fmt("%.0f", wall) + " s after the recording | " +
       (idlePercent >= 0 ? fmt("%.1f", idlePercent) + " % of one core" : std::string("unknown")) + " | near zero (<= 1 %) | " +
       met(idlePercent >= 0 && idlePercent <= 1.0) + " |\n";
  if (sheet.frames == 0)
    t += "| full frame of the sheet the recording left | none: " + noSheet + " | <= 1.5x the baseline | - |\n";
  else
    t += "| full frame of the sheet the recording left (" + std::to_string(sheet.operations) + " operations, " +
       std::to_string(sheet.setOperations) + " set operations, " + std::to_string(sheet.patina) + " patina strokes), " +
       std::to_string(o.width) + "x" + std::to_string(o.height) + " | " + fmt("%.1f", sheet.ms) + " ms (median of " +
       std::to_string(sheet.frames) + ")" +
       (sheet.baselineMs > 0 ? ", " + fmt("%.2f", sheet.ms / sheet.baselineMs) + "x the baseline's " + fmt("%.1f", sheet.baselineMs) + " ms" : "") +
       " | <= 1.5x the baseline | " + (sheet.baselineMs > 0 ? met(sheet.ms <= 1.5 * sheet.baselineMs) : std::string("no baseline")) + " |\n";
  t += "| attract mode | " + fmt("%.1f", pace) + " fps from its first frame on (" + std::to_string(frames) + " frames in " +
       fmt("%.1f", seconds) + " s) | >= 30 fps | " + met(pace >= 30.0) + " |\n";
  if (const std::string host = stealSentence(hostBefore, readHostCpuTimes()); !host.empty())
    t += "\nHost, while the kiosk ran: " + host + ".\n";
  if (sheet.frames > 0 && !sheet.kept.empty()) t += "\nThe sheet the recording left: " + sheet.kept + ".\n";
  return t;
}

}  // namespace emboss::cli
