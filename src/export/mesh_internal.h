// Between the mesh export's two files: what mesh.cpp (extraction, checks) and mesh_decimate.cpp
// (welding, mending, decimation) share. Not for other callers.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "export/mesh.h"

namespace emboss {

class Model;
class OpGrid;
class ThreadPool;

namespace mesh_detail {

// A sliver: |cross| <= kSliver * (longest edge)^2, i.e. its smallest angle under about 1e-4 rad.
// Its normal is lost in float rounding (readers such as admesh then recompute it).
inline constexpr float kSliver = 1e-4f;
// What the mending after simplification tries to flip away: under about 1.7 degrees. Such a
// triangle's normal is still defined, but it leans on float noise (0.004 mm across a 0.15 mm
// edge), and a smooth-shading reader weights it by its near-straight angle: a dark blotch on a
// flat face in a path tracer's picture of the mesh.
inline constexpr float kMendSliver = 3e-2f;

// Merges vertices whose float positions are equal and drops the triangles that degenerate.
void weldFloats(TriangleMesh& mesh);
// Keeps only the vertices some triangle uses, in first-use order.
void compact(TriangleMesh& mesh);
// |(b - a) x (c - a)|^2, the cross product itself in n.
float crossLength2(const float* a, const float* b, const float* c, float n[3]);
bool sliver(const float* a, const float* b, const float* c, float k = kSliver);
// |cross| / (longest edge)^2: about the smallest angle of a thin triangle, in radians.
float shape(const float* a, const float* b, const float* c);
// Flips the longest edge of each zero-area or sliver triangle (kMendSliver) among the first n
// indices (3 a triangle) with its neighbour's, where that makes two proper triangles facing the
// neighbour's way and the worse of the two is better than the worse before.
void mendFlatTriangles(std::vector<unsigned int>& ix, size_t n, const std::vector<float>& pos);
// A fold: two triangles across an edge whose normals are more than 120 degrees apart (cosine
// under kFoldCos), the surface folded over itself.
inline constexpr double kFoldCos = -0.5;
// Whether triangles a and b (of the vertices v) fold against each other.
bool foldsAcross(const std::vector<std::array<float, 3>>& v, const std::array<std::uint32_t, 3>& a,
                 const std::array<std::uint32_t, 3>& b);
// A thin triangle: its height under kThin of its longest edge (|cross| / longest edge^2); its
// normal is float noise, a speck in a smooth-shading reader.
inline constexpr double kThin = 1e-3;

// Removes the vertices of folds (the fine mesh's own, at a sharp crease) among the first n
// indices, each (or, where no one vertex will do, the two ends of an edge) by triangulating the
// hole again (ear clipping in the plane of its rim, or where no plane holds it, a single vertex's
// edge collapsed onto its rim) where that makes good triangles, takes fewer folds and moves the
// surface at the vertex by at most maxError; then, the same way, a vertex of each thin triangle
// left where the hole's worst triangle is better and it folds no more. n becomes the new count.
struct VertexRemovals {
  size_t folds = 0, thin = 0;  // vertices taken out for each
};
VertexRemovals removeFoldsAndThinTriangles(std::vector<unsigned int>& ix, size_t& n, const std::vector<float>& pos,
                                           double maxError);
// Decimates within maxError tile by tile (tile: the first tiles' side, mm, a whole number of the
// grid's cells; the tiles' edges on the grid's planes through (planeX, planeY)) on the pool,
// keeping fine where a tile's simplification would fold or leave a triangle under 1/1000 (no such
// flaw is made that the fine mesh had not); returns how many tiles failed their check in the last
// round (left fine). Then the seams: what is left fine simplified again in tiles across the first
// round's edges (`seams` false: not, for tests).
//
// With `onSurface`, the seams' tiles first take everything in them, the simplified patches beside
// the seam too, and simplify it again; a triangle that makes is kept only where `onSurface` finds
// it within maxError of the model's surface (meshoptimizer measures its error against what it is
// given, here already simplified triangles, not against the fine mesh).
// |f| / |grad f| at a point: the first-order distance to the model's surface.
double distanceAt(const Model& model, const OpGrid& grid, double x, double y, double z, std::vector<std::uint32_t>& scratch);
using SurfaceCheck = std::function<bool(const std::array<float, 3>&, const std::array<float, 3>&,
                                        const std::array<float, 3>&)>;
// The largest first-order distance (|f| / |grad f|) of a triangle's seven points from the model's
// surface: its centre, its edges' midpoints and the points halfway from each corner to the centre,
// read in that order; once one is beyond `enough` the rest are not read.
double farthestOfSeven(const Model& model, const OpGrid& grid, const std::array<float, 3>& a,
                       const std::array<float, 3>& b, const std::array<float, 3>& c, double enough,
                       std::vector<std::uint32_t>& scratch);
// Whether a triangle lies within maxError of the model's surface at its seven points
// (farthestOfSeven()). Holds references to the model and the grid.
SurfaceCheck surfaceCheck(const Model& model, const OpGrid& grid, double maxError);
size_t decimate(TriangleMesh& mesh, double maxError, double tile, double planeX, double planeY, ThreadPool& pool,
                bool seams = true, const SurfaceCheck* onSurface = nullptr);
// The folds left (the fine mesh's own, marching tetrahedra's at a sharp crease, that no removal
// took out): each vertex of a fold is moved to the surface's point nearest its neighbours' centre
// (Newton's steps along the gradient from there), where the vertex ends within 1e-4 mm of the
// surface, fewer of the edges around it fold, and no triangle of its fan becomes thin. The
// triangles stay as they are, so the mesh stays closed and manifold. Three sweeps over the folds'
// vertices. Returns how many moves were kept.
size_t moveOutOfFolds(TriangleMesh& mesh, const Model& model, const OpGrid& grid);
// Before the moves: each fold edge whose two triangles make a quad is flipped to the quad's other
// diagonal where that leaves fewer folds on the quad's five edges, no thin triangle and no new
// triangle further from the surface than the two before (farthestOfSeven()).
// Marching tetrahedra cut across a sharp ridge (a bowl's rim: its wall and its inner face) with an
// edge under it and two fins up to the ridge; the flip's diagonal runs along the ridge instead.
// Sweeps until none is flipped (at most eight). Returns how many flips were kept.
size_t flipFoldEdges(TriangleMesh& mesh, const Model& model, const OpGrid& grid);

}  // namespace mesh_detail
}  // namespace emboss
