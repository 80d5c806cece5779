// Dirty updates give exactly the bytes of a full render: random pieces, operations added, undone
// and redone one at a time, each followed by a dirty update only, compared with a fresh render of
// a freshly built model (other threads, other tiles) byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/piece_generator.h"
#include "frep/vm_generate.h"
#include "frep/vm_model.h"
#include "render/renderer.h"
#include "tools/metal.h"

namespace emboss {
namespace {

struct Case {
  PieceShape shape;  // Disc with vm set: an imported vm outline instead
  Deformation deformation;
  bool exactTracer;  // sheet model through the exact tracer (RenderOptions::exact)
  int width, height;
  int steps;
  unsigned seed;
  bool vm = false;
};

std::string describe(const Case& c) {
  return std::string(c.vm ? "vm" : c.shape == PieceShape::Disc ? "disc" : "plate") + "/" +
         (c.deformation == Deformation::Sheet ? (c.exactTracer ? "sheet-exact" : "sheet") : "offset") + "/seed " +
         std::to_string(c.seed);
}

// The camera moved along its line of sight to f times its distance from the target.
CameraSpec nearer(CameraSpec spec, double f) {
  spec.eye = {spec.target.x + f * (spec.eye.x - spec.target.x), spec.target.y + f * (spec.eye.y - spec.target.y),
              spec.target.z + f * (spec.eye.z - spec.target.z)};
  return spec;
}

ShadingParams shading(const Model& m) {
  ShadingParams s;
  s.metal = *metalByName("brass");
  s.tinge = *tingeByName("brown");  // the tinge reads the hit's depth: positions must match too
  s.frontZ = m.workpiece().bounds().z1;
  return s;
}

Model rebuilt(const Model& live) {
  Model m(live.workpiecePtr(), live.deformation());
  for (size_t i = 0; i < live.activeCount(); ++i) EXPECT_TRUE(m.add(live.operations()[i].op()).ok());
  return m;
}

// The first differing pixel, or an empty string.
std::string firstDifference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return "sizes differ";
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      if (std::memcmp(a.pixel(x, y), b.pixel(x, y), 4) != 0) {
        const auto* p = a.pixel(x, y);
        const auto* q = b.pixel(x, y);
        return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): dirty " + std::to_string(p[0]) + "," +
               std::to_string(p[1]) + "," + std::to_string(p[2]) + " full " + std::to_string(q[0]) + "," +
               std::to_string(q[1]) + "," + std::to_string(q[2]);
      }
  return {};
}

// A fresh model and renderer (one thread, other tiles) render the model in full; the first
// pixel where `image` differs from that, or an empty string.
std::string againstFresh(const Model& model, const Camera& camera, const RenderOptions& options, const Image& image,
                         bool antialias = true) {
  ThreadPool onePool(1);
  const Model fresh = rebuilt(model);
  Renderer full(onePool);
  full.setCamera(camera);
  full.setAntialias(antialias);
  full.setShading(shading(fresh));
  RenderOptions o = options;
  o.tileSize = 7;
  full.setOptions(o);
  full.sync(fresh);
  Image reference;
  full.renderFull(reference);
  return firstDifference(image, reference);
}

void runCase(const Case& c) {
  SCOPED_TRACE(describe(c));
  PieceOptions opt;
  opt.shape = c.shape;
  opt.width = 48, opt.height = 36;
  opt.halfThickness = 0.5;
  opt.deformation = c.deformation;
  opt.toolScale = 1.6;
  GeneratedPiece piece = generatePiece(c.steps, c.seed, opt);
  if (c.vm) {
    // A medallion outline from the vm generator as the workpiece (an outline sheet), the relief
    // moved onto it.
    auto program = VmProgram::parse(generateVmRelief(150, c.seed), "test");
    ASSERT_TRUE(program.ok()) << program.error();
    auto wp = VmWorkpiece::create(std::move(*program), "test.vm", 18.0, 0.5);
    ASSERT_TRUE(wp.ok()) << wp.error();
    const Box3 b = (*wp)->bounds();
    opt.width = b.x1 - b.x0, opt.height = b.y1 - b.y0;
    piece = generatePiece(c.steps, c.seed, opt);
    const double cx = 0.5 * (b.x0 + b.x1), cy = 0.5 * (b.y0 + b.y1);
    for (Operation& o : piece.operations) {
      for (Vec2& p : o.points) p.x += cx, p.y += cy;
      o.at.x += cx, o.at.y += cy;
      o.tool.center.x += cx, o.tool.center.y += cy;
    }
    piece.workpiece = *wp;
    piece.camera = defaultCamera(b);
  }
  PieceRandom rng(c.seed * 7919u + 13u);

  ThreadPool pool(2);
  Renderer live(pool);
  Model model(piece.workpiece, piece.deformation);
  const Camera camera(piece.camera, c.width, c.height);
  live.setCamera(camera);
  live.setShading(shading(model));
  RenderOptions options;
  options.exact = c.exactTracer;
  live.setOptions(options);
  live.sync(model);
  Image image;
  live.renderFull(image);

  size_t next = 0;
  long dirtyPixels = 0, framePixels = 0;
  std::uint64_t reshaded = 0;
  for (int step = 0; step < c.steps; ++step) {
    // Mostly strokes, some undos and redos, now and then a set operation.
    size_t index;
    const double r = rng.uniform(0, 1);
    std::string what;
    if (r < 0.2 && model.canUndo()) {
      model.undo();
      index = model.activeCount();
      what = "undo";
    } else if (r < 0.3 && model.canRedo()) {
      model.redo();
      index = model.activeCount() - 1;
      what = "redo";
    } else {
      Operation op = next < piece.operations.size() ? piece.operations[next++] : randomPunch(rng, piece, opt.toolScale);
      if (rng.chance(0.08)) op = randomSetOperation(rng, piece, 1.0);
      if (rng.chance(0.15)) op = randomTraceSegment(rng, piece, opt.toolScale);
      if (rng.chance(0.12)) {
        // A stroke of the patina brush: it colours, it moves nothing.
        const Operation t = randomTraceSegment(rng, piece, opt.toolScale);
        op = Operation{};
        op.kind = OpKind::Patina;
        op.points = t.points;
        op.tinge = 1 + static_cast<int>(rng.uniform(0, 3.999));
        op.a = rng.uniform(1.0, 5.0);
        op.strength = rng.uniform(0.3, 1.0);
      }
      ASSERT_TRUE(model.add(op).ok());
      index = model.activeCount() - 1;
      what = std::string("add ") + opKindName(op.kind);
    }
    SCOPED_TRACE("step " + std::to_string(step) + ": " + what + " (operation " + std::to_string(index) + ")");
    live.sync(model);
    const PixelSpans dirty = live.dirtySpans(model, index);
    RenderStats st;
    ASSERT_TRUE(live.render(image, dirty, &st));
    dirtyPixels += dirty.area();
    framePixels += c.width * c.height;
    reshaded += st.reshaded;

    const std::string diff = againstFresh(model, camera, options, image);
    ASSERT_TRUE(diff.empty()) << diff << "; dirty spans' box " << dirty.box.x << "," << dirty.box.y << " " << dirty.box.w << "x" << dirty.box.h;
  }
  // The dirty spans must be a real saving, not the whole frame.
  EXPECT_LT(dirtyPixels, framePixels * 3 / 4);
  // The field tracer shaded some pixels at their kept hits (what a change's shading alone reaches).
  if (c.deformation == Deformation::Sheet && !c.exactTracer) {
    EXPECT_GT(reshaded, 0u);
  }
}

