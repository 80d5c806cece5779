// Writing the model as POV-Ray functions: one helper per kernel, one stage per set operation.
#include "export/pov.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "frep/kernels.h"
#include "frep/vm_model.h"
#include "frep/workpieces.h"
#include "render/shading.h"
#include "tools/metal.h"

namespace emboss {

namespace {

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// The kernels as POV-Ray functions; parameters are capitalised so they never meet a keyword.
const char* kHelpers = R"(// Kernels of the embossing model (docs/kernels.md), shared by every operation below.
#declare Emboss_Taper = function(S) { select(S - 3, 1, select(S - 4, 1 - pow(S - 3, 3) * (10 - 15 * (S - 3) + 6 * pow(S - 3, 2)), 0)) }
#declare Emboss_SegT = function(Px, Py, Ex, Ey, Il) { min(max((Px * Ex + Py * Ey) * Il, 0), 1) }
#declare Emboss_SegD2T = function(Px, Py, Ex, Ey, T) { pow(Px - T * Ex, 2) + pow(Py - T * Ey, 2) }
#declare Emboss_SegD2 = function(Px, Py, Ex, Ey, Il) { Emboss_SegD2T(Px, Py, Ex, Ey, Emboss_SegT(Px, Py, Ex, Ey, Il)) }
#declare Emboss_Seg3T = function(Px, Py, Pz, Ex, Ey, Ez, Il) { min(max((Px * Ex + Py * Ey + Pz * Ez) * Il, 0), 1) }
#declare Emboss_Seg3D2T = function(Px, Py, Pz, Ex, Ey, Ez, T) { pow(Px - T * Ex, 2) + pow(Py - T * Ey, 2) + pow(Pz - T * Ez, 2) }
#declare Emboss_Seg3D2 = function(Px, Py, Pz, Ex, Ey, Ez, Il) { Emboss_Seg3D2T(Px, Py, Pz, Ex, Ey, Ez, Emboss_Seg3T(Px, Py, Pz, Ex, Ey, Ez, Il)) }
#declare Emboss_Agnesi = function(T2, A, L) { A * A * A / (T2 + A * A) * Emboss_Taper(sqrt(T2) / L) }
#declare Emboss_Punch = function(R2, A, P, Q, L) { P * A * A * A / (Q * R2 + A * A) * Emboss_Taper(sqrt(R2) / L) }
#declare Emboss_Region = function(Inside, T2, H, L) { select(Inside - 0.5, H * L * L / (T2 + L * L) * Emboss_Taper(sqrt(T2) / L), H) }
#declare Emboss_JoinS = function(S) { S * S * S * (10 + S * (-15 + 6 * S)) }
#declare Emboss_Join = function(U) { Emboss_JoinS(min(max(0.5 * (U + 1), 0), 1)) }
#declare Emboss_Brush = function(D2, R, S) { S * pow(max(1 - pow(D2 / (R * R), 2), 0), 2) }
#declare Emboss_Mix = function(F, R, W) { select(W - 1, F + W * (R - F), R) }
#declare Emboss_BU = function(F, G, A1, A2, A3) { F + G + sqrt(F * F + G * G) + A1 / (1 + pow(F / A2, 2) + pow(G / A3, 2)) }
#declare Emboss_BS = function(F, G, A1, A2, A3) { F - G - sqrt(F * F + G * G) + A1 / (1 + pow(F / A2, 2) + pow(G / A3, 2)) }
#declare Emboss_SetOp = function(Kind, F, G, A1, A2, A3, W) {
  Emboss_Mix(F, select(Kind - 1, Emboss_BU(F, G, A1, A2, A3), select(Kind - 2, min(F, -G), Emboss_BS(F, G, A1, A2, A3))), W)
}
)";

