// Marching tetrahedra over an interval-pruned grid, regula falsi onto the surface, meshoptimizer.
#include "export/mesh.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <unordered_map>
#include <unordered_set>

#include "frep/interval.h"
#include "frep/op_grid.h"
#include "export/mesh_internal.h"
#include "render/thread_pool.h"

namespace emboss {

using namespace mesh_detail;

namespace {

constexpr int kBlock = 16;  // cells per block edge; a block is one task and one candidate list
constexpr int kSamples = kBlock + 1;
constexpr double kClampT = 0.02;  // an edge vertex stays this fraction of the edge from its ends

// The six tetrahedra of a cube around its main diagonal, each the monotone path 0 -> a -> a|b -> 7
// over the cube's corners (bit 0: +x, bit 1: +y, bit 2: +z). Every cell is cut the same way, so the
// diagonals of a shared face agree and the surface has no cracks.
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

struct Grid {
  double ox = 0, oy = 0, oz = 0, h = 1;
  int nx = 0, ny = 0, nz = 0;  // cells; samples run 0..n
  int bx = 0, by = 0, bz = 0;  // blocks
};

// An edge of the grid: its lower sample and its direction (the corner bits it adds, 1..7).
std::uint64_t edgeKey(int i, int j, int k, int dir) {
  return (static_cast<std::uint64_t>(i) << 43) | (static_cast<std::uint64_t>(j) << 22) |
         (static_cast<std::uint64_t>(k) << 3) | static_cast<std::uint64_t>(dir);
}

// Whether the edge of `key` lies in a face of its block (every axis it does not run along at a
// multiple of kBlock): only such an edge, and its vertex, can be in two blocks.
bool edgeOnBlockFace(std::uint64_t key) {
  const auto i = static_cast<int>(key >> 43), j = static_cast<int>((key >> 22) & ((1u << 21) - 1)),
             k = static_cast<int>((key >> 3) & ((1u << 19) - 1)), dir = static_cast<int>(key & 7);
  return (i % kBlock == 0 && !(dir & 1)) || (j % kBlock == 0 && !(dir & 2)) || (k % kBlock == 0 && !(dir & 4));
}

struct BlockOut {
  std::vector<std::uint64_t> keys;
  std::vector<std::array<float, 3>> pos;  // the mesh's floats (found in double)
  std::vector<std::array<std::uint32_t, 3>> tris;  // indices into keys / pos
};

class BlockMesher {
 public:
  BlockMesher(const Model& model, const Grid& g, std::span<const std::uint32_t> candidates, int bi, int bj, int bk,
              long& evals)
      : model_(model), g_(g), cand_(candidates), evals_(evals) {
    i0_ = bi * kBlock;
    j0_ = bj * kBlock;
    k0_ = bk * kBlock;
    ni_ = std::min(kBlock, g.nx - i0_);
    nj_ = std::min(kBlock, g.ny - j0_);
    nk_ = std::min(kBlock, g.nz - k0_);
  }

  void run(BlockOut& out) {
    out_ = &out;
    active_.assign(static_cast<size_t>(kBlock) * kBlock * kBlock, 0);
    classify(0, 0, 0, kBlock);
    if (!any_) return;
    samples_.assign(static_cast<size_t>(kSamples) * kSamples * kSamples, std::numeric_limits<double>::quiet_NaN());
    for (int c = 0; c < nk_; ++c)
      for (int b = 0; b < nj_; ++b)
        for (int a = 0; a < ni_; ++a)
          if (active_[(static_cast<size_t>(c) * kBlock + b) * kBlock + a]) cell(a, b, c);
  }

 private:
  double x(int i) const { return g_.ox + (i0_ + i) * g_.h; }
  double y(int j) const { return g_.oy + (j0_ + j) * g_.h; }
  double z(int k) const { return g_.oz + (k0_ + k) * g_.h; }

