// Scene files: defaults, round trips, and one clear message for each kind of malformed file.
#include <gtest/gtest.h>

#include "scene/scene.h"
#include "test_support.h"

namespace emboss {
namespace {

Result<Scene> parse(const std::string& text) { return parseScene(text, "piece.json", "."); }

std::string errorOf(const std::string& text) {
  auto s = parse(text);
  EXPECT_FALSE(s) << "expected a failure for: " << text;
  return s ? std::string() : s.error();
}

TEST(SceneFile, MinimalFileGetsDefaults) {
  auto s = parse(R"({"format":"emboss-scene","version":1})");
  ASSERT_TRUE(s) << s.error();
  EXPECT_EQ(s->deformation, Deformation::Sheet);
  EXPECT_EQ(s->metal, "copper");
  EXPECT_FALSE(s->cameraGiven);
  EXPECT_TRUE(s->operations.empty());
  ASSERT_TRUE(s->workpiece);
}

TEST(SceneFile, EveryOperationRoundTrips) {
  const std::string text = R"({"format":"emboss-scene","version":1,"deformation":"offset",
    "workpiece":{"type":"disc","r":30,"d":0.4},"metal":"brass","tinge":"green",
    "camera":{"type":"ortho","eye":[0,0,100],"target":[0,0,0],"up":[0,1,0],"fov_deg":30,"height":70},
    "operations":[
      {"op":"trace","side":"front","a":0.5,"points":[[0,0],[10,0],[10,5]],"join_end":{"dir":[0,1],"r":0.7}},
      {"op":"trace","side":"front","a":0.5,"points":[[10,5],[12,9]],"join_start":{"dir":[0,1],"r":0.7}},
      {"op":"punch","side":"back","a":2,"p":0.3,"q":1.5,"at":[1,2,0.4]},
      {"op":"press","side":"front","a":1,"p":0.1,"q":1,"points":[[0,0],[5,5]]},
      {"op":"region","side":"back","contour":[[0,0],[5,0],[5,5]],"height":0.6,"falloff":1.5},
      {"op":"blend_union","tool":{"type":"sphere","center":[0,0,0.4],"r":2},"a1":0.5,"a2":1,"a3":2},
      {"op":"blend_subtract","tool":{"type":"flat","center":[5,5,0.4],"size":[4,3,1]},"a1":0.1,"a2":1,"a3":1},
      {"op":"subtract","tool":{"type":"cylinder","center":[-5,0,-1],"end":[-5,0,1],"r":1}}]})";
  auto s = parse(text);
  ASSERT_TRUE(s) << s.error();
  ASSERT_EQ(s->operations.size(), 8u);
  EXPECT_EQ(s->operations[0].joinEnd.r, 0.7);
  EXPECT_EQ(s->operations[1].joinStart.dir.y, 1.0);
  EXPECT_FALSE(s->operations[1].joinEnd.on());
  auto m = s->makeModel();
  ASSERT_TRUE(m) << m.error();
  const std::string out = sceneToJson(*s, &*m);
  auto again = parse(out);
  ASSERT_TRUE(again) << again.error() << "\n" << out;
  EXPECT_EQ(sceneToJson(*again), sceneToJson(*s));
  auto m2 = again->makeModel();
  ASSERT_TRUE(m2);
  for (double x = -10; x <= 10; x += 1.7)
    EXPECT_EQ(m2->evaluate(P3<double>{x, 0.3 * x, 0.1}), m->evaluate(P3<double>{x, 0.3 * x, 0.1}));
}

