// emboss: the command line (eval, render, export, bench) over the portable core.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "gl/text_image.h"
#include "version.h"

int main(int argc, char** argv) {
  CLI::App app{"emboss: virtual metal embossing (F-rep model of Sourin 2001, CPU ray tracing)"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Every subcommand's help");
  app.set_version_flag("--version", std::string("emboss ") + emboss::versionString());
  emboss::cli::Commands commands(app);
  commands.setTextPainterFactory([]() -> std::unique_ptr<emboss::TextPainter> {
    auto painter = emboss::AtlasTextPainter::create();
    if (!painter) {
      std::fprintf(stderr, "emboss: %s; the postcard gets no caption\n", painter.error().c_str());
      return nullptr;
    }
    return std::move(*painter);
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;  // bad usage
  }
  try {
    return commands.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "emboss: %s\n", e.what());
    return 1;
  }
}
