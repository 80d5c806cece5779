// Reading and writing scene files (docs/scene-format.md), with messages that name the place.
#include "scene/scene.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "util/durable_file.h"

#include "frep/vm_model.h"
#include "frep/workpieces.h"
#include "tools/metal.h"

namespace emboss {

using nlohmann::json;

namespace {

// Thrown inside the parser only, caught in parseScene: a malformed file is one message, never a crash.
struct SceneError {
  std::string where, what;
};

[[noreturn]] void bad(const std::string& where, const std::string& what) { throw SceneError{where, what}; }

const json* find(const json& obj, const char* key) {
  auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

double number(const json& obj, const char* key, const std::string& where, std::optional<double> fallback = std::nullopt) {
  const json* v = find(obj, key);
  if (!v) {
    if (fallback) return *fallback;
    bad(where + "." + key, "missing (a number is required)");
  }
  if (!v->is_number()) bad(where + "." + key, "must be a number, not " + std::string(v->type_name()));
  const double d = v->get<double>();
  if (!std::isfinite(d)) bad(where + "." + key, "must be a finite number");
  return d;
}

double positive(const json& obj, const char* key, const std::string& where, std::optional<double> fallback = std::nullopt) {
  const double d = number(obj, key, where, fallback);
  if (!(d > 0.0)) bad(where + "." + key, "must be a positive number (mm)");
  return d;
}

// A number within [lo, hi] (unit: how the range is written in the message).
double ranged(const json& obj, const char* key, const std::string& where, double lo, double hi, const char* unit,
              std::optional<double> fallback = std::nullopt) {
  const double d = number(obj, key, where, fallback);
  if (!(d >= lo && d <= hi)) {
    std::ostringstream m;
    m << d << " is out of range: " << lo << " to " << hi << unit;
    bad(where + "." + key, m.str());
  }
  return d;
}
// A size in mm (kMinLengthMm to kMaxLengthMm, as an operation's).
double size(const json& obj, const char* key, const std::string& where, std::optional<double> fallback = std::nullopt) {
  return ranged(obj, key, where, kMinLengthMm, kMaxLengthMm, " mm", fallback);
}
// A camera may stand well away from the sheet.
constexpr double kMaxCameraDistanceMm = 100 * kMaxLengthMm;

// Each of v's components within +-limit.
Vec3 within(const Vec3& v, const std::string& where, double limit) {
  const double c[3] = {v.x, v.y, v.z};
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(c[i]) <= limit)) {
      std::ostringstream m;
      m << c[i] << " is out of range: " << -limit << " to " << limit << " mm";
      bad(where + "[" + std::to_string(i) + "]", m.str());
    }
  }
  return v;
}

std::string text(const json& obj, const char* key, const std::string& where, std::optional<std::string> fallback = std::nullopt) {
  const json* v = find(obj, key);
  if (!v) {
    if (fallback) return *fallback;
    bad(where + "." + key, "missing (a string is required)");
  }
  if (!v->is_string()) bad(where + "." + key, "must be a string, not " + std::string(v->type_name()));
  return v->get<std::string>();
}

