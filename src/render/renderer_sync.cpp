// The renderer takes in the model (the displacement field, its columns and set operations); the
// kept hits a change can move are forgotten in renderer_kept_hits.cpp, the camera is
// renderer_camera.cpp's (renderer.h).
#include <algorithm>
#include <chrono>
#include <cstddef>

#include "render/renderer_internal.h"

namespace emboss {

using namespace render_internal;

// ---------------------------------------------------------------- sync

void Renderer::sync(const Model& model) {
  const bool followed = model_ == &model && fieldReady_;
  std::vector<std::uint64_t> setIdsBefore;
  std::vector<Box2> setSupportsBefore;
  for (const SetOp& s : setOps_) setIdsBefore.push_back(s.id), setSupportsBefore.push_back(s.support);
  // Another model is followed from scratch (its operation ids are its own).
  if (model_ != &model) fieldReady_ = false;
  model_ = &model;
  // The sheet model's offsets come from the field: the grid serves set operations, patina and
  // dirty regions, and cells of a millimetre at least keep a stroke's insert cheap on a small
  // workpiece (docs/performance.md, "Stop 53").
  const double minCell = model.deformation() == Deformation::Sheet ? kSheetGridCell : 0.0;
  grid_.setMinCellSize(minCell);
  grid_.sync(model);
  patinaGrid_.setMinCellSize(minCell);  // (cells as wide as grid_'s)
  patinaGrid_.sync(model);
  bounds_ = model.bounds();
  // The step: a quarter of the sheet's thickness, at most 0.25 mm: a sheet can never slip between
  // two samples, and the thin-feature splits go down to h / 16. Depends on the workpiece only.
  step_ = std::min(0.25, 0.5 * model.workpiece().halfThickness());
  all_.resize(model.activeCount());
  std::iota(all_.begin(), all_.end(), 0u);
  lastSync_ = {};
  fieldChanges_.clear();
  if (model.deformation() == Deformation::Sheet) {
    syncField(model);
  } else {
    field_.clear();
    fieldReady_ = false;
    fieldWorkpiece_ = nullptr;
    fieldIds_.clear();
    fieldSupports_.clear();
    fieldPeaks_.clear();
  }
  syncSetOps(model);
  syncPatina(model, followed);
  forgetMovedHits(followed, setIdsBefore);
  {
    // The pile's tops where f can have changed: where D and the shifts did, and the supports of
    // the set operations from the first that differs on (appended or undone, as a rule).
    std::vector<Box2> changed;
    for (const FieldChange& c : fieldChanges_) changed.push_back(c.region);
    size_t same = 0;
    while (same < setOps_.size() && same < setIdsBefore.size() && setOps_[same].id == setIdsBefore[same]) ++same;
    for (size_t k = same; k < setSupportsBefore.size(); ++k) changed.push_back(setSupportsBefore[k]);
    for (size_t k = same; k < setOps_.size(); ++k) changed.push_back(setOps_[k].support);
    refreshPileTops(!followed || !fieldReady_ || lastSync_.rebuilt, changed);
  }
  syncedRevision_ = model.revision();
  syncedWorkpiece_ = model.workpiecePtr();
}

size_t Renderer::memoryBytes() const {
  size_t n = field_.memoryBytes() + grid_.memoryBytes() + patinaGrid_.memoryBytes() + patinaCache_.memoryBytes();
  if (workpieceKind_ == 4) n += columns_.memoryBytes() + outlineMask_.size();
  n += saved_.samples.samples.capacity() * sizeof(HeightField::Sample);
  for (size_t k = 0; k < setOps_.size(); ++k)
    if (setOps_[k].shift && setOps_[k].owner == k) n += setOps_[k].shift->memoryBytes();
  if (pileTops_.top) n += static_cast<size_t>(pileTops_.nx) * static_cast<size_t>(pileTops_.ny) * sizeof(std::atomic<float>);
  return n;
}

void Renderer::rebuildField(const Model& model) {
  pending_ = {};
  saved_ = {};  // (its memory too: a cleared bench holds nothing of the last visitor's)
  const Box3 wb = model.workpiece().bounds();
  const Box2 domain = wb.xy().grown(kFieldMargin);
  const double area = (domain.x1 - domain.x0) * (domain.y1 - domain.y0);
  const double spacing = std::max(kFieldSpacing, std::sqrt(area / kMaxFieldSamples));
  field_.configure(domain, spacing, /*cavity=*/true);
  fieldWorkpiece_ = model.workpiecePtr();
  const Workpiece* w = fieldWorkpiece_.get();
  workpieceKind_ = dynamic_cast<const Plate*>(w) ? 1 : dynamic_cast<const Disc*>(w) ? 2 : dynamic_cast<const Bowl*>(w) ? 3 : 0;
  const auto* vm = dynamic_cast<const VmWorkpiece*>(w);
  if (vm && vm->isPlate()) workpieceKind_ = 4;
  if (workpieceKind_ == 4) buildColumns();
  frontThickness_ = workpieceKind_ == 1 || workpieceKind_ == 2 || workpieceKind_ == 4 ? w->halfThickness() : -1.0;
  bool anyOffset = false;
  for (size_t i = 0; i < model.activeCount() && !anyOffset; ++i) anyOffset = model.operations()[i].op().isOffset();
  if (anyOffset) {
    recomputeField(model, field_.all());
    field_.finish(field_.all(), &pool_);
  } else {
    field_.finishFlat();  // a bare sheet (a new attract piece, a new visitor): nothing to visit
  }
  fieldReady_ = true;
  lastSync_.rebuilt = true;
  lastSync_.samplesUpdated += field_.all().count();
  const size_t active = model.activeCount();
  fieldIds_.assign(model.operationIds().begin(), model.operationIds().begin() + static_cast<std::ptrdiff_t>(active));
  fieldSupports_.clear();
  fieldPeaks_.clear();
  for (size_t i = 0; i < active; ++i)
    fieldSupports_.push_back(model.operations()[i].support()), fieldPeaks_.push_back(peakOf(model.operations()[i].op()));
}

void Renderer::recomputeField(const Model& model, const HeightField::SampleRect& rIn) {
  const HeightField::SampleRect r = field_.clamp(rIn);
  if (r.empty()) return;
  const auto& ops = model.operations();
  auto work = [&](const Rect& t) {
    const HeightField::SampleRect tr{t.x, t.y, t.x + t.w - 1, t.y + t.h - 1};
    thread_local std::vector<std::uint32_t> scratch;
    thread_local std::vector<const PreparedOp*> list;
    const Box2 box{field_.sampleX(tr.i0), field_.sampleY(tr.j0), field_.sampleX(tr.i1), field_.sampleY(tr.j1)};
    list.clear();
    for (std::uint32_t i : grid_.in(box, scratch))
      if (ops[i].op().isOffset()) list.push_back(&ops[i]);
    field_.recompute(tr, list);
  };
  const Rect whole{r.i0, r.j0, r.i1 - r.i0 + 1, r.j1 - r.j0 + 1};
  if (whole.w <= kRecomputeTile && whole.h <= kRecomputeTile)
    work(whole);
  else
    pool_.parallelFor2D(whole, kRecomputeTile, work);
}

void Renderer::syncField(const Model& model) {
  if (!fieldReady_ || fieldWorkpiece_.get() != &model.workpiece()) {
    rebuildField(model);
    return;
  }
  const auto& ops = model.operations();
  const auto& ids = model.operationIds();
  const size_t active = model.activeCount();
  if (pending_.active) {
    // The model changed while an append was being added a band at a time. Standing, its other
    // rows first (every sample's sum stays in index order); undone or replaced, the paths below
    // put back or sum again the samples under it, its rows added so far and the rest alike.
    if (pending_.index < active && ids[pending_.index] == pending_.id && pending_.index + 1 == fieldIds_.size() &&
        fieldIds_.back() == pending_.id) {
      auto values = pending_.share ? std::make_shared<HeightField::OffsetValues>() : nullptr;
      const HeightField::SampleRect rest = addPendingRows(std::numeric_limits<double>::infinity(), values.get());
      const Box2 box = bandBox(rest);
      lastSync_.samplesUpdated += rest.count();
      fieldChanges_.push_back({.append = true, .index = static_cast<std::uint32_t>(pending_.index), .region = box, .peak = pending_.peak,
                               .band = true, .rows = bandRows(rest), .values = std::move(values)});
      lastSync_.pendingRows = box, lastSync_.pendingPeak = pending_.peak;
    }
    pending_.active = false;
  }
  size_t p = 0;
  while (p < fieldIds_.size() && p < active && fieldIds_[p] == ids[p]) ++p;
  // Appends each add their kernel to the samples under their support, continuing every sample's
  // sum in index order. The samples under the last one are saved first (see below). `appended`:
  // the set operations' shift fields add them too (else they sum the regions again).
  auto append = [&](size_t from, bool appended) {
    for (size_t i = from; i < active; ++i) {
      const PreparedOp& op = ops[i];
      if (op.op().isOffset()) {
        const HeightField::SampleRect r = field_.samplesIn(op.support());
        if (i + 1 == active) {
          field_.save(r, saved_.samples);
          saved_.id = ids[i];
          saved_.valid = true;
        }
        // Under set operations its values are found once, for their shift fields too.
        const auto under = [&](const SetOp& s) { return s.shift && s.shift->configured() && s.shift->domain().overlaps(op.support()); };
        const bool share = r.count() <= kSharedValuesMaxSamples && std::any_of(setOps_.begin(), setOps_.end(), under);
        auto values = share ? std::make_shared<HeightField::OffsetValues>() : nullptr;
        FieldChange change{.append = appended, .index = static_cast<std::uint32_t>(i), .region = op.support(), .peak = peakOf(op.op()),
                           .op = &op, .afterUndo = !appended};
        if (i + 1 == active && op.op().kind == OpKind::Region && options_.fieldBandMs > 0 && r.count() > kFieldBandMinSamples &&
            usesField()) {
          // A big raised region: its first rows now, the rest by continueField(). (Only regions:
          // a stroke's live preview is replaced at every pen event, and must show whole.) The
          // shift fields follow it a band at a time.
          pending_ = {true, ids[i], i, r, r.j0, peakOf(op.op()), share};
          const HeightField::SampleRect done = addPendingRows(options_.fieldBandMs, values.get());
          lastSync_.samplesUpdated += done.count();
          change.band = true, change.rows = bandRows(done);
        } else {
          field_.add(op, field_.all(), &pool_, values.get());
          field_.finish(r, &pool_);
          lastSync_.samplesUpdated += r.count();
        }
        change.values = std::move(values);
        fieldChanges_.push_back(std::move(change));
      }
      fieldIds_.push_back(ids[i]);
      fieldSupports_.push_back(op.support());
      fieldPeaks_.push_back(peakOf(op.op()));
    }
  };
  if (p == fieldIds_.size()) {
    append(p, true);  // a new stroke, a redo
    return;
  }
  // The last offset undone or replaced (a stroke's live preview growing under the pen): its
  // samples go back to what they were before it, and what follows is appended, the same sums in
  // the same order as a full build, without summing the area again over every operation there.
  if (p + 1 == fieldIds_.size() && saved_.valid && saved_.id == fieldIds_.back()) {
    saved_.valid = false;
    field_.restore(saved_.samples);
    const HeightField::SampleRect old = saved_.samples.r;
    // (The operation undone is still the model's, at index p, until another replaces it.)
    fieldChanges_.push_back({.append = false, .index = 0, .region = fieldSupports_.back(), .peak = fieldPeaks_.back(),
                             .op = p < ops.size() && ids[p] == fieldIds_.back() ? &ops[p] : nullptr, .undoneId = fieldIds_.back()});
    fieldIds_.pop_back();
    fieldSupports_.pop_back();
    fieldPeaks_.pop_back();
    append(p, false);
    field_.finish(old, &pool_);
    lastSync_.samplesUpdated += old.count();
    return;
  }
  saved_.valid = false;
  // Operations removed (undo) or replaced: the samples under them are summed again from 0.0 over
  // the active offsets, in index order, as a full build does.
  std::vector<HeightField::SampleRect> regions;
  long total = 0;
  auto note = [&](const Box2& support, double peak, const PreparedOp* op) {
    fieldChanges_.push_back({false, 0, support, peak, op});
    const HeightField::SampleRect r = field_.samplesIn(support);
    if (r.empty()) return;
    regions.push_back(r);
    total += r.count();
  };
  for (size_t i = p; i < fieldIds_.size(); ++i)
    note(fieldSupports_[i], fieldPeaks_[i], i < ops.size() && ids[i] == fieldIds_[i] ? &ops[i] : nullptr);
  for (size_t i = p; i < active; ++i)
    if (ops[i].op().isOffset()) note(ops[i].support(), peakOf(ops[i].op()), &ops[i]);
  if (total > field_.all().count() / 4) {
    rebuildField(model);
    return;
  }
  for (const auto& r : regions) {
    recomputeField(model, r);
    field_.finish(r, &pool_);
    lastSync_.samplesUpdated += r.count();
  }
  fieldIds_.assign(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(active));
  fieldSupports_.resize(p);
  fieldPeaks_.resize(p);
  for (size_t i = p; i < active; ++i) fieldSupports_.push_back(ops[i].support()), fieldPeaks_.push_back(peakOf(ops[i].op()));
}

double Renderer::peakOf(const Operation& o) const {
  switch (o.kind) {
    case OpKind::Trace: return o.a;
    case OpKind::Punch: return std::abs(o.p) * o.a;
    case OpKind::Press: return std::abs(o.p) * o.a * 17.0;
    case OpKind::Region: return std::abs(o.height);
    default: return 0.0;
  }
}

void Renderer::syncSetOps(const Model& model) {
  std::vector<SetOp> old;
  old.swap(setOps_);
  size_t reuse = 0;
  const auto& ops = model.operations();
  const auto& ids = model.operationIds();
  const size_t active = model.activeCount();
  // Each group's shift field (below), kept (following the field's changes) or made afresh; the
  // fields are independent, so they are brought up to date in parallel (an offset appended over
  // set operations changes several).
  size_t lastOffset = 0;  // (one past the last offset)
  for (size_t i = 0; i < active; ++i) {
    if (ops[i].op().isOffset()) lastOffset = i + 1;
    const PreparedOp& op = ops[i];
    if (!op.op().isSet()) continue;
    SetOp s;
    s.index = static_cast<std::uint32_t>(i);
    s.id = ids[i];
    s.support = op.support();
    s.upper = SetOpUpper(op.op());
    bool sameRun = !setOps_.empty();
    for (size_t j = sameRun ? setOps_.back().index + 1 : i; sameRun && j < i; ++j) sameRun = !ops[j].op().isOffset();
    s.run = sameRun ? setOps_.back().run : static_cast<std::uint32_t>(setOps_.size());
    setOps_.push_back(std::move(s));
  }
  // The set operations of a run whose windows (support and a sample round it) crowd together
  // share one shift field over the box of their windows: they hold the same bits there (SetOp::
  // shift), so an offset under a pile of them is added to one field, not to each of its dozens.
  // A run's next operation joins the group before it while the group's box stays within
  // kShiftShareSlack times the area of its members' windows (a pile, not a trail across the
  // sheet). A run that no offset follows yet (a visitor still beating the background) has no
  // shift: each of its operations keeps a field of its own, all zeros, whose next member costs
  // nothing to the others; the first offset after it groups them.
  const double spacing = field_.spacing();
  std::vector<Box2> groupBox(setOps_.size());  // at each group's first member (its owner)
  {
    std::vector<bool> closed(setOps_.size(), false);  // at a run's first member: an offset follows the run
    for (const SetOp& s : setOps_) closed[s.run] = s.index < lastOffset;
    size_t g = 0;
    double windows = 0.0;
    const auto area = [](const Box2& b) { return (b.x1 - b.x0) * (b.y1 - b.y0); };
    for (size_t k = 0; k < setOps_.size(); ++k) {
      const Box2 w = setOps_[k].support.grown(spacing);
      bool join = k > 0 && setOps_[k].run == setOps_[g].run && closed[setOps_[k].run];
      if (join) {
        Box2 u = groupBox[g];
        u.extend(w.x0, w.y0), u.extend(w.x1, w.y1);
        join = area(u) <= kShiftShareSlack * (windows + area(w));
        if (join) groupBox[g] = u, windows += area(w);
      }
      if (!join) g = k, groupBox[g] = w, windows = area(w);
      setOps_[k].owner = static_cast<std::uint32_t>(g);
    }
    for (size_t k = 0; k < setOps_.size(); ++k)
      if (setOps_[k].owner != k) setOps_[k].sharesShift = setOps_[setOps_[k].owner].sharesShift = true;
  }
  // A group is kept when the one before had the same members (its owner's field, saved samples).
  std::vector<bool> kept(setOps_.size(), false);
  for (size_t k = 0; k < setOps_.size(); ++k) {
    SetOp& s = setOps_[k];
    if (s.owner != k) {
      s.shift = setOps_[s.owner].shift;
      continue;
    }
    while (reuse < old.size() && old[reuse].id != s.id) ++reuse;
    bool keep = fieldReady_ && !lastSync_.rebuilt && reuse < old.size() && old[reuse].shift && old[reuse].owner == reuse;
    if (keep) {  // the same members, in order, and no other
      size_t n = k + 1;
      while (n < setOps_.size() && setOps_[n].owner == k) ++n;
      for (size_t m = k; m < n && keep; ++m) {
        const size_t o = reuse + (m - k);
        keep = o < old.size() && old[o].id == setOps_[m].id && old[o].owner == reuse;
      }
      const size_t after = reuse + (n - k);
      keep = keep && (after >= old.size() || old[after].owner != reuse);
    }
    if (keep) s.shift = old[reuse].shift, s.saved = old[reuse].saved, s.savedId = old[reuse].savedId;
    else if (fieldReady_) s.shift = std::make_shared<HeightField>();
    kept[k] = keep;
  }
  std::vector<Box2> supports;
  for (const SetOp& s : setOps_) supports.push_back(s.support);
  setOpSupports_.build(std::move(supports));
  // The offsets at index `from` or after that may reach a box, ascending.
  const auto offsetsIn = [&](const Box2& box, std::vector<std::uint32_t>& scratch, std::uint32_t from) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t j : grid_.in(box, scratch, from))
      if (ops[j].op().isOffset()) out.push_back(j);
    return out;
  };
  // Those of each recomputed region: the same for every shift field under it (found once, not
  // once a field).
  std::vector<std::vector<std::uint32_t>> inRegion(fieldChanges_.size());
  {
    std::vector<std::uint32_t> scratch;
    for (size_t c = 0; c < fieldChanges_.size(); ++c) {
      const FieldChange& fc = fieldChanges_[c];
      if (!fc.append && !setOps_.empty()) inRegion[c] = offsetsIn(fc.region, scratch, setOps_.front().index + 1);
    }
  }
  if (!setOps_.empty()) {
    pool_.parallelFor2D(Rect{0, 0, static_cast<int>(setOps_.size()), 1}, 1, [&](const Rect& t) {
      std::vector<std::uint32_t> scratch;
      std::vector<const PreparedOp*> list;
      for (int k = t.x; k < t.x + t.w; ++k) {
        SetOp& s = setOps_[static_cast<size_t>(k)];
        if (!s.shift || s.owner != static_cast<std::uint32_t>(k)) continue;
        if (kept[static_cast<size_t>(k)]) {
          followFieldChanges(s, fieldChanges_, inRegion, list);
          continue;
        }
        // Made afresh: the offsets after it, and the rows of the pending append added so far.
        // None (a run no offset follows yet): every sample is zero.
        HeightField& f = *s.shift;
        f.configureOn(field_, groupBox[static_cast<size_t>(k)]);
        const auto after = offsetsAfter(s.index, offsetsIn(f.domain(), scratch, s.index + 1), list);
        const bool rows = pending_.active && pending_.index > s.index;
        if (after.empty() && !rows) {
          f.finishFlat();
          continue;
        }
        // Flat, then the offsets after it added where they reach and finished there: the bits that
        // summing every sample again and finishing all() give, without visiting the samples none
        // of them reaches (a pile's field, made when the first offset follows the pile, spans the
        // pile; that offset, as a rule, is a stroke across part of it).
        f.finishFlat();
        HeightField::SampleRect touched;
        for (const PreparedOp* op : after) {
          f.add(*op, f.all());
          touched = HeightField::unite(touched, f.samplesIn(op->support()));
        }
        if (rows) {
          const HeightField::SampleRect& r = pending_.r;
          const HeightField::SampleRect band = f.fromLattice(bandRows({r.i0, r.j0, r.i1, pending_.nextRow - 1}));
          f.add(ops[pending_.index], band);
          touched = HeightField::unite(touched, HeightField::intersect(f.samplesIn(ops[pending_.index].support()), band));
        }
        f.finish(touched);
      }
    });
  }
  refreshSetOpRanges();
  lastSync_.shiftSamplesShared += shiftShared_.exchange(0), lastSync_.shiftSamplesComputed += shiftComputed_.exchange(0);
  if (fieldReady_) updateFieldClip(model);
}

