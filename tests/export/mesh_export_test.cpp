// The take-home exports: the mesh is closed, oriented and manifold, on the surface, and keeps the
// sheet's volume; STL and 3MF carry it unchanged; the height map holds the front face.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>

#include "export/heightmap.h"
#include "export/mesh.h"
#include "export/mesh_internal.h"
#include "export/stl.h"
#include "export/threemf.h"
#include "frep/op_grid.h"
#include "render/thread_pool.h"
#include "scene/scene.h"
#include "test_support.h"

namespace emboss {
namespace {

Model modelOf(const std::string& text) {
  auto scene = parseScene(text, "test.json", ".");
  EXPECT_TRUE(scene.ok()) << scene.error();
  auto model = scene->makeModel();
  EXPECT_TRUE(model.ok()) << model.error();
  return std::move(*model);
}

// A plate 40 x 30 x 1 mm (sheet model) with a groove, a raised punch, a region and a press.
const char* kPlate = R"({"deformation":"sheet","workpiece":{"type":"plate","w":20,"h":15,"d":0.5},
  "operations":[
   {"op":"trace","side":"front","a":0.6,"points":[[-12,-8],[-4,4],[8,6],[12,-4]]},
   {"op":"punch","side":"back","a":3,"p":0.5,"q":1.2,"at":[0,0,0.5]},
   {"op":"region","side":"back","contour":[[-14,-12],[-6,-12],[-6,-6],[-10,-3],[-14,-6]],"height":0.8,"falloff":1.2},
   {"op":"press","side":"back","a":0.8,"p":0.1,"q":1,"points":[[-12,9],[10,10]]}]})";

TEST(MeshExport, SheetIsClosedManifoldOnTheSurfaceAndKeepsItsVolume) {
  const Model model = modelOf(kPlate);
  MeshOptions o;
  o.threads = 2;
  MeshStats st;
  auto mesh = meshModel(model, o, &st);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  EXPECT_EQ(checkClosedManifold(*mesh), "");
  // The sheet model moves the sheet along z: its volume stays 40 x 30 x 1 mm^3.
  EXPECT_NEAR(st.volume, 1200.0, 1200.0 * 0.005);
  EXPECT_GT(st.volume, 0.0) << "the triangles face inward";
  EXPECT_LT(st.vertexMax, 0.1 * st.cell) << "vertices lie on the surface";
  EXPECT_LT(st.faceMax, 0.5 * st.cell);
  EXPECT_TRUE(st.decimated);
  EXPECT_LT(st.triangles, st.fineTriangles * 6 / 10) << "flat parts are decimated";
  EXPECT_EQ(st.triangles, mesh->triangles.size());
  // Raised by the punch: the front face above the centre is higher than at rest (d = 0.5).
  float top = -1e9f;
  for (const auto& v : mesh->vertices)
    if (std::abs(v[0]) < 0.5f && std::abs(v[1]) < 0.5f) top = std::max(top, v[2]);
  EXPECT_GT(top, 0.5f + 1.0f);
}

// The test plate at 0.15 mm, decimated, checked closed and manifold.
Result<TriangleMesh> decimatedPlate(MeshStats& st) {
  MeshOptions o;
  o.threads = 2;
  o.cell = 0.15;
  auto mesh = meshModel(modelOf(kPlate), o, &st);
  if (mesh.ok()) {
    EXPECT_EQ(checkClosedManifold(*mesh), "");
    EXPECT_TRUE(st.decimated);
  }
  return mesh;
}

// The test plate's fine mesh at 0.15 mm (no decimation), with the mesher's figures (its grid's
// planes among them).
Result<TriangleMesh> finePlate(MeshStats& st) {
  MeshOptions o;
  o.threads = 2;
  o.cell = 0.15;
  o.maxError = 0.0;
  return meshModel(modelOf(kPlate), o, &st);
}

// The test plate's fine mesh at 0.4 mm: no fold, its flat front face wide between the relief.
Result<TriangleMesh> coarseFinePlate(const Model& plate) {
  MeshOptions o;
  o.threads = 2;
  o.cell = 0.4;
  o.maxError = 0.0;
  return meshModel(plate, o);
}

// Triangles whose height is under 1/1000 of their longest edge.
size_t thinTriangles(const TriangleMesh& mesh) {
  size_t thin = 0;
  for (const auto& t : mesh.triangles) {
    const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    const double w[3] = {double(c[0]) - b[0], double(c[1]) - b[1], double(c[2]) - b[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double l2 = std::max({u[0] * u[0] + u[1] * u[1] + u[2] * u[2], v[0] * v[0] + v[1] * v[1] + v[2] * v[2],
                                w[0] * w[0] + w[1] * w[1] + w[2] * w[2]});
    thin += std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) < 1e-3 * l2;
  }
  return thin;
}

// A triangle's unit normal, in doubles.
std::array<double, 3> unitNormal(const TriangleMesh& mesh, const std::array<std::uint32_t, 3>& tri) {
  const auto &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
  const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
  const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  return {n[0] / l, n[1] / l, n[2] / l};
}

// Edges whose two triangles face more than 120 degrees apart: the surface folded over itself.
size_t foldEdges(const TriangleMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, size_t> edge;
  std::vector<std::array<double, 3>> normal;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    normal.push_back(unitNormal(mesh, tri));
    for (int k = 0; k < 3; ++k) edge[{tri[k], tri[(k + 1) % 3]}] = t;
  }
  size_t folds = 0;
  for (const auto& [e, t] : edge) {
    const auto it = edge.find({e.second, e.first});
    if (it == edge.end() || it->second < t) continue;
    const auto &m = normal[t], &n = normal[it->second];
    folds += m[0] * n[0] + m[1] * n[1] + m[2] * n[2] < -0.5;
  }
  return folds;
}