  // Marks the cells of the cube [a, a+n)^3 (block-local) that interval arithmetic cannot prove
  // to lie wholly inside or wholly outside.
  void classify(int a, int b, int c, int n) {
    if (a >= ni_ || b >= nj_ || c >= nk_) return;
    const int a1 = std::min(a + n, ni_), b1 = std::min(b + n, nj_), c1 = std::min(c + n, nk_);
    const P3<Interval> box{{x(a), x(a1)}, {y(b), y(b1)}, {z(c), z(c1)}};
    const Interval f = model_.evaluate(box, cand_);
    ++evals_;
    if (f.lo >= 0.0 || f.hi < 0.0) return;  // no sign change in it
    if (n <= 2) {
      for (int cc = c; cc < c1; ++cc)
        for (int bb = b; bb < b1; ++bb)
          for (int aa = a; aa < a1; ++aa) active_[(static_cast<size_t>(cc) * kBlock + bb) * kBlock + aa] = 1;
      any_ = true;
      return;
    }
    const int m = n / 2;
    for (int dc = 0; dc < 2; ++dc)
      for (int db = 0; db < 2; ++db)
        for (int da = 0; da < 2; ++da) classify(a + da * m, b + db * m, c + dc * m, m);
  }

  double eval(double px, double py, double pz) {
    ++evals_;
    return model_.evaluate(P3<double>{px, py, pz}, cand_);
  }

  // The model at a sample; on the grid's outer boundary it is taken as outside, so the surface is
  // closed even where a model reaches its bounds.
  double sample(int a, int b, int c) {
    double& s = samples_[(static_cast<size_t>(c) * kSamples + b) * kSamples + a];
    if (std::isnan(s)) {
      const int gi = i0_ + a, gj = j0_ + b, gk = k0_ + c;
      if (gi == 0 || gj == 0 || gk == 0 || gi == g_.nx || gj == g_.ny || gk == g_.nz) {
        s = -1.0;
      } else {
        s = eval(x(a), y(b), z(c));
        if (std::isnan(s)) s = -1.0;
      }
    }
    return s;
  }

  // The vertex on the edge between cube corners u and v (u's bits a subset of v's) of cell (a,b,c).
  std::uint32_t vertex(int a, int b, int c, int u, int v, const double* fc) {
    const int ua = a + (u & 1), ub = b + ((u >> 1) & 1), uc = c + ((u >> 2) & 1);
    const std::uint64_t key = edgeKey(i0_ + ua, j0_ + ub, k0_ + uc, u ^ v);
    auto [it, fresh] = local_.try_emplace(key, static_cast<std::uint32_t>(out_->keys.size()));
    if (!fresh) return it->second;
    const std::array<double, 3> pu{x(ua), y(ub), z(uc)};
    const std::array<double, 3> pv{x(a + (v & 1)), y(b + ((v >> 1) & 1)), z(c + ((v >> 2) & 1))};
    // Regula falsi (Illinois) from the inside end (f >= 0) at t = 0 to the outside end at t = 1.
    const bool uIn = fc[u] >= 0.0;
    const auto& pin = uIn ? pu : pv;
    const auto& pout = uIn ? pv : pu;
    double ta = 0, tb = 1, fa = uIn ? fc[u] : fc[v], fb = uIn ? fc[v] : fc[u];
    double wa = fa, wb = fb;  // Illinois weights
    int side = 0;
    for (int iter = 0; iter < 4 && wa - wb > 0.0; ++iter) {
      const double t = ta + (tb - ta) * wa / (wa - wb);
      const double ft = eval(pin[0] + t * (pout[0] - pin[0]), pin[1] + t * (pout[1] - pin[1]),
                             pin[2] + t * (pout[2] - pin[2]));
      if (std::isnan(ft)) break;
      if (ft >= 0.0) {
        ta = t;
        fa = wa = ft;
        if (side == 1) wb *= 0.5;
        side = 1;
      } else {
        tb = t;
        fb = wb = ft;
        if (side == -1) wa *= 0.5;
        side = -1;
      }
    }
    double t = fa - fb > 0.0 ? ta + (tb - ta) * fa / (fa - fb) : 0.5 * (ta + tb);
    t = std::clamp(t, kClampT, 1.0 - kClampT);
    out_->keys.push_back(key);
    out_->pos.push_back({static_cast<float>(pin[0] + t * (pout[0] - pin[0])), static_cast<float>(pin[1] + t * (pout[1] - pin[1])),
                         static_cast<float>(pin[2] + t * (pout[2] - pin[2]))});
    return it->second;
  }