std::vector<double> numbers(const json& v, const std::string& where, size_t n) {
  if (!v.is_array() || v.size() != n) bad(where, "must be an array of " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (size_t i = 0; i < n; ++i) {
    if (!v[i].is_number()) bad(where + "[" + std::to_string(i) + "]", "must be a number");
    out.push_back(v[i].get<double>());
    if (!std::isfinite(out.back())) bad(where + "[" + std::to_string(i) + "]", "must be a finite number");
  }
  return out;
}

Vec3 vec3(const json& obj, const char* key, const std::string& where, std::optional<Vec3> fallback = std::nullopt) {
  const json* v = find(obj, key);
  if (!v) {
    if (fallback) return *fallback;
    bad(where + "." + key, "missing ([x, y, z] is required)");
  }
  const auto n = numbers(*v, where + "." + key, 3);
  return {n[0], n[1], n[2]};
}

std::vector<Vec2> points(const json& obj, const char* key, const std::string& where) {
  const json* v = find(obj, key);
  if (!v) bad(where + "." + key, "missing (a list of [x, y] points is required)");
  if (!v->is_array()) bad(where + "." + key, "must be a list of [x, y] points");
  std::vector<Vec2> out;
  for (size_t i = 0; i < v->size(); ++i) {
    const auto n = numbers((*v)[i], where + "." + key + "[" + std::to_string(i) + "]", 2);
    out.push_back({n[0], n[1]});
  }
  if (out.empty()) bad(where + "." + key, "must hold at least one point");
  return out;
}

// A trace joint, {"dir": [x, y], "r": mm}; absent: none.
TraceJoin traceJoin(const json& obj, const char* key, const std::string& where) {
  const json* v = find(obj, key);
  if (!v) return {};
  const std::string w = where + "." + key;
  if (!v->is_object()) bad(w, "must be an object {\"dir\": [x, y], \"r\": mm}");
  TraceJoin j;
  const json* d = find(*v, "dir");
  if (!d) bad(w + ".dir", "missing ([x, y] is required)");
  const auto n = numbers(*d, w + ".dir", 2);
  if (std::hypot(n[0], n[1]) <= 1e-12) bad(w + ".dir", "must not be zero");
  j.dir = {n[0], n[1]};
  j.r = positive(*v, "r", w);
  return j;
}

Side side(const json& obj, const std::string& where, Side fallback) {
  const json* v = find(obj, "side");
  if (!v) return fallback;
  if (*v == "front") return Side::Front;
  if (*v == "back") return Side::Back;
  bad(where + ".side", "must be \"front\" or \"back\"");
}

ToolShape toolShape(const json& obj, const std::string& where) {
  const json* v = find(obj, "tool");
  if (!v || !v->is_object()) bad(where + ".tool", "missing (an object {\"type\": \"sphere\"|\"cylinder\"|\"flat\", ...} is required)");
  const std::string w = where + ".tool";
  ToolShape t;
  const std::string type = text(*v, "type", w);
  t.center = vec3(*v, "center", w);
  if (type == "sphere") {
    t.type = ToolShape::Type::Sphere;
    t.r = positive(*v, "r", w);
  } else if (type == "cylinder") {
    t.type = ToolShape::Type::Cylinder;
    t.r = positive(*v, "r", w);
    t.end = vec3(*v, "end", w);
  } else if (type == "flat") {
    t.type = ToolShape::Type::Flat;
    const json* s = find(*v, "size");
    if (!s) bad(w + ".size", "missing ([width, height, depth] of the flat face box, mm)");
    const auto n = numbers(*s, w + ".size", 3);
    if (!(n[0] > 0 && n[1] > 0 && n[2] > 0)) bad(w + ".size", "must be three positive numbers (mm)");
    t.half = {n[0] / 2, n[1] / 2, n[2] / 2};
  } else {
    bad(w + ".type", "unknown tool \"" + type + "\" (sphere, cylinder or flat)");
  }
  return t;
}

Operation operation(const json& v, const std::string& where) {
  if (!v.is_object()) bad(where, "must be an object with an \"op\" key");
  const std::string kind = text(v, "op", where);
  Operation op;
  if (kind == "trace") {
    op.kind = OpKind::Trace;
    op.side = side(v, where, Side::Front);
    op.a = positive(v, "a", where);
    op.points = points(v, "points", where);
    op.joinStart = traceJoin(v, "join_start", where);
    op.joinEnd = traceJoin(v, "join_end", where);
  } else if (kind == "punch" || kind == "press") {
    op.kind = kind == "punch" ? OpKind::Punch : OpKind::Press;
    op.side = side(v, where, Side::Back);
    op.a = positive(v, "a", where);
    op.p = number(v, "p", where, 1.0);
    op.q = number(v, "q", where, 1.0);
    if (!(op.q > 0)) bad(where + ".q", "must be a positive number");
    if (op.kind == OpKind::Punch)
      op.at = vec3(v, "at", where);
    else
      op.points = points(v, "points", where);
  } else if (kind == "region") {
    op.kind = OpKind::Region;
    op.side = side(v, where, Side::Back);
    op.points = points(v, "contour", where);
    if (op.points.size() < 3) bad(where + ".contour", "a closed contour needs at least 3 points");
    op.height = number(v, "height", where);
    op.falloff = positive(v, "falloff", where);
  } else if (kind == "blend_union" || kind == "blend_subtract" || kind == "subtract") {
    op.kind = kind == "blend_union" ? OpKind::BlendUnion : kind == "subtract" ? OpKind::Subtract : OpKind::BlendSubtract;
    op.tool = toolShape(v, where);
    if (op.kind != OpKind::Subtract) {
      op.a1 = number(v, "a1", where);
      op.a2 = positive(v, "a2", where);
      op.a3 = positive(v, "a3", where);
    }
  } else if (kind == "patina") {
    op.kind = OpKind::Patina;
    const std::string tinge = text(v, "tinge", where);
    const auto& all = tinges();
    op.tinge = 0;
    for (size_t i = 1; i < all.size(); ++i)
      if (all[i].name == tinge) op.tinge = static_cast<int>(i);
    if (op.tinge == 0) bad(where + ".tinge", "unknown tinge \"" + tinge + "\" (black, brown, green or golden)");
    op.points = points(v, "points", where);
    op.a = positive(v, "r", where);
    op.strength = number(v, "strength", where, 1.0);
  } else {
    bad(where + ".op", "unknown operation \"" + kind +
                           "\" (trace, punch, press, region, blend_union, subtract, blend_subtract, patina)");
  }
  // validate() checks the physical ranges; its message starts with the key.
  const std::string problem = validate(op);
  if (!problem.empty()) {
    const size_t colon = problem.find(": ");
    if (colon == std::string::npos) bad(where, problem);
    bad(where + "." + problem.substr(0, colon), problem.substr(colon + 2));
  }
  return op;
}

std::shared_ptr<const Workpiece> workpiece(const json& v, const std::filesystem::path& baseDir) {
  const std::string w = "workpiece";
  if (!v.is_object()) bad(w, "must be an object with a \"type\" key");
  const std::string type = text(v, "type", w);
  if (type == "plate") return std::make_shared<Plate>(size(v, "w", w), size(v, "h", w), size(v, "d", w));
  if (type == "disc") return std::make_shared<Disc>(size(v, "r", w), size(v, "d", w));
  if (type == "bowl") {
    const double r = size(v, "r", w), depth = size(v, "depth", w), d = size(v, "d", w);
    if (depth >= r) bad(w + ".depth", "must be less than the rim radius r (a shallow bowl)");
    return std::make_shared<Bowl>(r, depth, d);
  }
  if (type == "vm") {
    const std::string file = text(v, "file", w);
    // The model's unit in mm: its +-1000-unit search box times the scale stays a physical size.
    const double scale = ranged(v, "scale", w, 1e-6, kMaxLengthMm, " mm per unit", 1.0);
    const double d = size(v, "d", w, 0.5);
    std::filesystem::path p(file);
    if (p.is_relative()) p = baseDir / p;
    auto loaded = VmWorkpiece::open(p, file, scale, d);
    if (!loaded) bad(w + ".file", loaded.error());
    return *loaded;
  }
  bad(w + ".type", "unknown workpiece \"" + type + "\" (plate, disc, bowl or vm)");
}

CameraSpec camera(const json& v, const Box3& bounds) {
  const std::string w = "camera";
  if (!v.is_object()) bad(w, "must be an object");
  CameraSpec c = defaultCamera(bounds);
  const std::string type = text(v, "type", w, std::string("perspective"));
  if (type == "perspective")
    c.type = CameraSpec::Type::Perspective;
  else if (type == "ortho")
    c.type = CameraSpec::Type::Ortho;
  else
    bad(w + ".type", "must be \"perspective\" or \"ortho\"");
  c.eye = within(vec3(v, "eye", w, c.eye), w + ".eye", kMaxCameraDistanceMm);
  c.target = within(vec3(v, "target", w, c.target), w + ".target", kMaxCameraDistanceMm);
  c.up = within(vec3(v, "up", w, c.up), w + ".up", kMaxCameraDistanceMm);
  c.fovDeg = number(v, "fov_deg", w, c.fovDeg);
  if (!(c.fovDeg > 1 && c.fovDeg < 170)) bad(w + ".fov_deg", "must be between 1 and 170 degrees");
  c.height = ranged(v, "height", w, kMinLengthMm, kMaxCameraDistanceMm, " mm", c.height);
  const double dx = c.eye.x - c.target.x, dy = c.eye.y - c.target.y, dz = c.eye.z - c.target.z;
  if (dx * dx + dy * dy + dz * dz <= 0) bad(w + ".eye", "must differ from the target");
  return c;
}

// Line and column of a byte offset, for JSON syntax errors.
std::string lineColumn(const std::string& text, size_t offset) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

json vec(const Vec3& v) { return json::array({v.x, v.y, v.z}); }
json pts(const std::vector<Vec2>& p) {
  json a = json::array();
  for (const auto& q : p) a.push_back({q.x, q.y});
  return a;
}

json toolJson(const ToolShape& t) {
  switch (t.type) {
    case ToolShape::Type::Sphere: return {{"type", "sphere"}, {"center", vec(t.center)}, {"r", t.r}};
    case ToolShape::Type::Cylinder:
      return {{"type", "cylinder"}, {"center", vec(t.center)}, {"end", vec(t.end)}, {"r", t.r}};
    case ToolShape::Type::Flat:
      return {{"type", "flat"}, {"center", vec(t.center)}, {"size", json::array({2 * t.half.x, 2 * t.half.y, 2 * t.half.z})}};
  }
  return {};
}

json opJson(const Operation& o) {
  json j;
  j["op"] = opKindName(o.kind);
  const char* s = o.side == Side::Back ? "back" : "front";
  switch (o.kind) {
    case OpKind::Trace:
      j["side"] = s;
      j["a"] = o.a;
      j["points"] = pts(o.points);
      if (o.joinStart.on()) j["join_start"] = {{"dir", {o.joinStart.dir.x, o.joinStart.dir.y}}, {"r", o.joinStart.r}};
      if (o.joinEnd.on()) j["join_end"] = {{"dir", {o.joinEnd.dir.x, o.joinEnd.dir.y}}, {"r", o.joinEnd.r}};
      break;
    case OpKind::Punch: j["side"] = s; j["a"] = o.a; j["p"] = o.p; j["q"] = o.q; j["at"] = vec(o.at); break;
    case OpKind::Press: j["side"] = s; j["a"] = o.a; j["p"] = o.p; j["q"] = o.q; j["points"] = pts(o.points); break;
    case OpKind::Region: j["side"] = s; j["contour"] = pts(o.points); j["height"] = o.height; j["falloff"] = o.falloff; break;
    case OpKind::Subtract: j["tool"] = toolJson(o.tool); break;
    case OpKind::Patina:
      j["tinge"] = std::string(tinges()[o.tinge >= 1 && o.tinge <= 4 ? static_cast<size_t>(o.tinge) : 1].name);
      j["points"] = pts(o.points);
      j["r"] = o.a;
      j["strength"] = o.strength;
      break;
    default: j["tool"] = toolJson(o.tool); j["a1"] = o.a1; j["a2"] = o.a2; j["a3"] = o.a3; break;
  }
  return j;
}

}  // namespace

