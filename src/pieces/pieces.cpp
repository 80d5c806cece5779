// The attract pieces, authored as control curves and expanded into operations like a chaser's strokes.
#include "pieces/pieces.h"

#include <cmath>

#include "frep/workpieces.h"
#include "pieces/piece_art.h"
#include "util/portable_math.h"

namespace emboss {

using art::Chaser;
using art::Path;

namespace {

constexpr double kDeg = M_PI / 180.0;

Vec2 polar(double r, double deg) { return {r * portableCos(deg * kDeg), r * portableSin(deg * kDeg)}; }

Scene makeScene(std::shared_ptr<const Workpiece> wp, const std::string& metal, const std::string& tinge,
                const std::string& title, const Chaser& c) {
  Scene s;
  s.deformation = Deformation::Sheet;
  s.workpiece = std::move(wp);
  s.metal = metal;
  s.tinge = tinge;
  s.title = title;
  s.camera = defaultCamera(s.workpiece->bounds());
  s.cameraGiven = false;
  s.operations = c.operations();
  return s;
}

// A bead border: single strikes of a small punch every `pitch` mm around a circle.
void beadCircle(Chaser& c, Vec2 centre, double r, double pitch, double size, double pressure) {
  const ToolSpec t = Chaser::tool("Small punch", size);
  const int n = static_cast<int>(std::round(2 * M_PI * r / pitch));
  for (int i = 0; i < n; ++i) c.strike(t, {centre.x + r * portableCos(2 * M_PI * i / n), centre.y + r * portableSin(2 * M_PI * i / n)}, pressure);
}

void beadPath(Chaser& c, const Path& p, double pitch, double size, double pressure) {
  const ToolSpec t = Chaser::tool("Small punch", size);
  for (const auto& q : art::resampleEvery(p, pitch)) c.strike(t, q, pressure);
}

Path rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}; }

}  // namespace

// ------------------------------------------------------------------------------------------ rosette
Scene rosettePiece() {
  Chaser c("brass");
  const ToolSpec tracer = Chaser::tool("Tracer"), fine = Chaser::tool("Fine tracer"), wide = Chaser::tool("Wide tracer");
  // Eight petals and eight leaves between them, as contours in their own frame (along +x).
  const Path petal = art::spline({{8.5, 0}, {11.5, -3.6}, {17.5, -5.6}, {23.5, -3.6}, {26.5, 0}, {23.5, 3.6}, {17.5, 5.6}, {11.5, 3.6}}, true);
  const Path leaf = art::spline({{13, 0}, {16.5, -2.3}, {21, -2.0}, {23.5, 0}, {21, 2.0}, {16.5, 2.3}}, true);
  std::vector<Path> petals, leaves, gadroons;
  for (int i = 0; i < 8; ++i) petals.push_back(art::transform(petal, 1.0, i * 45.0, {0, 0}));
  for (int i = 0; i < 8; ++i) leaves.push_back(art::transform(leaf, 1.0, i * 45.0 + 22.5, {0, 0}));
  // Gadroons of the outer band: sixteen tongues between r = 32.5 and 42.
  const Path tongue = art::spline({{32.5, 0}, {34, -2.9}, {38.5, -3.6}, {42, -2.2}, {42.8, 0}, {42, 2.2}, {38.5, 3.6}, {34, 2.9}}, true);
  for (int i = 0; i < 16; ++i) gadroons.push_back(art::transform(tongue, 1.0, i * 22.5 + 11.25, {0, 0}));

  // 1. The layout traced from the front: rings, petals, leaves, tongues.
  for (double r : {7.5, 28.0, 30.8, 44.5, 48.6}) c.stroke(r > 40 ? wide : tracer, art::circle({0, 0}, r), 0.65);
  for (const auto& p : petals) c.stroke(tracer, p, 0.6);
  for (const auto& l : leaves) c.stroke(fine, l, 0.55);
  for (const auto& g : gadroons) c.stroke(tracer, g, 0.55);
  // 2. Raised from behind: the boss, petals, leaves and tongues.
  c.raise(art::circle({0, 0}, 7.0, 1.0), 1.0, 2.5);
  for (const auto& p : petals) c.raise(art::resampleEvery(p, 1.0), 0.85, 2.2);
  for (const auto& l : leaves) c.raise(art::resampleEvery(l, 1.0), 0.6, 1.6);
  for (const auto& g : gadroons) c.raise(art::resampleEvery(g, 1.0), 0.75, 1.8);
  c.strike(Chaser::tool("Large punch"), {0, 0}, 0.8);
  // 3. Petal veins chased from the front, and a dot at each leaf's heart.
  for (int i = 0; i < 8; ++i) c.stroke(fine, art::transform(art::spline({{11.5, 0}, {17, 0.4}, {23, 0}}, false), 1.0, i * 45.0, {0, 0}), 0.5);
  for (int i = 0; i < 8; ++i) c.strike(Chaser::tool("Hammer", 1.6), polar(18.2, i * 45.0 + 22.5), 0.9);
  // 4. The bead rows: between the inner rings and at the rim.
  beadCircle(c, {0, 0}, 29.4, 3.2, 2.6, 0.7);
  beadCircle(c, {0, 0}, 46.6, 3.0, 2.6, 0.7);
  // 5. The ground of the inner field matted with the hammer.
  const Path field = art::circle({0, 0}, 27.2, 1.0);
  std::vector<Path> holes = petals;
  holes.insert(holes.end(), leaves.begin(), leaves.end());
  holes.push_back(art::circle({0, 0}, 8.2, 1.0));
  c.matte(field, holes, 1.7, 0.6, 0.55, 11);
  // and between the tongues of the outer band.
  Path band = art::circle({0, 0}, 43.6, 1.0);
  std::vector<Path> bandHoles = gadroons;
  bandHoles.push_back(art::circle({0, 0}, 31.6, 1.0));
  c.matte(band, bandHoles, 1.8, 0.5, 0.5, 12);
  // 5. Patina: a brown tinge brushed round the matted ring, darkest in its dents.
  c.stroke(Chaser::tool("Brown patina", 9.0), art::circle({0, 0}, 37.8, 1.0), 0.7);
  return makeScene(std::make_shared<Disc>(50.0, 0.5), "brass", "none", "Rosette medallion", c);
}