  void cell(int a, int b, int c) {
    double fc[8];
    int inside = 0;
    for (int corner = 0; corner < 8; ++corner) {
      fc[corner] = sample(a + (corner & 1), b + ((corner >> 1) & 1), c + ((corner >> 2) & 1));
      if (fc[corner] >= 0.0) inside |= 1 << corner;
    }
    if (inside == 0 || inside == 0xff) return;
    for (const auto& tet : kTets) {
      int in[4], out[4], nin = 0, nout = 0;
      for (int q = 0; q < 4; ++q) (inside >> tet[q] & 1 ? in[nin++] : out[nout++]) = tet[q];
      if (nin == 0 || nout == 0) continue;
      // In a path tetrahedron every pair of corners is ordered by inclusion of their bits.
      auto edge = [&](int p, int q) { return (p & q) == p ? vertex(a, b, c, p, q, fc) : vertex(a, b, c, q, p, fc); };
      auto emit = [&](std::array<int, 2> e0, std::array<int, 2> e1, std::array<int, 2> e2) {
        std::array<std::uint32_t, 3> t{edge(e0[0], e0[1]), edge(e1[0], e1[1]), edge(e2[0], e2[1])};
        // Orientation from the edges' midpoints (never degenerate in a tetrahedron): the normal
        // points from the inside corners toward the outside ones.
        auto mid = [](std::array<int, 2> e, int axis) { return 0.5 * (((e[0] >> axis) & 1) + ((e[1] >> axis) & 1)); };
        double m[3][3];
        const std::array<int, 2> es[3] = {e0, e1, e2};
        for (int r = 0; r < 3; ++r)
          for (int axis = 0; axis < 3; ++axis) m[r][axis] = mid(es[r], axis);
        const double ux = m[1][0] - m[0][0], uy = m[1][1] - m[0][1], uz = m[1][2] - m[0][2];
        const double vx = m[2][0] - m[0][0], vy = m[2][1] - m[0][1], vz = m[2][2] - m[0][2];
        const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        double dir[3] = {0, 0, 0};
        for (int q = 0; q < nout; ++q)
          for (int axis = 0; axis < 3; ++axis) dir[axis] += ((out[q] >> axis) & 1) / double(nout);
        for (int q = 0; q < nin; ++q)
          for (int axis = 0; axis < 3; ++axis) dir[axis] -= ((in[q] >> axis) & 1) / double(nin);
        if (nx * dir[0] + ny * dir[1] + nz * dir[2] < 0.0) std::swap(t[1], t[2]);
        out_->tris.push_back(t);
      };
      if (nin == 1) {
        emit({in[0], out[0]}, {in[0], out[1]}, {in[0], out[2]});
      } else if (nout == 1) {
        emit({in[0], out[0]}, {in[1], out[0]}, {in[2], out[0]});
      } else {
        // The quad (in0,out0) (in1,out0) (in1,out1) (in0,out1), in cyclic order.
        emit({in[0], out[0]}, {in[1], out[0]}, {in[1], out[1]});
        emit({in[0], out[0]}, {in[1], out[1]}, {in[0], out[1]});
      }
    }
  }

