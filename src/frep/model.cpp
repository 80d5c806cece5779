// The model's edits and its evaluation under the two deformation models.
#include "frep/model.h"

#include <atomic>
#include <cmath>

#include "frep/kernels.h"

namespace emboss {

namespace {

// Iterates 0..n-1 without materialising the list.
struct AllIndices {
  size_t n;
  struct It {
    std::uint32_t i;
    std::uint32_t operator*() const { return i; }
    It& operator++() { ++i; return *this; }
    bool operator!=(const It& o) const { return i != o.i; }
  };
  It begin() const { return {0}; }
  It end() const { return {static_cast<std::uint32_t>(n)}; }
};

// Operation ids come from one counter for the whole process, so an id names one operation of one
// model: a cache that followed another model (or a model since destroyed) can never mistake an
// operation for one it has seen.
std::atomic<std::uint64_t> gNextOperationId{1};

}  // namespace

Model::Model(std::shared_ptr<const Workpiece> workpiece, Deformation deformation)
    : workpiece_(std::move(workpiece)), deformation_(deformation) {}

Status Model::add(Operation op) {
  const std::string problem = validate(op);
  if (!problem.empty()) return fail(std::string(opKindName(op.kind)) + ": " + problem);
  ops_.erase(ops_.begin() + static_cast<std::ptrdiff_t>(cursor_), ops_.end());
  ops_.emplace_back(std::move(op));
  ids_.resize(cursor_);
  ids_.push_back(gNextOperationId.fetch_add(1, std::memory_order_relaxed));
  cursor_ = ops_.size();
  ++revision_;
  return Ok{};
}

bool Model::undo() {
  if (!canUndo()) return false;
  --cursor_;
  ++revision_;
  return true;
}

bool Model::redo() {
  if (!canRedo()) return false;
  ++cursor_;
  ++revision_;
  return true;
}

void Model::clear() {
  ops_.clear();
  ids_.clear();
  cursor_ = 0;
  ++revision_;
}

template <class T, class Indices>
T Model::evaluateWith(const P3<T>& p, const Indices& indices) const {
  if (deformation_ == Deformation::Offset) {
    // The paper's algebra, in order: f_new = f +- f_offset, or f_new = F(f, f_tool).
    T f = workpiece_->value(p);
    for (std::uint32_t i : indices) {
      const PreparedOp& op = ops_[i];
      if (op.op().isOffset())
        f += op.offset(p, Deformation::Offset);
      else if (op.op().isSet())
        f = op.combine(f, p);
    }
    return f;
  }
  // The sheet: every offset warps space along z by a function of (x, y) alone, so the warps
  // commute and add. A set operation k sees the point moved by the offsets that come after it.
  // Pass 1 sums the offsets and notes the running sum before each set operation.
  thread_local std::vector<T> prefix;
  prefix.clear();
  T total(0.0);
  bool anySet = false;
  for (std::uint32_t i : indices) {
    const PreparedOp& op = ops_[i];
    if (op.op().isOffset()) {
      total += op.offset(p, Deformation::Sheet);
    } else if (op.op().isSet()) {
      prefix.push_back(total);
      anySet = true;
    }
  }
  T f = workpiece_->value(P3<T>{p.x, p.y, p.z - total});
  if (!anySet) return f;
  size_t k = 0;
  for (std::uint32_t i : indices) {
    const PreparedOp& op = ops_[i];
    if (!op.op().isSet()) continue;
    const T shift = total - prefix[k++];
    f = op.combine(f, P3<T>{p.x, p.y, p.z - shift});
  }
  return f;
}

template <class T>
T Model::evaluate(const P3<T>& p) const {
  return evaluateWith(p, AllIndices{cursor_});
}

template <class T>
T Model::evaluate(const P3<T>& p, std::span<const std::uint32_t> candidates) const {
  return evaluateWith(p, candidates);
}

template <class T>
Model::Line<T>::Line(const Model& model, const T& x, const T& y, std::span<const std::uint32_t> candidates)
    : model_(&model), x_(x), y_(y), candidates_(candidates), sheet_(model.deformation_ == Deformation::Sheet) {
  if (!sheet_) return;
  // evaluateWith()'s first pass, its z unread (a sheet's offsets are functions of x and y).
  // Each set operation's running sum first (evaluateWith()'s prefix), its shift once the sum is whole.
  const P3<T> p{x, y, T(0.0)};
  for (std::uint32_t i : candidates) {
    const PreparedOp& op = model.ops_[i];
    if (op.op().isOffset())
      total_ += op.offset(p, Deformation::Sheet);
    else if (op.op().isSet())
      sets_.push_back({i, total_});
  }
  for (SetStep& s : sets_) s.shift = total_ - s.shift;
}

template <class T>
T Model::Line<T>::operator()(const T& z) const {
  if (!sheet_) return model_->evaluate(P3<T>{x_, y_, z}, candidates_);
  // evaluateWith()'s second pass, in its arithmetic.
  T f = model_->workpiece_->value(P3<T>{x_, y_, z - total_});
  for (const SetStep& s : sets_) f = model_->ops_[s.op].combine(f, P3<T>{x_, y_, z - s.shift});
  return f;
}

template <class T>
T Model::displacement(const T& x, const T& y, const T& z, std::span<const std::uint32_t> candidates) const {
  T total(0.0);
  const P3<T> p{x, y, z};
  for (std::uint32_t i : candidates) {
    const PreparedOp& op = ops_[i];
    if (op.op().isOffset()) total += op.offset(p, deformation_);
  }
  return total;
}

void Model::evaluate(std::span<const P3<double>> points, std::span<double> out) const {
  for (size_t i = 0; i < points.size() && i < out.size(); ++i) out[i] = evaluate(points[i]);
}

void Model::evaluateGradient(std::span<const P3<double>> points, std::span<Grad> out) const {
  for (size_t i = 0; i < points.size() && i < out.size(); ++i) {
    const P3<double>& q = points[i];
    out[i] = evaluate(P3<Grad>{Grad(q.x, 1, 0, 0), Grad(q.y, 0, 1, 0), Grad(q.z, 0, 0, 1)});
  }
}

Box3 Model::bounds() const {
  Box3 b = workpiece_->bounds();
  // Offsets move the surface by at most the sum of their peaks (either way, since the offset model
  // mirrors them); a set operation changes nothing beyond its tool's box grown by its reach.
  double reach = 0.0;
  for (size_t i = 0; i < cursor_; ++i) {
    const Operation& o = ops_[i].op();
    switch (o.kind) {
      case OpKind::Trace: reach += o.a; break;
      case OpKind::Punch: reach += std::abs(o.p) * o.a; break;
      case OpKind::Press: reach += std::abs(o.p) * o.a * (4.0 * M_PI + 1.0); break;  // a comb at L/4 sums to ~4 pi peaks
      case OpKind::Region: reach += std::abs(o.height); break;
      case OpKind::Patina: break;  // colours, moves nothing
      default: {
        const Box3 t = o.tool.bounds();
        const double g = kernels::kSupportSpan * o.tool.size();
        b.x0 = std::min(b.x0, t.x0 - g), b.y0 = std::min(b.y0, t.y0 - g), b.z0 = std::min(b.z0, t.z0 - g);
        b.x1 = std::max(b.x1, t.x1 + g), b.y1 = std::max(b.y1, t.y1 + g), b.z1 = std::max(b.z1, t.z1 + g);
        break;
      }
    }
  }
  b.z0 -= reach;
  b.z1 += reach;
  return b;
}

template double Model::evaluate(const P3<double>&) const;
template Grad Model::evaluate(const P3<Grad>&) const;
template Interval Model::evaluate(const P3<Interval>&) const;
template double Model::evaluate(const P3<double>&, std::span<const std::uint32_t>) const;
template Grad Model::evaluate(const P3<Grad>&, std::span<const std::uint32_t>) const;
template Interval Model::evaluate(const P3<Interval>&, std::span<const std::uint32_t>) const;
template class Model::Line<double>;
template class Model::Line<Interval>;
template double Model::displacement(const double&, const double&, const double&, std::span<const std::uint32_t>) const;
template Interval Model::displacement(const Interval&, const Interval&, const Interval&, std::span<const std::uint32_t>) const;

}  // namespace emboss
