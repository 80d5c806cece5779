#include "render/table_cache.h"

#include <link.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <system_error>

namespace emboss {

namespace {

struct Cache {
  std::mutex mutex;
  std::filesystem::path dir;
  std::function<void(const std::string&)> say;
  std::set<std::string> told;  // reasons already reported (a full disk is said once, not per table)
};

Cache& cache() {
  static Cache c;
  return c;
}

void tell(Cache& c, const std::string& what, bool once) {
  if (!c.say) return;
  if (once && !c.told.insert(what).second) return;
  c.say(what);
}

// The file's header; the payload follows.
struct Header {
  char magic[8];
  std::uint32_t version;
  std::uint32_t reserved;
  std::uint64_t key;
  std::uint64_t size;
  std::uint64_t checksum;
};
constexpr char kMagic[8] = {'E', 'M', 'B', 'T', 'A', 'B', 'L', 'E'};
constexpr std::uint32_t kVersion = 1;

std::filesystem::path fileOf(const Cache& c, const std::string& name) { return c.dir / (name + ".table"); }

// The GNU build id note of the object that holds this code.
int findBuildId(dl_phdr_info* info, size_t, void* out) {
  const auto here = reinterpret_cast<ElfW(Addr)>(&findBuildId);
  bool mine = false;
  for (int i = 0; i < info->dlpi_phnum && !mine; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    const ElfW(Addr) start = info->dlpi_addr + ph.p_vaddr;
    mine = ph.p_type == PT_LOAD && here >= start && here < start + ph.p_memsz;
  }
  if (!mine) return 0;
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    if (ph.p_type != PT_NOTE) continue;
    const auto* p = reinterpret_cast<const unsigned char*>(info->dlpi_addr + ph.p_vaddr);
    const auto* end = p + ph.p_memsz;
    while (p + sizeof(ElfW(Nhdr)) <= end) {
      const auto* n = reinterpret_cast<const ElfW(Nhdr)*>(p);
      const unsigned char* name = p + sizeof(ElfW(Nhdr));
      const unsigned char* desc = name + ((n->n_namesz + 3) & ~3u);
      if (n->n_type == NT_GNU_BUILD_ID && n->n_namesz == 4 && std::memcmp(name, "GNU", 4) == 0 && desc + n->n_descsz <= end) {
        *static_cast<std::uint64_t*>(out) = fnv1a64(desc, n->n_descsz);
        return 1;
      }
      p = desc + ((n->n_descsz + 3) & ~3u);
    }
  }
  return 1;  // this object, without a build id
}

}  // namespace

std::uint64_t fnv1a64(const void* data, std::size_t size, std::uint64_t h) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  return h;
}

std::uint64_t buildFingerprint() {
  static const std::uint64_t id = [] {
    std::uint64_t v = 0;
    dl_iterate_phdr(findBuildId, &v);
    return v;
  }();
  return id;
}

void setTableCache(std::filesystem::path dir, std::function<void(const std::string&)> say) {
  Cache& c = cache();
  std::lock_guard lock(c.mutex);
  c.dir = std::move(dir);
  c.say = std::move(say);
  c.told.clear();
}

const std::filesystem::path& tableCacheDir() { return cache().dir; }

std::filesystem::path defaultTableCacheDir() {
  auto env = [](const char* name) -> std::string {
    const char* v = std::getenv(name);
    return v && *v ? v : "";
  };
  // systemd may pass several folders separated by ':'; the first is the unit's own.
  if (std::string d = env("CACHE_DIRECTORY"); !d.empty()) return d.substr(0, d.find(':'));
  if (std::string d = env("XDG_CACHE_HOME"); !d.empty()) return std::filesystem::path(d) / "emboss";
  if (std::string d = env("HOME"); !d.empty()) return std::filesystem::path(d) / ".cache" / "emboss";
  return {};
}

std::optional<std::vector<std::uint8_t>> loadTable(const std::string& name, std::uint64_t key, std::size_t size) {
  Cache& c = cache();
  std::lock_guard lock(c.mutex);
  if (c.dir.empty() || buildFingerprint() == 0) return std::nullopt;
  const std::filesystem::path path = fileOf(c, name);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;  // not there yet: the usual first start
  Header h{};
  std::vector<std::uint8_t> bytes;
  const char* wrong = nullptr;
  if (!in.read(reinterpret_cast<char*>(&h), sizeof h) || std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 ||
      h.version != kVersion)
    wrong = "not a table file of this version";
  else if (h.key != key)
    return std::nullopt;  // another build's: replaced quietly
  else if (h.size != size)
    wrong = "the wrong size";
  else {
    bytes.resize(size);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)) || in.peek() != EOF)
      wrong = "cut short or too long";
    else if (fnv1a64(bytes.data(), bytes.size()) != h.checksum)
      wrong = "a bad checksum";
    else {
      tell(c, "<7>tables: " + name + " read from " + path.string(), false);
      return bytes;
    }
  }
  tell(c, "<4>tables: " + path.string() + " is broken (" + wrong + "); computing them again", false);
  return std::nullopt;
}

void storeTable(const std::string& name, std::uint64_t key, const std::vector<std::uint8_t>& bytes) {
  Cache& c = cache();
  std::lock_guard lock(c.mutex);
  if (c.dir.empty() || buildFingerprint() == 0) return;
  std::error_code ec;
  std::filesystem::create_directories(c.dir, ec);
  const std::filesystem::path path = fileOf(c, name);
  const std::filesystem::path tmp = path.string() + ".tmp." + std::to_string(::getpid());
  Header h{};
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.version = kVersion;
  h.key = key;
  h.size = bytes.size();
  h.checksum = fnv1a64(bytes.data(), bytes.size());
  bool ok = !ec;
  if (ok) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    ok = out && out.write(reinterpret_cast<const char*>(&h), sizeof h) &&
         out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())) && out.flush();
    if (!ok) ec = std::error_code(errno ? errno : EIO, std::generic_category());
  }
  if (ok) std::filesystem::rename(tmp, path, ec), ok = !ec;
  if (!ok) {
    const std::string why = ec ? ec.message() : std::string("write failed");
    std::filesystem::remove(tmp, ec);
    tell(c, "<4>tables: cannot keep them in " + c.dir.string() + " (" + why + "); they are computed at each start", true);
    return;
  }
  tell(c, "tables: " + name + " kept in " + path.string(), false);
}

}  // namespace emboss