// ------------------------------------------------------------------------------------------ shell
Scene shellPiece() {
  Chaser c("copper");
  const ToolSpec tracer = Chaser::tool("Tracer"), fine = Chaser::tool("Fine tracer");
  const Vec2 hinge{0, -24};
  const int ribs = 11;
  const double a0 = 28, a1 = 152;  // the fan, degrees
  auto rim = [&](double deg) {  // the rim's radius: a scallop per rib
    const double u = (deg - a0) / (a1 - a0) * ribs;
    const double lobe = std::sqrt(std::max(0.0, 1.0 - (2 * (u - std::floor(u)) - 1) * (2 * (u - std::floor(u)) - 1)));
    return 44.0 - 6.0 * ((deg - 90) / 62.0) * ((deg - 90) / 62.0) + 2.2 * lobe;
  };
  Path outline;
  for (double d = a0; d <= a1 + 1e-9; d += 0.5) {
    const Vec2 p = polar(rim(d), d);
    outline.push_back({hinge.x + p.x, hinge.y + p.y});
  }
  // The ears at the hinge.
  const Path ears = {{hinge.x + polar(rim(a1), a1).x, hinge.y + polar(rim(a1), a1).y}, {-13, -25}, {-12, -31}, {12, -31},
                     {13, -25}, {hinge.x + polar(rim(a0), a0).x, hinge.y + polar(rim(a0), a0).y}};
  outline.insert(outline.end(), ears.begin() + 1, ears.end() - 1);
  outline = art::resampleEvery(outline, 1.0);
  outline.push_back(outline.front());

  // 1. Outline and ribs traced.
  c.stroke(Chaser::tool("Wide tracer"), outline, 0.7);
  std::vector<Path> ribShapes;
  for (int i = 0; i < ribs; ++i) {
    const double mid = a0 + (i + 0.5) * (a1 - a0) / ribs, half = 0.5 * (a1 - a0) / ribs * 0.78;
    Path rib;
    for (double r = 7; r <= rim(mid) - 2.2; r += 1.5) rib.push_back({hinge.x + polar(r, mid - half * r / 44).x, hinge.y + polar(r, mid - half * r / 44).y});
    for (double d = mid - half; d <= mid + half; d += 1) rib.push_back({hinge.x + polar(rim(d) - 2.4, d).x, hinge.y + polar(rim(d) - 2.4, d).y});
    for (double r = rim(mid) - 2.2; r >= 7; r -= 1.5) rib.push_back({hinge.x + polar(r, mid + half * r / 44).x, hinge.y + polar(r, mid + half * r / 44).y});
    ribShapes.push_back(rib);
  }
  for (int i = 1; i < ribs; ++i) {
    const double d = a0 + i * (a1 - a0) / ribs;
    Path groove;
    for (double r = 5; r <= rim(d) - 0.5; r += 1) groove.push_back({hinge.x + polar(r, d).x, hinge.y + polar(r, d).y});
    c.stroke(tracer, groove, 0.6);
  }
  // 2. The ribs raised from behind, each with an oval punch along its crest.
  c.raise(outline, 0.55, 3.0);
  for (const auto& r : ribShapes) c.raise(r, 0.8, 1.8);
  for (int i = 0; i < ribs; ++i) {
    const double mid = a0 + (i + 0.5) * (a1 - a0) / ribs;
    Path crest;
    for (double r = 9; r <= rim(mid) - 5; r += 1) crest.push_back({hinge.x + polar(r, mid).x, hinge.y + polar(r, mid).y});
    c.stroke(Chaser::tool("Oval punch", 3.5), crest, 0.45);
  }
  // 3. Growth lines across the ribs, lightly.
  for (double r : {14.0, 22.0, 30.0, 37.0}) {
    Path g;
    for (double d = a0 + 2; d <= a1 - 2; d += 0.7) g.push_back({hinge.x + polar(r, d).x, hinge.y + polar(r, d).y});
    c.stroke(fine, g, 0.35);
  }
  // The ears' lines.
  for (double x : {-9.0, -5.0, 5.0, 9.0}) c.stroke(fine, {{x, -30}, {x * 0.7, -25}}, 0.5);
  // 4. A frame: a traced border and beads, the ground matted.
  c.stroke(Chaser::tool("Wide tracer"), rect(-46, -36, 46, 36), 0.6);
  beadPath(c, rect(-43.5, -33.5, 43.5, 33.5), 3.0, 2.4, 0.65);
  c.matte(rect(-41.5, -31.5, 41.5, 31.5), {outline}, 1.9, 1.0, 0.5, 21);
  // 5. Patina: verdigris rubbed into the matted corners, where a shell on a rock would green.
  for (const Vec2 k : {Vec2{-36, 26}, Vec2{36, 26}, Vec2{-36, -26}, Vec2{36, -26}})
    c.stroke(Chaser::tool("Green patina", 10.0), art::circle(k, 2.5, 1.0), 0.55);
  return makeScene(std::make_shared<Plate>(50.0, 40.0, 0.5), "copper", "none", "Scallop shell", c);
}