// What the decimation must not leave. A fold: the simplifier's collapses fold the surface over
// itself here and there (a triangle turned upside down among its neighbours). A thin triangle
// (height under 1/1000 of its longest edge): its normal is float noise, and a smooth-shading reader
// weights it by its near-straight angle (a dark blotch on a flat face). The decimation keeps both
// out (TheSimplifierMakesNoFoldsOrThinTriangles, below); what the passes after it would still find
// (the fine mesh's own), the mesher takes out by flips in the same face and by removing a vertex
// and filling its hole again (the tests on grids below). On the test plate: 35 fold edges and 2 008
// thin triangles before any of these; with the passes after alone, 3 and 9; none now. The sheet
// keeps its volume.
TEST(MeshExport, DecimationLeavesNoFoldsOrThinTriangles) {
  MeshStats st;
  auto mesh = decimatedPlate(st);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  const size_t folds = foldEdges(*mesh), thin = thinTriangles(*mesh);
  std::printf("%zu triangles, %zu fold edges, %zu under 1/1000, %zu + %zu vertices taken out\n", mesh->triangles.size(),
              folds, thin, st.foldVertices, st.thinVertices);
  EXPECT_EQ(folds, 0u);
  EXPECT_EQ(thin, 0u);
  EXPECT_NEAR(st.volume, 1200.0, 1200.0 * 0.005);
  EXPECT_EQ(st.vertices, mesh->vertices.size()) << "the vertices taken out are dropped";
}

// The simplifier itself is kept from folding and from thin triangles: a tile whose simplified
// patch folds (against itself or the ring of fine triangles around it) or has a triangle under
// 1/1000 is simplified again with the fine triangles around those kept, and fails (a smaller tile
// next) while it still has one. The test plate's fine mesh, decimated as the mesher does, before
// any pass after it: no fold and no thin triangle (without: 25 fold edges and 266 thin
// triangles), for 2 % more triangles.
TEST(MeshExport, TheSimplifierMakesNoFoldsOrThinTriangles) {
  MeshStats st;
  auto mesh = finePlate(st);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  const size_t fine = mesh->triangles.size(), fineFolds = foldEdges(*mesh), fineThin = thinTriangles(*mesh);
  ThreadPool pool(2);
  mesh_detail::decimate(*mesh, 0.01, 48.0 * 0.15, st.planeX, st.planeY, pool);
  EXPECT_EQ(checkClosedManifold(*mesh), "");
  const size_t folds = foldEdges(*mesh), thin = thinTriangles(*mesh);
  std::printf("%zu -> %zu triangles, fold edges %zu -> %zu, thin %zu -> %zu\n", fine, mesh->triangles.size(), fineFolds,
              folds, fineThin, thin);
  EXPECT_LT(mesh->triangles.size(), fine / 3) << "flat parts are decimated";
  EXPECT_LE(folds, fineFolds);
  EXPECT_LE(thin, fineThin);
  EXPECT_NEAR(meshVolume(*mesh), 1200.0, 1200.0 * 0.005);
}

// A plate whose relief runs into its sides: a punch from the front on one side's middle, one from
// behind on another, a groove across a corner. The plate's sides lie on its bounds; were they on a
// plane of the grid's samples (a side 10 mm from the bounds' corner, a cell of 0.1, 0.15 or 0.2 mm),
// f would be 0 at the samples themselves, the vertices would crowd against them and the fine mesh
// would fold where the relief meets the side: 31, 28 and 20 fold edges at these three cells, every
// one on a side. The grid is set so that no end of the bounds lies within a quarter of a cell of
// its planes: at most one fold edge, and the vertices on the sides lie on them.
TEST(MeshExport, APlatesSidesLieBetweenTheGridsPlanes) {
  const Model model = modelOf(R"({"deformation":"sheet","workpiece":{"type":"plate","w":10,"h":8,"d":0.5},
    "operations":[{"op":"punch","side":"front","a":2,"p":0.6,"q":1.0,"at":[10,0,0.5]},
                  {"op":"punch","side":"back","a":1.5,"p":0.6,"q":1.0,"at":[-3,8,0.5]},
                  {"op":"trace","side":"front","a":0.8,"points":[[-12,-3],[-4,-6],[3,-9]]}]})");
  for (const double cell : {0.1, 0.15, 0.2}) {
    MeshOptions o;
    o.threads = 2;
    o.cell = cell;
    o.maxError = 0.0;  // the fine mesh, as marching tetrahedra make it
    auto mesh = meshModel(model, o);
    ASSERT_TRUE(mesh.ok()) << mesh.error();
    EXPECT_EQ(checkClosedManifold(*mesh), "");
    // The vertices nearest the sides lie on them (not a fiftieth of a cell off).
    float xMax = -1e9f, yMin = 1e9f;
    for (const auto& v : mesh->vertices) xMax = std::max(xMax, v[0]), yMin = std::min(yMin, v[1]);
    const size_t folds = foldEdges(*mesh);
    std::printf("cell %.2f: %zu triangles, %zu fold edges, sides at x %.5f and y %.5f\n", cell, mesh->triangles.size(), folds,
                xMax, yMin);
    EXPECT_LE(folds, 1u) << "cell " << cell;
    EXPECT_NEAR(xMax, 10.0f, 1e-4f) << "cell " << cell;
    EXPECT_NEAR(yMin, -8.0f, 1e-4f) << "cell " << cell;
  }
}

