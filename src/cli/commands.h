// The `emboss` subcommands, kept in the core so the tests can call them without a process.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "export/postcard.h"

namespace CLI {
class App;
}

namespace emboss::cli {

// Registers the subcommands on `app` at construction; run() executes the one that was parsed and
// returns the exit code (0 ok, 1 failure; bad usage is CLI11's, mapped to 2 by main()).
class Commands {
 public:
  explicit Commands(CLI::App& app);
  int run();
  // Where the postcard's caption painter comes from (the platform's FreeType; none: no caption).
  void setTextPainterFactory(std::function<std::unique_ptr<TextPainter>()> factory) { textFactory_ = std::move(factory); }

 private:
  int eval();
  int render();
  int exportScene();
  int bench();

  CLI::App& app_;
  CLI::App* evalCmd_ = nullptr;
  CLI::App* renderCmd_ = nullptr;
  CLI::App* exportCmd_ = nullptr;
  CLI::App* benchCmd_ = nullptr;

  std::string scene_;
  std::vector<double> xyz_;
  std::string pointsFile_;
  std::string out_;
  std::string size_ = "1280x800";
  std::string format_ = "pov";
  int threads_ = 0;
  double resolution_ = 0.0;
  double maxError_ = 0.01;
  int repeat_ = 1;
  bool naive_ = false;
  bool stats_ = false;
  bool incremental_ = false;
  bool quick_ = false;
  std::string only_;
  std::string kioskRecording_;
  int kioskLoops_ = 5;
  std::function<std::unique_ptr<TextPainter>()> textFactory_;
};

}  // namespace emboss::cli