std::span<const PreparedOp* const> Renderer::offsetsAfter(size_t i, std::span<const std::uint32_t> candidates,
                                                          std::vector<const PreparedOp*>& list) const {
  const auto& ops = model_->operations();
  list.clear();
  for (auto it = std::upper_bound(candidates.begin(), candidates.end(), static_cast<std::uint32_t>(i)); it != candidates.end(); ++it)
    if (!(pending_.active && *it == pending_.index)) list.push_back(&ops[*it]);
  return list;
}

void Renderer::followFieldChanges(SetOp& s, std::span<const FieldChange> changes,
                                  std::span<const std::vector<std::uint32_t>> inRegion, std::vector<const PreparedOp*>& list) {
  long shared = 0, computed = 0;
  // Appended offsets add (their values found once on the field's lattice, where they were kept),
  // recomputed regions are summed again, or put back where the field's last append was undone
  // and this field saved its samples under it. The pending append's rows come as the field's do.
  const auto& ops = model_->operations();
  const auto& ids = model_->operationIds();
  const size_t active = model_->activeCount();
  HeightField& f = *s.shift;
  const size_t i = s.index;
  auto addRows = [&](const FieldChange& c) {
    const PreparedOp& op = ops[c.index];
    const HeightField::SampleRect rows = c.band ? f.fromLattice(c.rows) : f.all();
    const HeightField::SampleRect r = HeightField::intersect(f.samplesIn(op.support()), rows);
    if (c.values && f.add(op, *c.values, rows)) {
      shared += r.count();
    } else {
      f.add(op, rows);
      computed += r.count();
    }
    return r;
  };
  bool putBack = false;
  for (size_t ci = 0; ci < changes.size(); ++ci) {
    const FieldChange& c = changes[ci];
    // (The field's lattice reaches up to a sample past the set operation's support: those
    // samples shape the patches inside it.)
    if (!c.region.overlaps(f.domain())) continue;
    HeightField::SampleRect r = f.samplesIn(c.region);
    if (r.empty() && !c.band) continue;
    if (c.undoneId != 0 && s.savedId == c.undoneId) {
      f.restore(*s.saved);
      r = s.saved->r;
      s.savedId = 0;
      putBack = true;
    } else if (c.append || (c.afterUndo && putBack)) {
      if (c.index <= i) continue;
      // (Not a big region's band: a live preview replaced at the next pen event is a stroke.)
      if (c.index + 1 == active && !c.band) {
        if (!s.saved) s.saved = std::make_shared<HeightField::Saved>();
        f.save(HeightField::intersect(f.samplesIn(ops[c.index].support()), f.all()), *s.saved);
        s.savedId = ids[c.index];
      }
      r = addRows(c);
    } else {
      const std::span<const std::uint32_t> candidates = ci < inRegion.size() ? inRegion[ci] : std::span<const std::uint32_t>();
      f.recompute(r, offsetsAfter(i, candidates, list));
      // The pending append's own rows, where this is it (after an undo this field could not put back).
      if (c.band && c.index > i && pending_.active && c.index == pending_.index) addRows(c);
    }
    if (!r.empty()) f.finish(r);
  }
  shiftShared_ += shared, shiftComputed_ += computed;
}

