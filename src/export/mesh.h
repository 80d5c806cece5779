// A closed triangle mesh of the model, for the take-home exports (STL, 3MF).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "frep/model.h"
#include "util/result.h"

namespace emboss {

// Vertices in millimetres in the scene's coordinates (the front face looks at +z); triangles
// counter-clockwise seen from outside the metal.
struct TriangleMesh {
  std::vector<std::array<float, 3>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

struct MeshOptions {
  // The sampling grid's step in mm; 0 picks it from the finest tool and the sheet's thickness
  // (autoMeshCell()).
  double cell = 0.0;
  // Decimation: the largest distance a simplified face may move from the fine mesh, in mm; 0 keeps
  // the fine mesh.
  double maxError = 0.01;
  int threads = 0;  // 0: one per core
  // For tests: the decimated mesh is taken as failing its final check, so the fine mesh is made
  // again and written (the path a real failure takes).
  bool rejectDecimated = false;
  // Called with the fraction done (0..1), from the calling thread or a worker, never concurrently.
  std::function<void(double)> progress;
  // Refused beyond this many grid cells, or columns of cells in the plate's plane (the fine mesh
  // has a few triangles per column and face: 10^8 columns would need tens of gigabytes).
  double maxCells = 4e10;
  double maxColumns = 1e8;
};

struct MeshStats {
  double cell = 0.0;
  std::size_t fineTriangles = 0;  // before decimation
  std::size_t triangles = 0;
  std::size_t vertices = 0;
  bool decimated = false;
  std::size_t fineTiles = 0;  // decimation tiles kept fine (their simplified patch failed the check)
  // A plane of the grid's samples along x and one along y: the decimation's tiles start on them.
  double planeX = 0.0, planeY = 0.0;
  std::size_t foldVertices = 0;  // vertices removed to take out folds the decimation left
  std::size_t thinVertices = 0;  // and thin triangles (height under 1/1000 of the longest edge)
  std::size_t flippedEdges = 0;   // fold edges of the fine mesh's own flipped along a ridge
  std::size_t movedVertices = 0;  // vertices moved along the surface out of the fine mesh's own folds
  double volume = 0.0;  // mm^3, from the final mesh
  double area = 0.0;    // mm^2
  // Distances to the model's surface (first order: |f| / |grad f|), in mm: of the vertices (max and
  // mean), and of the faces' centroids (max over a sample of up to 200 000 faces).
  double vertexMax = 0.0, vertexMean = 0.0, faceMax = 0.0;
  long evaluations = 0;  // of the model, points and boxes
  double seconds = 0.0;
};

// The grid step meshModel() uses when MeshOptions::cell is 0: half the finest operation's
// characteristic length but not under 0.1 mm (a printer's or a mill's detail), at most 0.8 of the
// sheet's half thickness (so both faces of the sheet fall into different cells) and 1 mm, and
// coarse enough for at most 25 million columns.
double autoMeshCell(const Model& model);

// Marching tetrahedra (each grid cell cut into the six tetrahedra of its main diagonal, the same
// cut in every cell, so the surface has no cracks) over the cells that interval arithmetic cannot
// prove empty; each vertex is the surface point found on its edge by regula falsi on the model
// itself. The result is closed, oriented and 2-manifold; then it is decimated where flat
// (meshoptimizer, within maxError) and checked again: when the decimated mesh fails the check the
// fine one is kept.
Result<TriangleMesh> meshModel(const Model& model, const MeshOptions& options, MeshStats* stats = nullptr);

// Empty when every edge is shared by exactly two triangles in opposite directions and no
// triangle is degenerate (two equal vertices or zero area in float); else what is wrong.
std::string checkClosedManifold(const TriangleMesh& mesh);
double meshVolume(const TriangleMesh& mesh);
double meshArea(const TriangleMesh& mesh);

}  // namespace emboss