// The decimation's tiles start on the grid's planes (their side is a whole number of cells), so a
// cell's triangles fall in one tile and only the vertices on a tile's edge are shared: the ring of
// fine triangles each tile leaves along its edges is as narrow as it can be. Tiles a half cell off
// the planes cut through cells, whose triangles then fall either side by their centroids. The test
// plate's fine mesh at 0.15 mm, decimated both ways.
TEST(MeshExport, TheDecimationsTilesStartOnTheGridsPlanes) {
  MeshStats st;
  auto fine = finePlate(st);
  ASSERT_TRUE(fine.ok()) << fine.error();
  ThreadPool pool(2);
  TriangleMesh on = *fine, off = *fine;
  mesh_detail::decimate(on, 0.01, 48.0 * 0.15, st.planeX, st.planeY, pool);
  mesh_detail::decimate(off, 0.01, 48.0 * 0.15, st.planeX + 0.075, st.planeY + 0.075, pool);
  EXPECT_EQ(checkClosedManifold(on), "");
  EXPECT_EQ(checkClosedManifold(off), "");
  std::printf("%zu fine triangles: %zu with the tiles on the planes, %zu half a cell off\n", fine->triangles.size(),
              on.triangles.size(), off.triangles.size());
  EXPECT_LT(on.triangles.size(), off.triangles.size() * 95 / 100);
}

// Every tile leaves a ring of fine triangles along its edges (a ring triangle touches a vertex of
// a simplified patch in every round after, so the rounds never take it). The seams are simplified
// once more at the end, in tiles across the first round's edges, each against the triangles around
// it. The test plate's fine mesh at 0.15 mm, decimated with and without: fewer triangles, still
// closed and manifold, no fold or thin triangle made, the same volume.
TEST(MeshExport, TheTilesSeamsAreSimplifiedToo) {
  MeshStats st;
  auto fine = finePlate(st);
  ASSERT_TRUE(fine.ok()) << fine.error();
  const size_t fineFolds = foldEdges(*fine), fineThin = thinTriangles(*fine);
  ThreadPool pool(2);
  TriangleMesh with = *fine, without = *fine;
  mesh_detail::decimate(with, 0.01, 48.0 * 0.15, st.planeX, st.planeY, pool);
  mesh_detail::decimate(without, 0.01, 48.0 * 0.15, st.planeX, st.planeY, pool, false);
  std::printf("%zu fine triangles: %zu with the seams simplified, %zu without\n", fine->triangles.size(),
              with.triangles.size(), without.triangles.size());
  EXPECT_EQ(checkClosedManifold(with), "");
  EXPECT_LT(with.triangles.size(), without.triangles.size() * 9 / 10);
  EXPECT_LE(foldEdges(with), fineFolds);
  EXPECT_LE(thinTriangles(with), fineThin);
  EXPECT_NEAR(meshVolume(with), meshVolume(without), 0.5);
}

// The area off the surface: the mesh's area (mm^2) more than `limit`, and more than twice it, from
// the model's surface (first-order distance, |f| / |grad f|), each triangle cut in 16 and each
// piece measured at its centre.
std::array<double, 2> areaOff(const Model& model, const TriangleMesh& mesh, double limit) {
  OpGrid grid;
  grid.sync(model);
  std::vector<std::uint32_t> scratch;
  std::array<double, 2> off = {0.0, 0.0};
  for (const auto& t : mesh.triangles) {
    const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double piece = 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 16.0;
    // The 16 pieces of a triangle cut in four along each side: their centres.
    for (int i = 0; i < 4; ++i)
      for (int j = 0; i + j < 4; ++j)
        for (int up = 0; up < (i + j < 3 ? 2 : 1); ++up) {
          const double s = up ? (i + 2.0 / 3) / 4 : (i + 1.0 / 3) / 4, r = up ? (j + 2.0 / 3) / 4 : (j + 1.0 / 3) / 4;
          double q[3];
          for (int k = 0; k < 3; ++k) q[k] = a[k] + s * u[k] + r * v[k];
          const Grad g = model.evaluate(P3<Grad>{{q[0], 1, 0, 0}, {q[1], 0, 1, 0}, {q[2], 0, 0, 1}}, grid.at(q[0], q[1], scratch));
          const double len = std::sqrt(g.dx * g.dx + g.dy * g.dy + g.dz * g.dz);
          const double d = len > 0.0 ? std::abs(g.v) / len : 0.0;
          off[0] += d > limit ? piece : 0.0;
          off[1] += d > 2.0 * limit ? piece : 0.0;
        }
  }
  return off;
}

