// The take-home files: the mesh (STL, 3MF), the height map and the postcard, from a scene.
#include "export/take_home.h"

#include <unistd.h>

#include <cstdio>
#include <ctime>
#include <fstream>
#include <iterator>
#include <sstream>
#include <filesystem>

#include "render/image.h"
#include "export/heightmap.h"
#include "export/mesh.h"
#include "export/stl.h"
#include "export/threemf.h"
#include "scene/scene.h"
#include "util/durable_file.h"

namespace emboss {

namespace {

// A bar on stderr when it is a terminal; nothing otherwise (logs and pipes stay clean).
class ProgressBar {
 public:
  explicit ProgressBar(const char* what) : what_(what), on_(isatty(STDERR_FILENO) == 1) {}
  ~ProgressBar() { finish(); }
  void operator()(double fraction) {
    if (!on_) return;
    const int width = 30;
    const int filled = static_cast<int>(fraction * width + 0.5);
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", what_, filled, "##############################", width - filled, "",
                 static_cast<int>(fraction * 100 + 0.5));
    std::fflush(stderr);
    shown_ = true;
  }
  void finish() {
    if (shown_) std::fputc('\n', stderr);
    shown_ = false;
  }

 private:
  const char* what_;
  bool on_;
  bool shown_ = false;
};

std::string description(const Scene& scene) {
  char date[32];
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  std::strftime(date, sizeof date, "%Y-%m-%d", &tm);
  return "Embossed in " + scene.metal + " with emboss; exported " + date + "; millimetres";
}

}  // namespace

