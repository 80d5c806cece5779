// Parser and compiler of vm-format F-rep models: text to a flat program over scratch slots.
#include "frep/vm_model.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "frep/vm_ops.h"

namespace emboss {

using namespace vm_detail;

namespace {

// Refuse texts with more clauses than this (slots are 32-bit; memory stays bounded).
constexpr std::size_t kMaxClauses = 20'000'000;
// Refuse files larger than this (bytes) before reading them.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 30;

std::string placeOf(std::string_view source, std::size_t line) {
  if (source.empty()) return "line " + std::to_string(line);
  return std::string(source) + ":" + std::to_string(line);
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Parses a whole token as a finite double (an optional leading '+' allowed).
std::optional<double> parseNumber(std::string_view tok) {
  if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-') tok.remove_prefix(1);
  double v = 0.0;
  const char* end = tok.data() + tok.size();
  const auto [ptr, ec] = std::from_chars(tok.data(), end, v, std::chars_format::general);
  if (ec != std::errc() || ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

std::string_view vmOpName(VmOp op) { return infoOf(op).name; }
int vmOpArity(VmOp op) {
  // The enum lists leaves, then unary, then binary operations (called per node while compiling).
  if (op >= VmOp::kAdd) return 2;
  if (op >= VmOp::kNeg) return 1;
  return 0;
}

// ---- parsing and compiling

Result<VmProgram> VmProgram::parse(std::string_view text, std::string_view sourceName) {
  struct Parsed {
    VmOp op;
    std::uint32_t a, b;
    double imm;
  };
  struct Defined {
    std::uint32_t index;
    std::size_t line;
  };
  std::vector<Parsed> all;
  std::unordered_map<std::string_view, Defined> ids;
  {
    const std::size_t lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    const std::size_t guess = std::min<std::size_t>(lines, 1u << 22);  // a hint only
    all.reserve(guess);
    ids.reserve(guess);
  }

  const auto failAt = [&](std::size_t line, const std::string& message) {
    return fail(placeOf(sourceName, line) + ": " + message);
  };

  std::size_t lineNo = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++lineNo;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);

    // Tokens: ID OPCODE [ARG...]; keep one more than any opcode takes, to report extras.
    std::array<std::string_view, 5> tok;
    std::size_t count = 0;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && isBlank(line[i])) ++i;
      if (i >= line.size()) break;
      const std::size_t start = i;
      while (i < line.size() && !isBlank(line[i])) ++i;
      if (count < tok.size()) tok[count] = line.substr(start, i - start);
      ++count;
    }
    if (count == 0) continue;
    if (count == 1) return failAt(lineNo, shown(tok[0]) + " has no opcode");

    const OpInfo* info = findOp(tok[1]);
    if (!info) return failAt(lineNo, "unknown opcode " + shown(tok[1]));
    const std::size_t args = count - 2;
    Parsed p{info->op, 0, 0, 0.0};
    if (info->op == VmOp::kConst) {
      if (args != 1) return failAt(lineNo, "'const' takes one number, got " + std::to_string(args) + " arguments");
      const std::optional<double> v = parseNumber(tok[2]);
      if (!v) return failAt(lineNo, shown(tok[2]) + " is not a finite number");
      p.imm = *v;
    } else {
      if (args != static_cast<std::size_t>(info->arity)) {
        const std::string name(info->name);
        if (info->arity == 0) return failAt(lineNo, "'" + name + "' takes no operands, got " + std::to_string(args));
        return failAt(lineNo, "'" + name + "' takes " + std::to_string(info->arity) + " operand" +
                                  (info->arity == 1 ? "" : "s") + ", got " + std::to_string(args));
      }
      for (int k = 0; k < info->arity; ++k) {
        const auto it = ids.find(tok[2 + k]);
        if (it == ids.end()) return failAt(lineNo, shown(tok[2 + k]) + " used before it is defined");
        (k == 0 ? p.a : p.b) = it->second.index;
      }
    }
    if (all.size() >= kMaxClauses) return failAt(lineNo, "too many clauses (the limit is " + std::to_string(kMaxClauses) + ")");
    const auto [it, inserted] = ids.try_emplace(tok[0], Defined{static_cast<std::uint32_t>(all.size()), lineNo});
    if (!inserted) {
      return failAt(lineNo, shown(tok[0]) + " is already defined on line " + std::to_string(it->second.line));
    }
    all.push_back(p);
    if (eol == text.size()) break;
  }
  if (all.empty()) {
    return fail(sourceName.empty() ? std::string("empty model (no clauses)")
                                   : std::string(sourceName) + ": empty model (no clauses)");
  }