// The seams' pass leaves a band about a cell wide along every first round's tile edge: its outer
// vertices belong to the simplified patches either side, locked. So the seams' tiles first take the
// simplified patches in them too and simplify everything again (three passes), keeping a new
// triangle only where it lies within the error of the model's surface itself (meshoptimizer's
// error would be measured from triangles already simplified). The test plate's fine mesh at
// 0.15 mm: fewer triangles than with the seams alone, closed and manifold, no fold or thin
// triangle the fine mesh had not, the same volume, and no more area off the surface by the error
// or by twice it (within 1 %; with a check that passes every triangle, about twice as much). With a
// check that refuses every triangle, the passes change nothing: the mesh is the seams' alone,
// triangle for triangle.
TEST(MeshExport, TheSeamsBandsAreSimplifiedOnTheSurface) {
  MeshStats st;
  auto fine = finePlate(st);
  ASSERT_TRUE(fine.ok()) << fine.error();
  const Model model = modelOf(kPlate);
  OpGrid grid;
  grid.sync(model);
  const mesh_detail::SurfaceCheck onSurface = mesh_detail::surfaceCheck(model, grid, 0.01);
  const mesh_detail::SurfaceCheck never = [](const auto&, const auto&, const auto&) { return false; };
  const size_t fineFolds = foldEdges(*fine), fineThin = thinTriangles(*fine);
  ThreadPool pool(2);
  TriangleMesh bands = *fine, seams = *fine, refused = *fine;
  mesh_detail::decimate(bands, 0.01, 48.0 * 0.15, st.planeX, st.planeY, pool, true, &onSurface);
  mesh_detail::decimate(seams, 0.01, 48.0 * 0.15, st.planeX, st.planeY, pool, true, nullptr);
  mesh_detail::decimate(refused, 0.01, 48.0 * 0.15, st.planeX, st.planeY, pool, true, &never);
  const auto off = areaOff(model, bands, 0.01), offSeams = areaOff(model, seams, 0.01);
  std::printf("%zu fine triangles: %zu with the bands, %zu with the seams alone; area off by 0.01: %.2f and %.2f mm^2, "
              "by 0.02: %.2f and %.2f mm^2\n",
              fine->triangles.size(), bands.triangles.size(), seams.triangles.size(), off[0], offSeams[0], off[1],
              offSeams[1]);
  EXPECT_EQ(checkClosedManifold(bands), "");
  EXPECT_LT(bands.triangles.size(), seams.triangles.size() * 8 / 10);
  EXPECT_LE(foldEdges(bands), fineFolds);
  EXPECT_LE(thinTriangles(bands), fineThin);
  EXPECT_NEAR(meshVolume(bands), meshVolume(seams), 0.5);
  EXPECT_LE(off[0], offSeams[0] * 1.01);
  EXPECT_LE(off[1], offSeams[1] * 1.01);
  // (The same triangles, in another order and so with other vertex numbers: the passes move them
  // between lists, and the vertices are numbered in the order of first use.)
  auto corners = [](const TriangleMesh& m) {
    std::vector<std::array<std::array<float, 3>, 3>> tris;
    for (auto t : m.triangles) {
      std::array<std::array<float, 3>, 3> c = {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
      std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
      tris.push_back(c);
    }
    std::sort(tris.begin(), tris.end());
    return tris;
  };
  EXPECT_EQ(corners(refused), corners(seams));
}

// A flat n x n grid of unit squares in z = 0, two triangles a square, as the indices and positions
// the mesher's clean-up works on.
struct FlatGrid {
  int n;
  std::vector<float> pos;
  std::vector<unsigned int> ix;
  explicit FlatGrid(int size = 6) : n(size) {
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) pos.insert(pos.end(), {float(i), float(j), 0.0f});
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) ix.insert(ix.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  unsigned int id(int i, int j) const { return static_cast<unsigned int>(j * (n + 1) + i); }
  TriangleMesh mesh(size_t count) const {
    TriangleMesh m;
    for (size_t v = 0; v < pos.size(); v += 3) m.vertices.push_back({pos[v], pos[v + 1], pos[v + 2]});
    for (size_t k = 0; k < count; k += 3) m.triangles.push_back({ix[k], ix[k + 1], ix[k + 2]});
    return m;
  }
  // The first `count` indices cover the grid once, every triangle facing up, with its border
  // (the grid's outer edges) and every inner edge used once each way, and `gone` in none.
  void expectCoveredOnce(size_t count, unsigned int gone) const {
    double area = 0;
    std::map<std::pair<unsigned int, unsigned int>, int> uses;
    for (size_t k = 0; k < count; k += 3) {
      const float *a = &pos[3 * ix[k]], *b = &pos[3 * ix[k + 1]], *c = &pos[3 * ix[k + 2]];
      const double z = (double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(b[1]) - a[1]) * (double(c[0]) - a[0]);
      EXPECT_GT(z, 0.0) << "triangle " << k / 3 << " faces down";
      area += 0.5 * z;
      for (int e = 0; e < 3; ++e) {
        ++uses[{ix[k + e], ix[k + (e + 1) % 3]}];
        EXPECT_NE(ix[k + e], gone);
      }
    }
    EXPECT_NEAR(area, double(n * n), 1e-6);
    size_t border = 0;
    for (const auto& [e, c] : uses) {
      EXPECT_EQ(c, 1);
      if (!uses.count({e.second, e.first})) ++border;
    }
    EXPECT_EQ(border, size_t(4 * n));
  }
};

// One vertex of the grid pushed across the edge between two of its neighbours: a triangle of its
// fan turns over. The vertex goes, its hole is filled with triangles facing up, and the border
// stays; a vertex further from the surface after than maxError stays.
// The decimation counts only the flaws it makes. A fold the fine mesh has already (marching
// tetrahedra's, at a sharp crease) keeps the fine triangles around it, and the rest of its tile is
// simplified all the same (when every fold counted, the tile failed on it: 470 of the 512
// triangles were left).
TEST(MeshExport, TheFineMeshsOwnFoldDoesNotStopTheDecimation) {
  FlatGrid g(16);
  const unsigned int v = g.id(8, 8);
  g.pos[3 * v] = 9.2f, g.pos[3 * v + 1] = 8.5f, g.pos[3 * v + 2] = 0.01f;  // over the triangle beyond
  TriangleMesh mesh = g.mesh(g.ix.size());
  const size_t fine = mesh.triangles.size(), folds = foldEdges(mesh);
  ASSERT_GT(folds, 0u);
  ThreadPool pool(1);
  mesh_detail::decimate(mesh, 0.001, 100.0, 0.0, 0.0, pool);
  std::printf("%zu -> %zu triangles, fold edges %zu -> %zu\n", fine, mesh.triangles.size(), folds, foldEdges(mesh));
  EXPECT_LT(mesh.triangles.size(), fine / 2);
  EXPECT_EQ(foldEdges(mesh), folds) << "the fold is the fine mesh's, kept as it was";
  // Still one sheet over the grid: every directed edge once, and the signed area the grid's.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    area += 0.5 * ((double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(b[1]) - a[1]) * (double(c[0]) - a[0]));
    for (int e = 0; e < 3; ++e) EXPECT_EQ(++uses[std::make_pair(t[e], t[(e + 1) % 3])], 1);
  }
  EXPECT_NEAR(area, 256.0, 1e-3);
}