const char* deformationName(Deformation d) { return d == Deformation::Sheet ? "sheet" : "offset"; }

CameraSpec defaultCamera(const Box3& b) {
  CameraSpec c;
  const double cx = 0.5 * (b.x0 + b.x1), cy = 0.5 * (b.y0 + b.y1);
  const double size = std::max(b.x1 - b.x0, b.y1 - b.y0);
  c.target = {cx, cy, 0.5 * (b.z0 + b.z1)};
  // A view from in front and a little below, like a visitor bending over a bench: the relief reads
  // by its shading; 35 degrees of field keeps the perspective mild.
  const double dist = 0.5 * size / std::tan(0.5 * 35.0 * M_PI / 180.0) * 1.12;
  c.eye = {cx, cy - 0.30 * dist, c.target.z + 0.95 * dist};
  c.up = {0, 1, 0};
  c.fovDeg = 35.0;
  c.height = size * 1.1;
  return c;
}

Result<Model> Scene::makeModel() const {
  Model m(workpiece, deformation);
  for (size_t i = 0; i < operations.size(); ++i) {
    Status s = m.add(operations[i]);
    if (!s) return fail("operations[" + std::to_string(i) + "]: " + s.error());
  }
  return m;
}

Result<Scene> parseScene(const std::string& textIn, const std::string& name, const std::filesystem::path& baseDir) {
  json doc;
  try {
    doc = json::parse(textIn);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    const auto pos = what.find("syntax error");
    return fail(name + ":" + lineColumn(textIn, e.byte == 0 ? 0 : e.byte - 1) + ": not valid JSON: " +
                (pos == std::string::npos ? what : what.substr(pos)));
  } catch (const json::exception& e) {
    // A number too large for a double, for instance (found by fuzzing).
    std::string what = e.what();
    const auto pos = what.find("] ");
    return fail(name + ": not valid JSON: " + (pos == std::string::npos ? what : what.substr(pos + 2)));
  }
  try {
    if (!doc.is_object()) bad("(top level)", "must be a JSON object");
    Scene s;
    const std::string format = text(doc, "format", "(top level)", std::string("emboss-scene"));
    if (format != "emboss-scene") bad("format", "must be \"emboss-scene\", not \"" + format + "\"");
    const double version = number(doc, "version", "(top level)", 1.0);
    if (version != 1.0) bad("version", "this program reads version 1 scenes, the file says " + json(version).dump());
    const std::string def = text(doc, "deformation", "(top level)", std::string("sheet"));
    if (def == "sheet")
      s.deformation = Deformation::Sheet;
    else if (def == "offset")
      s.deformation = Deformation::Offset;
    else
      bad("deformation", "must be \"sheet\" or \"offset\", not \"" + def + "\"");
    const json* wp = find(doc, "workpiece");
    s.workpiece = wp ? workpiece(*wp, baseDir) : std::make_shared<Plate>(60.0, 40.0, 0.5);
    s.metal = text(doc, "metal", "(top level)", std::string("copper"));
    if (!metalByName(s.metal)) bad("metal", "unknown metal \"" + s.metal + "\" (copper, brass, silver or aluminium)");
    s.tinge = text(doc, "tinge", "(top level)", std::string("none"));
    if (!tingeByName(s.tinge)) bad("tinge", "unknown tinge \"" + s.tinge + "\" (none, black, brown, green or golden)");
    s.title = text(doc, "title", "(top level)", std::string());
    if (const json* ops = find(doc, "operations")) {
      if (!ops->is_array()) bad("operations", "must be a list of operations");
      for (size_t i = 0; i < ops->size(); ++i) s.operations.push_back(operation((*ops)[i], "operations[" + std::to_string(i) + "]"));
    }
    const Box3 b = s.workpiece->bounds();
    if (const json* cam = find(doc, "camera")) {
      s.camera = camera(*cam, b);
      s.cameraGiven = true;
    } else {
      s.camera = defaultCamera(b);
    }
    return s;
  } catch (const SceneError& e) {
    return fail(name + ": " + e.where + ": " + e.what);
  } catch (const json::exception& e) {
    return fail(name + ": " + e.what());
  }
}