  const Model& model_;
  const Grid& g_;
  std::span<const std::uint32_t> cand_;
  long& evals_;
  int i0_ = 0, j0_ = 0, k0_ = 0, ni_ = 0, nj_ = 0, nk_ = 0;
  bool any_ = false;
  std::vector<std::uint8_t> active_;
  std::vector<double> samples_;
  std::unordered_map<std::uint64_t, std::uint32_t> local_;
  BlockOut* out_ = nullptr;
};

}  // namespace

namespace mesh_detail {

double distanceAt(const Model& model, const OpGrid& grid, double x, double y, double z, std::vector<std::uint32_t>& scratch) {
  const auto cand = grid.at(x, y, scratch);
  const Grad g = model.evaluate(P3<Grad>{{x, 1, 0, 0}, {y, 0, 1, 0}, {z, 0, 0, 1}}, cand);
  const double len = std::sqrt(g.dx * g.dx + g.dy * g.dy + g.dz * g.dz);
  return len > 0.0 ? std::abs(g.v) / len : 0.0;
}

double farthestOfSeven(const Model& model, const OpGrid& grid, const std::array<float, 3>& a,
                       const std::array<float, 3>& b, const std::array<float, 3>& c, double enough,
                       std::vector<std::uint32_t>& scratch) {
  constexpr double s = 1.0 / 6, t = 2.0 / 3;  // (t, s, s): halfway from a corner to the centre
  constexpr double kPoints[7][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5},
                                    {t, s, s},                   {s, t, s},     {s, s, t}};
  double farthest = 0.0;
  for (const auto& w : kPoints) {
    double q[3];
    for (int k = 0; k < 3; ++k) q[k] = w[0] * a[k] + w[1] * b[k] + w[2] * c[k];
    farthest = std::max(farthest, distanceAt(model, grid, q[0], q[1], q[2], scratch));
    if (farthest > enough) break;
  }
  return farthest;
}

SurfaceCheck surfaceCheck(const Model& model, const OpGrid& grid, double maxError) {
  return [&model, &grid, maxError](const std::array<float, 3>& a, const std::array<float, 3>& b,
                                    const std::array<float, 3>& c) {
    thread_local std::vector<std::uint32_t> scratch;
    return farthestOfSeven(model, grid, a, b, c, maxError, scratch) <= maxError;
  };
}

}  // namespace mesh_detail

double autoMeshCell(const Model& model) {
  double finest = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < model.activeCount(); ++i)
    finest = std::min(finest, model.operations()[i].op().characteristicLength());
  // Finer than 0.1 mm is finer than a printer or a mill works (unless the sheet is thinner).
  const double sheet = 0.8 * model.workpiece().halfThickness();
  double h = std::min({std::max(0.5 * finest, 0.1), sheet, 1.0});
  const Box3 b = model.bounds();
  const double area = std::max(0.0, b.x1 - b.x0) * std::max(0.0, b.y1 - b.y0);
  h = std::max(h, std::sqrt(area / 2.5e7));  // at most 25 million columns
  return std::max(h, 0.005);
}

