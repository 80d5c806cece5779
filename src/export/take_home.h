// The take-home files: what `emboss export` writes and what the staff export adds to each session.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "export/postcard.h"
#include "frep/model.h"
#include "scene/scene.h"
#include "util/result.h"

namespace emboss {

struct TakeHomeOptions {
  std::string format;       // stl, 3mf, heightmap, postcard
  double resolution = 0.0;  // mesh cell or height map pixel, mm; 0: automatic
  double maxError = 0.01;   // mesh decimation, mm; 0: none
  int threads = 0;
  bool progressBar = true;  // on stderr, only when it is a terminal
  TextPainter* text = nullptr;  // postcard: the caption's painter (none: no words)
};

// Writes `out` atomically; `summary` gets one line of figures (triangles, distances, time).
Status writeTakeHome(const Scene& scene, const Model& model, const TakeHomeOptions& options, const std::string& out,
                     std::string* summary = nullptr);

// Which take-home files the staff export adds beside each session's scene file: STEM.postcard.png,
// STEM.height.png, STEM.stl, STEM.3mf.
struct TakeHomeSet {
  bool postcard = false, heightmap = false, stl = false, threemf = false;
  bool any() const { return postcard || heightmap || stl || threemf; }
  // Room to keep free for one session's files before starting (an STL of a busy piece is ~100 MB).
  std::uintmax_t allowance() const;
};
// "postcard,heightmap", "stl, 3mf", "none"; an unknown name is an error naming it.
Result<TakeHomeSet> parseTakeHomeSet(const std::string& list);
std::string takeHomeSetText(const TakeHomeSet& set);

// Reads the exported scene file and writes the set's files beside it (height map at 0.2 mm, meshes
// with the automatic cell, one thread). Returns the number of files and bytes written; the first
// failure stops it and says which file.
struct TakeHomeWritten {
  size_t files = 0;
  std::uintmax_t bytes = 0;
};
Result<TakeHomeWritten> writeTakeHomeFiles(const std::filesystem::path& sceneFile, const TakeHomeSet& set, TextPainter* text,
                                           int threads = 1);

}  // namespace emboss