void Renderer::followFieldChanges(std::span<const FieldChange> changes, std::span<const std::vector<std::uint32_t>> inRegion) {
  if (setOps_.empty()) return;
  pool_.parallelFor2D(Rect{0, 0, static_cast<int>(setOps_.size()), 1}, 1, [&](const Rect& t) {
    std::vector<const PreparedOp*> list;
    for (int k = t.x; k < t.x + t.w; ++k)
      if (SetOp& s = setOps_[static_cast<size_t>(k)]; s.shift && s.owner == static_cast<std::uint32_t>(k))
        followFieldChanges(s, changes, inRegion, list);
  });
  refreshSetOpRanges();
  lastSync_.shiftSamplesShared += shiftShared_.exchange(0), lastSync_.shiftSamplesComputed += shiftComputed_.exchange(0);
}

void Renderer::refreshSetOpRanges() {
  for (SetOp& s : setOps_) {
    const Operation& o = model_->operations()[s.index].op();
    // (A field shared with others reaches past this one's window: bounded over the window.)
    const HeightField::Bound shift = !s.shift         ? HeightField::Bound{}
                                     : s.sharesShift ? s.shift->leafBound(s.support.grown(s.shift->spacing()))
                                                     : s.shift->rootBound();
    const Box3 tb = o.tool.bounds();
    const double reach = kernels::kSupportSpan * o.tool.size();
    s.zlo = tb.z0 - reach + shift.lo;
    s.zhi = tb.z1 + reach + shift.hi;
    const double margin = 1e-9 * (1.0 + std::max(std::abs(tb.z0), std::abs(tb.z1)) + reach);
    s.toolZlo = tb.z0 - reach - margin, s.toolZhi = tb.z1 + reach + margin;
    s.hair = 1e-6 * (1.0 + std::max({std::abs(s.support.x0), std::abs(s.support.x1), std::abs(s.support.y0),
                                     std::abs(s.support.y1), std::abs(s.zlo), std::abs(s.zhi)}));
    s.round = o.tool.type == ToolShape::Type::Sphere;
    if (s.round) {
      // combine() is the identity where the distance from the tool's surface, |p' - c| - r with p'
      // the point less the shift, is kSupportSpan tool sizes or more.
      s.cx = o.tool.center.x, s.cy = o.tool.center.y;
      s.czlo = o.tool.center.z + shift.lo, s.czhi = o.tool.center.z + shift.hi;
      s.radius = o.tool.r + reach + margin;
    }
    s.nearRadius = 0.0, s.farRaise = std::numeric_limits<double>::infinity();
    if (s.round)
      if (const std::optional<BallFar> far = ballFarBound(o, s.radius)) s.nearRadius = far->nearRadius, s.farRaise = far->raise;
  }
}