Result<TriangleMesh> meshModel(const Model& model, const MeshOptions& options, MeshStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  MeshStats st;
  const double h = options.cell > 0.0 ? options.cell : autoMeshCell(model);
  st.cell = h;
  const Box3 b = model.bounds();
  Grid g;
  g.h = h;
  // No end of the bounds may lie on a plane of samples: a plate's sides lie on its bounds, and a
  // wall on a plane has f = 0 at the samples themselves, its vertices crowd against them (kClampT,
  // 0.003 mm off the wall at a 0.15 mm cell) and the triangles where the relief meets the wall fold
  // over. Each axis's grid is set so that both ends lie at least a quarter of a cell from its
  // planes: with the bounds' span phi cells past a whole number, the low end lies delta into its
  // cell and the high end delta + phi, placed either side of a cell's middle (phi <= 1/2) or of a
  // plane (phi > 1/2).
  const auto origin = [&](double lo, double hi) {
    const double span = (hi - lo) / h, phi = span - std::floor(span);
    const double delta = phi <= 0.5 ? 0.5 - 0.5 * phi : 1.0 - 0.5 * phi;
    return lo - (1.0 + delta) * h;
  };
  g.ox = origin(b.x0, b.x1);
  g.oy = origin(b.y0, b.y1);
  g.oz = origin(b.z0, b.z1);
  st.planeX = g.ox, st.planeY = g.oy;
  const auto cells = [&](double o, double hi) { return static_cast<double>(std::ceil((hi - o) / h)) + 1.0; };
  const double cx = cells(g.ox, b.x1), cy = cells(g.oy, b.y1), cz = cells(g.oz, b.z1);
  if (!(cx * cy * cz <= options.maxCells) || !(cx * cy <= options.maxColumns) || cx >= (1 << 20) || cy >= (1 << 20) ||
      cz >= (1 << 18))
  {
    char msg[200];
    std::snprintf(msg, sizeof msg, "a mesh cell of %.3g mm is too fine for a piece of %.4g x %.4g mm (use --resolution %.2g or more)",
                  h, b.x1 - b.x0, b.y1 - b.y0, std::sqrt((b.x1 - b.x0) * (b.y1 - b.y0) / options.maxColumns) * 1.01);
    return fail(msg);
  }
  g.nx = static_cast<int>(cx);
  g.ny = static_cast<int>(cy);
  g.nz = static_cast<int>(cz);
  g.bx = (g.nx + kBlock - 1) / kBlock;
  g.by = (g.ny + kBlock - 1) / kBlock;
  g.bz = (g.nz + kBlock - 1) / kBlock;

  OpGrid opGrid;
  opGrid.sync(model);
  ThreadPool pool(options.threads);
  const long blocks = static_cast<long>(g.bx) * g.by * g.bz;
  std::atomic<long> evals{0};
  std::mutex progressMutex;
  int lastPercent = -1;
  auto report = [&](double fraction) {
    if (!options.progress) return;
    std::lock_guard<std::mutex> lock(progressMutex);
    const int percent = static_cast<int>(fraction * 100.0);
    if (percent == lastPercent) return;
    lastPercent = percent;
    options.progress(fraction);
  };
  report(0.0);
  // The fine mesh: the blocks' surfaces, merged. (Made again, rather than kept beside the
  // decimated one, in the rare case that the decimated mesh fails its check: on a busy piece that
  // copy was a fifth of the peak memory.)
  auto fineMesh = [&](bool reporting) {
    // Blocks share the vertices of their common faces: merged by edge key as the blocks are made.
    // Only an edge lying in a block's face can be in two blocks; the others (most) are new
    // vertices. The columns are merged in their own order (row by row, each bottom to top),
    // whichever thread finishes the column next in that order merging it and those made ahead of
    // it, so the mesh is the same whatever the threads' timing, and only the few columns made ahead
    // of that order wait in memory (keeping every block's output until a merge at the end was two
    // thirds of a busy piece's peak memory).
    TriangleMesh mesh;
    const size_t columns = static_cast<size_t>(g.bx) * g.by;
    std::vector<std::vector<BlockOut>> made(columns);  // a column's blocks (bz of them) once made
    size_t nextColumn = 0;
    std::mutex mergeMutex;
    std::unordered_map<std::uint64_t, std::uint32_t> global;
    std::vector<std::uint32_t> remap;
    auto merge = [&](const BlockOut& o) {
      remap.resize(o.keys.size());
      for (size_t v = 0; v < o.keys.size(); ++v) {
        const auto next = static_cast<std::uint32_t>(mesh.vertices.size());
        if (edgeOnBlockFace(o.keys[v])) {
          auto [it, fresh] = global.try_emplace(o.keys[v], next);
          remap[v] = it->second;
          if (!fresh) continue;
        } else {
          remap[v] = next;
        }
        mesh.vertices.push_back(o.pos[v]);
      }
      for (const auto& t : o.tris) mesh.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
    };
    std::atomic<long> done{0};
    // One tile per block column (x, y); the column's blocks run bottom to top.
    pool.parallelFor2D(Rect{0, 0, g.bx, g.by}, 1, [&](const Rect& r) {
      std::vector<std::uint32_t> scratch;
      for (int bj = r.y; bj < r.y + r.h; ++bj)
        for (int bi = r.x; bi < r.x + r.w; ++bi) {
          const Box2 xy{g.ox + bi * kBlock * h, g.oy + bj * kBlock * h, g.ox + std::min((bi + 1) * kBlock, g.nx) * h,
                        g.oy + std::min((bj + 1) * kBlock, g.ny) * h};
          const auto found = opGrid.in(xy, scratch);
          const std::vector<std::uint32_t> cand(found.begin(), found.end());
          std::vector<BlockOut> column(static_cast<size_t>(g.bz));
          long n = 0;
          for (int bk = 0; bk < g.bz; ++bk) {
            BlockMesher mesher(model, g, cand, bi, bj, bk, n);
            mesher.run(column[static_cast<size_t>(bk)]);
          }
          evals += n;
          {
            std::lock_guard lock(mergeMutex);
            const size_t c = static_cast<size_t>(bj) * g.bx + bi;
            made[c] = std::move(column);
            for (; nextColumn < columns && !made[nextColumn].empty(); ++nextColumn) {
              for (const BlockOut& o : made[nextColumn]) merge(o);
              made[nextColumn] = {};
            }
          }
          if (reporting) report(0.8 * static_cast<double>(done += g.bz) / static_cast<double>(blocks));
        }
    });
    weldFloats(mesh);
    return mesh;
  };
  TriangleMesh mesh = fineMesh(true);
  st.fineTriangles = mesh.triangles.size();
  if (mesh.triangles.empty()) return fail("the model has no surface inside its bounds (nothing to mesh)");
  report(0.85);

  if (options.maxError > 0.0) {
    const SurfaceCheck onSurface = surfaceCheck(model, opGrid, options.maxError);
    st.fineTiles = decimate(mesh, options.maxError, 48.0 * h, g.ox, g.oy, pool, true, &onSurface);
    const std::string problem =
        options.rejectDecimated ? "rejected" : mesh.triangles.empty() ? "empty" : checkClosedManifold(mesh);
    if (!problem.empty()) {
      mesh = {};
      mesh = fineMesh(false);  // keep the fine mesh rather than a broken one
    } else {
      st.decimated = true;
    }
  }
  // Slivers left anywhere (the fine mesh has a few too) are mended the same way, over the whole
  // mesh; then the folds and the thin triangles the simplifier left are taken out (the whole mesh
  // at once: a pass inside each tile reached only a fifth of the folds).
  {
    std::vector<unsigned int> ix(mesh.triangles.size() * 3);
    std::memcpy(ix.data(), mesh.triangles.data(), ix.size() * sizeof(unsigned int));
    std::vector<float> pos(mesh.vertices.size() * 3);
    std::memcpy(pos.data(), mesh.vertices.data(), pos.size() * sizeof(float));
    mendFlatTriangles(ix, ix.size(), pos);
    size_t n = ix.size();
    const VertexRemovals removed =
        st.decimated ? removeFoldsAndThinTriangles(ix, n, pos, options.maxError) : VertexRemovals{};
    // Checked in place (the vertices stay as they are: no copy of them), put back if it fails.
    auto before = std::move(mesh.triangles);
    mesh.triangles.resize(n / 3);
    std::memcpy(mesh.triangles.data(), ix.data(), n * sizeof(unsigned int));
    if (checkClosedManifold(mesh).empty()) {
      st.foldVertices = removed.folds, st.thinVertices = removed.thin;
      if (removed.folds + removed.thin > 0) compact(mesh);
    } else {
      mesh.triangles = std::move(before);
    }
  }
  // The fine mesh's own folds left (no removal took them out): flipped where they cut under a
  // ridge, then their vertices moved along the surface ("Fins on a ridge flipped" and "Folds moved
  // out", docs/exports.md).
  st.flippedEdges = flipFoldEdges(mesh, model, opGrid);
  st.movedVertices = moveOutOfFolds(mesh, model, opGrid);
  report(0.9);

  // Measure: the vertices' and a sample of the faces' distances to the model's surface.
  {
    const size_t nv = mesh.vertices.size();
    const size_t stride = std::max<size_t>(1, mesh.triangles.size() / 200000);
    const size_t nf = (mesh.triangles.size() + stride - 1) / stride;
    std::vector<double> dv(nv), df(nf);
    const int chunks = 256;
    pool.parallelFor2D(Rect{0, 0, chunks, 1}, 1, [&](const Rect& r) {
      std::vector<std::uint32_t> scratch;
      for (int c = r.x; c < r.x + r.w; ++c) {
        for (size_t v = nv * c / chunks; v < nv * (c + 1) / chunks; ++v) {
          const auto& p = mesh.vertices[v];
          dv[v] = distanceAt(model, opGrid, p[0], p[1], p[2], scratch);
        }
        for (size_t f = nf * c / chunks; f < nf * (c + 1) / chunks; ++f) {
          const auto& t = mesh.triangles[f * stride];
          double q[3];
          for (int a = 0; a < 3; ++a)
            q[a] = (double(mesh.vertices[t[0]][a]) + mesh.vertices[t[1]][a] + mesh.vertices[t[2]][a]) / 3.0;
          df[f] = distanceAt(model, opGrid, q[0], q[1], q[2], scratch);
        }
      }
    });
    double sum = 0;
    for (double d : dv) {
      st.vertexMax = std::max(st.vertexMax, d);
      sum += d;
    }
    st.vertexMean = nv ? sum / nv : 0.0;
    for (double d : df) st.faceMax = std::max(st.faceMax, d);
  }
  st.triangles = mesh.triangles.size();
  st.vertices = mesh.vertices.size();
  st.volume = meshVolume(mesh);
  st.area = meshArea(mesh);
  st.evaluations = evals.load();
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report(1.0);
  if (stats) *stats = st;
  return mesh;
}

