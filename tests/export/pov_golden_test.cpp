// POV-Ray itself evaluates the exported function and renders the exported scene; both must agree with ours.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

#include "export/pov.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "test_support.h"

namespace emboss {
namespace {

bool havePovray() { return std::system("command -v povray >/dev/null 2>&1") == 0; }

const char* kAllOps = R"({"format":"emboss-scene","version":1,"deformation":"%DEF%",
  "workpiece":%WP%,
  "operations":[
   {"op":"trace","side":"front","a":0.6,"points":[[-12,-8],[-4,4],[8,6],[12,-4]]},
   {"op":"punch","side":"back","a":3,"p":0.5,"q":1.2,"at":[0,0,0.5]},
   {"op":"punch","side":"front","a":1.5,"p":0.4,"q":1,"at":[6,-5,0.5]},
   {"op":"press","side":"back","a":0.8,"p":0.1,"q":1,"points":[[-12,9],[10,10]]},
   {"op":"region","side":"back","contour":[[-14,-12],[-6,-12],[-6,-6],[-10,-3],[-14,-6]],"height":0.8,"falloff":1.2},
   {"op":"blend_union","tool":{"type":"sphere","center":[10,2,0.5],"r":2},"a1":0.8,"a2":1,"a3":2},
   {"op":"trace","side":"back","a":0.5,"points":[[-2,-10],[4,-9]],"join_end":{"dir":[6,1],"r":0.75}},
   {"op":"trace","side":"back","a":0.45,"points":[[4,-9],[7,-6],[8,-2]],"join_start":{"dir":[6,1],"r":0.75}},
   {"op":"blend_subtract","tool":{"type":"flat","center":[-8,6,0.9],"size":[4,3,1]},"a1":0.1,"a2":1,"a3":1},
   {"op":"subtract","tool":{"type":"cylinder","center":[3,8,-2],"end":[3,8,2],"r":0.8}},
   {"op":"punch","side":"back","a":2,"p":0.3,"q":1,"at":[9,2,0.5]}]})";

std::string sceneText(const std::string& def, const std::string& wp) {
  std::string s = kAllOps;
  s.replace(s.find("%DEF%"), 5, def);
  s.replace(s.find("%WP%"), 4, wp);
  return s;
}

// Runs POV-Ray on `pov` in `dir`; returns false (and the log) on failure.
bool runPovray(const std::filesystem::path& dir, const std::string& args, std::string& log) {
  const std::string cmd = "cd '" + dir.string() + "' && povray " + args + " -D -V >povray.log 2>&1";
  const int rc = std::system(cmd.c_str());
  log = test::readText(dir / "povray.log");
  return rc == 0;
}

struct Case {
  const char* name;
  const char* deformation;
  const char* workpiece;
};

class PovGolden : public ::testing::TestWithParam<Case> {};

// Has POV-Ray evaluate the exported Emboss_Function at points around the piece and compares.
void expectPovrayAgrees(const std::string& text, const std::filesystem::path& baseDir, const std::string& name) {
  const auto dir = test::scratchDir("pov-eval-" + name);
  auto scene = parseScene(text, "golden.json", baseDir);
  ASSERT_TRUE(scene) << scene.error();
  auto model = scene->makeModel();
  ASSERT_TRUE(model) << model.error();
  auto pov = exportPov(*scene, *model, {});
  ASSERT_TRUE(pov) << pov.error();
  std::ofstream(dir / "scene.pov") << *pov;

  // Points near the surface and around every operation, where the kernels differ from each other.
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> px(-16, 16), py(-14, 14), pz(-2, 3);
  std::vector<P3<double>> pts;
  for (int i = 0; i < 300; ++i) pts.push_back({px(rng), py(rng), pz(rng)});
  std::ofstream probe(dir / "probe.pov");
  probe << "#declare Emboss_Declare_Only = 1;\n#include \"scene.pov\"\n#fopen Out \"values.txt\" write\n";
  for (const auto& p : pts)
    probe << "#write (Out, str(Emboss_Function(" << p.x << ", " << p.y << ", " << p.z << "), 0, 16), \"\\n\")\n";
  probe << "#fclose Out\ncamera { location <0, 0, -10> look_at <0, 0, 0> }\n";
  probe.close();
  std::string log;
  ASSERT_TRUE(runPovray(dir, "+Iprobe.pov +W2 +H2 -GA +O/dev/null", log)) << log;
  std::ifstream values(dir / "values.txt");
  size_t n = 0, inside = 0;
  for (const auto& p : pts) {
    double v;
    ASSERT_TRUE(values >> v) << "POV-Ray wrote " << n << " values; log:\n" << log;
    // The points were written with the stream's default 6 significant digits: evaluate there.
    std::ostringstream sx, sy, sz;
    sx << p.x, sy << p.y, sz << p.z;
    const double ours = model->evaluate(P3<double>{std::stod(sx.str()), std::stod(sy.str()), std::stod(sz.str())});
    EXPECT_NEAR(v, ours, 1e-9 * std::max(1.0, std::abs(ours))) << "at " << p.x << " " << p.y << " " << p.z;
    inside += ours >= 0;
    ++n;
  }
  EXPECT_GT(inside, 0u) << "no probe point fell inside the piece: the comparison would prove little";
}