TEST(DirtyRegion, SheetPlateEqualsFullRender) { runCase({PieceShape::Plate, Deformation::Sheet, false, 128, 80, 30, 1}); }
TEST(DirtyRegion, SheetDiscEqualsFullRender) { runCase({PieceShape::Disc, Deformation::Sheet, false, 112, 80, 30, 2}); }
TEST(DirtyRegion, OffsetPlateEqualsFullRender) { runCase({PieceShape::Plate, Deformation::Offset, false, 72, 48, 14, 3}); }
TEST(DirtyRegion, OffsetDiscEqualsFullRender) { runCase({PieceShape::Disc, Deformation::Offset, false, 64, 48, 14, 4}); }
TEST(DirtyRegion, SheetVmOutlineEqualsFullRender) { runCase({PieceShape::Plate, Deformation::Sheet, false, 96, 64, 20, 6, true}); }
TEST(DirtyRegion, SheetExactTracerEqualsFullRender) { runCase({PieceShape::Plate, Deformation::Sheet, true, 72, 48, 12, 5}); }

// A stroke's dirty spans at a kiosk's size: every pixel the stroke changes lies in them, and they
// are the projection of its support's pieces, not of its box (a round punch, a diagonal line,
// a raised region, a patina stroke), seen from above and at a slant.
// The field tracer keeps each pixel's hit and shades it again where a change cannot move it: the
// same bytes as a fresh render, fewer rays.
// A 48 x 36 mm plate, 1 mm thick.
PieceOptions smallPlate(double toolScale) {
  PieceOptions opt;
  opt.width = 48, opt.height = 36;
  opt.halfThickness = 0.5;
  opt.toolScale = toolScale;
  return opt;
}

// A bare small plate (its generator's seed), a renderer on two threads and an empty model of it.
struct SmallPlateScene {
  const GeneratedPiece piece;
  ThreadPool pool{2};
  Renderer live{pool};
  Model model;
  explicit SmallPlateScene(unsigned seed) : piece(generatePiece(1, seed, smallPlate(1.0))), model(piece.workpiece, piece.deformation) {}
};

// A small plate with the generator's dozen strokes on it (its set operations left out), a renderer
// on two threads for it.
struct StrokedPlateScene {
  const PieceOptions opt = smallPlate(1.6);
  const GeneratedPiece piece;
  ThreadPool pool{2};
  Renderer live{pool};
  Model model;
  explicit StrokedPlateScene(unsigned seed) : piece(generatePiece(12, seed, opt)), model(piece.workpiece, piece.deformation) {
    for (const Operation& op : piece.operations)
      if (!op.isSet()) {
        EXPECT_TRUE(model.add(op).ok());
      }
  }
};

TEST(DirtyRegion, KeptHitsAreShadedAgainWhereAChangeCannotMoveThem) {
  StrokedPlateScene scene(21);  // (set operations come last, below)
  const PieceOptions& opt = scene.opt;
  const GeneratedPiece& piece = scene.piece;
  Renderer& live = scene.live;
  Model& model = scene.model;
  PieceRandom rng(77);
  const Camera camera(piece.camera, 128, 80), small(piece.camera, 64, 40);
  live.setCamera(camera);
  live.setShading(shading(model));
  live.sync(model);
  Image image;
  RenderStats first;
  live.renderFull(image, &first);
  EXPECT_EQ(first.reshaded, 0u);  // a full frame traces every ray
  const RenderOptions options;
  auto update = [&](size_t index) {
    live.sync(model);
    RenderStats st;
    EXPECT_TRUE(live.render(image, live.dirtySpans(model, index), &st));
    const std::string diff = againstFresh(model, camera, options, image);
    EXPECT_TRUE(diff.empty()) << diff;
    return st;
  };
  auto patina = [&] {
    Operation op;
    op.kind = OpKind::Patina;
    op.points = randomTraceSegment(rng, piece, opt.toolScale).points;
    op.tinge = 2;
    op.a = 3.0;
    op.strength = 0.8;
    return op;
  };

  // A patina stroke moves nothing: every ray is shaded at its kept hit, the edges' two extra rays
  // too (kept by the full frame).
  ASSERT_TRUE(model.add(patina()).ok());
  RenderStats st = update(model.activeCount() - 1);
  EXPECT_GT(st.edgePixels, 0u);
  EXPECT_GT(st.reshaded, 100u + 2 * st.edgePixels);
  EXPECT_EQ(st.rays, 0u);
  // A punch: the rays near it are traced, those only its cavity reach adds are shaded again.
  ASSERT_TRUE(model.add(randomPunch(rng, piece, opt.toolScale)).ok());
  st = update(model.activeCount() - 1);
  EXPECT_GT(st.reshaded, 0u);
  EXPECT_GT(st.rays, 2 * st.edgePixels + 100);
  // A coarse picture's camera, the coarsest one a stopped picture falls back to, and back: the
  // frame's hits are still kept. Then the punch undone.
  const Camera coarsest(piece.camera, 16, 10);
  live.setCamera(small);
  Image low;
  live.renderFull(low);
  live.setCamera(coarsest);
  live.renderFull(low);
  live.setCamera(camera);
  model.undo();
  st = update(model.activeCount());
  EXPECT_GT(st.reshaded, 0u);
  // A set operation may move every hit near its tool (and its tool with the sheet): no kept hit
  // is used after it until traced again.
  const Operation set = randomSetOperation(rng, piece, 1.0);
  ASSERT_TRUE(model.add(set).ok());
  st = update(model.activeCount() - 1);
  EXPECT_EQ(st.reshaded, 0u);
  // A punch under it moves its tool with the sheet: what the tool can change is traced again too.
  live.renderFull(image);
  Operation under = randomPunch(rng, piece, opt.toolScale);
  under.at.x = set.tool.center.x, under.at.y = set.tool.center.y;
  ASSERT_TRUE(model.add(under).ok());
  st = update(model.activeCount() - 1);
  EXPECT_GT(st.reshaded, 0u);
  // Without reuse every ray is traced, to the same bytes.
  RenderOptions noReuse;
  noReuse.reuseHits = false;
  live.setOptions(noReuse);
  ASSERT_TRUE(model.add(patina()).ok());
  st = update(model.activeCount() - 1);
  EXPECT_EQ(st.reshaded, 0u);
  EXPECT_GT(st.rays, 2 * st.edgePixels);
}

