// POV-Ray 3.7 function text of a compiled vm program.
#include "frep/vm_model.h"

#include <algorithm>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <utility>
#include <vector>

#include "frep/vm_ops.h"

namespace emboss {

using namespace vm_detail;

// ---- POV-Ray output

namespace {

// POV-Ray text of each operation: @0 / @1 stand for the operands (each already self-delimiting:
// a number in parentheses if negative, a variable, a parameter, a call or a parenthesised
// expression). POV's select(a,b,c) is b if a < 0 else c; select(a,b,c,d) is b if a < 0, c if
// a = 0, else d.
std::string_view povTemplate(VmOp op) {
  switch (op) {
    case VmOp::kNeg: return "(-@0)";
    case VmOp::kAbs: return "abs(@0)";
    case VmOp::kRecip: return "(1/@0)";
    case VmOp::kSqrt: return "sqrt(@0)";
    case VmOp::kSquare: return "pow(@0,2)";
    case VmOp::kFloor: return "floor(@0)";
    case VmOp::kCeil: return "ceil(@0)";
    case VmOp::kRound: return "select(@0,(-floor(0.5-@0)),floor(@0+0.5))";  // half away from zero
    case VmOp::kSin: return "sin(@0)";
    case VmOp::kCos: return "cos(@0)";
    case VmOp::kTan: return "tan(@0)";
    case VmOp::kAsin: return "asin(@0)";
    case VmOp::kAcos: return "acos(@0)";
    case VmOp::kAtan: return "atan(@0)";
    case VmOp::kExp: return "exp(@0)";
    case VmOp::kLn: return "ln(@0)";  // POV's log is base 10
    case VmOp::kNot: return "select(@0,0,1,0)";
    case VmOp::kAdd: return "(@0+@1)";
    case VmOp::kSub: return "(@0-@1)";
    case VmOp::kMul: return "(@0*@1)";
    case VmOp::kDiv: return "(@0/@1)";
    case VmOp::kMin: return "min(@0,@1)";
    case VmOp::kMax: return "max(@0,@1)";
    case VmOp::kAtan2: return "atan2(@0,@1)";
    case VmOp::kPow: return "pow(@0,@1)";
    // Euclidean remainder from POV's fmod-like mod: r < 0 ? r + |b| : r.
    case VmOp::kMod: return "select(mod(@0,@1),mod(@0,@1)+abs(@1),mod(@0,@1))";
    case VmOp::kCompare: return "select(@0-@1,-1,0,1)";
    case VmOp::kAnd: return "select(-abs(@0),@1,0)";
    case VmOp::kOr: return "select(-abs(@0),@0,@1)";
    case VmOp::kConst:
    case VmOp::kVarX:
    case VmOp::kVarY:
    case VmOp::kVarZ: break;
  }
  return "";
}

struct TemplateShape {
  std::size_t fixedChars = 0;  // characters other than the @k markers
  int uses[2] = {0, 0};        // how often @0 / @1 appear
  int depth = 0;               // deepest parenthesis nesting
};

TemplateShape shapeOf(std::string_view t) {
  TemplateShape s;
  int open = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] == '@' && i + 1 < t.size()) {
      ++s.uses[t[i + 1] - '0'];
      ++i;
      continue;
    }
    ++s.fixedChars;
    if (t[i] == '(') s.depth = std::max(s.depth, ++open);
    if (t[i] == ')') --open;
  }
  return s;
}

bool isIdentifier(std::string_view s) {
  if (s.empty() || s.size() > 24) return false;
  const auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  if (!alpha(s[0])) return false;
  return std::all_of(s.begin(), s.end(), [&](char c) { return alpha(c) || (c >= '0' && c <= '9'); });
}

std::size_t satAdd(std::size_t a, std::size_t b, std::size_t cap) { return a >= cap || b >= cap - a ? cap : a + b; }
std::size_t satMul(std::size_t a, std::size_t k, std::size_t cap) {
  return k == 0 ? 0 : (a >= cap / k ? cap : a * k);
}