  // Dead-clause removal and constant folding, in one forward pass over the live clauses (operands
  // come first, so a folded operand is known when its user is reached).
  const std::size_t n = all.size();
  std::vector<char> live(n, 0);
  live[n - 1] = 1;
  for (std::size_t i = n; i-- > 0;) {
    if (!live[i]) continue;
    const int arity = vmOpArity(all[i].op);
    if (arity >= 1) live[all[i].a] = 1;
    if (arity >= 2) live[all[i].b] = 1;
  }
  std::vector<Node> folded;
  std::vector<std::uint32_t> newIndex(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!live[i]) continue;
    Node nd{all[i].op, 0, 0, all[i].imm};
    const int arity = vmOpArity(nd.op);
    if (arity >= 1) nd.a = newIndex[all[i].a];
    if (arity >= 2) nd.b = newIndex[all[i].b];
    if (arity >= 1) {
      const bool constA = folded[nd.a].op == VmOp::kConst;
      const bool constB = arity < 2 || folded[nd.b].op == VmOp::kConst;
      if (constA && constB) {
        const double v = applyDouble(nd.op, folded[nd.a].imm, arity >= 2 ? folded[nd.b].imm : 0.0);
        if (std::isfinite(v)) nd = Node{VmOp::kConst, 0, 0, v};  // keep non-finite ones as written
      }
    }
    newIndex[i] = static_cast<std::uint32_t>(folded.size());
    folded.push_back(nd);
  }
  std::vector<char>().swap(live);
  std::vector<Parsed>().swap(all);

  // Folding may leave constants unused: drop dead nodes again.
  VmProgram prog;
  prog.sourceName_ = std::string(sourceName);
  prog.clauseCount_ = n;
  {
    const std::size_t m = folded.size();
    std::vector<char> used(m, 0);
    used[m - 1] = 1;
    for (std::size_t i = m; i-- > 0;) {
      if (!used[i]) continue;
      const int arity = vmOpArity(folded[i].op);
      if (arity >= 1) used[folded[i].a] = 1;
      if (arity >= 2) used[folded[i].b] = 1;
    }
    std::vector<std::uint32_t> remap(m, 0);
    prog.nodes_.reserve(m);
    for (std::size_t i = 0; i < m; ++i) {
      if (!used[i]) continue;
      Node nd = folded[i];
      const int arity = vmOpArity(nd.op);
      if (arity >= 1) nd.a = remap[nd.a];
      if (arity >= 2) nd.b = remap[nd.b];
      remap[i] = static_cast<std::uint32_t>(prog.nodes_.size());
      prog.nodes_.push_back(nd);
      if (nd.op == VmOp::kVarZ) prog.usesZ_ = true;
    }
  }

  prog.compileSlots();
  return prog;
}

void VmProgram::compileSlots() {
  // Slot allocation: a node's slot is freed after its last use and reused (LIFO, so recently
  // touched memory stays hot). An instruction reads its operands before writing its result, so
  // the result may take an operand's freed slot.
  const std::vector<Node>& nodes = nodes_;
  code_.clear();
  const std::size_t m = nodes.size();
  if (m == 0) return;
  std::vector<std::uint32_t> lastUse(m, 0);
  for (std::size_t i = 0; i < m; ++i) {
    const int arity = vmOpArity(nodes[i].op);
    if (arity >= 1) lastUse[nodes[i].a] = static_cast<std::uint32_t>(i);
    if (arity >= 2) lastUse[nodes[i].b] = static_cast<std::uint32_t>(i);
  }
  std::vector<std::uint32_t> slot(m, 0);
  std::vector<std::uint32_t> freeSlots;
  std::uint32_t slots = 0;
  code_.reserve(m);
  for (std::size_t i = 0; i < m; ++i) {
    const Node& nd = nodes[i];
    const int arity = vmOpArity(nd.op);
    if (arity >= 1 && lastUse[nd.a] == i) freeSlots.push_back(slot[nd.a]);
    if (arity >= 2 && nd.b != nd.a && lastUse[nd.b] == i) freeSlots.push_back(slot[nd.b]);
    if (!freeSlots.empty()) {
      slot[i] = freeSlots.back();
      freeSlots.pop_back();
    } else {
      slot[i] = slots++;
    }
    Instr in;
    in.op = nd.op;
    in.out = slot[i];
    in.a = arity >= 1 ? slot[nd.a] : 0;
    in.b = arity >= 2 ? slot[nd.b] : 0;
    in.imm = nd.imm;
    code_.push_back(in);
  }
  slotCount_ = slots;
  resultSlot_ = slot[m - 1];
}

Result<VmProgram> VmProgram::load(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) return fail("cannot read '" + name + "': it is a folder");
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (ec) return fail("cannot read '" + name + "': " + ec.message());
  if (bytes > kMaxFileBytes) return fail("cannot read '" + name + "': the file is too large for a model");
  std::ifstream in(file, std::ios::binary);
  if (!in) return fail("cannot open '" + name + "'");
  std::string text(static_cast<std::size_t>(bytes), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.gcount() != static_cast<std::streamsize>(text.size())) return fail("cannot read '" + name + "': read failed");
  return parse(text, name);
}

}  // namespace emboss