// The edges' kept samples belong to the camera that traced them: four views of one size, each
// nearer the plate than the last (one more than the renderer keeps, so a view takes over the
// cache of another, whose rays end sooner), two punches at each: the same bytes as a fresh render
// every time. Before them a coarse picture of another size without anti-aliasing, and a view's
// cache taken over by another whose first picture is a dirty update.
TEST(DirtyRegion, KeptEdgeSamplesAreTheirCamerasOwn) {
  StrokedPlateScene scene(23);
  const PieceOptions& opt = scene.opt;
  const GeneratedPiece& piece = scene.piece;
  Renderer& live = scene.live;
  Model& model = scene.model;
  PieceRandom rng(31);
  live.setShading(shading(model));
  live.sync(model);
  Image image;
  live.setCamera(Camera(piece.camera, 32, 20));
  live.setAntialias(false);
  live.renderFull(image);
  live.setAntialias(true);
  std::vector<Camera> views;
  for (int k = 0; k < 4; ++k) {
    views.emplace_back(nearer(piece.camera, 1.0 - 0.12 * k), 128, 80);
  }
  const RenderOptions options;
  // The nearest view's frame; then the three others set (the last takes over its cache) and the
  // last one's whole picture rendered as a dirty update: no ray of it is kept yet.
  live.setCamera(views[3]);
  live.renderFull(image);
  for (int k = 0; k < 3; ++k) live.setCamera(views[static_cast<size_t>(k)]);
  RenderStats first;
  ASSERT_TRUE(live.render(image, Rect{0, 0, 128, 80}, &first));
  EXPECT_EQ(first.reshaded, 0u);
  ASSERT_TRUE(againstFresh(model, views[2], options, image).empty());
  std::uint64_t reshaded = 0, edges = 0;
  for (int round = 0; round < 3; ++round)
    for (size_t k = 0; k < views.size(); ++k) {
      SCOPED_TRACE("round " + std::to_string(round) + ", view " + std::to_string(k));
      live.setCamera(views[k]);
      live.renderFull(image);  // (the punches made at the other views)
      for (int punch = 0; punch < 2; ++punch) {
        const Operation op = punch == 0 ? randomPunch(rng, piece, opt.toolScale) : randomTraceSegment(rng, piece, opt.toolScale);
        ASSERT_TRUE(model.add(op).ok());
        live.sync(model);
        RenderStats st;
        ASSERT_TRUE(live.render(image, live.dirtySpans(model, model.activeCount() - 1), &st));
        reshaded += st.reshaded, edges += st.edgePixels;
        const std::string diff = againstFresh(model, views[k], options, image);
        ASSERT_TRUE(diff.empty()) << diff << " (punch " << punch << ")";
      }
    }
  EXPECT_GT(edges, 0u);
  EXPECT_GT(reshaded, 0u);
}

// A camera's kept hits in a slot that held a bigger picture before: the slots grow without
// clearing (HitCache), so the other camera's hits are still in the memory a new camera takes
// over. A view of the plate, three small pictures (the last takes over the view's slot, shrinking
// it), the first two of them again, then another view of the first one's size, which grows that
// slot again: its whole picture as a dirty update, after a punch, must trace every ray (none of
// them is kept yet) and give a fresh render's bytes.
TEST(DirtyRegion, ASlotGrownAgainKeepsNoHitOfTheCameraBefore) {
  StrokedPlateScene scene(29);
  const GeneratedPiece& piece = scene.piece;
  Renderer& live = scene.live;
  Model& model = scene.model;
  live.setShading(shading(model));
  live.sync(model);
  const Camera view(piece.camera, 128, 80), other(nearer(piece.camera, 0.8), 128, 80);
  const Camera small[3] = {Camera(piece.camera, 32, 20), Camera(piece.camera, 24, 15), Camera(piece.camera, 16, 10)};
  Image image;
  live.setCamera(view);
  live.renderFull(image);
  for (const Camera& c : small) {
    live.setCamera(c);
    live.renderFull(image);
  }
  live.setCamera(small[0]);
  live.setCamera(small[1]);
  live.setCamera(other);  // (the slot of small[2], once the view's)
  PieceRandom rng(5);
  ASSERT_TRUE(model.add(randomPunch(rng, piece, scene.opt.toolScale)).ok());
  live.sync(model);
  image = Image();
  RenderStats st;
  ASSERT_TRUE(live.render(image, Rect{0, 0, 128, 80}, &st));
  EXPECT_EQ(st.reshaded, 0u);
  const std::string diff = againstFresh(model, other, RenderOptions{}, image);
  EXPECT_TRUE(diff.empty()) << diff;
}

// A bead floating above the sheet moves with the sheet under it: strokes under it reshape it
// where they reach, at its heights, not the sheet's. The kept hits there are traced again.
TEST(DirtyRegion, KeptHitsUnderASetOperationsToolAreTracedAgain) {
  SmallPlateScene scene(5);
  const GeneratedPiece& piece = scene.piece;
  Renderer& live = scene.live;
  Model& model = scene.model;
  PieceRandom rng(91);
  Operation bead = randomSetOperation(rng, piece, 2.0);
  bead.kind = OpKind::BlendUnion;
  bead.tool.center = {0.0, 0.0, 0.5 + 6.0 * bead.tool.r};
  ASSERT_TRUE(model.add(bead).ok());
  const Camera camera(piece.camera, 160, 100);
  live.setCamera(camera);
  live.setShading(shading(model));
  live.sync(model);
  Image image;
  live.renderFull(image);
  const RenderOptions options;
  std::uint64_t reshaded = 0;
  for (int k = 0; k < 6; ++k) {
    Operation punch = randomPunch(rng, piece);
    punch.at.x = bead.tool.center.x + rng.uniform(-2.0, 2.0), punch.at.y = bead.tool.center.y + rng.uniform(-2.0, 2.0);
    if (k % 2 == 1) punch.p = -punch.p;  // from both sides
    ASSERT_TRUE(model.add(punch).ok());
    live.sync(model);
    RenderStats st;
    ASSERT_TRUE(live.render(image, live.dirtySpans(model, model.activeCount() - 1), &st));
    reshaded += st.reshaded;
    const std::string diff = againstFresh(model, camera, options, image);
    ASSERT_TRUE(diff.empty()) << "punch " << k << ": " << diff;
  }
  EXPECT_GT(reshaded, 0u);
}

