// fsync of files and folders, and the durable rename a write-then-rename needs.
#include "util/durable_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

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

bool isStandardOutput(const fs::path& path) {
  if (path == "-") return true;
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec).lexically_normal();
  return p == "/dev/stdout" || p == "/dev/fd/1" || p == "/proc/self/fd/1";
}

OutputPath resolveOutput(const fs::path& path) {
  if (path == "-") return {"/dev/stdout", true};
  std::error_code ec;
  const fs::file_status self = fs::symlink_status(path, ec);
  if (ec || !fs::exists(self)) return {path, false};  // a new file
  // A device, a pipe, a socket (through links too: /dev/stdout to a terminal or a pipe).
  const fs::file_status target = fs::status(path, ec);
  if (!ec && fs::exists(target) && !fs::is_regular_file(target)) return {path, true};
  if (fs::is_symlink(self)) {
    // /dev/stdout, /dev/fd/N, /proc/self/fd/N: a file this process holds open, written through
    // that (the standard output redirected to a file, say).
    const std::string lexical = fs::absolute(path, ec).lexically_normal().string();
    if (lexical.rfind("/dev/", 0) == 0 || lexical.rfind("/proc/", 0) == 0) return {path, true};
    if (fs::path real = fs::canonical(path, ec); !ec) return {real, false};
    // A link to nothing yet: the file it names is created (one link followed).
    const fs::path to = fs::read_symlink(path, ec);
    if (!ec) return {to.is_absolute() ? to : path.parent_path() / to, false};
  }
  return {path, false};
}

Status writeInPlace(const fs::path& path, const std::string& bytes, const std::string& name) {
  const bool stdOut = isStandardOutput(path);
  const int fd = stdOut ? STDOUT_FILENO : ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) return fail("cannot write '" + name + "': " + std::strerror(errno));
  // A regular file opened by name here (/dev/fd/N or /proc/self/fd/N of one) is emptied first, as
  // `>` empties it; the standard output is written from where the shell left it.
  struct stat st {};
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  if (regular && !stdOut && ::ftruncate(fd, 0) != 0) {
    const int err = errno;
    ::close(fd);
    return fail("cannot write '" + name + "': " + std::strerror(err));
  }
  size_t done = 0;
  int err = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      err = n < 0 ? errno : EIO;
      break;
    }
    done += static_cast<size_t>(n);
  }
  if (err == 0 && regular && ::fsync(fd) != 0) err = errno;
  if (!stdOut && ::close(fd) != 0 && err == 0) err = errno;
  if (err != 0) return fail("cannot write '" + name + "': " + std::strerror(err));
  return Ok{};
}

Status writeFileAtomically(const fs::path& path, const std::string& bytes) {
  const OutputPath out = resolveOutput(path);
  if (out.inPlace) return writeInPlace(out.path, bytes, path.string());
  const fs::path tmp = out.path.string() + ".part";
  {
    std::ofstream file(tmp, std::ios::binary | std::ios::trunc);
    if (!file) return fail("cannot write '" + path.string() + "': " + std::strerror(errno));
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    file.flush();
    if (!file) {
      std::error_code ec;
      fs::remove(tmp, ec);
      return fail("cannot write '" + path.string() + "' (disk full?)");
    }
  }
  return commitFile(tmp, out.path);
}

}  // namespace emboss
