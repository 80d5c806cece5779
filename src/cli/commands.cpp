// The `emboss` subcommands: eval, render, export (bench lives in bench.cpp).
#include "cli/commands.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "export/studio.h"
#include "export/take_home.h"
#include "export/pov.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace emboss::cli {

namespace {

bool parseSize(const std::string& s, int& w, int& h) {
  return std::sscanf(s.c_str(), "%dx%d", &w, &h) == 2 && w > 0 && h > 0 && w <= 16384 && h <= 16384;
}

// Where the command's own lines go: standard error when the output itself is the standard output
// (-o -, /dev/stdout), so that the file in a pipe is only the file.
FILE* infoStream(const std::string& out) { return isStandardOutput(out) ? stderr : stdout; }

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

ShadingParams shadingFor(const Scene& scene, const Model& model) {
  return sheetShading(scene.metal, scene.tinge, model.workpiece().bounds().z1);
}

}  // namespace

int benchMain(const std::string& out, int threads, bool quick, const std::string& only, const std::string& kioskRecording,
              int kioskLoops);

Commands::Commands(CLI::App& app) : app_(app) {
  evalCmd_ = app.add_subcommand("eval", "Print f (>= 0 inside) of a scene's model at points");
  evalCmd_->add_option("scene", scene_, "Scene file (JSON)")->required();
  evalCmd_->add_option("xyz", xyz_, "A point: X Y Z (mm)")->expected(3);
  evalCmd_->add_option("--points", pointsFile_, "A file of 'x y z' lines; prints one value per line");

  renderCmd_ = app.add_subcommand("render", "Ray trace a scene to a PNG");
  renderCmd_->add_option("scene", scene_, "Scene file (JSON)")->required();
  renderCmd_->add_option("-o,--output", out_, "Output PNG (- for the standard output)")->required();
  renderCmd_->add_option("--size", size_, "Picture size WxH")->capture_default_str();
  renderCmd_->add_option("--threads", threads_, "Threads in the pool (0: one per core)")->check(CLI::Range(0, 256));
  renderCmd_->add_option("--repeat", repeat_, "Render the whole frame N times, no reuse; writes the last")->check(CLI::Range(1, 100000));
  renderCmd_->add_flag("--naive", naive_, "No index: every operation at every point (for comparison)");
  renderCmd_->add_flag("--stats", stats_, "Print the tracer's counts: pixels traced, steps and evaluations per ray, operations per evaluation, rays in lanes, Lipschitz steps in windows");
  renderCmd_->add_flag("--incremental", incremental_,
                       "Render the bare workpiece, then apply the operations one by one with dirty updates only");

  exportCmd_ = app.add_subcommand("export", "Export a scene for another program");
  exportCmd_->add_option("scene", scene_, "Scene file (JSON)")->required();
  exportCmd_->add_option("--format", format_,
                         "pov (POV-Ray 3.7 isosurface), stl (binary, mm), 3mf, heightmap (16-bit greyscale PNG of the front face), "
                         "postcard (PNG, the piece with its title and date), studio (the lighting as a Radiance .hdr, with "
                         "the camera and the metal's optical constants in a .json beside it, for a path tracer)")
      ->check(CLI::IsMember({"pov", "stl", "3mf", "heightmap", "postcard", "studio"}))
      ->capture_default_str();
  exportCmd_->add_option("-o,--output", out_, "Output file (- for the standard output)")->required();
  exportCmd_->add_option("--size", size_, "Picture size WxH the POV camera is set up for")->capture_default_str();
  exportCmd_->add_option("--resolution", resolution_, "stl, 3mf: the mesh's grid step; heightmap: the pixel (mm; 0: automatic)")
      ->check(CLI::Range(0.0, 100.0));
  exportCmd_->add_option("--max-error", maxError_, "stl, 3mf: how far decimation may move a face (mm; 0: no decimation)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  exportCmd_->add_option("--threads", threads_, "Threads (0: one per core)")->check(CLI::Range(0, 256));

  benchCmd_ = app.add_subcommand("bench", "Benchmark the renderer on generated pieces; prints a table");
  benchCmd_->add_option("-o,--output", out_, "Also write the table (Markdown) to this file");
  benchCmd_->add_option("--threads", threads_, "Threads in the pool (0: one per core)")->check(CLI::Range(0, 256));
  benchCmd_->add_flag("--quick", quick_, "Small sizes, for a smoke test");
  benchCmd_->add_option("--only", only_, "Measure only the pieces whose name holds this text (\"vm\", \"plate\"; \"kiosk\": no piece); the baseline always");
  benchCmd_->add_option("--kiosk", kioskRecording_,
                        "Also run emboss-kiosk headless with this tablet recording (evemu) at its own pace: stroke-to-screen "
                        "latency, CPU when idle, full frames of the sheet it left (with -o T.md, kept as T-sheet.json and "
                        "T-sheet.png), attract frames a second")
      ->check(CLI::ExistingFile);
  benchCmd_->add_option("--kiosk-loops", kioskLoops_, "Play the --kiosk recording this many times in a row (default 5)")
      ->check(CLI::Range(1, 100));
}

int Commands::run() {
  if (evalCmd_->parsed()) return eval();
  if (renderCmd_->parsed()) return render();
  if (exportCmd_->parsed()) return exportScene();
  if (benchCmd_->parsed()) return bench();
  return 2;
}

int Commands::eval() {
  auto scene = loadScene(scene_);
  if (!scene) {
    std::fprintf(stderr, "emboss eval: %s\n", scene.error().c_str());
    return 1;
  }
  auto model = scene->makeModel();
  if (!model) {
    std::fprintf(stderr, "emboss eval: %s\n", model.error().c_str());
    return 1;
  }
  if (xyz_.empty() == pointsFile_.empty()) {
    std::fprintf(stderr, "emboss eval: give either a point X Y Z or --points FILE\n");
    return 2;
  }
  if (!xyz_.empty()) {
    if (!std::isfinite(xyz_[0]) || !std::isfinite(xyz_[1]) || !std::isfinite(xyz_[2])) {
      std::fprintf(stderr, "emboss eval: X Y Z must be finite numbers (mm)\n");
      return 2;
    }
    std::printf("%.17g\n", model->evaluate(P3<double>{xyz_[0], xyz_[1], xyz_[2]}));
    return 0;
  }
  std::ifstream in(pointsFile_);
  if (!in) {
    std::fprintf(stderr, "emboss eval: cannot open '%s'\n", pointsFile_.c_str());
    return 1;
  }
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    std::istringstream ls(line);
    double x, y, z;
    if (!(ls >> x >> y >> z) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      std::fprintf(stderr, "emboss eval: %s:%d: expected three finite numbers 'x y z'\n", pointsFile_.c_str(), lineNo);
      return 1;
    }
    std::printf("%.17g\n", model->evaluate(P3<double>{x, y, z}));
  }
  return 0;
}