// A ray whose kept hit lies in front of a change (on metal nearer the eye than where the change's
// column reaches) keeps it, though the column's projection holds it: a low view over a tall
// raised band, punches just beyond its far edge. Their dirty updates still give the bytes of a
// fresh full render.
TEST(DirtyRegion, KeptHitsInFrontOfAChangeAreShadedAgainNotTraced) {
  SmallPlateScene scene(5);
  PieceRandom rng(17);
  Operation band = randomRegion(rng, scene.piece, 1.0);
  band.points = {{-22.0, -15.0}, {22.0, -15.0}, {22.0, 0.0}, {-22.0, 0.0}};
  band.height = 3.0, band.falloff = 1.5;
  ASSERT_TRUE(scene.model.add(band).ok());
  CameraSpec spec = scene.piece.camera;
  spec.eye = {0.0, -70.0, 45.0}, spec.target = {0.0, 4.0, 0.0};
  const Camera camera(spec, 160, 100);
  scene.live.setCamera(camera);
  scene.live.setShading(shading(scene.model));
  scene.live.setAntialias(false);  // one ray a pixel: every pixel of the spans is traced or shaded again
  RenderOptions options;
  scene.live.sync(scene.model);
  Image image;
  scene.live.renderFull(image);
  long kept = 0;
  for (int k = 0; k < 3; ++k) {
    // Every pixel's hit now, as the renderer traces it.
    std::vector<std::optional<glm::dvec3>> before(static_cast<size_t>(camera.width()) * camera.height());
    for (int y = 0; y < camera.height(); ++y)
      for (int x = 0; x < camera.width(); ++x)
        ASSERT_TRUE(scene.live.pick(scene.model, camera, x + 0.5, y + 0.5, before[static_cast<size_t>(y) * camera.width() + x]));
    Operation punch = randomPunch(rng, scene.piece);
    punch.at.x = -8.0 + 8.0 * k, punch.at.y = 5.0;
    ASSERT_TRUE(scene.model.add(punch).ok());
    scene.live.sync(scene.model);
    const PixelSpans dirty = scene.live.dirtySpans(scene.model, scene.model.activeCount() - 1);
    // The pixels whose ray, from the eye to its hit, stays well clear of the punch's support
    // seen from above (its radius, the field's stencil and a ray cell less than 1.5 mm): no
    // change of the sheet there can move their hits.
    const double clear = scene.model.operations().back().supportPieces().radius + 1.5;
    const glm::dvec2 c(punch.at.x, punch.at.y), eye(spec.eye.x, spec.eye.y);
    long inFront = 0;
    for (int y = dirty.box.y; y < dirty.box.y + dirty.box.h; ++y) {
      const PixelSpans::Span row = dirty.row(y);
      for (int x = row.x0; x < row.x1; ++x) {
        const auto& h = before[static_cast<size_t>(y) * camera.width() + x];
        if (!h) continue;
        const glm::dvec2 e = glm::dvec2(h->x, h->y) - eye;
        const double u = std::clamp(glm::dot(c - eye, e) / glm::dot(e, e), 0.0, 1.0);
        inFront += glm::length(eye + u * e - c) > clear;
      }
    }
    RenderStats st;
    ASSERT_TRUE(scene.live.render(image, dirty, &st));
    // Those are shaded again at their kept hits, not traced.
    EXPECT_LE(static_cast<long>(st.rays) + inFront, dirty.area()) << "punch " << k;
    kept += inFront;
    const std::string diff = againstFresh(scene.model, camera, options, image, /*antialias=*/false);
    ASSERT_TRUE(diff.empty()) << "punch " << k << ": " << diff;
  }
  // The view holds many such pixels (a band of metal in front of each punch's column).
  EXPECT_GT(kept, 600);
}

// A blending punch's beads gone round an ellipse three times: the rays through the tangle are
// searched on their cells' ends (dense rays), and a dirty update after each bead still gives the
// bytes of a fresh full render.
TEST(DirtyRegion, ATangleOfBlendBeadsEndsAsAFullRender) {
  SmallPlateScene scene(0);
  const GeneratedPiece& piece = scene.piece;
  Renderer& live = scene.live;
  Model& model = scene.model;
  const Camera camera(piece.camera, 160, 100);
  live.setCamera(camera);
  live.setShading(shading(model));
  live.sync(model);
  Image image;
  live.renderFull(image);
  const RenderOptions options;
  std::uint64_t dense = 0;
  constexpr int kBeads = 36;
  for (int i = 0; i < kBeads; ++i) {
    // 2.1 mm apart round an ellipse of some 75 mm: three laps, each bead on the last lap's.
    const double a = i * 2.1 / 12.0;
    Operation bead;
    bead.kind = OpKind::BlendUnion;
    bead.tool.type = ToolShape::Type::Sphere;
    bead.tool.r = 1.5;
    bead.tool.center = {14.0 * std::cos(a), 9.0 * std::sin(a), 0.5 - 1.5 + 0.4};
    bead.a1 = 0.45, bead.a2 = 0.75, bead.a3 = 1.5;
    ASSERT_TRUE(model.add(bead).ok());
    live.sync(model);
    RenderStats st;
    ASSERT_TRUE(live.render(image, live.dirtySpans(model, model.activeCount() - 1), &st));
    dense += st.denseRays;
    if (i % 6 == 5 || i == kBeads - 1) {
      const std::string diff = againstFresh(model, camera, options, image);
      ASSERT_TRUE(diff.empty()) << "bead " << i << ": " << diff;
    }
  }
  EXPECT_GT(dense, 100u);
  RenderStats full;
  live.renderFull(image, &full);
  EXPECT_GT(full.denseRays, 100u);
}

// The pixels that differ between two frames; each must lie in the spans (the first that does not
// fails the test and ends the count).
int changedWithin(const Image& before, const Image& after, const PixelSpans& dirty) {
  int changed = 0;
  for (int y = 0; y < after.height; ++y)
    for (int x = 0; x < after.width; ++x)
      if (std::memcmp(after.pixel(x, y), before.pixel(x, y), 4) != 0) {
        ++changed;
        if (!dirty.contains(x, y)) {
          ADD_FAILURE() << "pixel (" << x << ", " << y << ") changed outside the spans";
          return changed;
        }
      }
  return changed;
}

