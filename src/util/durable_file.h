// Files that survive a power cut: data and folder entries flushed to the disk before a write counts as done.
#pragma once

#include <filesystem>
#include <string>

#include "util/result.h"

namespace emboss {

// fsync of a file already written (its data and size).
Status syncFile(const std::filesystem::path& path);
// fsync of a folder: the names created or renamed in it are on the disk.
Status syncDirectory(const std::filesystem::path& dir);
// Moves `tmp` over `path`, then makes both the file and the rename durable. `tmp` is removed on failure.
Status commitFile(const std::filesystem::path& tmp, const std::filesystem::path& path);

// Where a file someone names is written. A regular file, or none yet, is written beside itself and
// renamed over it (atomically: the old file or the new one, never half of one); through a symbolic
// link, its target is, the link kept. Anything else that exists (a device such as /dev/null or
// /dev/full, a named pipe), and whatever a link in /dev or /proc names (/dev/stdout, /dev/fd/N,
// /proc/self/fd/N: a file this process holds open), is written in place: a rename would replace
// it. "-" is the standard output.
struct OutputPath {
  std::filesystem::path path;  // where the bytes go
  bool inPlace = false;        // written straight into it
};
OutputPath resolveOutput(const std::filesystem::path& path);
// Whether `path` is this process's standard output ("-", /dev/stdout, /dev/fd/1, /proc/self/fd/1).
bool isStandardOutput(const std::filesystem::path& path);
// All of `bytes` into the file at `path` as it stands (resolveOutput()'s in-place outputs): every
// error reported (a full disk or device, a closed pipe). `name` is what messages call it.
Status writeInPlace(const std::filesystem::path& path, const std::string& bytes, const std::string& name);
// The file `path` with exactly `bytes` (resolveOutput()): a regular file through a temporary file,
// fsync, a rename and an fsync of the folder, so that a full disk or a power cut leaves the old
// file or the new one; anything else in place.
Status writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace emboss
