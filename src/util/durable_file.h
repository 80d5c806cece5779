// Files that survive a power cut: data and folder entries flushed to the disk before a write counts as done.
#pragma once

#include <filesystem>

#include "util/result.h"

namespace emboss {

// fsync of a file already written (its data and size).
Status syncFile(const std::filesystem::path& path);
// fsync of a folder: the names created or renamed in it are on the disk.
Status syncDirectory(const std::filesystem::path& dir);
// Moves `tmp` over `path`, then makes both the file and the rename durable. `tmp` is removed on failure.
Status commitFile(const std::filesystem::path& tmp, const std::filesystem::path& path);

}  // namespace emboss