// The piece's own camera (view 0) or one at a slant from its front right (view 1), at 480x300.
Camera fromAboveOrASlant(CameraSpec spec, int view) {
  if (view == 1) spec.eye = {25, -45, 40};
  return Camera(spec, 480, 300);
}

TEST(DirtyRegion, AStrokesSpansHoldWhatItChangesAndLessThanItsRectangle) {
  const GeneratedPiece piece = generatePiece(60, 21, PieceOptions{PieceShape::Plate, 60.0, 40.0, 0.4, Deformation::Sheet, 1.0});
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok()) << model.error();
  ThreadPool pool(2);
  for (int view = 0; view < 2; ++view) {
    const Camera camera = fromAboveOrASlant(piece.camera, view);
    Renderer r(pool);
    r.setCamera(camera);
    r.setShading(shading(*model));
    r.sync(*model);
    Image before;
    ASSERT_TRUE(r.renderFull(before));
    PieceRandom rng(5 + view);
    long spanPixels = 0, boxPixels = 0;
    for (int k = 0; k < 8; ++k) {
      Operation op = k % 4 == 0 ? randomPunch(rng, piece) : k % 4 == 1 ? randomTraceSegment(rng, piece) : k % 4 == 2 ? randomRegion(rng, piece, 0.5) : randomTraceSegment(rng, piece);
      if (k % 4 == 3) op.kind = OpKind::Patina, op.tinge = 2, op.a = 2.0, op.strength = 0.8;
      SCOPED_TRACE("view " + std::to_string(view) + ", stroke " + std::to_string(k) + " (" + opKindName(op.kind) + ")");
      ASSERT_TRUE(model->add(op).ok());
      r.sync(*model);
      const PixelSpans dirty = r.dirtySpans(*model, model->activeCount() - 1);
      Image after;
      ASSERT_TRUE(r.renderFull(after));
      EXPECT_GT(changedWithin(before, after, dirty), 0);
      spanPixels += dirty.area(), boxPixels += dirty.box.area();
      model->undo();
      r.sync(*model);
    }
    EXPECT_LT(spanPixels, boxPixels * 85 / 100) << "view " << view;
  }
}

// A ball (a sphere tool's set operation) changes the pixels of its capsule's column, not of its
// box: its spans hold every pixel it changes and are smaller than the box's projection.
TEST(DirtyRegion, ABallsSpansAreItsColumnsNotItsBox) {
  const GeneratedPiece piece = generatePiece(60, 22, PieceOptions{PieceShape::Plate, 60.0, 40.0, 0.4, Deformation::Sheet, 1.0});
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok()) << model.error();
  ThreadPool pool(2);
  for (int view = 0; view < 2; ++view) {
    const Camera camera = fromAboveOrASlant(piece.camera, view);
    Renderer r(pool), boxes(pool);
    RenderOptions o;
    o.roundWindows = false;
    boxes.setOptions(o);
    for (Renderer* x : {&r, &boxes}) x->setCamera(camera), x->setShading(shading(*model)), x->sync(*model);
    Image before;
    ASSERT_TRUE(r.renderFull(before));
    PieceRandom rng(11 + view);
    long spanPixels = 0, boxPixels = 0;
    for (int k = 0; k < 4; ++k) {
      SCOPED_TRACE("view " + std::to_string(view) + ", ball " + std::to_string(k));
      ASSERT_TRUE(model->add(randomSetOperation(rng, piece, 1.0)).ok());
      r.sync(*model), boxes.sync(*model);
      const PixelSpans dirty = r.dirtySpans(*model, model->activeCount() - 1);
      Image after;
      ASSERT_TRUE(r.renderFull(after));
      EXPECT_GT(changedWithin(before, after, dirty), 0);
      spanPixels += dirty.area(), boxPixels += boxes.dirtySpans(*model, model->activeCount() - 1).area();
      model->undo();
      r.sync(*model), boxes.sync(*model);
    }
    EXPECT_LT(spanPixels, boxPixels * 9 / 10) << "view " << view;
  }
}

// Longer runs, more seeds and larger pictures.
// Pixels outside the projection of the clip box are taken as misses without a ray: the picture
// is the one every pixel's ray gives, seen from above, at a slant, close up (the plate beyond the
// frame's edges), from low down and from beside the sheet, for both tracers.
TEST(DirtyRegion, CullingOutsideTheClipBoxChangesNoPixel) {
  const GeneratedPiece piece = generatePiece(50, 9, PieceOptions{PieceShape::Plate, 80.0, 60.0, 0.4, Deformation::Sheet, 2.0});
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok()) << model.error();
  // With a set operation lifting the clip box above the sheet.
  PieceRandom rng(3);
  ASSERT_TRUE(model->add(randomSetOperation(rng, piece, 2.0)).ok());
  const std::vector<CameraSpec> cameras = [] {
    std::vector<CameraSpec> c(5);
    c[0].eye = {0, 0, 150};
    c[1].eye = {30, -90, 80};
    c[2].eye = {5, -20, 35};   // close up: the plate fills the frame and more
    c[3].eye = {0, -120, 6};   // low down, nearly along the sheet
    c[4].eye = {70, 10, 1};    // beside the sheet, at its height
    return c;
  }();
  ThreadPool pool(2);
  for (bool exact : {false, true}) {
    for (size_t k = 0; k < cameras.size(); ++k) {
      Renderer culled(pool), all(pool);
      const Camera cam(cameras[k], 96, 64);
      for (Renderer* r : {&culled, &all}) {
        RenderOptions o;
        o.exact = exact;
        o.cullOutsideClip = r == &culled;
        r->setOptions(o);
        r->setCamera(cam);
        r->setShading(shading(*model));
        r->sync(*model);
      }
      Image a, b;
      culled.renderFull(a);
      all.renderFull(b);
      EXPECT_EQ(firstDifference(a, b), "") << "camera " << k << (exact ? " (exact tracer)" : "");
    }
  }
}

// A flat tool beating the relief down, its face half sizes `half`, at `center`.
Operation flatTool(OpKind kind, const Vec3& center, const Vec3& half, double a1) {
  Operation flat;
  flat.kind = kind;
  flat.tool.type = ToolShape::Type::Flat;
  flat.tool.half = half;
  flat.tool.center = center;
  flat.a1 = a1, flat.a2 = 1.2, flat.a3 = 1.2;
  return flat;
}

// A pile of `count` flat tools beating one spot down, as a visitor does, `pitch` apart along x and
// up to `spreadY` off the line: rays through it are dense.
void addFlatPile(Model& model, PieceRandom& rng, double d, int count, double pitch, double spreadY) {
  for (int i = 0; i < count; ++i) {
    const Vec3 c{-10.0 + pitch * i + rng.uniform(-0.5, 0.5), 5.0 + rng.uniform(-spreadY, spreadY), d + rng.uniform(0.3, 1.5)};
    EXPECT_TRUE(model.add(flatTool(OpKind::BlendSubtract, c, {3.0, 2.1, 1.0}, 0.135)).ok());
  }
}