// A fold of the fine mesh's own that no removal takes out (at a sharp crease the hole around a
// vertex lies in no plane): its vertices are moved along the surface, each to the surface's point
// nearest its neighbours' centre, where that leaves fewer folds and no thin triangle. Here a vertex
// of the test plate's flat front face (far from its relief, at 0.4 mm) is pushed across the edge
// beyond it, on the face: its fan folds. The move takes the folds out, the vertex ends on the
// surface, and the mesh stays closed and manifold with the same triangles.
TEST(MeshExport, AFoldsVertexIsMovedAlongTheSurface) {
  const Model model = modelOf(kPlate);
  auto mesh = coarseFinePlate(model);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  const size_t folds0 = foldEdges(*mesh), thin0 = thinTriangles(*mesh);
  // A front-face vertex near (17, -12) and a triangle of its fan, turned to start at it.
  std::uint32_t v = UINT32_MAX;
  std::array<std::uint32_t, 3> fan{};
  for (const auto& t : mesh->triangles) {
    for (int k = 0; k < 3 && v == UINT32_MAX; ++k) {
      const auto& p = mesh->vertices[t[k]];
      if (std::abs(p[2] - 0.5f) < 1e-4f && std::abs(p[0] - 17.0f) < 1.5f && std::abs(p[1] + 12.0f) < 1.5f)
        v = t[k], fan = {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
    }
    if (v != UINT32_MAX) break;
  }
  ASSERT_NE(v, UINT32_MAX) << "no front-face vertex found there";
  const auto home = mesh->vertices[v];
  const auto &a = mesh->vertices[fan[1]], &b = mesh->vertices[fan[2]];
  mesh->vertices[v] = {a[0] + b[0] - home[0], a[1] + b[1] - home[1], home[2]};  // across the edge a b
  const size_t folds1 = foldEdges(*mesh);
  OpGrid grid;
  grid.sync(model);
  const size_t moved = mesh_detail::moveOutOfFolds(*mesh, model, grid);
  const auto& p = mesh->vertices[v];
  const Grad g = model.evaluate(P3<Grad>{{p[0], 1, 0, 0}, {p[1], 0, 1, 0}, {p[2], 0, 0, 1}});
  const double distance = std::abs(g.v) / std::sqrt(g.dx * g.dx + g.dy * g.dy + g.dz * g.dz);
  std::printf("fold edges %zu, pushed %zu, after %zu moves %zu; the vertex %.4f mm from home, %.6f mm off the surface\n",
              folds0, folds1, moved, foldEdges(*mesh), std::hypot(p[0] - home[0], p[1] - home[1]), distance);
  EXPECT_GT(folds1, folds0);
  EXPECT_GE(moved, 1u);
  EXPECT_LE(foldEdges(*mesh), folds0);
  EXPECT_LE(thinTriangles(*mesh), thin0);
  EXPECT_LT(distance, 1e-4);
  EXPECT_EQ(checkClosedManifold(*mesh), "");
}

// A bowl's rim is a sharp ridge: its wall meets its inner face at an acute angle. At a 0.4 mm cell
// marching tetrahedra cut under it in places, with an edge from the wall to the inner face and two
// thin fins up to the ridge, folded against each other (4 fold edges were left on this bowl before
// the flips; the vertices' moves could not take them out).
TEST(MeshExport, ABowlsRimHasNoFins) {
  const Model model = modelOf(R"({"deformation":"sheet","workpiece":{"type":"bowl","r":30,"depth":8,"d":0.5},
    "operations":[{"op":"trace","side":"front","a":0.8,"points":[[-20,-5],[-5,10],[10,5],[22,-8]]},
     {"op":"punch","side":"back","a":4,"p":0.6,"q":1.0,"at":[0,0,0.5]},
     {"op":"punch","side":"front","a":3,"p":0.5,"q":1.0,"at":[15,-10,0.5]}]})");
  MeshOptions o;
  o.threads = 2;
  o.cell = 0.4;
  MeshStats st;
  auto mesh = meshModel(model, o, &st);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  std::printf("bowl: %zu triangles, %zu fold edges flipped, %zu vertices moved; fold edges %zu, thin %zu\n",
              st.triangles, st.flippedEdges, st.movedVertices, foldEdges(*mesh), thinTriangles(*mesh));
  EXPECT_TRUE(st.decimated);
  EXPECT_GE(st.flippedEdges, 1u);
  EXPECT_EQ(foldEdges(*mesh), 0u);
  EXPECT_EQ(thinTriangles(*mesh), 0u);
  EXPECT_EQ(checkClosedManifold(*mesh), "");
  EXPECT_LT(st.vertexMax, 0.05);
}