int Commands::render() {
  int w, h;
  if (!parseSize(size_, w, h)) {
    std::fprintf(stderr, "emboss render: --size must be WxH, e.g. 1280x800\n");
    return 2;
  }
  FILE* const info = infoStream(out_);
  auto scene = loadScene(scene_);
  if (!scene) {
    std::fprintf(stderr, "emboss render: %s\n", scene.error().c_str());
    return 1;
  }
  auto model = scene->makeModel();
  if (!model) {
    std::fprintf(stderr, "emboss render: %s\n", model.error().c_str());
    return 1;
  }
  ThreadPool pool(threads_);
  Renderer renderer(pool);
  renderer.setCamera(Camera(scene->camera, w, h));
  renderer.setShading(shadingFor(*scene, *model));
  RenderOptions options;
  options.naive = naive_;
  renderer.setOptions(options);
  Image image;
  RenderStats stats;
  double totalMs = 0.0;

  if (incremental_) {
    // Start from the bare sheet and replay the operations as a visitor would, tracing only what
    // each one can change.
    Model live(model->workpiecePtr(), model->deformation());
    auto t0 = std::chrono::steady_clock::now();
    renderer.sync(live);
    renderer.renderFull(image, &stats);
    const double firstMs = msSince(t0);
    double sum = 0.0, worst = 0.0;
    long pixels = 0;
    for (size_t i = 0; i < model->activeCount(); ++i) {
      t0 = std::chrono::steady_clock::now();
      live.add(model->operations()[i].op());
      renderer.sync(live);
      const PixelSpans r = renderer.dirtySpans(live, i);
      renderer.render(image, r, &stats);
      const double ms = msSince(t0);
      sum += ms;
      worst = std::max(worst, ms);
      pixels += r.area();
    }
    const size_t n = model->activeCount();
    std::fprintf(info, "incremental: first frame %.1f ms; %zu updates, mean %.2f ms, worst %.2f ms, mean %.0f pixels per update\n",
                firstMs, n, n ? sum / n : 0.0, worst, n ? static_cast<double>(pixels) / n : 0.0);
  } else {
    renderer.sync(*model);
    for (int i = 0; i < repeat_; ++i) {
      RenderStats st;
      const auto t0 = std::chrono::steady_clock::now();
      renderer.renderFull(image, &st);
      totalMs += msSince(t0);
      stats = st;
    }
    std::fprintf(info, "render: %dx%d, %zu operations, %d threads, %.1f ms per frame (mean of %d)\n", w, h, model->activeCount(),
                pool.size(), totalMs / repeat_, repeat_);
  }
  if (stats_) {
    std::fprintf(info, "stats: pixels traced %llu, hits %llu, mean steps per ray %.2f, mean evaluations per ray %.2f, "
                "mean operations per evaluation %.2f, edge pixels %llu (anti-aliased), rays walked in lanes %llu, "
                "dense rays %llu, Lipschitz steps in set operations' windows %llu, steps in balls' far windows %llu, "
                "skips above the pile's tops %llu\n",
                static_cast<unsigned long long>(stats.rays), static_cast<unsigned long long>(stats.hits), stats.meanStepsPerRay(),
                stats.meanEvaluationsPerRay(), stats.meanOpsPerEvaluation(), static_cast<unsigned long long>(stats.edgePixels),
                static_cast<unsigned long long>(stats.laneRays), static_cast<unsigned long long>(stats.denseRays),
                static_cast<unsigned long long>(stats.windowSteps), static_cast<unsigned long long>(stats.farSteps),
                static_cast<unsigned long long>(stats.pileSkips));
  }
  Status s = writePng(image, out_);
  if (!s) {
    std::fprintf(stderr, "emboss render: %s\n", s.error().c_str());
    return 1;
  }
  std::fprintf(info, "wrote %s\n", out_.c_str());
  return 0;
}

