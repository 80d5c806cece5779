// Finding and reading the attract pieces, with the built-in ones as the fallback that always works.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "app/attract_player.h"
#include "app/kiosk_log.h"

namespace emboss {

// Every *.json scene in `dir`, by name. A file that does not read is logged (with the parser's
// message naming the place) and skipped; the others still play.
std::vector<AttractPiece> loadAttractPieces(const std::filesystem::path& dir, const KioskLog& log);

// The pieces of src/pieces, made in memory: attract mode never lacks something to show.
std::vector<AttractPiece> builtinAttractPieces();

// Where the pieces are: `configured` if given; else $EMBOSS_PIECES; else firmware-app/pieces
// under the working directory or above the program (a build tree inside the checkout); else
// /usr/share/emboss/pieces. nullopt when none of these is a folder.
std::optional<std::filesystem::path> findPiecesDir(const std::filesystem::path& configured,
                                                   const std::filesystem::path& program);

}  // namespace emboss
