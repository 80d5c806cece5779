// Tape pruning: a vm program specialised to a box (VmProgram::specialised).
#include <cmath>
#include <vector>

#include "frep/vm_model.h"
#include "frep/vm_ops.h"

namespace emboss {

using namespace vm_detail;

namespace vm_detail {

void pruneNodes(const std::vector<VmProgram::Node>& t, const std::vector<std::uint8_t>& choice, PruneScratch& s,
                std::vector<VmProgram::Node>& out) {
  out.clear();
  const std::size_t n = t.size();
  if (n == 0) return;
  // A decided node stands for its deciding operand (itself perhaps an alias).
  s.alias.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.alias[i] = static_cast<std::uint32_t>(i);
    if (choice[i] == 1) s.alias[i] = s.alias[t[i].a];
    else if (choice[i] == 2) s.alias[i] = s.alias[t[i].b];
  }
  s.live.assign(n, 0);
  s.live[s.alias[n - 1]] = 1;
  for (std::size_t k = n; k-- > 0;) {
    if (!s.live[k] || s.alias[k] != k) continue;
    const int arity = vmOpArity(t[k].op);
    if (arity >= 1) s.live[s.alias[t[k].a]] = 1;
    if (arity == 2) s.live[s.alias[t[k].b]] = 1;
  }
  s.remap.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!s.live[i] || s.alias[i] != i) continue;
    VmProgram::Node nd = t[i];
    const int arity = vmOpArity(nd.op);
    if (arity >= 1) nd.a = s.remap[s.alias[nd.a]];
    if (arity == 2) nd.b = s.remap[s.alias[nd.b]];
    s.remap[i] = static_cast<std::uint32_t>(out.size());
    out.push_back(nd);
  }
}

// Whether op on constant operands gives the same bits as a constant in every arithmetic a tape
// runs in: double, Grad (zero derivatives) and Interval (a point interval, no outward rounding).
static bool foldsExactly(VmOp op) {
  switch (op) {
    case VmOp::kNeg: case VmOp::kAbs: case VmOp::kSquare: case VmOp::kAdd: case VmOp::kSub:
    case VmOp::kMul: case VmOp::kMin: case VmOp::kMax:
      return true;
    default:
      return false;
  }
}

void foldConstants(const std::vector<VmProgram::Node>& t, std::vector<std::uint8_t>& choice,
                   std::vector<VmProgram::Node>& out) {
  out = t;
  const std::size_t n = t.size();
  thread_local std::vector<double> value;  // a node's value where it is constant
  thread_local std::vector<char> constant;
  value.assign(n, 0.0);
  constant.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    VmProgram::Node& nd = out[i];
    const int arity = vmOpArity(nd.op);
    if (choice[i] == 1 || choice[i] == 2) {  // stands for an operand: its value too
      const std::uint32_t o = choice[i] == 1 ? nd.a : nd.b;
      value[i] = value[o], constant[i] = constant[o];
      continue;
    }
    if (nd.op == VmOp::kConst) {
      value[i] = nd.imm, constant[i] = 1;
      continue;
    }
    const bool operandsConstant = arity >= 1 && constant[nd.a] && (arity == 1 || constant[nd.b]);
    if (operandsConstant && foldsExactly(nd.op)) {
      const double v = applyNode<double>(nd, value.data(), 0.0, 0.0, 0.0);
      if (std::isfinite(v)) {
        nd = VmProgram::Node{VmOp::kConst, 0, 0, v};
        value[i] = v, constant[i] = 1;
        continue;
      }
    }
    // x - (+0) is x, bit for bit (-0 and NaN included) and in every arithmetic.
    if (nd.op == VmOp::kSub && constant[nd.b] && value[nd.b] == 0.0 && !std::signbit(value[nd.b])) choice[i] = 1;
  }
}

}  // namespace vm_detail

VmProgram VmProgram::specialised(Interval x, Interval y, Interval z, Interval* value) const {
  thread_local std::vector<Interval> iv;
  thread_local std::vector<std::uint8_t> choice;
  thread_local PruneScratch scratch;
  thread_local std::vector<Node> work;
  VmProgram p;
  p.sourceName_ = sourceName_;
  p.clauseCount_ = clauseCount_;
  const std::size_t n = nodes_.size();
  if (n == 0) {
    if (value) *value = Interval::whole();
    return p;
  }
  iv.resize(n);
  choice.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Node& nd = nodes_[i];
    iv[i] = applyNode<Interval>(nd, iv.data(), x, y, z);
    if (nd.op == VmOp::kMin || nd.op == VmOp::kMax) choice[i] = decidingOperand(nd.op, iv[nd.a], iv[nd.b]);
  }
  if (value) *value = iv[n - 1];
  foldConstants(nodes_, choice, work);
  pruneNodes(work, choice, scratch, p.nodes_);
  for (const Node& nd : p.nodes_) p.usesZ_ = p.usesZ_ || nd.op == VmOp::kVarZ;
  p.compileSlots();
  return p;
}

}  // namespace emboss
