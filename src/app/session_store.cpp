// Saving and exporting visitors' sessions, atomically and without ever losing one.
#include "app/session_store.h"

#include "util/durable_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>

namespace emboss {

namespace fs = std::filesystem;

SessionStore::SessionStore(fs::path dir, KioskLog log) : dir_(std::move(dir)), log_(std::move(log)) {}

std::string SessionStore::freeStem(const std::string& stamp) const {
  std::string stem = "session-" + stamp;
  std::error_code ec;
  for (int n = 2; fs::exists(dir_ / (stem + ".json"), ec) || std::any_of(pending_.begin(), pending_.end(), [&](const Pending& p) {
                    return p.stem == stem;
                  });
       ++n)
    stem = "session-" + stamp + "-" + std::to_string(n);
  return stem;
}

Status SessionStore::write(const Pending& p) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec && !fs::is_directory(dir_)) return fail("cannot create '" + dir_.string() + "': " + ec.message());
  // The picture first: a scene file present means the session is complete.
  if (p.picture) {
    Status s = writePng(*p.picture, dir_ / (p.stem + ".png"));
    if (!s) return s;
  }
  return writeFileAtomically(dir_ / (p.stem + ".json"), p.json);
}

Result<fs::path> SessionStore::save(const Scene& scene, const Model& model, const Image* picture, const std::string& stamp) {
  Pending p{freeStem(stamp), sceneToJson(scene, &model), picture ? std::optional<Image>(*picture) : std::nullopt};
  Status s = write(p);
  const fs::path path = dir_ / (p.stem + ".json");
  if (!s) {
    if (log_ && s.error() != lastError_)
      log_("session: " + s.error() + "; keeping the session (" + std::to_string(model.activeCount()) +
           " operations) in memory and trying again");
    lastError_ = s.error();
    pending_.push_back(std::move(p));
    return fail(s.error());
  }
  ++saved_;
  lastError_.clear();
  if (log_) log_("session: saved " + path.string() + " (" + std::to_string(model.activeCount()) + " operations)");
  return path;
}

size_t SessionStore::retryPending() {
  while (!pending_.empty()) {
    Status s = write(pending_.front());
    if (!s) break;
    ++saved_;
    if (log_) log_("session: saved " + (dir_ / (pending_.front().stem + ".json")).string() + " (after a retry)");
    pending_.erase(pending_.begin());
    lastError_.clear();
  }
  return pending_.size();
}

std::vector<fs::path> SessionStore::list() const {
  std::vector<fs::path> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path p = it->path();
    const std::string name = p.filename().string();
    if (p.extension() == ".json" && name.rfind("session-", 0) == 0) out.push_back(p);
  }
  std::sort(out.begin(), out.end());
  return out;
}

