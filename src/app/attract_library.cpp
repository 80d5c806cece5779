// Reading the attract pieces from disk, forgiving file by file.
#include "app/attract_library.h"

#include <algorithm>
#include <cstdlib>

#include "pieces/pieces.h"

namespace emboss {

namespace fs = std::filesystem;

std::vector<AttractPiece> loadAttractPieces(const fs::path& dir, const KioskLog& log) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".json") files.push_back(it->path());
  if (ec && log) log("attract: cannot list '" + dir.string() + "': " + ec.message());
  std::sort(files.begin(), files.end());
  std::vector<AttractPiece> out;
  for (const auto& f : files) {
    auto scene = loadScene(f);
    if (!scene) {
      if (log) log("attract: skipping a piece that does not read: " + scene.error());
      continue;
    }
    // Operations the model refuses would stop the replay half way: check them all now.
    auto model = scene->makeModel();
    if (!model) {
      if (log) log("attract: skipping " + f.filename().string() + ": " + model.error());
      continue;
    }
    if (scene->operations.empty()) {
      if (log) log("attract: skipping " + f.filename().string() + ": it has no operations to replay");
      continue;
    }
    out.push_back({f.stem().string(), std::move(*scene)});
  }
  return out;
}

std::vector<AttractPiece> builtinAttractPieces() {
  std::vector<AttractPiece> out;
  for (auto& p : generateAttractPieces()) out.push_back({fs::path(p.file).stem().string(), std::move(p.scene)});
  return out;
}

std::optional<fs::path> findPiecesDir(const fs::path& configured, const fs::path& program) {
  std::error_code ec;
  if (!configured.empty()) return fs::is_directory(configured, ec) ? std::optional<fs::path>(configured) : std::nullopt;
  std::vector<fs::path> tries;
  if (const char* env = std::getenv("EMBOSS_PIECES"); env && *env) tries.emplace_back(env);
  tries.push_back(fs::current_path(ec) / "firmware-app" / "pieces");
  if (!program.empty()) {
    fs::path p = fs::absolute(program, ec).parent_path();
    for (int i = 0; i < 4 && !p.empty(); ++i, p = p.parent_path()) tries.push_back(p / "firmware-app" / "pieces");
    tries.push_back(fs::absolute(program, ec).parent_path().parent_path() / "share" / "emboss" / "pieces");
  }
  tries.emplace_back("/usr/share/emboss/pieces");
  for (const auto& t : tries)
    if (fs::is_directory(t, ec)) return t;
  return std::nullopt;
}

}  // namespace emboss