TEST(SceneFile, MalformedFilesGetOneClearMessage) {
  EXPECT_EQ(errorOf("{\"format\":\"emboss-scene\",\n \"version\":1,,}"),
            "piece.json:2:14: not valid JSON: syntax error while parsing object key - unexpected ','; expected string literal");
  EXPECT_EQ(errorOf(R"({"format":"something-else"})"), "piece.json: format: must be \"emboss-scene\", not \"something-else\"");
  EXPECT_EQ(errorOf(R"({"version":2})"), "piece.json: version: this program reads version 1 scenes, the file says 2.0");
  EXPECT_EQ(errorOf(R"({"deformation":"rubber"})"), "piece.json: deformation: must be \"sheet\" or \"offset\", not \"rubber\"");
  EXPECT_EQ(errorOf(R"({"metal":"gold"})"), "piece.json: metal: unknown metal \"gold\" (copper, brass, silver or aluminium)");
  EXPECT_EQ(errorOf(R"({"workpiece":{"type":"plate","w":10,"h":-1,"d":0.5}})"), "piece.json: workpiece.h: -1 is out of range: 0.001 to 2000 mm");
  EXPECT_EQ(errorOf(R"({"workpiece":{"type":"cube"}})"), "piece.json: workpiece.type: unknown workpiece \"cube\" (plate, disc, bowl or vm)");
  EXPECT_EQ(errorOf(R"({"operations":[{"op":"punch","a":1,"at":[0,0,0]},{"op":"punch","a":"big","at":[0,0,0]}]})"),
            "piece.json: operations[1].a: must be a number, not string");
  EXPECT_EQ(errorOf(R"({"operations":[{"op":"trace","a":1,"points":[[0,0],[1]]}]})"),
            "piece.json: operations[0].points[1]: must be an array of 2 numbers");
  EXPECT_EQ(errorOf(R"({"operations":[{"op":"trace","a":1,"points":[[0,0]],"join_end":{"dir":[0,0],"r":1}}]})"),
            "piece.json: operations[0].join_end.dir: must not be zero");
  EXPECT_EQ(errorOf(R"({"operations":[{"op":"trace","a":1,"points":[[0,0]],"join_start":{"dir":[1,0]}}]})"),
            "piece.json: operations[0].join_start.r: missing (a number is required)");
  EXPECT_EQ(errorOf(R"({"operations":[{"op":"twist"}]})"),
            "piece.json: operations[0].op: unknown operation \"twist\" (trace, punch, press, region, blend_union, subtract, blend_subtract, patina)");
  EXPECT_EQ(errorOf(R"({"operations":[{"op":"region","contour":[[0,0],[1,1]],"height":1,"falloff":1}]})"),
            "piece.json: operations[0].contour: a closed contour needs at least 3 points");
  EXPECT_EQ(errorOf(R"({"operations":[{"op":"punch","a":1}]})"), "piece.json: operations[0].at: missing ([x, y, z] is required)");
  EXPECT_EQ(errorOf(R"({"camera":{"eye":[0,0,0],"target":[0,0,0]}})"), "piece.json: camera.eye: must differ from the target");
  EXPECT_EQ(errorOf(R"({"version":1e999})"), "piece.json: not valid JSON: number overflow parsing '1e999'");
  EXPECT_EQ(errorOf("[1,2]"), "piece.json: (top level): must be a JSON object");
  EXPECT_EQ(errorOf(""), "piece.json:1:1: not valid JSON: syntax error while parsing value - unexpected end of input; expected '[', '{', or a literal");
}

