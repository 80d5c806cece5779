// Importer and evaluator for F-rep models in the SSA text format ("vm" format) of libfive/MPR/Fidget.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "frep/box.h"
#include "frep/scalar.h"
#include "frep/workpiece.h"
#include "util/result.h"

namespace emboss {

// The operations of the format. Semantics follow Fidget's point evaluator (NaN in min/max
// propagates, `mod` is the Euclidean remainder, `compare` gives -1/0/1, `and`/`or`/`not` treat
// 0 as false). `pow` (a^b) is an extension from libfive's format, `log` is read as `ln`.
// Order: leaves, then unary, then binary operations (vmOpArity relies on it).
enum class VmOp : std::uint8_t {
  kConst,
  kVarX,
  kVarY,
  kVarZ,
  // unary
  kNeg,
  kAbs,
  kRecip,
  kSqrt,
  kSquare,
  kFloor,
  kCeil,
  kRound,
  kSin,
  kCos,
  kTan,
  kAsin,
  kAcos,
  kAtan,
  kExp,
  kLn,
  kNot,
  // binary
  kAdd,
  kSub,
  kMul,
  kDiv,
  kMin,
  kMax,
  kAtan2,
  kPow,
  kMod,
  kCompare,
  kAnd,
  kOr,
};

// The opcode's name in the text format ("add", "var-x", ...).
std::string_view vmOpName(VmOp op);
// How many operands (earlier IDs) the opcode takes: 0, 1 or 2 (`const` takes a number instead).
int vmOpArity(VmOp op);

// POV-Ray output of a program (see VmProgram::povFunction).
struct PovFunction {
  // `#declare <prefix>_<n> = function(x,y,z,...){ ... }` lines, in dependency order; put them
  // before the function that uses `expression`. May be empty.
  std::string declarations;
  // The value as a POV-Ray function expression in x, y, z, for use inside function(x,y,z){ ... }.
  std::string expression;
  // How many #declare lines `declarations` holds.
  std::size_t declarationCount = 0;
  // Deepest nesting of function calls POV-Ray makes evaluating `expression` (it crashes beyond
  // about 1000).
  int callDepth = 0;
};

struct PovOptions {
  // Name prefix of the auxiliary functions and their parameters (a POV-Ray identifier of at most
  // 24 characters; make it unique per model in one scene).
  std::string prefix = "Vm";
  // Upper limit of declarations + expression, in characters; above it povFunction fails.
  std::size_t maxChars = std::size_t{64} << 20;
  // Deepest nesting of one expression before it is moved into its own function (POV-Ray parses
  // recursively; tens of thousands of levels crash it).
  int maxDepth = 400;
  // Deepest nesting of function calls at evaluation; beyond it povFunction fails. POV-Ray 3.7
  // corrupts memory a little above 1000.
  int maxCallDepth = 900;
  // false: one self-contained expression, no declarations (shared sub-expressions are repeated,
  // so the text may grow exponentially; exceeding maxChars or maxDepth fails).
  bool allowDeclarations = true;
};

// A parsed, compiled vm model: a flat list of instructions over integer slots, in topological
// order, evaluated by a loop (no recursion, so depth does not matter). Dead clauses are dropped,
// constant sub-expressions folded and slots reused once their value is dead, so the working set
// stays small. The value uses the format's convention: NEGATIVE inside.
//
// Thread-safety: immutable after parse; eval may be called from any number of threads at once.
// eval neither allocates nor throws (the scratch-less overloads use a thread_local buffer that
// grows once per thread to the largest program evaluated there).
class VmProgram {
 public:
  // Parses the text. Errors name the place: "<sourceName>:<line>: <problem>", or "line <n>: ..."
  // when sourceName is empty. Never crashes on any input.
  static Result<VmProgram> parse(std::string_view text, std::string_view sourceName);
  // Reads and parses a file; messages name the file as given.
  static Result<VmProgram> load(const std::filesystem::path& file);

  double eval(double x, double y, double z) const;
  Grad eval(Grad x, Grad y, Grad z) const;
  Interval eval(Interval x, Interval y, Interval z) const;

  // The same with a caller-provided scratch buffer of at least slotCount() elements (when it is
  // smaller the result is NaN / the whole line).
  double eval(double x, double y, double z, std::span<double> scratch) const;
  Grad eval(Grad x, Grad y, Grad z, std::span<Grad> scratch) const;
  Interval eval(Interval x, Interval y, Interval z, std::span<Interval> scratch) const;

  // The program specialised to a box (model units), as libfive, MPR and Fidget prune their
  // tapes: every min and max that one operand decides over the whole box (by intervals, with a
  // margin for their undirected rounding) is replaced by that operand, and what then no longer
  // reaches the result is dropped. Inside the box it computes exactly what this program computes
  // (the same operations on the same values); outside it, anything. *value, when given, gets the
  // program's interval over the box.
  VmProgram specialised(Interval x, Interval y, Interval z, Interval* value = nullptr) const;

  // Lets go of the SSA graph (nodes()), which only specialised() and povFunction() read: a
  // specialised tape kept for evaluation needs its instructions alone.
  void dropNodes() { std::vector<Node>().swap(nodes_); }
  // The bytes the program holds beyond its own object.
  std::size_t memoryBytes() const {
    return code_.capacity() * sizeof(Instr) + nodes_.capacity() * sizeof(Node) + sourceName_.capacity();
  }