int Commands::exportScene() {
  int w, h;
  if (!parseSize(size_, w, h)) {
    std::fprintf(stderr, "emboss export: --size must be WxH, e.g. 1280x800\n");
    return 2;
  }
  FILE* const info = infoStream(out_);
  auto scene = loadScene(scene_);
  if (!scene) {
    std::fprintf(stderr, "emboss export: %s\n", scene.error().c_str());
    return 1;
  }
  auto model = scene->makeModel();
  if (!model) {
    std::fprintf(stderr, "emboss export: %s\n", model.error().c_str());
    return 1;
  }
  if (format_ == "studio") {
    if (resolveOutput(out_).inPlace) {
      std::fprintf(stderr, "emboss export: studio writes two files (the .hdr and a .json beside it): give a file name\n");
      return 2;
    }
    std::filesystem::path json = out_;
    json.replace_extension(".json");
    if (json == std::filesystem::path(out_)) json += ".json";
    if (Status s = writeStudio(*scene, out_, json.string()); !s) {
      std::fprintf(stderr, "emboss export: %s\n", s.error().c_str());
      return 1;
    }
    std::fprintf(info, "wrote %s\nwrote %s\n", out_.c_str(), json.string().c_str());
    return 0;
  }
  if (format_ != "pov") {
    TakeHomeOptions o;
    o.format = format_;
    o.resolution = resolution_;
    o.maxError = maxError_;
    o.threads = threads_;
    std::unique_ptr<TextPainter> painter;
    if (format_ == "postcard" && textFactory_) painter = textFactory_();
    o.text = painter.get();
    std::string summary;
    if (Status s = writeTakeHome(*scene, *model, o, out_, &summary); !s) {
      std::fprintf(stderr, "emboss export: %s\n", s.error().c_str());
      return 1;
    }
    std::fprintf(info, "%s\nwrote %s\n", summary.c_str(), out_.c_str());
    return 0;
  }
  PovExportOptions options;
  options.width = w;
  options.height = h;
  auto text = exportPov(*scene, *model, options);
  if (!text) {
    std::fprintf(stderr, "emboss export: %s\n", text.error().c_str());
    return 1;
  }
  Status s = writeFileAtomically(out_, *text);
  if (!s) {
    std::fprintf(stderr, "emboss export: %s\n", s.error().c_str());
    return 1;
  }
  std::fprintf(info, "wrote %s\n", out_.c_str());
  return 0;
}

int Commands::bench() { return benchMain(out_, threads_, quick_, only_, kioskRecording_, kioskLoops_); }

}  // namespace emboss::cli