using PovNode = VmProgram::Node;

// x, y, z or a number (negative ones in parentheses); an empty string for a non-finite constant.
std::string povLeafText(const PovNode& nd) {
  switch (nd.op) {
    case VmOp::kVarX: return "x";
    case VmOp::kVarY: return "y";
    case VmOp::kVarZ: return "z";
    default: break;
  }
  if (!std::isfinite(nd.imm)) return {};
  const std::string s = formatNumber(nd.imm);
  return std::signbit(nd.imm) ? "(" + s + ")" : s;
}

Status checkConstants(const std::vector<PovNode>& nodes, const std::string& where) {
  for (const PovNode& nd : nodes) {
    if (nd.op == VmOp::kConst && !std::isfinite(nd.imm)) {
      return fail(where + ": constant " + formatNumber(nd.imm) + " cannot be written for POV-Ray");
    }
  }
  return Ok{};
}

// One self-contained expression: every use repeats its operand's text. Sizes are computed first
// (saturating), so an exponential expansion is refused before anything is built.
Result<PovFunction> povInline(const std::vector<PovNode>& nodes, const PovOptions& o, const std::string& where) {
  const std::size_t m = nodes.size();
  const std::size_t root = m - 1;
  const std::size_t cap = o.maxChars + 1;
  std::vector<std::size_t> len(m, 0);
  std::vector<int> depth(m, 0);
  std::vector<std::uint32_t> uses(m, 0);
  for (std::size_t i = 0; i < m; ++i) {
    const PovNode& nd = nodes[i];
    if (isLeaf(nd.op)) {
      len[i] = povLeafText(nd).size();
      continue;
    }
    const TemplateShape sh = shapeOf(povTemplate(nd.op));
    std::size_t l = satAdd(sh.fixedChars, satMul(len[nd.a], static_cast<std::size_t>(sh.uses[0]), cap), cap);
    int d = depth[nd.a];
    uses[nd.a] += static_cast<std::uint32_t>(sh.uses[0]);
    if (vmOpArity(nd.op) == 2) {
      l = satAdd(l, satMul(len[nd.b], static_cast<std::size_t>(sh.uses[1]), cap), cap);
      d = std::max(d, depth[nd.b]);
      uses[nd.b] += static_cast<std::uint32_t>(sh.uses[1]);
    }
    len[i] = l;
    depth[i] = d + sh.depth;
  }
  if (len[root] > o.maxChars) {
    return fail(where + ": the POV-Ray expression would exceed " + std::to_string(o.maxChars) +
                " characters (shared sub-expressions repeat without declarations)");
  }
  if (depth[root] > o.maxDepth) {
    return fail(where + ": the POV-Ray expression would nest " + std::to_string(depth[root]) +
                " levels deep, over the limit of " + std::to_string(o.maxDepth) + " (allow declarations)");
  }
  std::vector<std::string> text(m);
  for (std::size_t i = 0; i < m; ++i) {
    const PovNode& nd = nodes[i];
    if (isLeaf(nd.op)) {
      text[i] = povLeafText(nd);
      continue;
    }
    const std::string_view t = povTemplate(nd.op);
    const std::uint32_t operands[2] = {nd.a, nd.b};
    std::string s;
    s.reserve(len[i]);
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (t[k] == '@' && k + 1 < t.size()) {
        const std::uint32_t j = operands[t[k + 1] - '0'];
        s += text[j];
        if (--uses[j] == 0) std::string().swap(text[j]);  // its last user has copied it
        ++k;
      } else {
        s += t[k];
      }
    }
    text[i] = std::move(s);
  }
  PovFunction out;
  out.expression = std::move(text[root]);
  out.callDepth = 1;  // the function the expression goes into
  return out;
}

// Text in the let-by-parameter scheme, with the bound values it refers to by parameter name.
struct PovText {
  std::string s;
  std::vector<std::uint32_t> free;  // bound nodes it names, ascending
  int nesting = 0;                  // parse nesting depth of s
  int calls = 0;                    // function-call depth POV-Ray needs to evaluate s
};

