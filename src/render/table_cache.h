// Tables a program computes before its first picture (the metals' prefiltered environments), kept in
// a folder between runs so that a restart does not compute them again. A file is used only when it
// was written by this very build (the key holds the program's build id) and is whole (its size and
// checksum match); anything else is computed afresh and the file replaced. A cache that cannot be
// read or written costs time, never a picture.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace emboss {

// Where tables are kept from now on (empty: nowhere, the default) and whom to tell what happened
// (a broken file, a folder that cannot be written, tables read or written; a warning starts "<4>").
void setTableCache(std::filesystem::path dir, std::function<void(const std::string&)> say = {});
const std::filesystem::path& tableCacheDir();

// A program's folder for them: $CACHE_DIRECTORY (systemd's CacheDirectory=), else
// $XDG_CACHE_HOME/emboss, else $HOME/.cache/emboss; empty when none of these is set.
std::filesystem::path defaultTableCacheDir();

// The running program's GNU build id folded into 64 bits; 0 when it has none (nothing is cached then).
std::uint64_t buildFingerprint();

// FNV-1a, 64 bits: for keys and checksums.
std::uint64_t fnv1a64(const void* data, std::size_t size, std::uint64_t h = 0xcbf29ce484222325ull);

// The bytes stored as `name` when the file is whole, holds exactly `size` bytes and was stored with
// `key`; nullopt when there is no cache, no file, or a file that does not fit (reported).
std::optional<std::vector<std::uint8_t>> loadTable(const std::string& name, std::uint64_t key, std::size_t size);
// Keeps `bytes` as `name` with `key` (written beside, then renamed over the old file). Failures are
// reported once per reason and otherwise ignored.
void storeTable(const std::string& name, std::uint64_t key, const std::vector<std::uint8_t>& bytes);

}  // namespace emboss
