// Evaluation of a compiled vm program for doubles, gradients and intervals.
#include "frep/vm_model.h"

#include <vector>

#include "frep/vm_ops.h"

namespace emboss {

using namespace vm_detail;

// ---- evaluation

template <class T>
T VmProgram::run(T x, T y, T z, T* s) const {
  for (const Instr& in : code_) {
    switch (in.op) {
      case VmOp::kConst: s[in.out] = T(in.imm); break;
      case VmOp::kVarX: s[in.out] = x; break;
      case VmOp::kVarY: s[in.out] = y; break;
      case VmOp::kVarZ: s[in.out] = z; break;
      case VmOp::kNeg: s[in.out] = fix(opNeg(s[in.a])); break;
      case VmOp::kAbs: s[in.out] = fix(opAbs(s[in.a])); break;
      case VmOp::kRecip: s[in.out] = fix(opRecip(s[in.a])); break;
      case VmOp::kSqrt: s[in.out] = fix(opSqrt(s[in.a])); break;
      case VmOp::kSquare: s[in.out] = fix(opSquare(s[in.a])); break;
      case VmOp::kFloor: s[in.out] = fix(opFloor(s[in.a])); break;
      case VmOp::kCeil: s[in.out] = fix(opCeil(s[in.a])); break;
      case VmOp::kRound: s[in.out] = fix(opRound(s[in.a])); break;
      case VmOp::kSin: s[in.out] = fix(opSin(s[in.a])); break;
      case VmOp::kCos: s[in.out] = fix(opCos(s[in.a])); break;
      case VmOp::kTan: s[in.out] = fix(opTan(s[in.a])); break;
      case VmOp::kAsin: s[in.out] = fix(opAsin(s[in.a])); break;
      case VmOp::kAcos: s[in.out] = fix(opAcos(s[in.a])); break;
      case VmOp::kAtan: s[in.out] = fix(opAtan(s[in.a])); break;
      case VmOp::kExp: s[in.out] = fix(opExp(s[in.a])); break;
      case VmOp::kLn: s[in.out] = fix(opLn(s[in.a])); break;
      case VmOp::kNot: s[in.out] = fix(opNot(s[in.a])); break;
      case VmOp::kAdd: s[in.out] = fix(opAdd(s[in.a], s[in.b])); break;
      case VmOp::kSub: s[in.out] = fix(opSub(s[in.a], s[in.b])); break;
      case VmOp::kMul: s[in.out] = fix(opMul(s[in.a], s[in.b])); break;
      case VmOp::kDiv: s[in.out] = fix(opDiv(s[in.a], s[in.b])); break;
      case VmOp::kMin: s[in.out] = fix(opMin(s[in.a], s[in.b])); break;
      case VmOp::kMax: s[in.out] = fix(opMax(s[in.a], s[in.b])); break;
      case VmOp::kAtan2: s[in.out] = fix(opAtan2(s[in.a], s[in.b])); break;
      case VmOp::kPow: s[in.out] = fix(opPow(s[in.a], s[in.b])); break;
      case VmOp::kMod: s[in.out] = fix(opMod(s[in.a], s[in.b])); break;
      case VmOp::kCompare: s[in.out] = fix(opCompare(s[in.a], s[in.b])); break;
      case VmOp::kAnd: s[in.out] = fix(opAnd(s[in.a], s[in.b])); break;
      case VmOp::kOr: s[in.out] = fix(opOr(s[in.a], s[in.b])); break;
    }
  }
  return s[resultSlot_];
}

template <class T>
T VmProgram::runWithThreadScratch(T x, T y, T z) const {
  // One buffer per thread and scalar type; it grows to the largest program seen, then never
  // allocates again.
  thread_local std::vector<T> scratch;
  if (scratch.size() < slotCount_) scratch.resize(slotCount_);
  return run(x, y, z, scratch.data());
}

double VmProgram::eval(double x, double y, double z) const {
  if (code_.empty()) return kNaN;
  return runWithThreadScratch(x, y, z);
}
Grad VmProgram::eval(Grad x, Grad y, Grad z) const {
  if (code_.empty()) return Grad(kNaN);
  return runWithThreadScratch(x, y, z);
}
Interval VmProgram::eval(Interval x, Interval y, Interval z) const {
  if (code_.empty()) return Interval::whole();
  return runWithThreadScratch(x, y, z);
}
double VmProgram::eval(double x, double y, double z, std::span<double> scratch) const {
  if (code_.empty() || scratch.size() < slotCount_) return kNaN;
  return run(x, y, z, scratch.data());
}
Grad VmProgram::eval(Grad x, Grad y, Grad z, std::span<Grad> scratch) const {
  if (code_.empty() || scratch.size() < slotCount_) return Grad(kNaN);
  return run(x, y, z, scratch.data());
}
Interval VmProgram::eval(Interval x, Interval y, Interval z, std::span<Interval> scratch) const {
  if (code_.empty() || scratch.size() < slotCount_) return Interval::whole();
  return run(x, y, z, scratch.data());
}

}  // namespace emboss
