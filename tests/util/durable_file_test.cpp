// Outputs someone names: a regular file replaced atomically, and anything else (a pipe, a device,
// the standard output) written in place, never renamed over; a symbolic link kept.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "render/image.h"
#include "util/durable_file.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;

class OutputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("emboss-output-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  // All a named pipe gets until its writer closes it, or what came within 10 s without one (never
  // blocked for good: a writer that replaced the pipe by a rename leaves its reader waiting).
  static std::string readPipe(const fs::path& p) {
    const int fd = ::open(p.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return "(cannot open)";
    std::string got;
    bool seen = false;  // (before a writer opens it, the pipe reports no hang-up)
    for (;;) {
      pollfd pfd{fd, POLLIN, 0};
      if (::poll(&pfd, 1, 10000) <= 0) break;
      char buf[65536];
      const ssize_t n = ::read(fd, buf, sizeof buf);
      if (n > 0) got.append(buf, static_cast<size_t>(n)), seen = true;
      else if (n == 0 && (seen || (pfd.revents & POLLHUP))) break;
      else if (n < 0 && errno != EAGAIN && errno != EINTR) break;
    }
    ::close(fd);
    return got;
  }
  // Every name in the folder (a temporary file left behind shows here).
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const auto& e : fs::directory_iterator(dir_)) n.push_back(e.path().filename().string());
    std::sort(n.begin(), n.end());
    return n;
  }
  fs::path dir_;
};

TEST_F(OutputFiles, WhereEachKindGoes) {
  EXPECT_TRUE(resolveOutput("-").inPlace);
  EXPECT_EQ(resolveOutput("-").path, "/dev/stdout");
  EXPECT_TRUE(resolveOutput("/dev/stdout").inPlace);
  EXPECT_TRUE(resolveOutput("/proc/self/fd/1").inPlace);
  EXPECT_FALSE(resolveOutput(dir_ / "new.png").inPlace);
  EXPECT_EQ(resolveOutput(dir_ / "new.png").path, dir_ / "new.png");
  ASSERT_EQ(::mkfifo((dir_ / "pipe").c_str(), 0600), 0);
  EXPECT_TRUE(resolveOutput(dir_ / "pipe").inPlace);
  EXPECT_TRUE(isStandardOutput("-"));
  EXPECT_TRUE(isStandardOutput("/dev/stdout"));
  EXPECT_TRUE(isStandardOutput("/dev/fd/1"));
  EXPECT_FALSE(isStandardOutput("/dev/stderr"));
  EXPECT_FALSE(isStandardOutput(dir_ / "stdout"));
}

TEST_F(OutputFiles, ARegularFileUnderDevIsAFileLikeAnyOther) {
  // (/dev/shm: a memory file system people write pictures to.)
  if (!fs::is_directory("/dev/shm") || ::access("/dev/shm", W_OK) != 0) GTEST_SKIP() << "no writable /dev/shm here";
  const fs::path f = fs::path("/dev/shm") / ("emboss-output-" + std::to_string(::getpid()) + ".pov");
  EXPECT_FALSE(resolveOutput(f).inPlace);
  ASSERT_TRUE(writeFileAtomically(f, "first"));
  ASSERT_TRUE(writeFileAtomically(f, "second"));
  EXPECT_EQ(read(f), "second");
  EXPECT_FALSE(fs::exists(f.string() + ".part"));
  fs::remove(f);
}

TEST_F(OutputFiles, ARegularFileIsReplacedWithNothingLeftBeside) {
  const fs::path f = dir_ / "piece.pov";
  ASSERT_TRUE(writeFileAtomically(f, "an old and longer text"));
  ASSERT_TRUE(writeFileAtomically(f, "new"));
  EXPECT_EQ(read(f), "new");
  EXPECT_EQ(names(), std::vector<std::string>{"piece.pov"});
}

TEST_F(OutputFiles, ANamedPipeIsWrittenInPlace) {
  const fs::path pipe = dir_ / "pipe";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = readPipe(pipe); });
  const std::string bytes(300000, 'x');  // more than a pipe holds: the writer waits for the reader
  const Status s = writeFileAtomically(pipe, bytes);
  reader.join();
  ASSERT_TRUE(s) << s.error();
  EXPECT_EQ(got.size(), bytes.size());
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(pipe)));
  EXPECT_EQ(names(), std::vector<std::string>{"pipe"});
}

TEST_F(OutputFiles, APictureThroughAPipeReadsBack) {
  const fs::path pipe = dir_ / "pipe";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  Image image(5, 3);
  for (size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = static_cast<std::uint8_t>(i * 7);
  for (size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;
  std::string got;
  std::thread reader([&] { got = readPipe(pipe); });
  const Status s = writePng(image, pipe);
  reader.join();
  ASSERT_TRUE(s) << s.error();
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(pipe)));
  EXPECT_EQ(names(), std::vector<std::string>{"pipe"});
  const fs::path copy = dir_ / "copy.png";
  std::ofstream(copy, std::ios::binary) << got;
  auto back = readPng(copy);
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(back->rgba, image.rgba);
}

TEST_F(OutputFiles, AFullDeviceIsAnErrorAndStaysADevice) {
  struct stat st {};
  if (::stat("/dev/full", &st) != 0 || !S_ISCHR(st.st_mode)) GTEST_SKIP() << "no /dev/full here";
  const Status s = writeFileAtomically("/dev/full", "bytes");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().find("No space left on device"), std::string::npos) << s.error();
  ASSERT_EQ(::stat("/dev/full", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  EXPECT_FALSE(fs::exists("/dev/full.part"));
}

TEST_F(OutputFiles, ALinkKeepsPointingAtItsNewTarget) {
  fs::create_directories(dir_ / "real");
  ASSERT_TRUE(writeFileAtomically(dir_ / "real" / "card.png", "old"));
  fs::create_symlink("real/card.png", dir_ / "card.png");
  ASSERT_TRUE(writeFileAtomically(dir_ / "card.png", "new"));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "card.png")));
  EXPECT_EQ(read(dir_ / "real" / "card.png"), "new");
  EXPECT_EQ(names(), (std::vector<std::string>{"card.png", "real"}));
  // A link to a file not there yet: the file is made, the link kept.
  fs::create_symlink("real/later.png", dir_ / "later.png");
  ASSERT_TRUE(writeFileAtomically(dir_ / "later.png", "made"));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "later.png")));
  EXPECT_EQ(read(dir_ / "real" / "later.png"), "made");
}

}  // namespace
}  // namespace emboss