Result<Scene> loadScene(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path.string() + ": cannot open the scene file (" + std::strerror(errno) + ")");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseScene(ss.str(), path.filename().string(), path.parent_path());
}

std::string sceneToJson(const Scene& scene, const Model* model) {
  json doc;
  doc["format"] = "emboss-scene";
  doc["version"] = 1;
  if (!scene.title.empty()) doc["title"] = scene.title;
  doc["deformation"] = deformationName(model ? model->deformation() : scene.deformation);
  doc["workpiece"] = (model ? model->workpiece() : *scene.workpiece).toJson();
  doc["metal"] = scene.metal;
  if (scene.tinge != "none") doc["tinge"] = scene.tinge;
  const CameraSpec& c = scene.camera;
  doc["camera"] = {{"type", c.type == CameraSpec::Type::Perspective ? "perspective" : "ortho"},
                   {"eye", vec(c.eye)}, {"target", vec(c.target)}, {"up", vec(c.up)},
                   {"fov_deg", c.fovDeg}, {"height", c.height}};
  json ops = json::array();
  if (model) {
    for (size_t i = 0; i < model->activeCount(); ++i) ops.push_back(opJson(model->operations()[i].op()));
  } else {
    for (const auto& o : scene.operations) ops.push_back(opJson(o));
  }
  doc["operations"] = std::move(ops);
  // One operation a line keeps long sessions readable and diffable.
  std::string out = doc.dump(1);
  return out + "\n";
}

std::string operationToJson(const Operation& op) { return opJson(op).dump(); }

Result<std::string> sceneWithOperations(const std::string& head, const std::vector<std::string>& operations) {
  json doc = json::parse(head, nullptr, false);
  if (!doc.is_object()) return fail("the session's head is not a scene");
  json ops = json::array();
  for (size_t i = 0; i < operations.size(); ++i) {
    json o = json::parse(operations[i], nullptr, false);
    if (!o.is_object()) return fail("operation " + std::to_string(i) + " is not JSON");
    ops.push_back(std::move(o));
  }
  doc["operations"] = std::move(ops);
  return doc.dump(1) + "\n";
}

Status saveScene(const Scene& scene, const Model* model, const std::filesystem::path& path) {
  return writeFileAtomically(path, sceneToJson(scene, model));
}

}  // namespace emboss