Result<SessionStore::ExportSummary> SessionStore::exportAll(const fs::path& target, const std::string& stamp,
                                                            const std::optional<Extra>& current,
                                                            const SpaceProbe& spaceIn, double sinceUnix,
                                                            const ExportProgressSink& progress,
                                                            const std::atomic<bool>* stop, const ExportTakeHome& takeHome) const {
  std::error_code ec;
  if (!fs::is_directory(target, ec))
    return fail("export: '" + target.string() + "' is not a folder (is the USB stick in?)");
  // What to copy: every saved session's scene file and picture, a session at a time.
  std::vector<std::vector<fs::path>> sessions;
  size_t fileCount = 0;
  std::uintmax_t need = current ? current->json.size() + (current->picture ? current->picture->rgba.size() : 0) : 0;
  for (const auto& scene : list()) {
    struct stat st {};
    if (sinceUnix > 0 && ::stat(scene.c_str(), &st) == 0 && double(st.st_mtime) < sinceUnix) continue;
    std::vector<fs::path> files{scene};
    fs::path png = scene;
    png.replace_extension(".png");
    if (fs::exists(png, ec)) files.push_back(png);
    for (const auto& f : files) need += fs::file_size(f, ec) + 4096;
    fileCount += files.size();
    sessions.push_back(std::move(files));
  }
  need += 1 << 20;  // headroom for the file system's own records
  if (takeHome.make) need += takeHome.allowance * (sessions.size() + (current ? 1 : 0));
  const SpaceProbe space = spaceIn ? spaceIn : [](const fs::path& p) -> std::optional<std::uintmax_t> {
    std::error_code e;
    const auto s = fs::space(p, e);
    if (e) return std::nullopt;
    return s.available;
  };
  if (const auto avail = space(target); avail && *avail < need)
    return fail("export: not enough space on '" + target.string() + "': " + std::to_string(need / 1024) +
                " KiB needed, " + std::to_string(*avail / 1024) + " KiB free; nothing was copied");
  ExportSummary sum;
  ExportProgress done;
  done.sessions = sessions.size() + (current ? 1 : 0);
  const auto report = [&] {
    done.files = sum.files, done.bytes = sum.bytes;
    if (progress) progress(done);
  };
  report();
  sum.folder = target / ("emboss-sessions-" + stamp);
  fs::create_directories(sum.folder, ec);
  if (ec) return fail("export: cannot create '" + sum.folder.string() + "': " + ec.message());
  const auto makeTakeHome = [&](const fs::path& exportedScene) {
    if (!takeHome.make) return;
    auto made = takeHome.make(exportedScene);
    if (!made) {
      sum.warnings.push_back(made.error());
      return;
    }
    sum.files += made->first;
    sum.bytes += made->second;
  };
  const auto stopped = [&]() -> Result<ExportSummary> {
    Status s = syncDirectory(sum.folder);
    if (s) s = syncDirectory(target);
    return fail("export: stopped (the kiosk is stopping) after " + std::to_string(done.sessionsDone) + " of " +
                std::to_string(done.sessions) + " sessions; the " + std::to_string(sum.files) + " files copied are complete" +
                (s ? "" : " (" + s.error() + ")"));
  };
  for (const auto& files : sessions) {
    for (const auto& f : files) {
      if (stop && stop->load()) return stopped();
      std::ifstream in(f, std::ios::binary);
      if (!in) return fail("export: cannot read '" + f.string() + "': " + std::strerror(errno) + " (" + std::to_string(sum.files) + " files copied)");
      std::stringstream ss;
      ss << in.rdbuf();
      const std::string bytes = ss.str();
      Status s = writeFileAtomically(sum.folder / f.filename(), bytes);
      if (!s) return fail("export: " + s.error() + " after " + std::to_string(sum.files) + " of " + std::to_string(fileCount) + " files");
      ++sum.files;
      sum.bytes += bytes.size();
    }
    if (stop && stop->load()) return stopped();
    makeTakeHome(sum.folder / files.front().filename());
    ++done.sessionsDone;
    report();
  }
  if (current && stop && stop->load()) return stopped();
  if (current) {
    const fs::path json = sum.folder / ("current-" + stamp + ".json"), png = sum.folder / ("current-" + stamp + ".png");
    Status s = writeFileAtomically(json, current->json);
    if (s && current->picture) s = writePng(*current->picture, png);
    if (!s) return fail("export: " + s.error() + " (the " + std::to_string(sum.files) + " saved files were copied)");
    sum.files += current->picture ? 2 : 1;
    sum.bytes += current->json.size() + (current->picture ? fs::file_size(png, ec) : 0);
    makeTakeHome(json);
    ++done.sessionsDone;
    report();
  }
  // The take-home files are written through temporary files and renames; their names too.
  if (takeHome.make)
    if (Status s = syncDirectory(sum.folder); !s) return fail("export: " + s.error());
  // The export's folder itself is a new name in the stick's root: make that durable too.
  if (Status s = syncDirectory(target); !s) return fail("export: " + s.error());
  return sum;
}

size_t SessionStore::prune(double before, std::uintmax_t maxBytes) {
  struct Entry {
    fs::path json, png;
    double mtime;
    std::uintmax_t bytes;
  };
  std::vector<Entry> all;
  std::uintmax_t total = 0;
  for (const fs::path& j : list()) {
    Entry e{j, fs::path(j).replace_extension(".png"), 0, 0};
    struct stat st {};
    if (::stat(j.c_str(), &st) == 0) e.mtime = double(st.st_mtime), e.bytes += std::uintmax_t(st.st_size);
    if (::stat(e.png.c_str(), &st) == 0) e.bytes += std::uintmax_t(st.st_size);
    total += e.bytes;
    all.push_back(std::move(e));
  }
  size_t n = 0;
  for (const Entry& e : all) {  // oldest first
    if (!(e.mtime < before) && total <= maxBytes) break;
    std::error_code ec;
    fs::remove(e.png, ec);
    if (fs::remove(e.json, ec)) ++n, total -= e.bytes;
  }
  if (n) syncDirectory(dir_);
  return n;
}

}  // namespace emboss