void addFree(std::vector<std::uint32_t>& into, std::uint32_t v) {
  const auto it = std::lower_bound(into.begin(), into.end(), v);
  if (it == into.end() || *it != v) into.insert(it, v);
}
void addFree(std::vector<std::uint32_t>& into, const std::vector<std::uint32_t>& from) {
  if (from.empty()) return;
  if (into.empty()) {
    into = from;
    return;
  }
  std::vector<std::uint32_t> merged;
  merged.reserve(into.size() + from.size());
  std::set_union(into.begin(), into.end(), from.begin(), from.end(), std::back_inserter(merged));
  into.swap(merged);
}

// Shared sub-expressions become function parameters: a value used more than once is bound at
// its immediate post-dominator p (the first node every path from it to the result passes), as
// p's text = P_k(x,y,z, ..., <the value's text>, ...) with P_k's body using the parameter. Its
// text sits inside every use's scope there, and each value is computed once per evaluation.
// Values bound at the same node that depend on each other get nested functions. Expressions
// nested deeper than maxDepth move into a function of their own (with their free parameters).
class PovLetWriter {
 public:
  PovLetWriter(const std::vector<PovNode>& nodes, const PovOptions& o, std::string where)
      : nodes_(nodes), o_(o), where_(std::move(where)) {}

  Result<PovFunction> write() {
    const std::size_t m = nodes_.size();
    const std::uint32_t root = static_cast<std::uint32_t>(m - 1);
    if (Status s = findPostDominators(); !s) return fail(s.error());
    std::vector<PovText> t(m);
    std::vector<char> bound(m, 0);
    std::vector<std::uint32_t> remaining = uses_;
    std::vector<std::uint32_t> seen(m, std::numeric_limits<std::uint32_t>::max());
    std::vector<std::int32_t> groupOf(m, -1);

    for (std::uint32_t v = 0; v < m; ++v) {
      const PovNode& nd = nodes_[v];
      if (isLeaf(nd.op)) {
        t[v].s = povLeafText(nd);
        continue;
      }
      // The node's own expression over its operands (inline texts or parameter names).
      PovText raw;
      const std::string_view tmpl = povTemplate(nd.op);
      const TemplateShape sh = shapeOf(tmpl);
      const std::uint32_t operands[2] = {nd.a, nd.b};
      int nest = 0;
      for (std::size_t k = 0; k < tmpl.size(); ++k) {
        if (!(tmpl[k] == '@' && k + 1 < tmpl.size())) {
          raw.s += tmpl[k];
          continue;
        }
        const std::uint32_t j = operands[tmpl[k + 1] - '0'];
        ++k;
        if (bound[j]) {
          raw.s += paramName(j);
          addFree(raw.free, j);
          continue;
        }
        raw.s += t[j].s;
        addFree(raw.free, t[j].free);
        nest = std::max(nest, t[j].nesting);
        raw.calls = std::max(raw.calls, t[j].calls);
        if (--remaining[j] == 0) t[j] = PovText{};  // its last user has copied it
      }
      raw.nesting = sh.depth + nest;

      // The bound values whose uses all meet here: from the references of this text, and
      // transitively of those values' own texts.
      std::vector<std::uint32_t> here;
      std::vector<std::uint32_t> todo;
      for (const std::uint32_t b : raw.free) {
        if (ipdom_[b] == v) todo.push_back(b);
      }
      while (!todo.empty()) {
        const std::uint32_t b = todo.back();
        todo.pop_back();
        if (seen[b] == v) continue;
        seen[b] = v;
        here.push_back(b);
        for (const std::uint32_t c : t[b].free) {
          if (ipdom_[c] == v && seen[c] != v) todo.push_back(c);
        }
      }
      if (here.empty()) {
        t[v] = std::move(raw);
      } else {
        Result<PovText> let = bindHere(std::move(raw), std::move(here), t, groupOf);
        if (!let) return fail(let.error());
        t[v] = std::move(*let);
      }

      if (t[v].nesting >= o_.maxDepth) {
        Result<PovText> cut = ownFunction(std::move(t[v]));
        if (!cut) return fail(cut.error());
        t[v] = std::move(*cut);
      }
      // Bind a shared value unless it is short and free of calls (then repeating it is cheaper).
      bound[v] = v != root && uses_[v] > 1 && (t[v].s.size() > kShareInlineChars || t[v].calls > 0);
      if (out_.declarations.size() + t[v].s.size() > o_.maxChars) return tooLong();
    }
    if (!t[root].free.empty()) return fail(where_ + ": internal error writing POV-Ray text (unbound value)");
    out_.expression = std::move(t[root].s);
    out_.callDepth = t[root].calls + 1;  // the function the expression goes into
    if (out_.callDepth > o_.maxCallDepth) {
      return fail(where_ + ": POV-Ray would nest function calls " + std::to_string(out_.callDepth) +
                  " deep, over the limit of " + std::to_string(o_.maxCallDepth));
    }
    if (out_.declarations.size() + out_.expression.size() > o_.maxChars) return tooLong();
    return std::move(out_);
  }