  // Whether the value depends on var-z (false: a 2D outline in x, y).
  bool usesZ() const { return usesZ_; }
  // Instructions in the compiled program (after dropping dead clauses and folding constants).
  std::size_t size() const { return code_.size(); }
  // Clauses (non-blank, non-comment lines) in the source text.
  std::size_t clauseCount() const { return clauseCount_; }
  // Scratch elements an evaluation needs.
  std::size_t slotCount() const { return slotCount_; }
  const std::string& sourceName() const { return sourceName_; }

  // The value (same convention and value as eval) as POV-Ray 3.7 function text, x y z being the
  // function's variables. POV-Ray has no let and does not remember function results, so a shared
  // sub-expression is computed once and handed on as a function parameter: it is bound where all
  // its uses meet (its post-dominator), making POV-Ray's work linear in the model's size, like
  // eval's. Fails when the text would exceed options.maxChars, nest calls deeper than
  // options.maxCallDepth, need more than POV-Ray's 56 function parameters, when the prefix is not
  // an identifier, or the model holds a constant POV-Ray cannot write (inf, NaN).
  Result<PovFunction> povFunction(const PovOptions& options = {}) const;

  // One instruction of the compiled program: out = op(a, b) over scratch slots.
  struct Instr {
    VmOp op = VmOp::kConst;
    std::uint32_t out = 0, a = 0, b = 0;
    double imm = 0.0;  // kConst only
  };
  // One node of the SSA graph the program was compiled from.
  struct Node {
    VmOp op = VmOp::kConst;
    std::uint32_t a = 0, b = 0;  // operand node indices (earlier nodes)
    double imm = 0.0;            // kConst only
  };
  // The live nodes in topological order (operands first); the last is the result.
  const std::vector<Node>& nodes() const { return nodes_; }

 private:
  template <class T>
  T run(T x, T y, T z, T* slots) const;
  template <class T>
  T runWithThreadScratch(T x, T y, T z) const;
  // code_, slotCount_ and resultSlot_ from nodes_.
  void compileSlots();

  std::vector<Instr> code_;
  std::vector<Node> nodes_;  // reachable nodes, topological order; the last is the result
  std::size_t slotCount_ = 0;
  std::size_t clauseCount_ = 0;
  std::uint32_t resultSlot_ = 0;
  bool usesZ_ = false;
  std::string sourceName_;
};

// A workpiece from a vm model, in millimetres, with f >= 0 inside (the model's sign flipped).
// `scale` maps model units to mm: f(P) = -vm(P / scale) * scale stays distance-like in mm.
// A 3D model (uses var-z) is used as it is; a 2D model becomes a plate of that outline and
// thickness 2d: f = min(-vm(x/s, y/s) * s, d - |z|). Thread-safe; evaluation does not allocate.
class VmWorkpiece : public Workpiece {
 public:
  // Reads `file`; `fileAsWritten` is how the scene names it (kept for toJson and messages).
  static Result<std::shared_ptr<VmWorkpiece>> open(const std::filesystem::path& file, std::string fileAsWritten,
                                                   double scale, double d);
  // From a parsed program. Fails for a non-positive scale or d, and for a model whose inside is
  // empty or not bounded within +-kSearchHalfWidth model units (bounds() could not hold).
  static Result<std::shared_ptr<VmWorkpiece>> create(VmProgram program, std::string fileAsWritten, double scale,
                                                     double d);

  // Half-width of the box searched for the model's inside, in model units.
  static constexpr double kSearchHalfWidth = 1000.0;

  double value(const P3<double>& p) const override;
  Grad value(const P3<Grad>& p) const override;
  Interval value(const P3<Interval>& p) const override;
  // The same values computed with `tape`: this workpiece's program specialised to a box (model
  // units) that holds p / scale (VmProgram::specialised), so fewer operations.
  double value(const VmProgram& tape, const P3<double>& p) const;
  Grad value(const VmProgram& tape, const P3<Grad>& p) const;
  Interval value(const VmProgram& tape, const P3<Interval>& p) const;
  // An outline sheet's (isPlate()) O over a box of the plane, in mm, with `tape` as above: the
  // same operations as value(), whose W is min(O, d - |z|).
  Interval outline(const VmProgram& tape, const Interval& x, const Interval& y) const;
  // Found at creation by vmModelBounds: outside it f < 0 (proven by intervals up to rounding, or
  // sampled where intervals are too loose).
  Box3 bounds() const override { return bounds_; }
  double halfThickness() const override { return d_; }
  nlohmann::json toJson() const override;

  const VmProgram& program() const { return program_; }
  double scale() const { return scale_; }
  const std::string& file() const { return file_; }
  bool isPlate() const { return !program_.usesZ(); }

 private:
  VmWorkpiece(VmProgram program, std::string file, double scale, double d);
  template <class T>
  T valueT(const VmProgram& program, const P3<T>& p) const;

  VmProgram program_;
  std::string file_;
  double scale_ = 1.0;
  double invScale_ = 1.0;
  double d_ = 1.0;
  Box3 bounds_;
};

// The box (model units) outside which the model is positive (outside, vm convention), by
// interval subdivision of [-halfWidth, halfWidth]^n (n = 3 if it uses z, else 2; for 2D models the
// z range is returned as 0..0), then branch and bound inside the coarse box found. Where intervals
// stay too loose to prove a cell outside at the finest level the cell budget allows, the cell
// counts as outside when the model is positive at all 3^n points of a grid over it. Fails when the
// inside is empty or reaches the edge of the search box. Exposed for tests and tools.
Result<Box3> vmModelBounds(const VmProgram& program, double halfWidth = VmWorkpiece::kSearchHalfWidth);

}  // namespace emboss