// The same fin made by hand on the test plate's fine mesh: an edge along its rim (the front face
// and a side wall) flipped to the quad's other diagonal, which runs under the rim. The flips put
// the edge back along the rim: the same triangles as before, no fold, closed and manifold.
TEST(MeshExport, AFinUnderARidgeIsFlippedAlongIt) {
  const Model model = modelOf(kPlate);
  auto mesh = coarseFinePlate(model);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  const size_t folds0 = foldEdges(*mesh);
  auto& T = mesh->triangles;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> owner;
  for (std::uint32_t t = 0; t < T.size(); ++t)
    for (int k = 0; k < 3; ++k) owner[{T[t][k], T[t][(k + 1) % 3]}] = t;
  auto sorted = [](std::vector<std::array<std::uint32_t, 3>> ts) {
    for (auto& t : ts) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    std::sort(ts.begin(), ts.end());
    return ts;
  };
  const auto original = sorted(T);
  // An edge c -> d of the front face's rim (one triangle facing up, the other sideways), whose
  // flip to the other diagonal folds.
  bool made = false;
  for (const auto& [e, t1] : owner) {
    const auto [c, d] = e;
    const auto it = owner.find({d, c});
    if (it == owner.end()) continue;
    const std::uint32_t t2 = it->second;
    const auto n1 = unitNormal(*mesh, T[t1]), n2 = unitNormal(*mesh, T[t2]);
    if (!(std::max(n1[2], n2[2]) > 0.9 && std::min(std::abs(n1[2]), std::abs(n2[2])) < 0.1)) continue;
    auto third = [&](const std::array<std::uint32_t, 3>& t) {
      for (std::uint32_t w : t)
        if (w != c && w != d) return w;
      return UINT32_MAX;
    };
    const std::uint32_t u = third(T[t1]), v = third(T[t2]);  // t1 = (c, d, u), t2 = (d, c, v)
    if (owner.count({u, v}) || owner.count({v, u})) continue;
    const auto keep1 = T[t1], keep2 = T[t2];
    T[t1] = {u, c, v}, T[t2] = {v, d, u};
    if (foldEdges(*mesh) > folds0 && checkClosedManifold(*mesh).empty()) {
      made = true;
      break;
    }
    T[t1] = keep1, T[t2] = keep2;
  }
  ASSERT_TRUE(made) << "no edge of the rim whose flip folds";
  const size_t folds1 = foldEdges(*mesh);
  OpGrid grid;
  grid.sync(model);
  const size_t flipped = mesh_detail::flipFoldEdges(*mesh, model, grid);
  std::printf("fold edges %zu, with the fin %zu, after %zu flips %zu\n", folds0, folds1, flipped, foldEdges(*mesh));
  EXPECT_EQ(flipped, 1u);
  EXPECT_EQ(foldEdges(*mesh), folds0);
  EXPECT_EQ(sorted(T), original);
  EXPECT_EQ(checkClosedManifold(*mesh), "");
}

TEST(MeshExport, AFoldedVertexIsTakenOutAndItsHoleFilled) {
  FlatGrid g;
  const unsigned int v = g.id(3, 3);
  // Across the edge from (4, 3) to (4, 4), over the triangle beyond it, and 0.01 above the plane:
  // the surface after is that far from it.
  g.pos[3 * v] = 4.2f, g.pos[3 * v + 1] = 3.5f, g.pos[3 * v + 2] = 0.01f;
  const std::vector<unsigned int> before = g.ix;
  ASSERT_GT(foldEdges(g.mesh(g.ix.size())), 0u);
  size_t count = g.ix.size();
  const auto removed = mesh_detail::removeFoldsAndThinTriangles(g.ix, count, g.pos, 0.05);
  EXPECT_EQ(removed.folds, 1u);
  EXPECT_EQ(removed.thin, 0u);
  EXPECT_EQ(count, g.ix.size() - 6) << "a vertex of six triangles gone: two triangles fewer";
  EXPECT_EQ(foldEdges(g.mesh(count)), 0u);
  g.expectCoveredOnce(count, v);
  // maxError below the lift: left as it is.
  g.ix = before;
  count = g.ix.size();
  EXPECT_EQ(mesh_detail::removeFoldsAndThinTriangles(g.ix, count, g.pos, 0.001).folds, 0u);
  EXPECT_EQ(count, g.ix.size());
  EXPECT_EQ(g.ix, before);
}

// One vertex of the grid 1e-4 from the edge between two of its neighbours: a triangle of its fan
// is thin (its normal float noise, a speck in a smooth-shading viewer). The vertex goes and the
// hole's triangles are all better than that one.
TEST(MeshExport, AThinTrianglesVertexIsTakenOut) {
  FlatGrid g;
  const unsigned int v = g.id(3, 3);
  g.pos[3 * v] = 4.0f - 1e-4f, g.pos[3 * v + 1] = 3.5f;
  size_t count = g.ix.size();
  const auto removed = mesh_detail::removeFoldsAndThinTriangles(g.ix, count, g.pos, 0.01);
  EXPECT_EQ(removed.folds, 0u);
  EXPECT_EQ(removed.thin, 1u);
  EXPECT_EQ(count, g.ix.size() - 6);
  g.expectCoveredOnce(count, v);
  for (size_t k = 0; k < count; k += 3) {
    const float *a = &g.pos[3 * g.ix[k]], *b = &g.pos[3 * g.ix[k + 1]], *c = &g.pos[3 * g.ix[k + 2]];
    const double z = (double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(b[1]) - a[1]) * (double(c[0]) - a[0]);
    const double l2 = std::max({std::hypot(b[0] - a[0], b[1] - a[1]), std::hypot(c[0] - b[0], c[1] - b[1]),
                                std::hypot(a[0] - c[0], a[1] - c[1])});
    EXPECT_GT(z / (l2 * l2), 0.1) << "triangle " << k / 3 << " is thin";
  }
}

