// Tape pruning: a vm program specialised to a box (VmProgram::specialised).
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

}  // namespace vm_detail

VmProgram VmProgram::specialised(Interval x, Interval y, Interval z, Interval* value) const {
  thread_local std::vector<Interval> iv;
  thread_local std::vector<std::uint8_t> choice;
  thread_local PruneScratch scratch;
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
  pruneNodes(nodes_, choice, scratch, p.nodes_);
  for (const Node& nd : p.nodes_) p.usesZ_ = p.usesZ_ || nd.op == VmOp::kVarZ;
  p.compileSlots();
  return p;
}

}  // namespace emboss
