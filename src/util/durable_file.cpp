// fsync of files and folders, and the durable rename a write-then-rename needs.
#include "util/durable_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace emboss {

namespace fs = std::filesystem;

namespace {

Status syncPath(const fs::path& path, int flags, const char* what) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) return fail(std::string("cannot open ") + what + " '" + path.string() + "' to sync it: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) return fail(std::string("cannot sync ") + what + " '" + path.string() + "': " + std::strerror(err));
  return Ok{};
}

}  // namespace

Status syncFile(const fs::path& path) { return syncPath(path, O_RDONLY, "file"); }

Status syncDirectory(const fs::path& dir) {
  return syncPath(dir.empty() ? fs::path(".") : dir, O_RDONLY | O_DIRECTORY, "folder");
}

Status commitFile(const fs::path& tmp, const fs::path& path) {
  std::error_code ec;
  if (Status s = syncFile(tmp); !s) {
    fs::remove(tmp, ec);
    return fail("cannot write '" + path.string() + "': " + s.error());
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return fail("cannot write '" + path.string() + "': " + ec.message());
  }
  return syncDirectory(path.parent_path());
}

}  // namespace emboss