// The grid bent down along its row j = 3 (a sheet's face and its side wall), and one vertex of
// that crease pushed along it beyond its neighbour: two triangles of its fan turn over. No one
// plane holds the hole there; the vertex's edge is collapsed instead, and the crease stays: every
// triangle after lies on the face or the wall, and the corner is not cut.
TEST(MeshExport, AFoldedVertexOnACreaseIsTakenOutAndTheCreaseKept) {
  FlatGrid g;
  for (int j = 4; j <= g.n; ++j)
    for (int i = 0; i <= g.n; ++i) {
      float* q = &g.pos[3 * g.id(i, j)];
      q[1] = 3.0f, q[2] = -static_cast<float>(j - 3);
    }
  const unsigned int v = g.id(3, 3);
  g.pos[3 * v] = 4.4f;
  ASSERT_GT(foldEdges(g.mesh(g.ix.size())), 0u);
  size_t count = g.ix.size();
  const auto removed = mesh_detail::removeFoldsAndThinTriangles(g.ix, count, g.pos, 0.05);
  EXPECT_GE(removed.folds, 1u);
  EXPECT_EQ(count, g.ix.size() - 6 * removed.folds) << "each vertex gone: two triangles fewer";
  EXPECT_EQ(foldEdges(g.mesh(count)), 0u);
  // How far a point is from the bent grid: the face (z = 0, y <= 3) or the wall (y = 3, z <= 0).
  auto off = [](double y, double z) {
    return std::min(y <= 3.0 ? std::abs(z) : std::hypot(y - 3.0, z), z <= 0.0 ? std::abs(y - 3.0) : std::hypot(y - 3.0, z));
  };
  std::map<std::pair<unsigned int, unsigned int>, int> uses;
  for (size_t k = 0; k < count; k += 3) {
    const float *a = &g.pos[3 * g.ix[k]], *b = &g.pos[3 * g.ix[k + 1]], *c = &g.pos[3 * g.ix[k + 2]];
    for (int e = 0; e < 3; ++e) {
      EXPECT_NE(g.ix[k + e], v);
      ++uses[{g.ix[k + e], g.ix[k + (e + 1) % 3]}];
    }
    const double cy = (double(a[1]) + b[1] + c[1]) / 3.0, cz = (double(a[2]) + b[2] + c[2]) / 3.0;
    EXPECT_LT(off(cy, cz), 1e-6) << "triangle " << k / 3 << " cuts the corner";
  }
  for (const auto& [e, n] : uses) EXPECT_EQ(n, 1);
}

TEST(MeshExport, AHoleThroughTheSheetStaysClosed) {
  const Model model = modelOf(R"({"deformation":"sheet","workpiece":{"type":"plate","w":10,"h":10,"d":0.5},
    "operations":[{"op":"punch","side":"back","a":2,"p":0.4,"q":1,"at":[-4,0,0.5]},
                  {"op":"subtract","tool":{"type":"cylinder","center":[3,0,-3],"end":[3,0,3],"r":2}}]})");
  MeshOptions o;
  o.cell = 0.2;
  MeshStats st;
  auto mesh = meshModel(model, o, &st);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  EXPECT_EQ(checkClosedManifold(*mesh), "");
  // 20 x 20 x 1 less the hole (radius 2 through 1 mm).
  EXPECT_NEAR(st.volume, 400.0 - M_PI * 4.0, 2.0);
}

TEST(MeshExport, WithoutDecimationEveryCellIsMeshed) {
  const Model model = modelOf(R"({"workpiece":{"type":"disc","r":8,"d":0.4},"operations":[]})");
  MeshOptions o;
  o.cell = 0.25;
  o.maxError = 0.0;
  MeshStats st;
  auto mesh = meshModel(model, o, &st);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  EXPECT_EQ(checkClosedManifold(*mesh), "");
  EXPECT_FALSE(st.decimated);
  EXPECT_EQ(st.triangles, st.fineTriangles);
  EXPECT_NEAR(st.volume, M_PI * 64.0 * 0.8, M_PI * 64.0 * 0.8 * 0.01);
}

// The blocks are merged as the threads make them, in the columns' order: the same mesh, vertex for
// vertex, on one thread or four (four on this piece's few columns make them out of order), fine
// or decimated, run after run.
TEST(MeshExport, TheSameMeshWhateverTheThreads) {
  const Model model = modelOf(kPlate);
  for (double maxError : {0.0, 0.01}) {
    MeshOptions o;
    o.cell = 0.2;
    o.maxError = maxError;
    o.threads = 1;
    auto one = meshModel(model, o, nullptr);
    ASSERT_TRUE(one.ok()) << one.error();
    ASSERT_EQ(checkClosedManifold(*one), "");
    for (int run = 0; run < 2; ++run) {
      o.threads = 4;
      auto four = meshModel(model, o, nullptr);
      ASSERT_TRUE(four.ok()) << four.error();
      ASSERT_EQ(four->vertices.size(), one->vertices.size()) << "max error " << maxError << ", run " << run;
      ASSERT_EQ(four->triangles.size(), one->triangles.size()) << "max error " << maxError << ", run " << run;
      EXPECT_TRUE(four->vertices == one->vertices) << "max error " << maxError << ", run " << run;
      EXPECT_TRUE(four->triangles == one->triangles) << "max error " << maxError << ", run " << run;
    }
  }
}

// When the decimated mesh fails its check, the fine mesh is made again and written: the very mesh
// made without decimation.
TEST(MeshExport, AFailedDecimationWritesTheFineMesh) {
  const Model model = modelOf(kPlate);
  MeshOptions o;
  o.threads = 2;
  o.cell = 0.3;
  o.rejectDecimated = true;
  MeshStats st;
  auto fallback = meshModel(model, o, &st);
  ASSERT_TRUE(fallback.ok()) << fallback.error();
  EXPECT_FALSE(st.decimated);
  EXPECT_EQ(st.triangles, st.fineTriangles);
  o.rejectDecimated = false;
  o.maxError = 0.0;
  auto fine = meshModel(model, o);
  ASSERT_TRUE(fine.ok()) << fine.error();
  EXPECT_EQ(checkClosedManifold(*fallback), "");
  ASSERT_EQ(fallback->vertices, fine->vertices);
  ASSERT_EQ(fallback->triangles, fine->triangles);
}