TEST_P(PovGolden, PovrayEvaluatesTheSameFunction) {
  if (!havePovray()) GTEST_SKIP() << "povray is not installed (platform/debian/packages.txt installs it)";
  const Case c = GetParam();
  expectPovrayAgrees(sceneText(c.deformation, c.workpiece), ".", c.name);
}

TEST(PovGoldenVm, PovrayEvaluatesImportedModels) {
  if (!havePovray()) GTEST_SKIP() << "povray is not installed";
  EMBOSS_REQUIRE_FIXTURES(fx);
  // A 2D outline made a plate, and a 3D model, each with every operation on top.
  expectPovrayAgrees(sceneText("sheet", R"({"type":"vm","file":"vm/hi.vm","scale":12,"d":0.5})"), fx, "vm_hi");
  expectPovrayAgrees(sceneText("offset", R"({"type":"vm","file":"vm/tanglecube.vm","scale":4,"d":0.5})"), fx, "vm_tanglecube");
}

// One picture is enough: POV-Ray's isosurfaces are slow.
TEST(PovGoldenPicture, PovrayRendersTheSamePicture) {
  if (!havePovray()) GTEST_SKIP() << "povray is not installed";
  const Case c{"plate_sheet", "sheet", R"({"type":"plate","w":16,"h":14,"d":0.5})"};
  const auto dir = test::scratchDir(std::string("pov-render-") + c.name);
  auto scene = parseScene(sceneText(c.deformation, c.workpiece), "golden.json", dir);
  ASSERT_TRUE(scene);
  auto model = scene->makeModel();
  ASSERT_TRUE(model);
  const int w = 72, h = 45;
  PovExportOptions opt;
  opt.width = w, opt.height = h;
  auto pov = exportPov(*scene, *model, opt);
  ASSERT_TRUE(pov);
  std::ofstream(dir / "scene.pov") << *pov;
  std::string log;
  ASSERT_TRUE(runPovray(dir, "+Iscene.pov +W72 +H45 +FN +Opov.png", log)) << log;
  auto theirs = readPng(dir / "pov.png");
  ASSERT_TRUE(theirs) << theirs.error();

  ThreadPool pool(2);
  Renderer r(pool);
  r.sync(*model);
  r.setCamera(Camera(scene->camera, w, h));
  ShadingParams sh;
  sh.metal = *metalByName("copper");
  sh.tinge = *tingeByName("none");
  r.setShading(sh);
  Image ours;
  r.renderFull(ours);
  ASSERT_TRUE(writePng(ours, dir / "ours.png"));
  // The same silhouette: pixels that show metal rather than the backdrop (emboss's vignetted
  // backdrop, POV-Ray's plain background as its corner shows it). Not a brightness threshold: the
  // metal mirrors the studio's dark room too.
  auto differs = [](const std::uint8_t* p, const std::array<std::uint8_t, 3>& bg) {
    return std::abs(p[0] - bg[0]) + std::abs(p[1] - bg[1]) + std::abs(p[2] - bg[2]) > 6;
  };
  const std::uint8_t* corner = theirs->pixel(0, 0);
  const std::array<std::uint8_t, 3> theirBackground{corner[0], corner[1], corner[2]};
  int both = 0, either = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool a = differs(ours.pixel(x, y), toSrgb8(backdrop(x, y, w, h)));
      const bool b = differs(theirs->pixel(x, y), theirBackground);
      both += a && b, either += a || b;
    }
  ASSERT_GT(either, 0);
  const double iou = static_cast<double>(both) / either;
  EXPECT_GT(iou, 0.95) << "silhouettes differ; see " << dir;
}

INSTANTIATE_TEST_SUITE_P(Scenes, PovGolden,
                         ::testing::Values(Case{"plate_sheet", "sheet", R"({"type":"plate","w":16,"h":14,"d":0.5})"},
                                           Case{"plate_offset", "offset", R"({"type":"plate","w":16,"h":14,"d":0.5})"},
                                           Case{"disc_sheet", "sheet", R"({"type":"disc","r":15,"d":0.4})"},
                                           Case{"bowl_offset", "offset", R"({"type":"bowl","r":15,"depth":3,"d":0.5})"}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace emboss