// Full frames of `model` by two renderers alike but for `option`, set for the first and cleared for
// the second, seen from above, at the kiosk's slant, close up and low down: calls check(view, with,
// its stats, without, its stats) for each view. The other options are `base`'s.
template <class Check>
void framesWithAndWithout(const Model& model, bool RenderOptions::*option, int w, int h, Check&& check,
                          const RenderOptions& base = {}) {
  std::vector<CameraSpec> views(4);
  views[0].eye = {0, 0, 150};
  views[1].eye = {0, -70, 170};  // the kiosk's slant
  views[2].eye = {8, -25, 30};   // close up
  views[3].eye = {0, -110, 12};  // low down
  ThreadPool pool(2);
  for (size_t k = 0; k < views.size(); ++k) {
    Renderer with(pool), without(pool);
    const Camera cam(views[k], w, h);
    for (Renderer* r : {&with, &without}) {
      RenderOptions o = base;
      o.*option = r == &with;
      r->setOptions(o);
      r->setCamera(cam);
      r->setShading(shading(model));
      r->sync(model);
    }
    Image a, b;
    RenderStats sa, sb;
    with.renderFull(a, &sa);
    without.renderFull(b, &sb);
    check(k, a, sa, b, sb);
  }
}

// A ray's list of set operations leaves out those whose support meets its reach but whose box it
// misses: the picture is still the one the whole list gives. Beads, cuts and flat tools beating
// the relief down, between the strokes that move them after (their shifts), seen from above, at a
// slant, close up and low down.
TEST(DirtyRegion, LeavingOutTheSetOperationsARayMissesChangesNoPixel) {
  const GeneratedPiece piece = generatePiece(60, 4, PieceOptions{PieceShape::Plate, 60.0, 40.0, 0.25, Deformation::Sheet, 2.0});
  Model model(piece.workpiece, piece.deformation);
  PieceRandom rng(11);
  const double d = piece.workpiece->halfThickness();
  for (size_t k = 0; k < piece.operations.size(); ++k) {
    ASSERT_TRUE(model.add(piece.operations[k]).ok());
    if (k % 3 != 0) continue;
    ASSERT_TRUE(model.add(randomSetOperation(rng, piece, 1.0)).ok());
    const Vec3 c{rng.uniform(-26.0, 26.0), rng.uniform(-16.0, 16.0), d + rng.uniform(0.5, 3.0)};
    ASSERT_TRUE(model.add(flatTool(OpKind::BlendSubtract, c, {3.0, 2.1, 1.0}, 0.135)).ok());
  }
  framesWithAndWithout(model, &RenderOptions::cullRaySetOps, 120, 80,
                       [](size_t k, const Image& a, const RenderStats& sa, const Image& b, const RenderStats& sb) {
                         EXPECT_EQ(firstDifference(a, b), "") << "camera " << k;
                         EXPECT_GT(sa.setOpsLeftOut, sa.rays / 8) << "camera " << k;
                         EXPECT_EQ(sb.setOpsLeftOut, 0u) << "camera " << k;
                         EXPECT_GT(sb.opsVisited, sa.opsVisited) << "camera " << k;
                       });
}

// Inside the windows of flat tools beating the relief down (subtractions alone) a ray takes
// Lipschitz steps from high above the sheet, their bumps counted: the picture is still the one the
// interval tests alone give, from above, at a slant, close up and low down, with tools from just
// over the sheet to well above it, and a pile of them whose rays are dense (their steps land on
// their cells' ends).
TEST(DirtyRegion, LipschitzStepsInsideTheSubtractionsWindowsChangeNoPixel) {
  const GeneratedPiece piece = generatePiece(60, 4, PieceOptions{PieceShape::Plate, 60.0, 40.0, 0.25, Deformation::Sheet, 2.0});
  Model model(piece.workpiece, piece.deformation);
  PieceRandom rng(17);
  const double d = piece.workpiece->halfThickness();
  for (size_t k = 0; k < piece.operations.size(); ++k) {
    ASSERT_TRUE(model.add(piece.operations[k]).ok());
    if (k % 2 != 0) continue;
    const Vec3 half{rng.uniform(1.0, 3.0), rng.uniform(1.0, 2.1), rng.uniform(0.5, 1.0)};
    const Vec3 c{rng.uniform(-26.0, 26.0), rng.uniform(-16.0, 16.0), d + rng.uniform(0.2, 3.0)};
    const double a1 = rng.uniform(0.05, 0.4);
    ASSERT_TRUE(model.add(flatTool(k % 8 == 0 ? OpKind::Subtract : OpKind::BlendSubtract, c, half, a1)).ok());
  }
  addFlatPile(model, rng, d, 14, 0.7, 1.0);
  // (The window's steps on their own: the pile's tops, tried first, would take most of them.)
  RenderOptions withoutPileTops;
  withoutPileTops.pileTops = false;
  framesWithAndWithout(model, &RenderOptions::lipschitzInWindows, 160, 100,
                       [](size_t k, const Image& a, const RenderStats& sa, const Image& b, const RenderStats& sb) {
                         EXPECT_EQ(firstDifference(a, b), "") << "camera " << k;
                         EXPECT_GT(sa.windowSteps, sa.rays / 20) << "camera " << k;
                         EXPECT_GT(sa.denseRays, sa.rays / 100) << "camera " << k;
                         EXPECT_EQ(sb.windowSteps, 0u) << "camera " << k;
                       },
                       withoutPileTops);
}

// A pile of flat tools beating one spot down, as a visitor does (its rays dense), beside blended
// beads floating above it (unions, whose boxes reach far above the sheet), and flat tools over the
// rest of the plate.
Model pileOfFlatTools(std::uint32_t seed) {
  const GeneratedPiece piece = generatePiece(40, seed, PieceOptions{PieceShape::Plate, 60.0, 40.0, 0.25, Deformation::Sheet, 2.0});
  Model model(piece.workpiece, piece.deformation);
  PieceRandom rng(seed * 31u + 7u);
  const double d = piece.workpiece->halfThickness();
  for (size_t k = 0; k < piece.operations.size(); ++k) {
    EXPECT_TRUE(model.add(piece.operations[k]).ok());
    if (k % 4 != 0) continue;
    const Vec3 c{rng.uniform(-26.0, 26.0), rng.uniform(-16.0, 16.0), d + rng.uniform(0.2, 2.0)};
    EXPECT_TRUE(model.add(flatTool(OpKind::BlendSubtract, c, {3.0, 2.1, 1.0}, 0.135)).ok());
  }
  addFlatPile(model, rng, d, 16, 0.6, 1.5);
  for (int i = 0; i < 2; ++i) {
    Operation bead;
    bead.kind = OpKind::BlendUnion;
    bead.tool.type = ToolShape::Type::Sphere;
    bead.tool.r = 1.5;
    bead.tool.center = {-6.0 + 5.0 * i, 5.0, d + 6.0 + 3.0 * i};
    bead.a1 = 0.27, bead.a2 = 1.0, bead.a3 = 2.0;
    EXPECT_TRUE(model.add(bead).ok());
  }
  return model;
}