std::string checkClosedManifold(const TriangleMesh& mesh) {
  std::vector<std::uint64_t> directed;
  directed.reserve(mesh.triangles.size() * 3);
  size_t degenerate = 0;
  for (const auto& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++degenerate;
      continue;
    }
    float n[3];
    if (crossLength2(mesh.vertices[t[0]].data(), mesh.vertices[t[1]].data(), mesh.vertices[t[2]].data(), n) == 0.0f) ++degenerate;
    for (int e = 0; e < 3; ++e) directed.push_back((static_cast<std::uint64_t>(t[e]) << 32) | t[(e + 1) % 3]);
  }
  std::sort(directed.begin(), directed.end());
  size_t open = 0, repeated = 0;
  for (size_t i = 0; i < directed.size(); ++i) {
    const std::uint64_t key = directed[i];
    if (i + 1 < directed.size() && directed[i + 1] == key) {
      ++repeated;
      continue;
    }
    if (!std::binary_search(directed.begin(), directed.end(), (key << 32) | (key >> 32))) ++open;
  }
  if (degenerate == 0 && open == 0 && repeated == 0) return {};
  return std::to_string(open) + " open edges, " + std::to_string(repeated) + " edges used twice the same way, " +
         std::to_string(degenerate) + " degenerate triangles";
}

double meshVolume(const TriangleMesh& mesh) {
  double v = 0.0;
  for (const auto& t : mesh.triangles) {
    const auto& a = mesh.vertices[t[0]];
    const auto& b = mesh.vertices[t[1]];
    const auto& c = mesh.vertices[t[2]];
    v += (double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) - double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
          double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0]));
  }
  return v / 6.0;
}

double meshArea(const TriangleMesh& mesh) {
  double s = 0.0;
  for (const auto& t : mesh.triangles) {
    const auto& a = mesh.vertices[t[0]];
    const auto& b = mesh.vertices[t[1]];
    const auto& c = mesh.vertices[t[2]];
    const double ux = double(b[0]) - a[0], uy = double(b[1]) - a[1], uz = double(b[2]) - a[2];
    const double vx = double(c[0]) - a[0], vy = double(c[1]) - a[1], vz = double(c[2]) - a[2];
    const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    s += 0.5 * std::sqrt(nx * nx + ny * ny + nz * nz);
  }
  return s;
}

}  // namespace emboss