TEST(MeshExport, CheckFindsOpenAndFlippedMeshes) {
  TriangleMesh tet;
  tet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_EQ(checkClosedManifold(tet), "");
  EXPECT_NEAR(meshVolume(tet), 1.0 / 6.0, 1e-9);
  TriangleMesh open = tet;
  open.triangles.pop_back();
  EXPECT_NE(checkClosedManifold(open), "");
  TriangleMesh flipped = tet;
  std::swap(flipped.triangles[3][0], flipped.triangles[3][1]);
  EXPECT_NE(checkClosedManifold(flipped), "");
  TriangleMesh flat = tet;
  flat.vertices[3] = {0.5f, 0.5f, 0.0f};  // (1, 2, 3) collinear: zero area
  EXPECT_NE(checkClosedManifold(flat), "");
}

TEST(MeshExport, StlHoldsTheMeshLittleEndianWithUnitNormals) {
  TriangleMesh tet;
  tet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const std::string bytes = stlBytes(tet, "solid piece");
  ASSERT_EQ(bytes.size(), 84u + 4 * 50);
  EXPECT_NE(bytes.rfind("solid", 0), 0u) << "a binary STL must not start with 'solid'";
  std::uint32_t n;
  std::memcpy(&n, bytes.data() + 80, 4);
  EXPECT_EQ(n, 4u);
  float rec[12];
  std::memcpy(rec, bytes.data() + 84, sizeof rec);
  EXPECT_FLOAT_EQ(rec[2], -1.0f);  // (0, 2, 1) faces -z
  EXPECT_FLOAT_EQ(rec[6], 0.0f);
  EXPECT_FLOAT_EQ(rec[7], 1.0f);  // second vertex (0, 1, 0)
}

TEST(MeshExport, ThreeMfRoundTripsThroughLib3mf) {
  const Model model = modelOf(kPlate);
  MeshOptions o;
  o.cell = 0.4;
  auto mesh = meshModel(model, o);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  const auto path = test::scratchDir("mesh_export") / "piece.3mf";
  Status s = write3mf(*mesh, {"Rosette", "a test"}, path.string());
  ASSERT_TRUE(s.ok()) << s.error();
  auto back = read3mfSummary(path.string());
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->triangles, mesh->triangles.size());
  EXPECT_EQ(back->vertices, mesh->vertices.size());
  EXPECT_TRUE(back->manifoldAndOriented);
  EXPECT_EQ(back->unit, "millimeter");
  EXPECT_FALSE(write3mf(*mesh, {}, "/nonexistent-folder/x.3mf").ok());
}

TEST(HeightMapExport, HoldsTheFrontFace) {
  const Model model = modelOf(R"({"workpiece":{"type":"disc","r":20,"d":0.5},
    "operations":[{"op":"punch","side":"back","a":3,"p":0.5,"q":1,"at":[0,0,0.5]},
                  {"op":"trace","side":"front","a":0.5,"points":[[-6,-16],[-6,6]]}]})");
  HeightMapOptions o;
  o.pixel = 0.2;
  auto map = heightMap(model, o);
  ASSERT_TRUE(map.ok()) << map.error();
  auto zAt = [&](double x, double y) {
    const int col = static_cast<int>(std::lround((x - map->x0) / map->pixel));
    const int row = static_cast<int>(std::lround((map->y1 - y) / map->pixel));
    const std::uint16_t v = map->values[static_cast<size_t>(row) * map->width + col];
    return v == 0 ? std::nan("") : map->z(v);
  };
  // At rest the front face is at z = d; the punch raises the centre; the groove lowers x = -6.
  EXPECT_NEAR(zAt(12.0, -12.0), 0.5, 0.001);
  EXPECT_GT(zAt(0.0, 0.0), 0.5 + 1.0);
  EXPECT_LT(zAt(-6.0, 0.0), 0.5 - 0.1);
  EXPECT_TRUE(std::isnan(zAt(map->x0, map->y1))) << "the corner of the square is not metal";
  // The value found is the top: the model is >= 0 just below it and < 0 just above.
  // (at a pixel's centre; the values are quantised to 1/65535 of the range)
  const double px = map->x0 + 60 * map->pixel, py = map->y1 - 90 * map->pixel;
  const double z = zAt(px, py), q = (map->zMax - map->zMin) / 65534.0;
  EXPECT_GE(model.evaluate(P3<double>{px, py, z - q}), 0.0);
  EXPECT_LT(model.evaluate(P3<double>{px, py, z + q}), 0.0);

  auto png = heightMapPng(*map, "Disc");
  ASSERT_TRUE(png.ok()) << png.error();
  ASSERT_GT(png->size(), 33u);
  EXPECT_EQ(png->substr(1, 3), "PNG");
  EXPECT_EQ(static_cast<unsigned char>((*png)[24]), 16) << "16 bits a sample";
  EXPECT_EQ(static_cast<unsigned char>((*png)[25]), 0) << "greyscale";
  EXPECT_NE(png->find("emboss:pixel_mm"), std::string::npos);
  EXPECT_NE(png->find("emboss:z_min_mm"), std::string::npos);
  EXPECT_NE(png->find("pHYs"), std::string::npos);
}

}  // namespace
}  // namespace emboss