// Inside the windows of set operations a ray first skips what lies above the pile's tops of the
// columns it crosses: the picture is still the one the windows' own steps and interval tests give,
// from above, at a slant, close up and low down, with fewer evaluations.
TEST(DirtyRegion, SkippingAboveThePilesTopsChangesNoPixel) {
  const Model model = pileOfFlatTools(19);
  framesWithAndWithout(model, &RenderOptions::pileTops, 160, 100,
                       [](size_t k, const Image& a, const RenderStats& sa, const Image& b, const RenderStats& sb) {
                         EXPECT_EQ(firstDifference(a, b), "") << "camera " << k;
                         EXPECT_GT(sa.pileSkips, sa.rays / 50) << "camera " << k;
                         EXPECT_GT(sa.denseRays, sa.rays / 100) << "camera " << k;
                         EXPECT_EQ(sb.pileSkips, 0u) << "camera " << k;
                         EXPECT_LT(sa.evaluations, sb.evaluations) << "camera " << k;
                       });
}

// The pile's tops are found once and kept: strokes under the pile (punches raising it from
// behind, a raised region, a trace), more flat tools on it, undos and redos move them, and after
// each the full frame (which reads the tops kept) and the dirty update (which does not) still give
// the bytes of a fresh full render.
TEST(DirtyRegion, ThePilesTopsFollowWhatChangesUnderThem) {
  Model model = pileOfFlatTools(23);
  ThreadPool pool(2);
  Renderer live(pool);
  CameraSpec view;
  view.eye = {-4, -60, 60}, view.target = {-4, 5, 0};
  const Camera camera(view, 160, 100);
  live.setCamera(camera);
  live.setShading(shading(model));
  live.sync(model);
  Image image;
  RenderStats first;
  live.renderFull(image, &first);
  ASSERT_GT(first.pileSkips, 0u);
  PieceRandom rng(5);
  const double d = model.workpiece().halfThickness();
  for (int step = 0; step < 12; ++step) {
    std::string what;
    size_t index;
    if (step % 4 == 3 && model.canUndo()) {
      model.undo();
      index = model.activeCount();
      what = "undo";
    } else if (step % 4 == 0 && model.canRedo() && step > 0) {
      model.redo();
      index = model.activeCount() - 1;
      what = "redo";
    } else {
      Operation op;
      const double x = rng.uniform(-11.0, 0.0), y = rng.uniform(3.0, 7.0);
      if (step % 3 == 0) {
        op.kind = OpKind::Punch, op.side = Side::Back, op.a = rng.uniform(1.2, 2.0), op.p = rng.uniform(0.6, 1.0), op.q = 1.0;
        op.at = {x, y, 0.0};
      } else if (step % 3 == 1) {
        op = flatTool(OpKind::BlendSubtract, {x, y, d + rng.uniform(0.5, 1.5)}, {3.0, 2.1, 1.0}, 0.135);
      } else if (step == 2) {
        op.kind = OpKind::Region, op.side = Side::Back, op.height = 1.5, op.falloff = 2.0;
        for (int i = 0; i < 16; ++i) {
          const double a = 2.0 * std::numbers::pi * i / 16;
          op.points.push_back({-6.0 + 6.0 * std::cos(a), 5.0 + 4.0 * std::sin(a)});
        }
      } else {
        op.kind = OpKind::Trace, op.side = Side::Back, op.a = 0.8;
        op.points = {{x - 4.0, y}, {x + 4.0, y + 1.0}};
      }
      ASSERT_TRUE(model.add(op).ok());
      index = model.activeCount() - 1;
      what = std::string("add ") + opKindName(op.kind);
    }
    SCOPED_TRACE("step " + std::to_string(step) + ": " + what);
    live.sync(model);
    ASSERT_TRUE(live.render(image, live.dirtySpans(model, index)));
    std::string diff = againstFresh(model, camera, RenderOptions{}, image);
    ASSERT_TRUE(diff.empty()) << "dirty update: " << diff;
    RenderStats st;
    ASSERT_TRUE(live.renderFull(image, &st));
    EXPECT_GT(st.pileSkips, 0u);
    diff = againstFresh(model, camera, RenderOptions{}, image);
    ASSERT_TRUE(diff.empty()) << "full frame: " << diff;
  }
}

