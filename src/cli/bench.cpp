// `emboss bench`: the renderer's benchmark table (filled in by the interactive tracer work).
#include <cstdio>
#include <string>

namespace emboss::cli {

int benchMain(const std::string& out, int threads, bool quick) {
  std::fprintf(stderr, "emboss bench: not available yet\n");
  return 1;
}

}  // namespace emboss::cli
