// The visitor's bench: strokes into operations, undo by strokes, tools, metals and turning the piece.
#include "app/workbench.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "frep/workpieces.h"

namespace emboss {

namespace {
constexpr double kTurnSeconds = 0.9;
constexpr double kTurnAzimuth = -25.0;   // degrees the piece turns (its right side toward the visitor)
constexpr double kTurnElevation = 50.0;  // a raking view: the relief stands out, the lights do not glare
constexpr size_t kFirstTool = 1;         // a visitor starts with the middle tracer: a clear line at once
}  // namespace

double benchSideRoom(int height) { return 186.0 * height / 800.0; }

CameraSpec benchCamera(const Box3& b, int width, int height, double fill, double sideRoom) {
  CameraSpec c = defaultCamera(b);
  Orbit o = orbitOf(c);
  o.azimuthDeg = 0;
  o.elevationDeg = 68;
  for (int i = 0; i < 4; ++i) {
    const CameraSpec s = cameraAt(o, c);
    const ScreenBox r = sheetOnScreen(Camera(s, width, height), b);
    const double k = std::max(r.h / (fill * height), r.w / std::min(fill * width, width - 2 * sideRoom));
    if (!(k > 0) || !std::isfinite(k)) break;
    o.distance *= k;
  }
  c = cameraAt(o, c);
  // Centre the sheet (the view from below shifts it down the screen).
  const ScreenBox r = sheetOnScreen(Camera(c, width, height), b);
  const double dy = (r.y + 0.5 * r.h) - 0.5 * height;
  const double mmPerPx = (2.0 * o.distance * std::tan(0.5 * c.fovDeg * M_PI / 180.0)) / height;
  o.target.y -= dy * mmPerPx * 0.9;
  return cameraAt(o, c);
}

Workbench::Workbench(BenchSetup setup) : setup_(std::move(setup)) {
  if (!setup_.workpiece) setup_.workpiece = std::make_shared<Plate>(60.0, 40.0, 0.5);
  model_ = std::make_unique<Model>(setup_.workpiece, setup_.deformation);
  tool_ = kFirstTool;
  metal_ = metalByName(setup_.metal).value_or(metals()[0]);
  home_ = benchCamera(setup_.workpiece->bounds(), setup_.width, setup_.height, 0.78, benchSideRoom(setup_.height));
  homeOrbit_ = orbitOf(home_);
  turnedOrbit_ = homeOrbit_;
  turnedOrbit_.azimuthDeg += kTurnAzimuth;
  turnedOrbit_.elevationDeg = kTurnElevation;
  turnedOrbit_.distance *= 1.1;  // a step back: the turned sheet stays on the screen
  current_ = home_;
  fromOrbit_ = toOrbit_ = homeOrbit_;
  refreshMapping();
}

ToolSpec Workbench::tool() const {
  ToolSpec t = toolCatalogue()[tool_ % toolCatalogue().size()];
  t.size *= std::pow(1.25, sizeStep_);
  return t;
}

ShadingParams Workbench::shading() const {
  ShadingParams s;
  s.metal = metal_;
  s.tinge = tinges()[0];
  s.frontZ = setup_.workpiece->bounds().z1;
  return s;
}

Scene Workbench::scene(const std::string& title) const {
  Scene s;
  s.deformation = setup_.deformation;
  s.workpiece = setup_.workpiece;
  s.metal = std::string(metal_.name);
  s.camera = home_;
  s.cameraGiven = true;
  s.title = title;
  return s;
}

void Workbench::refreshMapping() {
  camera_.emplace(current_, setup_.width, setup_.height);
  tabletArea_ = emboss::tabletArea(sheetOnScreen(*camera_, setup_.workpiece->bounds()), setup_.tabletAspect);
}

void Workbench::resetForVisitor(double now) {
  tool_ = kFirstTool;
  sizeStep_ = 0;
  metal_ = metalByName(setup_.metal).value_or(metals()[0]);
  newSheet(now);
}

void Workbench::newSheet(double now) {
  stroke_.end();
  strokeOpen_ = false;
  model_->clear();
  strokes_.clear();
  redo_.clear();
  strokesMade_ = 0;
  turned_ = false;
  animating_ = false;
  current_ = home_;
  fromOrbit_ = toOrbit_ = homeOrbit_;
  refreshMapping();
  hover_ = {};
  changes_ = {};
  changes_.full = true;
}

void Workbench::apply(Action action, double now) {
  switch (action) {
    case Action::NextTool:
      endStroke();
      tool_ = (tool_ + 1) % toolCatalogue().size();
      break;
    case Action::PrevTool:
      endStroke();
      tool_ = (tool_ + toolCatalogue().size() - 1) % toolCatalogue().size();
      break;
    case Action::SizeUp:
      endStroke();
      sizeStep_ = std::min(kMaxSizeStep, sizeStep_ + 1);
      break;
    case Action::SizeDown:
      endStroke();
      sizeStep_ = std::max(kMinSizeStep, sizeStep_ - 1);
      break;
    case Action::NextMetal: {
      endStroke();
      const auto& all = metals();
      size_t i = 0;
      while (i < all.size() && all[i].name != metal_.name) ++i;
      metal_ = all[(i + 1) % all.size()];
      changes_.full = true;  // the whole sheet changes colour
      break;
    }
    case Action::Undo:
      endStroke();
      if (!strokes_.empty()) {
        const size_t n = strokes_.back();
        strokes_.pop_back();
        undoOps(n);
        redo_.push_back(n);
      }
      break;
    case Action::Redo:
      endStroke();
      if (!redo_.empty()) {
        const size_t n = redo_.back();
        redo_.pop_back();
        size_t done = 0;
        for (; done < n && model_->redo(); ++done) changes_.ops.push_back(model_->activeCount() - 1);
        if (done) strokes_.push_back(done);
      }
      break;
    case Action::Turn:
      endStroke();
      setView(!turned_, now);
      break;
    case Action::NewSheet: newSheet(now); break;
    case Action::None:
    case Action::Capture:
    case Action::Staff:
    case Action::Quit: break;
  }
}

void Workbench::setView(bool turned, double now) {
  // From wherever the camera is now (a turn may be reversed half way).
  fromOrbit_ = orbitOf(current_);
  fromOrbit_.target = homeOrbit_.target;
  toOrbit_ = turned ? turnedOrbit_ : homeOrbit_;
  turned_ = turned;
  animating_ = true;
  animStart_ = now;
}

void Workbench::update(double now) {
  if (!animating_) return;
  const double t = (now - animStart_) / kTurnSeconds;
  if (t >= 1.0) {
    animating_ = false;
    current_ = cameraAt(toOrbit_, home_);
    if (!turned_) current_ = home_;  // exactly home, so the blank-sheet picture can be reused
  } else {
    current_ = cameraAt(mix(fromOrbit_, toOrbit_, easeInOut(t)), home_);
  }
  refreshMapping();
  changes_.camera = true;
}

void Workbench::pen(double sx, double sy, double pressure, bool tip, bool inRange, double now) {
  pressure_ = tip ? std::clamp(pressure, 0.0, 1.0) : 0.0;
  if (!tip && !inRange) {
    penAway();
    return;
  }
  std::optional<glm::dvec3> hit;
  if (!picker_ || !picker_(*model_, *camera_, sx, sy, hit)) hit = pickSurface(*model_, *camera_, sx, sy);
  if (!hit) {
    hover_ = {};
    endStroke();  // off the metal: the stroke ends at its edge
    return;
  }
  const ToolSpec t = tool();
  hover_.visible = true;
  hover_.touching = tip;
  hover_.sx = sx, hover_.sy = sy;
  if (const auto p = camera_->project(*hit)) hover_.sx = p->x, hover_.sy = p->y;
  hover_.radius = std::max(3.0, projectedRadius(*camera_, *hit, 0.5 * t.size));
  if (!tip) {
    endStroke();
    return;
  }
  if (!stroke_.active()) stroke_.begin(t, metal_);
  commit(stroke_.add({hit->x, hit->y, hit->z, pressure_}));
}

void Workbench::penAway() {
  hover_ = {};
  pressure_ = 0;
  endStroke();
}

void Workbench::endStroke() {
  if (!stroke_.active()) return;
  const size_t handed = stroke_.handedOut();
  const auto f = stroke_.end();
  if (f.keep < handed) {
    // Never expected (the builder hands out only settled operations), but if it happened the
    // model must still hold exactly the stroke's operations.
    const size_t back = handed - f.keep;
    for (size_t i = 0; i < back && model_->undo(); ++i) changes_.ops.push_back(model_->activeCount());
    if (strokeOpen_ && !strokes_.empty()) {
      strokes_.back() -= std::min(strokes_.back(), back);
      if (strokes_.back() == 0) strokes_.pop_back(), strokeOpen_ = false;
    }
  }
  // The rest belongs to the same stroke as the operations already handed out.
  const size_t before = model_->activeCount();
  for (const auto& op : f.rest)
    if (admit(op) && model_->add(op)) changes_.ops.push_back(model_->activeCount() - 1), ++committed_;
  const size_t added = model_->activeCount() - before;
  if (added) {
    if (strokeOpen_ && !strokes_.empty()) strokes_.back() += added;
    else strokes_.push_back(added);
    redo_.clear();
  }
  if (added || strokeOpen_) ++strokesMade_;
  strokeOpen_ = false;
}

namespace {

// A flat punch's strike: a region lowered from the front (the region raiser works from behind).
bool isStrike(const Operation& o) { return o.kind == OpKind::Region && o.side == Side::Front && o.points.size() >= 3; }

Vec2 centroid(const std::vector<Vec2>& pts) {
  Vec2 c;
  for (const auto& p : pts) c.x += p.x, c.y += p.y;
  return {c.x / pts.size(), c.y / pts.size()};
}

}  // namespace

bool Workbench::admit(const Operation& op) const {
  const auto& ops = model_->operations();
  int covering = 0;
  if (isStrike(op)) {
    const Vec2 c = centroid(op.points);
    for (size_t i = 0; i < model_->activeCount(); ++i)
      if (isStrike(ops[i].op()) && ops[i].insideRegion(c.x, c.y) && ++covering >= kMaxStrikesOnASpot) return false;
    return true;
  }
  if (op.kind != OpKind::BlendUnion && op.kind != OpKind::BlendSubtract) return true;
  const Vec3& c = op.tool.center;
  for (size_t i = 0; i < model_->activeCount(); ++i) {
    const Operation& o = ops[i].op();
    if (o.isOffset() || o.kind == OpKind::Patina) continue;
    const Box3 b = o.tool.bounds();
    if (c.x >= b.x0 && c.x <= b.x1 && c.y >= b.y0 && c.y <= b.y1 && ++covering >= kMaxBlendsOnASpot) return false;
  }
  return true;
}

void Workbench::commit(const std::vector<Operation>& ops) {
  size_t added = 0;
  for (const auto& op : ops)
    if (admit(op) && model_->add(op)) changes_.ops.push_back(model_->activeCount() - 1), ++added, ++committed_;
  if (!added) return;
  redo_.clear();
  if (strokeOpen_) strokes_.back() += added;
  else strokes_.push_back(added), strokeOpen_ = true;
}

size_t Workbench::addStroke(const std::vector<Operation>& ops) {
  endStroke();
  const size_t before = model_->activeCount();
  commit(ops);
  strokeOpen_ = false;
  const size_t added = model_->activeCount() - before;
  if (added) ++strokesMade_;
  return added;
}

bool Workbench::restore(const std::vector<Operation>& ops, size_t cursor, std::vector<size_t> strokes, std::vector<size_t> redo,
                        const std::string& metal, std::uint64_t strokesMade) {
  stroke_.end();
  strokeOpen_ = false;
  model_->clear();
  bool all = true;
  for (const auto& op : ops)
    if (!model_->add(op)) all = false;
  const size_t n = model_->operations().size();
  cursor = std::min(cursor, n);
  while (model_->activeCount() > cursor && model_->undo()) {
  }
  size_t inStrokes = 0, inRedo = 0;
  for (size_t k : strokes) inStrokes += k;
  for (size_t k : redo) inRedo += k;
  if (inStrokes != cursor || inStrokes + inRedo > n) {
    strokes.assign(cursor, 1);
    redo.clear();
  }
  strokes_ = std::move(strokes);
  redo_ = std::move(redo);
  if (const auto m = metalByName(metal)) metal_ = *m;
  strokesMade_ = std::max<std::uint64_t>(strokesMade, strokes_.size());
  committed_ += model_->activeCount();
  changes_ = {};
  changes_.full = true;
  return all;
}

void Workbench::undoOps(size_t n) {
  for (size_t i = 0; i < n && model_->undo(); ++i) changes_.ops.push_back(model_->activeCount());
}

std::vector<std::pair<double, double>> Workbench::openContour() const {
  std::vector<std::pair<double, double>> out;
  if (!stroke_.active() || stroke_.tool().kind != ToolKind::RegionRaiser) return out;
  for (const auto& p : stroke_.points())
    if (const auto q = camera_->project({p.x, p.y, p.z})) out.emplace_back(q->x, q->y);
  return out;
}

ViewChanges Workbench::takeChanges() {
  ViewChanges c;
  std::swap(c, changes_);
  return c;
}

}  // namespace emboss