// On an outline sheet only the pixels over the column leaves the outline reaches, and over the set
// operations' boxes, are traced: the picture is still the one every pixel's ray gives, with a bead
// blended on beside the outline (where no column is inside), from above, at a slant and low down.
TEST(DirtyRegion, CullingOutsideAnOutlineChangesNoPixel) {
  auto outline = generateOutlinePiece(150, 5, 18.0, 0.5, 30, 5, true);
  ASSERT_TRUE(outline.ok()) << outline.error();
  const GeneratedPiece& piece = *outline;
  const Box3 b = piece.workpiece->bounds();
  Model model(piece.workpiece, piece.deformation);
  for (const Operation& o : piece.operations) ASSERT_TRUE(model.add(o).ok());
  // A bead at a corner of the bounds, outside the outline: a surface no inside column holds.
  Operation bead;
  bead.kind = OpKind::BlendUnion;
  bead.tool.type = ToolShape::Type::Sphere;
  bead.tool.r = 1.5;
  bead.tool.center = {b.x0 + 1.0, b.y0 + 1.0, 0.5};
  bead.a1 = 0.4, bead.a2 = 1.0, bead.a3 = 3.0;
  ASSERT_TRUE(piece.workpiece->value(P3<double>{bead.tool.center.x, bead.tool.center.y, 0.0}) < 0.0) << "the bead should lie outside";
  ASSERT_TRUE(model.add(bead).ok());
  const double cx = 0.5 * (b.x0 + b.x1), cy = 0.5 * (b.y0 + b.y1), span = b.x1 - b.x0;
  std::vector<CameraSpec> cameras(3);
  cameras[0].eye = {cx, cy, 2.5 * span}, cameras[0].target = {cx, cy, 0};
  cameras[1].eye = {cx + 0.6 * span, cy - 1.2 * span, 1.0 * span}, cameras[1].target = {cx, cy, 0};
  cameras[2].eye = {cx, cy - 1.6 * span, 0.15 * span}, cameras[2].target = {cx, cy, 0};
  ThreadPool pool(2);
  long beadPixels = 0;
  for (size_t k = 0; k < cameras.size(); ++k) {
    Renderer culled(pool), all(pool);
    const Camera cam(cameras[k], 320, 200);
    for (Renderer* r : {&culled, &all}) {
      RenderOptions o;
      o.cullOutsideClip = r == &culled;
      r->setOptions(o);
      r->setCamera(cam);
      r->setShading(shading(model));
      r->sync(model);
    }
    Image a, c;
    culled.renderFull(a);
    all.renderFull(c);
    EXPECT_EQ(firstDifference(a, c), "") << "camera " << k;
    // The bead shows: its pixels differ from the backdrop's.
    if (const auto q = cam.project({bead.tool.center.x, bead.tool.center.y, bead.tool.center.z + bead.tool.r}))
      if (q->x >= 0 && q->y >= 0 && q->x < a.width && q->y < a.height) {
        Image bare;
        Renderer none(pool);
        none.setCamera(cam);
        none.setShading(shading(model));
        Model plain(piece.workpiece, piece.deformation);
        none.sync(plain);
        none.renderFull(bare);
        beadPixels += std::memcmp(a.pixel(static_cast<int>(q->x), static_cast<int>(q->y)),
                                  bare.pixel(static_cast<int>(q->x), static_cast<int>(q->y)), 3) != 0;
      }
  }
  EXPECT_GT(beadPixels, 0) << "the bead should be seen from some camera";
}

// A big raised region added to the field a band of rows at a time (RenderOptions::fieldBandMs:
// here so short that each call adds eight rows), each band's pixels traced as it lands: part of
// it shows after the first, and after the last the bytes are a fresh full render's. A stroke made
// while bands are pending finishes them first, and an undo puts back the samples, both to the
// same bytes.
TEST(DirtyRegion, ABigRegionAddedABandOfRowsAtATimeEndsAsAFullRender) {
  const PieceOptions opt = smallPlate(1.6);
  const GeneratedPiece piece = generatePiece(16, 23, opt);  // set operations among them
  PieceRandom rng(41);
  ThreadPool pool(2);
  Renderer live(pool);
  Model model(piece.workpiece, piece.deformation);
  for (const Operation& op : piece.operations) ASSERT_TRUE(model.add(op).ok());
  const Camera camera(piece.camera, 128, 80);
  live.setCamera(camera);
  live.setShading(shading(model));
  RenderOptions options;
  options.fieldBandMs = 1e-6;
  constexpr long least = Renderer::kFieldBandMinSamples;
  live.setOptions(options);
  live.sync(model);
  Image image;
  live.renderFull(image);
  auto region = [&] {
    // One that more than a few bands hold.
    for (;;) {
      Operation o = randomRegion(rng, piece, opt.toolScale);
      const PreparedOp p(o);
      if (live.field().samplesIn(p.support()).count() > 5 * least) return o;
    }
  };

  ASSERT_TRUE(model.add(region()).ok());
  live.sync(model);
  ASSERT_TRUE(live.fieldPending());
  EXPECT_LE(live.lastSync().samplesUpdated, 8 * live.field().nx());  // its first eight rows only
  ASSERT_TRUE(live.render(image, live.dirtySpans(model, model.activeCount() - 1)));
  EXPECT_FALSE(againstFresh(model, camera, options, image).empty()) << "most of the region is not added yet";
  int bands = 1;
  while (live.fieldPending()) {
    const PixelSpans s = live.continueField(options.fieldBandMs);
    ASSERT_FALSE(s.empty());
    ASSERT_TRUE(live.render(image, s));
    ++bands;
  }
  EXPECT_GE(bands, 10);
  EXPECT_TRUE(live.continueField(options.fieldBandMs).empty());
  std::string diff = againstFresh(model, camera, options, image);
  EXPECT_TRUE(diff.empty()) << "after " << bands << " bands: " << diff;

  // A punch while a region's bands are pending: the sync adds the region's other rows first.
  ASSERT_TRUE(model.add(region()).ok());
  live.sync(model);
  ASSERT_TRUE(live.render(image, live.dirtySpans(model, model.activeCount() - 1)));
  ASSERT_TRUE(live.fieldPending());
  EXPECT_TRUE(live.pendingSpans().empty());
  ASSERT_TRUE(live.render(image, live.continueField(options.fieldBandMs)));
  ASSERT_TRUE(live.fieldPending());
  Operation punch = randomPunch(rng, piece, 0.3);
  while (live.field().samplesIn(PreparedOp(punch).support()).count() > least) punch = randomPunch(rng, piece, 0.3);
  ASSERT_TRUE(model.add(punch).ok());
  live.sync(model);
  EXPECT_FALSE(live.fieldPending());
  const PixelSpans rest = live.pendingSpans();
  EXPECT_FALSE(rest.empty());
  ASSERT_TRUE(live.render(image, rest));
  ASSERT_TRUE(live.render(image, live.dirtySpans(model, model.activeCount() - 1)));
  diff = againstFresh(model, camera, options, image);
  EXPECT_TRUE(diff.empty()) << "a punch after a pending region: " << diff;

  // Undone while its bands are pending: the samples before it, the bytes before it.
  ASSERT_TRUE(model.add(region()).ok());
  live.sync(model);
  ASSERT_TRUE(live.render(image, live.dirtySpans(model, model.activeCount() - 1)));
  ASSERT_TRUE(live.render(image, live.continueField(options.fieldBandMs)));
  ASSERT_TRUE(live.fieldPending());
  model.undo();
  live.sync(model);
  EXPECT_FALSE(live.fieldPending());
  EXPECT_TRUE(live.pendingSpans().empty());
  ASSERT_TRUE(live.render(image, live.dirtySpans(model, model.activeCount())));
  diff = againstFresh(model, camera, options, image);
  EXPECT_TRUE(diff.empty()) << "a pending region undone: " << diff;
}

TEST(DirtyRegionSlow, ManySeeds) {
  for (unsigned seed = 10; seed < 16; ++seed) {
    runCase({seed % 2 ? PieceShape::Disc : PieceShape::Plate, Deformation::Sheet, false, 320, 200, 80, seed});
    runCase({seed % 2 ? PieceShape::Plate : PieceShape::Disc, Deformation::Offset, false, 96, 64, 24, seed});
  }
}

}  // namespace
}  // namespace emboss
