// emboss-soak: the kiosk's soak (src/bench/soak.h): many visitors' strokes through the real kiosk
// logic, headless, with resident memory and file descriptors checked. A benchmark, not a CI test.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

#include "app/kiosk_config.h"
#include "bench/soak.h"
#include "util/heap_release.h"
#include "version.h"

int main(int argc, char** argv) {
  CLI::App cli{"emboss-soak: strokes with undo, resets, restores and attract cycles through the kiosk's logic, "
               "headless; prints RSS, open files and the journal's size as it goes, and PASS or FAIL"};
  emboss::SoakOptions o;
  std::string size = "96x60", dir;
  cli.add_option("--strokes", o.strokes, "How many strokes (default 200000)")->check(CLI::PositiveNumber);
  cli.add_option("--report-every", o.reportEvery, "A table row every N strokes (default: strokes / 20)");
  cli.add_option("--warmup", o.warmup, "Strokes before the baseline is taken (default: strokes / 10)");
  cli.add_option("--size", size, "The kiosk's screen in memory, WxH (default 96x60)");
  cli.add_option("--threads", o.threads, "Render threads (default 1)")->check(CLI::Range(1, 64));
  cli.add_option("--dir", dir, "Keep the sessions folder under DIR (default: a temporary folder, removed at the end)");
  cli.add_option("--attract-seconds", o.attractSeconds, "Attract mode's play between two visitors, seconds (default 12)");
  cli.add_option("--attract-every", o.attractEvery, "Attract plays after every N-th visitor (default 10; 0: never)");
  cli.add_option("--restart-every", o.restartEvery, "Kill and restart the kiosk mid-session every N-th visitor (default 7; 0: never)");
  cli.add_option("--seed", o.seed, "The visitors' random seed");
  cli.add_option("--leak-kib-per-visitor", o.leakKibPerVisitor,
                 "Hold this many KiB more after every visitor, on purpose: shows that the verdict catches a leak (default 0)");
  cli.set_version_flag("--version", std::string("emboss-soak ") + emboss::versionString());
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e) == 0 ? 0 : 2;
  }
  emboss::tuneHeapForKiosk();  // the kiosk's memory comes back down after each piece (util/heap_release.h)
  if (!emboss::parseSizeWxH(size, o.width, o.height)) {
    std::fprintf(stderr, "emboss-soak: --size must be WxH, e.g. 96x60, not '%s'\n", size.c_str());
    return 2;
  }
  o.dir = dir;
  try {
    return emboss::runSoak(o, stdout).pass ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "emboss-soak: %s\n", e.what());
    return 1;
  }
}