// Squared distance from (x, y) to a polyline, as a POV expression.
std::string polylineD2(const std::vector<Vec2>& pts, bool closed) {
  if (pts.size() == 1) return "(pow(x - " + num(pts[0].x) + ", 2) + pow(y - " + num(pts[0].y) + ", 2))";
  std::vector<std::string> terms;
  auto seg = [&](const Vec2& a, const Vec2& b) {
    const double ex = b.x - a.x, ey = b.y - a.y, len2 = ex * ex + ey * ey;
    if (len2 <= 0) return "(pow(x - " + num(a.x) + ", 2) + pow(y - " + num(a.y) + ", 2))";
    return "Emboss_SegD2(x - " + num(a.x) + ", y - " + num(a.y) + ", " + num(ex) + ", " + num(ey) + ", " + num(1.0 / len2) + ")";
  };
  for (size_t i = 1; i < pts.size(); ++i) terms.push_back(seg(pts[i - 1], pts[i]));
  if (closed && pts.size() > 2) terms.push_back(seg(pts.back(), pts[0]));
  if (terms.size() == 1) return terms[0];
  // POV's min takes any number of arguments, but long lists are split to keep expressions shallow.
  std::string out;
  for (size_t start = 0; start < terms.size(); start += 32) {
    std::string part = "min(";
    for (size_t i = start; i < std::min(terms.size(), start + 32); ++i) part += (i > start ? ", " : "") + terms[i];
    part += start + 1 == std::min(terms.size(), start + 32) ? ", 1e300)" : ")";
    out = out.empty() ? part : "min(" + out + ", " + part + ")";
  }
  return out;
}

// The even-odd crossing count of (x, y) against a closed contour, as a POV expression.
std::string parity(const std::vector<Vec2>& c) {
  std::string out = "mod(0";
  for (size_t i = 0, j = c.size() - 1; i < c.size(); j = i++) {
    if (c[i].y == c[j].y) continue;  // a horizontal edge is never crossed
    const double k = (c[i].x - c[j].x) / (c[i].y - c[j].y);
    // Crossed when exactly one end is above y and x is left of the crossing.
    out += " + select(y - " + num(std::min(c[i].y, c[j].y)) + ", 0, select(y - " + num(std::max(c[i].y, c[j].y)) +
           ", select(x - (" + num(c[j].x) + " + (y - " + num(c[j].y) + ") * " + num(k) + "), 1, 0), 0))";
  }
  return out + ", 2)";
}

std::string offsetTerm(const PreparedOp& prep, Deformation model) {
  const Operation& o = prep.op();
  const double L = o.characteristicLength();
  const std::string sign = o.sign() > 0 ? "+" : "-";
  switch (o.kind) {
    case OpKind::Trace: {
      if (!o.joinStart.on() && !o.joinEnd.on())
        return sign + " Emboss_Agnesi(" + polylineD2(o.points, false) + ", " + num(o.a) + ", " + num(L) + ")";
      // Joints (docs/kernels.md): the line continued through each for r, and the hand-over weights,
      // as PreparedOp made them ready.
      std::string d2 = polylineD2(o.points, false), weights;
      for (int e = 0; e < 2; ++e) {
        const PreparedOp::Joint& k = prep.joint(e);
        if (!k.on) continue;
        d2 = "min(" + d2 + ", " + polylineD2({k.e0, k.e1}, false) + ")";
        const std::string u = "Emboss_Join((x - " + num(k.px) + ") * " + num(k.kx) + " + (y - " + num(k.py) + ") * " + num(k.ky) + ")";
        weights += e == 0 ? " * " + u : " * (1 - " + u + ")";
      }
      return sign + " Emboss_Agnesi(" + d2 + ", " + num(o.a) + ", " + num(L) + ")" + weights;
    }
    case OpKind::Punch: {
      std::string r2 = "pow(x - " + num(o.at.x) + ", 2) + pow(y - " + num(o.at.y) + ", 2)";
      if (model == Deformation::Offset) r2 += " + pow(z - " + num(o.at.z) + ", 2)";
      return sign + " Emboss_Punch(" + r2 + ", " + num(o.a) + ", " + num(o.p) + ", " + num(o.q) + ", " + num(L) + ")";
    }
    case OpKind::Press: {
      std::string out;
      for (const Vec3& c : prep.pressPoints()) {
        std::string r2 = "pow(x - " + num(c.x) + ", 2) + pow(y - " + num(c.y) + ", 2)";
        if (model == Deformation::Offset) r2 += " + pow(z - " + num(c.z) + ", 2)";
        out += " " + sign + " Emboss_Punch(" + r2 + ", " + num(o.a) + ", " + num(o.p) + ", " + num(o.q) + ", " + num(L) + ")";
      }
      return out;
    }
    case OpKind::Region:
      return sign + " Emboss_Region(" + parity(o.points) + ", " + polylineD2(o.points, true) + ", " + num(o.height) + ", " + num(L) + ")";
    default:
      return "";
  }
}