void Renderer::updateFieldClip(const Model& model) {
  // Every surface of the field tracer's function: the workpiece moved by the field's range, and
  // the set operations' boxes.
  const Box3 wb = model.workpiece().bounds();
  const HeightField::Bound r = field_.rootBound();
  Box3 clip{wb.x0, wb.y0, wb.z0 + r.lo, wb.x1, wb.y1, wb.z1 + r.hi};
  for (const SetOp& s : setOps_) clip = unite(clip, Box3{s.support.x0, s.support.y0, s.zlo, s.support.x1, s.support.y1, s.zhi});
  const double m = 1e-6 * (1.0 + std::max({std::abs(clip.x0), std::abs(clip.x1), std::abs(clip.y0), std::abs(clip.y1)}));
  fieldClip_ = {clip.x0 - m, clip.y0 - m, clip.z0 - m, clip.x1 + m, clip.y1 + m, clip.z1 + m};
}

HeightField::SampleRect Renderer::addPendingRows(double budgetMs, HeightField::OffsetValues* keep) {
  // The rows of the operation (each sample the bits a whole add() gives it: a row's lanes are the
  // same whatever the band), then finish() over them: the twists, leaves and cavities around the
  // rows read the rows beside them, so the rows of the band before are refreshed again and the
  // last band leaves every one as a whole add() and finish() do. First kMinRows rows, then as many
  // more as the time they took says fit in the budget (finish() costs about 0.7 of the adding), at
  // most doubling the rows each time.
  constexpr int kMinRows = 8;
  const HeightField::SampleRect& r = pending_.r;
  const PreparedOp& op = model_->operations()[pending_.index];
  const auto t0 = std::chrono::steady_clock::now();
  HeightField::SampleRect done{r.i0, pending_.nextRow, r.i1, pending_.nextRow - 1};
  int rows = kMinRows;
  while (done.j1 < r.j1) {
    const HeightField::SampleRect band{r.i0, done.j1 + 1, r.i1, std::min(r.j1, done.j1 + rows)};
    field_.add(op, band, &pool_, keep);
    done.j1 = band.j1;
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const int n = done.j1 - done.j0 + 1;
    const double perRow = ms / n, left = budgetMs / 1.7 - ms;
    if (!(left >= kMinRows * perRow)) break;
    // (At most as many rows again: a region's first rows, mostly outside its contour, can cost
    // a fraction of those through its middle.)
    rows = static_cast<int>(std::min({left / perRow, 1e6, static_cast<double>(n)}));
  }
  field_.finish(done, &pool_);
  pending_.nextRow = done.j1 + 1;
  if (pending_.nextRow > r.j1) pending_.active = false;
  return done;
}

