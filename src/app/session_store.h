// Visitors' sessions on disk: saved atomically (scene file + picture), never lost, exported by staff.
#pragma once

#include <atomic>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/kiosk_log.h"
#include "render/image.h"
#include "scene/scene.h"
#include "util/file_stamp.h"

namespace emboss {

// Makes a session's take-home files beside its exported scene file (export/take_home.h);
// `allowance` is the room to keep free for one session's files.
struct ExportTakeHome {
  std::function<Result<std::pair<size_t, std::uintmax_t>>(const std::filesystem::path& exportedScene)> make;
  std::uintmax_t allowance = 0;
};

class SessionStore {
 public:
  // Free bytes at a path (std::filesystem::space by default; tests pass their own).
  using SpaceProbe = std::function<std::optional<std::uintmax_t>(const std::filesystem::path&)>;

  SessionStore(std::filesystem::path dir, KioskLog log);

  const std::filesystem::path& dir() const { return dir_; }

  // Saves `scene` with `model`'s active operations as DIR/session-STAMP.json, and `picture` (when
  // given) as DIR/session-STAMP.png, each through a temporary file and a rename. When the disk
  // refuses, the session stays in memory, the failure is logged once, and retryPending() tries
  // again; nothing a visitor made is dropped while the kiosk runs. Returns the scene file's path.
  Result<std::filesystem::path> save(const Scene& scene, const Model& model, const Image* picture, const std::string& stamp);
  // Writes sessions kept in memory after a failure. Returns how many are still waiting.
  size_t retryPending();
  size_t pendingCount() const { return pending_.size(); }
  size_t savedCount() const { return saved_; }

  // Deletes saved sessions (scene file and picture) written before `before` (Unix seconds), then
  // the oldest until their files take at most `maxBytes`. Returns how many were deleted.
  size_t prune(double before, std::uintmax_t maxBytes);
  // Every saved session's scene file, oldest first.
  std::vector<std::filesystem::path> list() const;

  struct Extra {  // the session in progress, exported without being saved as a finished one
    std::string json;
    const Image* picture = nullptr;
  };
  struct ExportSummary {
    std::filesystem::path folder;
    size_t files = 0;
    std::uintmax_t bytes = 0;
    std::vector<std::string> warnings;  // take-home files that could not be made (the sessions are copied)
  };
  // How far an export is: sessions (a scene file and its picture; the one in progress counts as one)
  // copied of all it copies, and the files and bytes written so far.
  struct ExportProgress {
    size_t sessionsDone = 0, sessions = 0, files = 0;
    std::uintmax_t bytes = 0;
  };
  using ExportProgressSink = std::function<void(const ExportProgress&)>;
  // Copies every saved session (scene files and pictures), plus `current`, into a new folder
  // TARGET/emboss-sessions-STAMP. Checks the free space first; fails with a message that says how
  // much is needed and free, or which file could not be written. The sessions themselves are
  // never touched. With `sinceUnix`, only sessions saved since then. Every file and folder written
  // is fsynced before the export counts as done. `progress` (when given) hears of the start and of
  // every session copied, on the calling thread. Const and touching nothing but the files: another
  // thread may run it on a copy of the store. `stop` (when given and set) ends it between two
  // files: what was copied is complete and durable, and the result says how far it got. With
  // `takeHome`, each session's take-home files are made beside its copy; one that cannot be made
  // is a warning in the summary, never a lost session.
  Result<ExportSummary> exportAll(const std::filesystem::path& target, const std::string& stamp,
                                  const std::optional<Extra>& current, const SpaceProbe& space = {}, double sinceUnix = 0,
                                  const ExportProgressSink& progress = {}, const std::atomic<bool>* stop = nullptr,
                                  const ExportTakeHome& takeHome = {}) const;

 private:
  struct Pending {
    std::string stem;
    std::string json;
    std::optional<Image> picture;
  };
  Status write(const Pending& p);
  std::string freeStem(const std::string& stamp) const;

  std::filesystem::path dir_;
  KioskLog log_;
  std::vector<Pending> pending_;
  size_t saved_ = 0;
  std::string lastError_;
};

}  // namespace emboss
