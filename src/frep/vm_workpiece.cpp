// A workpiece (millimetres, positive inside) made of a vm model.
#include "frep/vm_model.h"

#include <cmath>
#include <utility>

#include "frep/vm_ops.h"

namespace emboss {

using namespace vm_detail;

// ---- the workpiece

VmWorkpiece::VmWorkpiece(VmProgram program, std::string file, double scale, double d)
    : program_(std::move(program)), file_(std::move(file)), scale_(scale), invScale_(1.0 / scale), d_(d) {}

Result<std::shared_ptr<VmWorkpiece>> VmWorkpiece::open(const std::filesystem::path& file, std::string fileAsWritten,
                                                       double scale, double d) {
  Result<VmProgram> program = VmProgram::load(file);
  if (!program) {
    // Name the file as the scene wrote it, not as it was resolved.
    const std::string resolved = file.string();
    std::string message = program.error();
    if (!fileAsWritten.empty() && message.rfind(resolved, 0) == 0 && message.size() > resolved.size() &&
        message[resolved.size()] == ':') {
      message = fileAsWritten + message.substr(resolved.size());
    }
    return fail(message);
  }
  return create(std::move(*program), std::move(fileAsWritten), scale, d);
}

Result<std::shared_ptr<VmWorkpiece>> VmWorkpiece::create(VmProgram program, std::string fileAsWritten, double scale,
                                                         double d) {
  const std::string what = fileAsWritten.empty() ? std::string("vm model") : "vm model '" + fileAsWritten + "'";
  if (!(scale > 0.0) || !std::isfinite(scale)) return fail(what + ": scale must be a positive number of mm per unit");
  if (!(d > 0.0) || !std::isfinite(d)) return fail(what + ": half thickness d must be a positive number of mm");
  Result<Box3> model = vmModelBounds(program);
  if (!model) return fail(model.error());
  std::shared_ptr<VmWorkpiece> w(new VmWorkpiece(std::move(program), std::move(fileAsWritten), scale, d));
  Box3 b = *model;
  b.x0 *= scale, b.x1 *= scale, b.y0 *= scale, b.y1 *= scale;
  if (w->program_.usesZ()) {
    b.z0 *= scale, b.z1 *= scale;
  } else {
    b.z0 = -d, b.z1 = d;
  }
  w->bounds_ = b;
  return w;
}

template <class T>
T VmWorkpiece::valueT(const VmProgram& program, const P3<T>& p) const {
  const T s(invScale_);
  const T m = -program.eval(p.x * s, p.y * s, p.z * s) * T(scale_);
  if (program_.usesZ()) return m;
  return min(m, T(d_) - abs(p.z));
}

double VmWorkpiece::value(const P3<double>& p) const { return valueT(program_, p); }
Grad VmWorkpiece::value(const P3<Grad>& p) const { return valueT(program_, p); }
Interval VmWorkpiece::value(const P3<Interval>& p) const { return valueT(program_, p); }
double VmWorkpiece::value(const VmProgram& tape, const P3<double>& p) const { return valueT(tape, p); }
Grad VmWorkpiece::value(const VmProgram& tape, const P3<Grad>& p) const { return valueT(tape, p); }
Interval VmWorkpiece::value(const VmProgram& tape, const P3<Interval>& p) const { return valueT(tape, p); }
Interval VmWorkpiece::outline(const VmProgram& tape, const Interval& x, const Interval& y) const {
  const Interval s(invScale_);
  return -tape.eval(x * s, y * s, Interval(0.0) * s) * Interval(scale_);
}

nlohmann::json VmWorkpiece::toJson() const {
  return nlohmann::json{{"type", "vm"}, {"file", file_}, {"scale", scale_}, {"d", d_}};
}

}  // namespace emboss