// ------------------------------------------------------------------------------------------ horse
// A six-pointed folk rosette (a circle, six petals from arcs, a boss), common on Georgian chased work.
void folkRosette(Chaser& c, Vec2 at, double r, double pressure) {
  const ToolSpec fine = Chaser::tool("Fine tracer");
  c.stroke(fine, art::circle(at, r, 0.5), pressure);
  for (int i = 0; i < 6; ++i) {
    const Vec2 p = polar(r, i * 60.0);
    c.stroke(fine, art::arc({at.x + p.x, at.y + p.y}, r, i * 60.0 + 120, i * 60.0 + 240, 0.5), pressure * 0.85);
  }
  c.strike(Chaser::tool("Small punch", r * 0.7), at, 0.8);
}

Scene horsePiece() {
  Chaser c("silver");
  const ToolSpec tracer = Chaser::tool("Tracer"), fine = Chaser::tool("Fine tracer");
  const Vec2 shift{2, 2};
  auto place = [&](const Path& p) { return art::transform(p, 1.0, 0, shift); };
  auto at = [&](double x, double y) { return Vec2{x + shift.x, y + shift.y}; };
  // The horse facing right, the near legs: one contour from the nose round the chest, the planted
  // foreleg, the belly, the hind leg, the rump, the back and the arched neck to the ears.
  const Path horse = place(art::spline(
      {{41, 18},    {39.5, 14.5}, {35.5, 13},   {31, 13.5},   {27.5, 11},   {23.5, 4},   {20.5, -2},  {19.5, -8},
       {20, -17},   {19.3, -26},  {20.8, -29.5}, {16.2, -30}, {16.3, -26},  {15.8, -17}, {14.5, -10}, {8, -11.5},
       {0, -12.5},  {-10, -11.5}, {-15, -12},   {-19, -17},   {-21.5, -19.5}, {-21, -26}, {-19.8, -29.5}, {-24.5, -30},
       {-25, -26},  {-26.5, -17.5}, {-28, -9},  {-28, -2},    {-26.5, 5},   {-19, 10.5}, {-8, 8},     {2, 8.5},
       {9, 12.5},   {14, 20.5},   {20.5, 27},   {26.5, 30.5}, {28, 34.5},   {30, 30.5},  {34, 27},    {39, 21.5}},
      true, 0.5));
  // The far legs: the foreleg lifted and bent at the knee (the horse steps out), the hind leg planted.
  const Path farFore = place(art::spline({{13, -8}, {17.5, -15.5}, {16, -19}, {12.5, -23}, {10, -25.5}, {8.5, -23.5},
                                          {11.5, -20.5}, {12.5, -17.5}, {9.5, -10}},
                                         true, 0.5));
  const Path farHind = place(art::spline({{-13, -10}, {-15, -18}, {-14.5, -26}, {-13.2, -29.5}, {-17.5, -30}, {-18.2, -26},
                                          {-19.5, -18}, {-20, -10}},
                                         true, 0.5));
  const Path tail = place(art::spline({{-26, 5}, {-31, 4}, {-35, -2}, {-38, -11}, {-41, -19}, {-36.5, -15}, {-33, -8},
                                       {-30.5, -2}, {-27.5, 1}},
                                      true, 0.5));
  const Path mane = place(art::spline({{8, 12.5}, {12.5, 21}, {19, 28}, {26, 32}, {24.5, 28}, {19, 23.5}, {14, 17.5}},
                                      true, 0.5));
  const Path saddle = place(art::spline({{-12, 7.5}, {-2, 6.5}, {4.5, 7.5}, {5.5, -3}, {3, -8}, {-9, -8}, {-12, -3}}, true, 0.5));

  // 1. Contours traced from the front: the figure, its far legs, tail and mane.
  c.stroke(tracer, horse, 0.75);
  c.stroke(tracer, farFore, 0.6);
  c.stroke(tracer, farHind, 0.6);
  c.stroke(tracer, tail, 0.65);
  c.stroke(fine, mane, 0.55);
  // 2. Raised from behind: far legs low, the body high (twice, the second inside the first), then
  //    the tail, the mane and the saddle cloth on top.
  c.raise(art::resampleEvery(farFore, 1.0), 0.45, 1.4);
  c.raise(art::resampleEvery(farHind, 1.0), 0.45, 1.4);
  c.raise(art::resampleEvery(horse, 1.0), 0.9, 2.5);
  c.raise(art::resampleEvery(art::offsetContour(horse, -3.5), 1.0), 0.75, 3.0);
  c.raise(art::resampleEvery(tail, 1.0), 0.7, 1.5);
  c.raise(art::resampleEvery(mane, 1.0), 0.5, 1.2);
  // 3. Modelling with the large punch: chest, shoulder, barrel, haunch, and the jowl.
  for (const Vec2 p : {Vec2{16, 1}, Vec2{10, 3}, Vec2{-2, 0}, Vec2{-18, 2}, Vec2{-21, -5}, Vec2{31, 19}})
    c.strike(Chaser::tool("Large punch"), at(p.x, p.y), 0.55);
  // 4. The saddle cloth: outlined, edged with dots, a rosette in the middle.
  c.stroke(fine, saddle, 0.6);
  beadPath(c, art::offsetContour(saddle, -1.6), 2.2, 1.6, 0.6);
  folkRosette(c, at(-3.5, 0), 3.0, 0.55);
  // 5. Head and harness chased from the front: eye, nostril, mouth, bridle with studs, the breast collar.
  c.strike(Chaser::tool("Hammer", 2.4), at(33.5, 23), 1.0);
  c.stroke(fine, place(art::circle({33.5, 23}, 1.9, 0.4)), 0.55);
  c.strike(Chaser::tool("Hammer", 1.5), at(39.6, 17.2), 0.9);
  c.stroke(fine, place({{40.2, 15.2}, {36.5, 15.4}}), 0.5);
  c.stroke(fine, place(art::spline({{37.5, 22.5}, {36, 18}, {36.5, 14}}, false, 0.5)), 0.55);  // noseband
  c.stroke(fine, place(art::spline({{29, 28.5}, {29.5, 22}, {31, 16}}, false, 0.5)), 0.55);     // cheek strap
  c.stroke(fine, place(art::spline({{31, 16}, {36.5, 17}}, false, 0.5)), 0.5);                  // rein ring to the bit
  for (const Vec2 p : {Vec2{29.3, 25}, Vec2{29.8, 19.5}, Vec2{37, 20}}) c.strike(Chaser::tool("Small punch", 1.4), at(p.x, p.y), 0.8);
  const Path collar = place(art::spline({{22.5, 6}, {19, 2}, {18.5, -4}}, false, 0.5));
  c.stroke(fine, collar, 0.55);
  beadPath(c, place(art::spline({{21.3, 7.5}, {17.2, 2}, {17, -4}}, false, 0.5)), 2.0, 1.5, 0.7);
  // 6. The mane's and tail's hair, the shoulder and haunch lines.
  for (int i = 0; i < 10; ++i) {
    const double t = i / 9.0;
    const Vec2 a{9.5 + 16 * t, 14 + 16.5 * t};
    c.stroke(fine, place(art::spline({a, {a.x + 0.6, a.y + 2.2}, {a.x - 0.4, a.y + 4.2}}, false, 0.4)), 0.55);
  }
  for (int i = 0; i < 5; ++i)
    c.stroke(fine, place(art::spline({{-28 - i * 0.4, 3.2 - i * 0.3}, {-32.5 - i * 0.5, -3.0 - i * 0.4}, {-37.5 + i * 0.6, -15.0 + i * 0.5}}, false, 0.5)), 0.5);
  c.stroke(fine, place(art::spline({{20.5, 3}, {15.5, -1}, {15.5, -7}}, false, 0.5)), 0.45);
  c.stroke(fine, place(art::arc({-19, -1}, 7.5, 30, 200, 0.5)), 0.45);
  // 7. Around the horse, in folk style: a ground of zigzags, a sun rosette and stars.
  const Path ground = art::spline({{-48, -31}, {-20, -30.5}, {0, -31.2}, {24, -30.5}, {48, -31}}, false, 0.5);
  c.stroke(Chaser::tool("Wide tracer"), ground, 0.6);
  Path zig;
  for (int i = 0; i <= 32; ++i) zig.push_back({-48 + i * 3.0, i % 2 ? -33.8 : -31.8});
  c.stroke(fine, zig, 0.5);
  const Vec2 sun{-38, 22};
  c.raise(art::circle(sun, 5.0, 1.0), 0.8, 1.5);
  folkRosette(c, sun, 3.2, 0.55);
  for (int i = 0; i < 16; ++i) {
    const Vec2 a = polar(7, i * 22.5), b = polar(i % 2 ? 9.5 : 11.5, i * 22.5);
    c.stroke(fine, {{sun.x + a.x, sun.y + a.y}, {sun.x + b.x, sun.y + b.y}}, 0.6);
  }
  const std::vector<Vec2> stars = {{-14, 26}, {8, 28}, {46, 26}, {-44, 2}, {46, -8}};
  for (const Vec2 s : stars) folkRosette(c, s, 2.8, 0.5);
  // 8. The frame: a traced border, beads inside it, and the ground matted up to the figures.
  c.stroke(Chaser::tool("Wide tracer"), rect(-56, -38, 56, 38), 0.6);
  beadPath(c, rect(-53.5, -35.5, 53.5, 35.5), 3.0, 2.4, 0.65);
  std::vector<Path> keep = {horse, farFore, farHind, tail, mane, art::circle(sun, 12, 1.0)};
  for (const Vec2 s : stars) keep.push_back(art::circle(s, 4.2, 1.0));
  c.matte(rect(-51.5, -29.5, 51.5, 33.5), keep, 1.9, 0.9, 0.5, 31);
  // 9. Patina: the sun gilded with a golden tinge.
  c.stroke(Chaser::tool("Golden patina", 8.0), art::circle(sun, 4.0, 1.0), 0.8);
  c.stroke(Chaser::tool("Golden patina", 6.0), art::circle(sun, 8.5, 1.0), 0.6);
  return makeScene(std::make_shared<Plate>(60.0, 40.0, 0.5), "silver", "black", "Horse, after Georgian chased silver", c);
}

std::vector<GeneratedPiece> generateAttractPieces() {
  return {{"1-rosette.json", rosettePiece()}, {"2-shell.json", shellPiece()}, {"3-horse.json", horsePiece()}};
}

}  // namespace emboss