 private:
  static constexpr std::size_t kShareInlineChars = 24;
  static constexpr std::size_t kMaxParams = 56 - 3;  // POV-Ray's limit, less x, y, z

  Error tooLong() const {
    return fail(where_ + ": the POV-Ray function would exceed " + std::to_string(o_.maxChars) + " characters");
  }
  std::string paramName(std::uint32_t j) const { return o_.prefix + "_v" + std::to_string(j); }

  // Textual uses, users and immediate post-dominators (users come later in the order, so one
  // backward pass with the Cooper-Harvey-Kennedy intersection suffices).
  Status findPostDominators() {
    const std::size_t m = nodes_.size();
    const std::uint32_t root = static_cast<std::uint32_t>(m - 1);
    uses_.assign(m, 0);
    std::vector<std::uint32_t> start(m + 1, 0);
    for (const PovNode& nd : nodes_) {
      if (isLeaf(nd.op)) continue;
      const TemplateShape sh = shapeOf(povTemplate(nd.op));
      uses_[nd.a] += static_cast<std::uint32_t>(sh.uses[0]);
      ++start[nd.a + 1];
      if (vmOpArity(nd.op) == 2) {
        uses_[nd.b] += static_cast<std::uint32_t>(sh.uses[1]);
        if (nd.b != nd.a) ++start[nd.b + 1];
      }
    }
    for (std::size_t i = 0; i < m; ++i) start[i + 1] += start[i];
    std::vector<std::uint32_t> users(start[m]);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t u = 0; u < m; ++u) {
      const PovNode& nd = nodes_[u];
      if (isLeaf(nd.op)) continue;
      users[fill[nd.a]++] = u;
      if (vmOpArity(nd.op) == 2 && nd.b != nd.a) users[fill[nd.b]++] = u;
    }
    ipdom_.assign(m, root);
    // A budget against quadratic walks on pathological graphs.
    std::size_t steps = 0;
    const std::size_t budget = 64 * m + 100'000'000;
    for (std::uint32_t v = root; v-- > 0;) {
      if (isLeaf(nodes_[v].op) || start[v] == start[v + 1]) continue;  // leaves are never bound
      std::uint32_t d = users[start[v]];
      for (std::uint32_t k = start[v] + 1; k < start[v + 1]; ++k) {
        std::uint32_t a = d, b = users[k];
        while (a != b) {
          while (a < b) a = ipdom_[a], ++steps;
          while (b < a) b = ipdom_[b], ++steps;
        }
        d = a;
        if (steps > budget) return fail(where_ + ": the model's sharing is too tangled to write for POV-Ray");
      }
      ipdom_[v] = d;
    }
    return Ok{};
  }

  // Declares a function of x, y, z and `params` with `body`; returns its name.
  std::string declare(const std::vector<std::uint32_t>& params, const std::string& body) {
    const std::string name = o_.prefix + "_" + std::to_string(++out_.declarationCount);
    out_.declarations += "#declare ";
    out_.declarations += name;
    out_.declarations += " = function(x,y,z";
    for (const std::uint32_t p : params) (out_.declarations += ',') += paramName(p);
    out_.declarations += "){ ";
    out_.declarations += body;
    out_.declarations += " }\n";
    return name;
  }

  Error tooManyParams(std::size_t n) const {
    return fail(where_ + ": writing for POV-Ray needs " + std::to_string(n) +
                " shared values at once; POV-Ray functions take at most " + std::to_string(kMaxParams) +
                " besides x, y, z");
  }

  // Binds `here` (ascending) around `raw`: groups of mutually independent values, each group one
  // function whose call passes the group's texts as arguments.
  Result<PovText> bindHere(PovText raw, std::vector<std::uint32_t> here, std::vector<PovText>& t,
                           std::vector<std::int32_t>& groupOf) {
    std::sort(here.begin(), here.end());
    std::vector<std::vector<std::uint32_t>> groups;
    for (const std::uint32_t b : here) {
      bool dependent = groups.empty();
      if (!dependent) {
        const std::int32_t current = static_cast<std::int32_t>(groups.size()) - 1;
        for (const std::uint32_t c : t[b].free) {
          if (groupOf[c] == current) dependent = true;
        }
      }
      if (dependent) groups.emplace_back();
      groups.back().push_back(b);
      groupOf[b] = static_cast<std::int32_t>(groups.size()) - 1;
    }
    PovText body = std::move(raw);
    for (std::size_t gi = groups.size(); gi-- > 0;) {
      const std::vector<std::uint32_t>& params = body.free;
      if (params.size() > kMaxParams) return tooManyParams(params.size());
      const std::string name = declare(params, body.s);
      PovText call;
      call.s = name + "(x,y,z";
      call.nesting = 1;
      call.calls = 1 + body.calls;
      for (const std::uint32_t p : params) {
        call.s += ',';
        if (groupOf[p] == static_cast<std::int32_t>(gi)) {
          call.s += t[p].s;
          addFree(call.free, t[p].free);
          call.nesting = std::max(call.nesting, 1 + t[p].nesting);
          call.calls = std::max(call.calls, t[p].calls);
        } else {
          call.s += paramName(p);
          addFree(call.free, p);
        }
      }
      call.s += ')';
      body = std::move(call);
    }
    for (const std::uint32_t b : here) {
      groupOf[b] = -1;
      t[b] = PovText{};  // consumed: computed once, here
    }
    return body;
  }

  // Moves a deeply nested text into a function of its own.
  Result<PovText> ownFunction(PovText text) {
    if (text.free.size() > kMaxParams) return tooManyParams(text.free.size());
    const std::string name = declare(text.free, text.s);
    PovText call;
    call.s = name + "(x,y,z";
    for (const std::uint32_t p : text.free) (call.s += ',') += paramName(p);
    call.s += ')';
    call.free = std::move(text.free);
    call.nesting = 1;
    call.calls = 1 + text.calls;
    return call;
  }

  const std::vector<PovNode>& nodes_;
  const PovOptions& o_;
  std::string where_;
  std::vector<std::uint32_t> uses_;
  std::vector<std::uint32_t> ipdom_;
  PovFunction out_;
};

}  // namespace

Result<PovFunction> VmProgram::povFunction(const PovOptions& options) const {
  if (nodes_.empty()) return fail("the model is empty");
  if (!isIdentifier(options.prefix)) {
    return fail("POV-Ray name prefix " + shown(options.prefix) +
                " is not an identifier (a letter or _, then letters, digits, _; at most 24)");
  }
  const std::string where = sourceName_.empty() ? std::string("the model") : "'" + sourceName_ + "'";
  if (Status s = checkConstants(nodes_, where); !s) return fail(s.error());
  PovOptions o = options;
  o.maxDepth = std::max(o.maxDepth, 4);
  if (!o.allowDeclarations) return povInline(nodes_, o, where);
  return PovLetWriter(nodes_, o, where).write();
}

}  // namespace emboss