// Every number is checked against a physical range; the message names the operation, the key and
// the value (a punch of 1e308 mm used to render without a word).
TEST(SceneFile, NumbersOutOfTheirPhysicalRangeAreNamed) {
  const auto op = [](const std::string& o) { return errorOf(R"({"operations":[{"op":"punch","a":1,"at":[0,0,0]},)" + o + "]}"); };
  EXPECT_EQ(op(R"({"op":"punch","a":1e308,"at":[0,0,0]})"), "piece.json: operations[1].a: 1e+308 is out of range: 0.001 to 2000 mm");
  EXPECT_EQ(op(R"({"op":"punch","a":1,"at":[0,3000,0]})"), "piece.json: operations[1].at[1]: 3000 is out of range: -2000 to 2000 mm");
  EXPECT_EQ(op(R"({"op":"punch","a":1,"q":1e6,"at":[0,0,0]})"), "piece.json: operations[1].q: 1e+06 is out of range: 0.001 to 1000");
  EXPECT_EQ(op(R"({"op":"punch","a":1,"p":-5000,"at":[0,0,0]})"), "piece.json: operations[1].p: -5000 is out of range: -1000 to 1000");
  // The fuzzer's press path: coordinates far beyond any sheet.
  EXPECT_EQ(op(R"({"op":"press","a":1,"points":[[0,0],[1.37778e36,0]]})"),
            "piece.json: operations[1].points[1][0]: 1.37778e+36 is out of range: -2000 to 2000 mm");
  // In range, but a path too long for its punch spacing.
  EXPECT_EQ(op(R"({"op":"press","a":0.001,"q":1000,"points":[[-2000,-2000],[2000,2000]]})"),
            "piece.json: operations[1].points: the path needs 7.15542e+08 punches at a spacing of 7.90569e-06 mm, at most 100000");
  EXPECT_EQ(op(R"({"op":"trace","a":1,"points":[[0,0]],"join_end":{"dir":[1,0],"r":1e9}})"),
            "piece.json: operations[1].join_end.r: 1e+09 is out of range: 1e-06 to 2000 mm");
  EXPECT_EQ(op(R"({"op":"region","contour":[[0,0],[1,0],[0,1]],"height":-2500,"falloff":1})"),
            "piece.json: operations[1].height: -2500 is out of range: -2000 to 2000 mm");
  EXPECT_EQ(op(R"({"op":"region","contour":[[0,0],[1,0],[0,1]],"height":1,"falloff":1e-9})"),
            "piece.json: operations[1].falloff: 1e-09 is out of range: 0.001 to 2000 mm");
  EXPECT_EQ(op(R"({"op":"blend_union","tool":{"type":"sphere","center":[0,0,0],"r":5000},"a1":1,"a2":1,"a3":1})"),
            "piece.json: operations[1].tool.r: 5000 is out of range: 0.001 to 2000 mm");
  EXPECT_EQ(op(R"({"op":"subtract","tool":{"type":"flat","center":[0,0,0],"size":[1,1,4001]}})"),
            "piece.json: operations[1].tool.size[2]: 4001 is out of range: 0.001 to 2000 mm");
  EXPECT_EQ(op(R"({"op":"blend_subtract","tool":{"type":"sphere","center":[0,0,0],"r":1},"a1":1,"a2":1,"a3":3000})"),
            "piece.json: operations[1].a3: 3000 is out of range: 0.001 to 2000 mm");
  EXPECT_EQ(errorOf(R"({"workpiece":{"type":"disc","r":1e308,"d":1}})"), "piece.json: workpiece.r: 1e+308 is out of range: 0.001 to 2000 mm");
  EXPECT_EQ(errorOf(R"({"workpiece":{"type":"vm","file":"m.vm","scale":1e5}})"),
            "piece.json: workpiece.scale: 100000 is out of range: 1e-06 to 2000 mm per unit");
  EXPECT_EQ(errorOf(R"({"camera":{"eye":[0,0,1e9]}})"), "piece.json: camera.eye[2]: 1e+09 is out of range: -200000 to 200000 mm");
  EXPECT_EQ(errorOf(R"({"camera":{"fov_deg":500}})"), "piece.json: camera.fov_deg: must be between 1 and 170 degrees");
  // The edges of the ranges are inside.
  EXPECT_TRUE(parse(R"({"workpiece":{"type":"plate","w":2000,"h":0.001,"d":1},"operations":[{"op":"punch","a":2000,"p":-1000,"q":0.001,"at":[-2000,2000,0]}]})"));
}

TEST(SceneFile, MissingFileSaysSo) {
  auto s = loadScene("/nonexistent/piece.json");
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error(), "/nonexistent/piece.json: cannot open the scene file (No such file or directory)");
}

TEST(SceneFile, SavingIsAtomic) {
  const auto dir = test::scratchDir("scene-save");
  auto s = parse(R"({"operations":[{"op":"punch","a":1,"at":[0,0,0]}]})");
  ASSERT_TRUE(s);
  ASSERT_TRUE(saveScene(*s, nullptr, dir / "a.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "a.json.part"));
  auto back = loadScene(dir / "a.json");
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(back->operations.size(), 1u);
  // A folder that does not exist: a message, nothing half-written.
  const Status bad = saveScene(*s, nullptr, dir / "missing" / "b.json");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("cannot write"), std::string::npos);
}

TEST(SceneFile, VmWorkpieceLoadsRelativeToTheScene) {
  EMBOSS_REQUIRE_FIXTURES(fx);
  auto s = parseScene(R"({"workpiece":{"type":"vm","file":"vm/quarter.vm","scale":20,"d":0.5}})", "piece.json", fx);
  ASSERT_TRUE(s) << s.error();
  auto m = s->makeModel();
  ASSERT_TRUE(m);
  // quarter.vm: max(max(x, y), x^2 + y^2 - 0.5) < 0 inside: the lower-left quarter disc of radius
  // sqrt(0.5). At (-5, -5) mm = (-0.25, -0.25) model units it is inside, in the sheet's middle.
  EXPECT_GT(m->evaluate(P3<double>{-5, -5, 0}), 0.0);
  EXPECT_LT(m->evaluate(P3<double>{5, 5, 0}), 0.0);
  EXPECT_LT(m->evaluate(P3<double>{-5, -5, 0.6}), 0.0);
  auto missing = parseScene(R"({"workpiece":{"type":"vm","file":"vm/none.vm"}})", "piece.json", fx);
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("piece.json: workpiece.file: "), std::string::npos) << missing.error();
}

}  // namespace
}  // namespace emboss