HeightField::SampleRect Renderer::bandRows(const HeightField::SampleRect& band) const {
  constexpr int kFar = 1 << 29;
  const HeightField::SampleRect l = field_.toLattice(band);
  return {-kFar, band.j0 <= pending_.r.j0 ? -kFar : l.j0, kFar, band.j1 >= pending_.r.j1 ? kFar : l.j1};
}

Box2 Renderer::bandBox(const HeightField::SampleRect& band) const {
  // (The shift fields' samples past the field's, where the append's support reaches there.)
  const Box2 s = model_->operations()[pending_.index].support();
  Box2 b{field_.sampleX(band.i0), field_.sampleY(band.j0), field_.sampleX(band.i1), field_.sampleY(band.j1)};
  b.x0 = std::min(b.x0, s.x0), b.x1 = std::max(b.x1, s.x1);
  if (band.j0 <= pending_.r.j0) b.y0 = std::min(b.y0, s.y0);
  if (band.j1 >= pending_.r.j1) b.y1 = std::max(b.y1, s.y1);
  return b;
}

PixelSpans Renderer::continueField(double budgetMs) {
  if (!pending_.active) return {};
  if (!model_ || pending_.index >= model_->activeCount() || model_->operationIds()[pending_.index] != pending_.id) {
    pending_.active = false;  // (sync() was not called after the model changed: it will see to it)
    return {};
  }
  auto values = pending_.share ? std::make_shared<HeightField::OffsetValues>() : nullptr;
  const size_t index = pending_.index;
  const HeightField::SampleRect band = addPendingRows(budgetMs, values.get());
  // The shift fields under the band follow it; the kept hits it can move are forgotten, and the
  // box of every surface found again.
  const Box2 box = bandBox(band);
  const std::vector<FieldChange> changes{{.append = true, .index = static_cast<std::uint32_t>(index), .region = box, .peak = pending_.peak,
                                          .band = true, .rows = bandRows(band), .values = std::move(values)}};
  followFieldChanges(changes, {});
  forgetHitsNear(changes);
  refreshPileTops(false, {box});
  updateFieldClip(*model_);
  return fieldRowsSpans(box, pending_.peak);
}

PixelSpans Renderer::pendingSpans() const {
  return lastSync_.pendingRows.empty() ? PixelSpans{} : fieldRowsSpans(lastSync_.pendingRows, lastSync_.pendingPeak);
}

PixelSpans Renderer::fieldRowsSpans(const Box2& box, double peak) const {
  if (!camera_ || !model_) return {};
  // As dirtySpans() for an offset: the samples' stencil, a ray cell, the shading's reach and a
  // pixel for the anti-aliasing.
  const double cell = step_ + 1e-6;
  const Box3 reach = offsetReach(model_->workpiece().bounds(), box, 2.0 * std::sqrt(2.0) * field_.spacing() + cell + kCavityReach, peak);
  return PixelSpans::of(projectBox(reach)).grown(1, camera_->width(), camera_->height());
}

}  // namespace emboss