std::string toolValue(const ToolShape& t) {
  switch (t.type) {
    case ToolShape::Type::Sphere:
      return num(t.r * t.r) + " - (pow(x - " + num(t.center.x) + ", 2) + pow(y - " + num(t.center.y) + ", 2) + pow(z - " + num(t.center.z) + ", 2))";
    case ToolShape::Type::Cylinder: {
      const double ex = t.end.x - t.center.x, ey = t.end.y - t.center.y, ez = t.end.z - t.center.z;
      const double len2 = ex * ex + ey * ey + ez * ez;
      return num(t.r * t.r) + " - Emboss_Seg3D2(x - " + num(t.center.x) + ", y - " + num(t.center.y) + ", z - " + num(t.center.z) +
             ", " + num(ex) + ", " + num(ey) + ", " + num(ez) + ", " + num(len2 > 0 ? 1.0 / len2 : 0.0) + ")";
    }
    case ToolShape::Type::Flat:
      return "min(" + num(t.half.x) + " - abs(x - " + num(t.center.x) + "), " + num(t.half.y) + " - abs(y - " + num(t.center.y) + "), " +
             num(t.half.z) + " - abs(z - " + num(t.center.z) + "))";
  }
  return "0";
}

// The taper weight of a set operation: distance from the tool's surface over L.
std::string toolWeight(const ToolShape& t) {
  const double L = t.size();
  std::string dist;
  switch (t.type) {
    case ToolShape::Type::Sphere:
      dist = "max(sqrt(pow(x - " + num(t.center.x) + ", 2) + pow(y - " + num(t.center.y) + ", 2) + pow(z - " + num(t.center.z) + ", 2)) - " + num(t.r) + ", 0)";
      break;
    case ToolShape::Type::Cylinder: {
      const double ex = t.end.x - t.center.x, ey = t.end.y - t.center.y, ez = t.end.z - t.center.z;
      const double len2 = ex * ex + ey * ey + ez * ez;
      dist = "max(sqrt(Emboss_Seg3D2(x - " + num(t.center.x) + ", y - " + num(t.center.y) + ", z - " + num(t.center.z) + ", " + num(ex) +
             ", " + num(ey) + ", " + num(ez) + ", " + num(len2 > 0 ? 1.0 / len2 : 0.0) + ")) - " + num(t.r) + ", 0)";
      break;
    }
    case ToolShape::Type::Flat:
      dist = "sqrt(pow(max(abs(x - " + num(t.center.x) + ") - " + num(t.half.x) + ", 0), 2) + pow(max(abs(y - " + num(t.center.y) + ") - " +
             num(t.half.y) + ", 0), 2) + pow(max(abs(z - " + num(t.center.z) + ") - " + num(t.half.z) + ", 0), 2))";
      break;
  }
  return "Emboss_Taper(" + dist + " / " + num(L) + ")";
}

Result<std::string> workpieceFunction(const Workpiece& wp) {
  const nlohmann::json j = wp.toJson();
  const std::string type = j.at("type");
  if (type == "plate") {
    const double w = j.at("w"), h = j.at("h"), d = j.at("d");
    return "min(x + " + num(w) + ", " + num(w) + " - x, y + " + num(h) + ", " + num(h) + " - y, z + " + num(d) + ", " + num(d) + " - z)";
  }
  if (type == "disc") {
    const double r = j.at("r"), d = j.at("d");
    return "min(" + num(r) + " - sqrt(x * x + y * y), z + " + num(d) + ", " + num(d) + " - z)";
  }
  if (type == "bowl") {
    const double r = j.at("r"), depth = j.at("depth"), d = j.at("d");
    const double R = (r * r + depth * depth) / (2 * depth);
    return "min(" + num(d) + " - abs(sqrt(x * x + y * y + pow(z - " + num(R) + ", 2)) - " + num(R) + "), " + num(r) + " - sqrt(x * x + y * y))";
  }
  return fail("POV-Ray export: workpiece type '" + type + "' is not supported");
}

}  // namespace

