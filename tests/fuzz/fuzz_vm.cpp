// libFuzzer target for the vm-format importer: parse anything; what parses must evaluate and print.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "frep/vm_model.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace emboss;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Result<VmProgram> p = VmProgram::parse(text, "fuzz.vm");
  if (!p) {
    if (p.error().empty()) std::abort();  // every failure must say something
    return 0;
  }
  if (p->size() == 0 || p->size() > p->clauseCount()) std::abort();
  static constexpr double kPoints[][3] = {{0, 0, 0}, {0.5, -0.25, 1}, {-3, 7, -0.001}, {1e10, -1e-10, 2}};
  for (const auto& q : kPoints) {
    const double v = p->eval(q[0], q[1], q[2]);
    const Grad g = p->eval(Grad(q[0], 1, 0, 0), Grad(q[1], 0, 1, 0), Grad(q[2], 0, 0, 1));
    // The gradient's value is the plain value, bit for bit (NaN stays NaN).
    if (!(g.v == v || (std::isnan(g.v) && std::isnan(v)))) std::abort();
    // A degenerate interval is never NaN and holds the value (up to rounding).
    const Interval iv = p->eval(Interval(q[0]), Interval(q[1]), Interval(q[2]));
    if (std::isnan(iv.lo) || std::isnan(iv.hi) || iv.lo > iv.hi) std::abort();
    const Interval box = p->eval(Interval(q[0] - 1, q[0] + 1), Interval(q[1] - 0.5, q[1]), Interval(q[2], q[2] + 2));
    if (std::isnan(box.lo) || std::isnan(box.hi) || box.lo > box.hi) std::abort();
  }
  // POV-Ray text, with a small size limit so blow-ups are refused quickly.
  // An "internal error" would mean the let-by-parameter scheme lost a shared value.
  PovOptions o;
  o.maxChars = 1 << 20;
  for (const bool declarations : {true, false}) {
    o.allowDeclarations = declarations;
    Result<PovFunction> pov = p->povFunction(o);
    if (!pov && pov.error().find("internal error") != std::string::npos) std::abort();
    if (pov && pov->expression.empty()) std::abort();
  }
  return 0;
}