Status writeTakeHome(const Scene& scene, const Model& model, const TakeHomeOptions& options, const std::string& out,
                     std::string* summary) {
  char line[512];
  if (options.format == "heightmap") {
    ProgressBar bar("height map");
    HeightMapOptions o;
    o.pixel = options.resolution;
    o.threads = options.threads;
    if (options.progressBar) o.progress = [&](double f) { bar(f); };
    auto map = heightMap(model, o);
    bar.finish();
    if (!map) return fail(map.error());
    auto png = heightMapPng(*map, scene.title);
    if (!png) return fail(png.error());
    if (Status s = writeFileAtomically(out, *png); !s) return s;
    std::snprintf(line, sizeof line, "height map %dx%d, %.4g mm a pixel, z %.4f to %.4f mm", map->width, map->height,
                  map->pixel, map->zMin, map->zMax);
    if (summary) *summary = line;
    return Ok{};
  }
  if (options.format == "postcard") {
    PostcardOptions o;
    o.threads = options.threads;
    auto card = postcard(scene, model, o, options.text);
    if (!card) return fail(card.error());
    if (Status s = writePng(*card, out); !s) return s;
    std::snprintf(line, sizeof line, "postcard %dx%d%s", card->width, card->height, options.text ? "" : " (no font: no caption)");
    if (summary) *summary = line;
    return Ok{};
  }
  if (options.format != "stl" && options.format != "3mf") return fail("unknown format '" + options.format + "'");
  ProgressBar bar("mesh");
  MeshOptions o;
  o.cell = options.resolution;
  o.maxError = options.maxError;
  o.threads = options.threads;
  if (options.progressBar) o.progress = [&](double f) { bar(f); };
  MeshStats st;
  auto mesh = meshModel(model, o, &st);
  bar.finish();
  if (!mesh) return fail(mesh.error());
  if (const std::string problem = checkClosedManifold(*mesh); !problem.empty())
    std::fprintf(stderr, "emboss export: warning: the mesh is not closed (%s); try a finer --resolution\n", problem.c_str());
  if (options.format == "stl") {
    const std::string title = scene.title.empty() ? "emboss piece" : scene.title;
    if (Status s = writeFileAtomically(out, stlBytes(*mesh, title + " (mm)")); !s) return s;
  } else {
    // lib3mf writes a file by name: beside the output and renamed over it, or, for an output
    // written in place (a pipe, a device: resolveOutput()), in the temporary folder and copied.
    const OutputPath target = resolveOutput(out);
    std::error_code ec;
    const std::filesystem::path tmp =
        target.inPlace ? std::filesystem::temp_directory_path(ec) / ("emboss-" + std::to_string(::getpid()) + ".3mf")
                       : std::filesystem::path(target.path.string() + ".tmp");
    std::filesystem::remove(tmp, ec);
    Status s = write3mf(*mesh, {scene.title, description(scene)}, tmp.string());
    if (s && target.inPlace) {
      std::ifstream in(tmp, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      s = in.bad() ? fail("cannot read back '" + tmp.string() + "'") : writeInPlace(target.path, bytes, out);
      std::filesystem::remove(tmp, ec);
    } else if (s) {
      s = commitFile(tmp, target.path);
    }
    if (!s) {
      std::filesystem::remove(tmp, ec);
      return s;
    }
  }
  std::snprintf(line, sizeof line,
                "mesh: %zu triangles (%zu before decimation; %zu vertices taken out of folds, %zu of thin triangles, "
                "%zu fold edges flipped, %zu vertices moved out of folds), %zu vertices, cell %.4g mm, volume %.1f mm^3, area %.1f mm^2, distance to the "
                "surface: vertices max %.4f mean %.5f mm, faces max %.4f mm, %.1f s",
                st.triangles, st.fineTriangles, st.foldVertices, st.thinVertices, st.flippedEdges, st.movedVertices, st.vertices, st.cell,
                st.volume, st.area,
                st.vertexMax, st.vertexMean, st.faceMax, st.seconds);
  if (summary) *summary = line;
  return Ok{};
}

std::uintmax_t TakeHomeSet::allowance() const {
  return (postcard ? (4u << 20) : 0) + (heightmap ? (4u << 20) : 0) + (stl ? (150u << 20) : 0) + (threemf ? (60u << 20) : 0);
}

Result<TakeHomeSet> parseTakeHomeSet(const std::string& list) {
  TakeHomeSet set;
  std::string item;
  std::stringstream ss(list);
  bool none = false;
  while (std::getline(ss, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item == "postcard") set.postcard = true;
    else if (item == "heightmap") set.heightmap = true;
    else if (item == "stl") set.stl = true;
    else if (item == "3mf") set.threemf = true;
    else if (item == "none") none = true;
    else return fail("'" + item + "' is not a take-home file (postcard, heightmap, stl, 3mf or none)");
  }
  if (none && set.any()) return fail("'none' cannot be listed with files");
  return set;
}

std::string takeHomeSetText(const TakeHomeSet& set) {
  std::string s;
  auto add = [&](bool on, const char* name) {
    if (on) s += (s.empty() ? "" : ",") + std::string(name);
  };
  add(set.postcard, "postcard");
  add(set.heightmap, "heightmap");
  add(set.stl, "stl");
  add(set.threemf, "3mf");
  return s.empty() ? "none" : s;
}

Result<TakeHomeWritten> writeTakeHomeFiles(const std::filesystem::path& sceneFile, const TakeHomeSet& set, TextPainter* text,
                                           int threads) {
  TakeHomeWritten w;
  if (!set.any()) return w;
  auto scene = loadScene(sceneFile);
  if (!scene) return fail(scene.error());
  auto model = scene->makeModel();
  if (!model) return fail(sceneFile.string() + ": " + model.error());
  const std::string stem = (sceneFile.parent_path() / sceneFile.stem()).string();
  struct Item {
    bool on;
    const char* format;
    std::string path;
    double resolution;
  };
  const Item items[] = {{set.postcard, "postcard", stem + ".postcard.png", 0.0},
                        {set.heightmap, "heightmap", stem + ".height.png", 0.2},
                        {set.stl, "stl", stem + ".stl", 0.0},
                        {set.threemf, "3mf", stem + ".3mf", 0.0}};
  for (const Item& it : items) {
    if (!it.on) continue;
    TakeHomeOptions o;
    o.format = it.format;
    o.resolution = it.resolution;
    o.threads = threads;
    o.progressBar = false;
    o.text = text;
    if (Status s = writeTakeHome(*scene, *model, o, it.path); !s) return fail(it.path + ": " + s.error());
    std::error_code ec;
    ++w.files;
    w.bytes += std::filesystem::file_size(it.path, ec);
  }
  return w;
}

}  // namespace emboss