Result<std::string> exportPov(const Scene& scene, const Model& model, const PovExportOptions& options) {
  std::ostringstream out;
  out << "// emboss scene for POV-Ray 3.7: render with  povray +W" << options.width << " +H" << options.height << " +A0.1 file.pov\n";
  out << "// Emboss_Function(x, y, z) is the model's value (>= 0 inside) in the scene's right-handed coordinates.\n";
  out << "#version 3.7;\n";
  out << kHelpers;

  // The workpiece.
  std::string wpBody;
  if (const auto* vm = dynamic_cast<const VmWorkpiece*>(&model.workpiece())) {
    PovOptions vmOptions;
    vmOptions.prefix = "EmbossVm";
    auto body = vm->program().povFunction(vmOptions);
    if (!body) return fail("POV-Ray export of '" + vm->file() + "': " + body.error());
    out << body->declarations;
    out << "#declare Emboss_VmModel = function(x, y, z) { " << body->expression << " }\n";
    // The same scaling and sign as VmWorkpiece: f = -vm(P / s) * s, a 2D outline made a plate.
    const double inv = 1.0 / vm->scale();
    const std::string value = "-Emboss_VmModel(x * " + num(inv) + ", y * " + num(inv) + ", z * " + num(inv) + ") * " + num(vm->scale());
    wpBody = vm->isPlate() ? "min(" + value + ", " + num(vm->halfThickness()) + " - abs(z))" : value;
  } else {
    auto body = workpieceFunction(model.workpiece());
    if (!body) return fail(body.error());
    wpBody = *body;
  }
  out << "#declare Emboss_Stage0 = function(x, y, z) { " << wpBody << " }\n";

  // Runs of offsets between set operations, then the set operation, each a function of its own.
  const Deformation def = model.deformation();
  const auto& ops = model.operations();
  int stage = 0, run = 0;
  std::string runTerms;
  auto flushRun = [&]() {
    out << "#declare Emboss_Run" << run << " = function(x, y, z) { 0" << runTerms << " }\n";
    runTerms.clear();
  };
  // The patina brush's strokes, by tinge: 1 - prod(1 - brush) of each tinge's strokes (as the renderer).
  std::array<std::string, 5> patina;
  for (size_t i = 0; i < model.activeCount(); ++i) {
    const PreparedOp& prep = ops[i];
    const Operation& o = prep.op();
    if (o.isPatina()) {
      auto& f = patina[static_cast<size_t>(std::clamp(o.tinge, 1, 4))];
      f += "\n  * (1 - Emboss_Brush(" + polylineD2(o.points, false) + ", " + num(o.a) + ", " + num(o.strength) + "))";
      continue;
    }
    if (o.isOffset()) {
      runTerms += "\n  " + offsetTerm(prep, def);
      continue;
    }
    flushRun();
    const int kind = o.kind == OpKind::BlendUnion ? 0 : o.kind == OpKind::Subtract ? 1 : 2;
    // Sheet: the offsets of the run move the point along z; offset: they add to the value.
    const std::string prev = def == Deformation::Sheet
                                 ? "Emboss_Stage" + std::to_string(stage) + "(x, y, z - Emboss_Run" + std::to_string(run) + "(x, y, 0))"
                                 : "Emboss_Stage" + std::to_string(stage) + "(x, y, z) + Emboss_Run" + std::to_string(run) + "(x, y, z)";
    out << "#declare Emboss_Stage" << stage + 1 << " = function(x, y, z) { Emboss_SetOp(" << kind << ", " << prev << ", "
        << toolValue(o.tool) << ", " << num(o.a1) << ", " << num(o.a2) << ", " << num(o.a3) << ", " << toolWeight(o.tool) << ") }\n";
    ++stage;
    ++run;
  }
  flushRun();
  // The sheet's displacement D (the sum of every run of offsets) and, from it, the cavity term and
  // how far the tinge settles (shadeMetal: below the front face over tingeDepth, and in the grooves
  // the cavity finds). POV's z is mirrored: the model's z is -z.
  if (def == Deformation::Sheet) {
    out << "#declare Emboss_D = function(x, y) { 0";
    for (int i = 0; i <= run; ++i) out << " + Emboss_Run" << i << "(x, y, 0)";
    out << " }\n#declare Emboss_CavityOf = function(depth) { select(depth, 0, 0, depth / (depth + " << num(kCavityHalfDepth) << ")) }\n";
    out << "#declare Emboss_Cavity = function(x, y) { Emboss_CavityOf((0";
    for (const auto& u : kCavityRing) out << " + Emboss_D(x + " << num(kCavityReach * u[0]) << ", y + " << num(kCavityReach * u[1]) << ")";
    out << ") / 6 - Emboss_D(x, y)) }\n";
  } else {
    out << "#declare Emboss_Cavity = function(x, y) { 0 }\n";
  }
  const ShadingParams shadingDefaults{};
  out << "#declare Emboss_Settle = function(x, y, z) { max(min(max((" << num(model.workpiece().bounds().z1) << " + z) / "
      << num(shadingDefaults.tingeDepth) << ", 0), 1), Emboss_Cavity(x, y)) }\n";
  // The tinge of each layer: the scene's over the whole sheet (a quarter of it on open metal), the
  // brush's where it went (three quarters on open metal), 1 - prod(1 - brush) of its strokes.
  const Tinge sceneTinge = *tingeByName(scene.tinge);
  if (sceneTinge.strength > 0)
    out << "#declare Emboss_Tinge_scene = function(x, y, z) { " << num(sceneTinge.strength) << " * (0.25 + 0.75 * Emboss_Settle(x, y, z)) }\n";
  for (size_t t = 1; t < patina.size(); ++t)
    if (!patina[t].empty())
      out << "#declare Emboss_Tinge_" << tinges()[t].name << " = function(x, y, z) { min(1, (1 - (1" << patina[t]
          << "))\n  * (0.75 + 0.25 * Emboss_Settle(x, y, z))) }\n";
  const std::string last = "Emboss_Stage" + std::to_string(stage);
  const std::string lastRun = "Emboss_Run" + std::to_string(run);
  out << "#declare Emboss_Function = function(x, y, z) { "
      << (def == Deformation::Sheet ? last + "(x, y, z - " + lastRun + "(x, y, 0))" : last + "(x, y, z) + " + lastRun + "(x, y, z)")
      << " }\n";

  // The isosurface: POV's inside is where its function is below the threshold, and its space is
  // left-handed, so the function is negated and z mirrored.
  const Box3 b = model.bounds();
  double maxGrad = 1.0;
  for (int ix = 0; ix <= 24; ++ix)
    for (int iy = 0; iy <= 24; ++iy)
      for (int iz = 0; iz <= 8; ++iz) {
        const double x = b.x0 + (b.x1 - b.x0) * ix / 24, y = b.y0 + (b.y1 - b.y0) * iy / 24, z = b.z0 + (b.z1 - b.z0) * iz / 8;
        const Grad g = model.evaluate(P3<Grad>{Grad(x, 1, 0, 0), Grad(y, 0, 1, 0), Grad(z, 0, 0, 1)});
        maxGrad = std::max(maxGrad, std::sqrt(g.dx * g.dx + g.dy * g.dy + g.dz * g.dz));
      }
  const Metal metal = *metalByName(scene.metal);
  const auto& f0 = metal.f0;
  const double pad = 0.01;
  out << "#declare Emboss_Metal = texture {\n"
      << "  pigment { rgb <" << num(f0[0]) << ", " << num(f0[1]) << ", " << num(f0[2]) << "> }\n"
      << "  finish { ambient 0 emission 0 diffuse 0.04 brilliance 2 specular 0.6 roughness " << num(0.002 + 0.02 * metal.roughness)
      << " metallic 1 reflection { 0.55, 0.95 fresnel on metallic 1 } conserve_energy }\n"
      << "}\n";
  out << "#declare Emboss_Object = isosurface {\n  function { -Emboss_Function(x, y, -z) }\n  threshold 0\n"
      << "  contained_by { box { <" << num(b.x0 - pad) << ", " << num(b.y0 - pad) << ", " << num(-b.z1 - pad) << ">, <" << num(b.x1 + pad)
      << ", " << num(b.y1 + pad) << ", " << num(-b.z0 + pad) << "> } }\n"
      << "  max_gradient " << num(maxGrad * 1.5) << "\n  accuracy 0.0005\n  texture { Emboss_Metal }\n";
  // Each tinge as a layer that filters what is under it by the tinge's colour, as much as it
  // settled there: the renderer's mix(1, colour, k), layer upon layer.
  const auto layer = [&](const std::string& function, const Tinge& tg) {
    out << "  texture {\n    pigment { function { " << function << "(x, y, z) }\n"
        << "      color_map { [0 rgbf <1, 1, 1, 1>] [1 rgbf <" << num(tg.color[0]) << ", " << num(tg.color[1]) << ", " << num(tg.color[2])
        << ", 1>] } }\n"
        << "    finish { ambient 0 emission 0 diffuse 0 specular 0 }\n  }\n";
  };
  if (sceneTinge.strength > 0) layer("Emboss_Tinge_scene", sceneTinge);
  for (size_t t = 1; t < patina.size(); ++t)
    if (!patina[t].empty()) layer("Emboss_Tinge_" + std::string(tinges()[t].name), tinges()[t]);
  out << "}\n";

  // Camera, lights and the object, unless the includer only wants the declarations.
  const CameraSpec& c = scene.camera;
  const double aspect = static_cast<double>(options.width) / options.height;
  out << "#ifndef (Emboss_Declare_Only)\n";
  out << "global_settings { assumed_gamma 1.0 max_trace_level 6 }\n";
  out << "background { rgb <0.018, 0.020, 0.026> }\n";
  if (c.type == CameraSpec::Type::Perspective) {
    const double hfov = 2.0 * std::atan(std::tan(0.5 * c.fovDeg * M_PI / 180.0) * aspect) * 180.0 / M_PI;
    out << "camera { perspective location <" << num(c.eye.x) << ", " << num(c.eye.y) << ", " << num(-c.eye.z) << "> sky <" << num(c.up.x)
        << ", " << num(c.up.y) << ", " << num(-c.up.z) << "> right x * " << num(aspect) << " up y angle " << num(hfov) << " look_at <"
        << num(c.target.x) << ", " << num(c.target.y) << ", " << num(-c.target.z) << "> }\n";
  } else {
    out << "camera { orthographic location <" << num(c.eye.x) << ", " << num(c.eye.y) << ", " << num(-c.eye.z) << "> sky <" << num(c.up.x)
        << ", " << num(c.up.y) << ", " << num(-c.up.z) << "> right x * " << num(c.height * aspect) << " up y * " << num(c.height)
        << " look_at <" << num(c.target.x) << ", " << num(c.target.y) << ", " << num(-c.target.z) << "> }\n";
  }
  // The studio of the renderer's shading (render/shading.cpp): softboxes above left and right and a
  // strip light, here as area lights and as glowing panels the metal can reflect.
  const double R = std::max(b.x1 - b.x0, b.y1 - b.y0) * 3.0;
  auto panel = [&](double dx, double dy, double dz, double size, double power, const char* rgb) {
    const double n = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double px = dx / n * R, py = dy / n * R, pz = -dz / n * R;
    const double s = R * std::tan(size);
    // Shadowless, as in the renderer's shading (no cast shadows: a stroke's change stays local).
    out << "light_source { <" << num(px) << ", " << num(py) << ", " << num(pz) << "> rgb " << rgb << " * " << num(power * 0.35)
        << " shadowless }\n";
    out << "sphere { <" << num(px) << ", " << num(py) << ", " << num(pz) << ">, " << num(s) << " pigment { rgb " << rgb
        << " } finish { emission " << num(power) << " diffuse 0 } no_shadow no_image }\n";
  };
  panel(-0.55, 0.65, 0.55, 0.33, 5.0, "<1, 0.97, 0.92>");
  panel(0.65, 0.45, 0.60, 0.25, 3.0, "<0.9, 0.95, 1>");
  panel(0.0, 0.9, 0.45, 0.12, 6.0, "<1, 1, 1>");
  out << "sky_sphere { pigment { gradient y color_map { [0 rgb <0.03, 0.028, 0.026>] [1 rgb <0.16, 0.15, 0.14>] } scale 2 translate -y } }\n";
  // The dark backdrop behind the piece, as the renderer draws it; never seen in the metal.
  out << "plane { z, " << num(R) << " pigment { rgb <0.018, 0.020, 0.026> } finish { emission 1 diffuse 0 } no_reflection no_shadow }\n";
  out << "object { Emboss_Object }\n";
  out << "#end\n";
  return out.str();
}

}  // namespace emboss
