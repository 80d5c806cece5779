// The attract mode's pieces, authored as code: control curves expanded into the paper's operations.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace emboss {

struct GeneratedPiece {
  std::string file;  // "1-rosette.json": the name it ships under in firmware-app/pieces/ (played in name order)
  Scene scene;
};

// Every piece, in the order attract mode plays them. Deterministic: the same scenes every time
// (tests check that firmware-app/pieces/*.json equal sceneToJson() of these).
std::vector<GeneratedPiece> generateAttractPieces();

// The pieces one by one.
Scene rosettePiece();  // a medallion rosette on a disc, in brass
Scene shellPiece();    // a scallop shell on a copper plate
Scene horsePiece();    // a horse in the chased style of Georgian folk embossing, in silver

}  // namespace emboss
