// hid-recorder captures (R: descriptor, N:, P:, I: bus vid pid, E: time len bytes) parsed and decoded.
#include "input/hidrecord.h"

#include <cctype>
#include <charconv>
#include <fstream>
#include <optional>
#include <sstream>

#include "input/hid_decode.h"
#include "input/text_fields.h"

namespace emboss {

namespace {

using text::parseInt;
using text::parseTime;
using text::splitWords;

Error bad(size_t line, const std::string& what) { return fail("hid-recorder line " + std::to_string(line) + ": " + what); }

// "len b0 b1 ..." with the count checked.
Result<std::vector<uint8_t>> lengthAndBytes(const std::vector<std::string_view>& w, size_t first, size_t line) {
  if (w.size() <= first) return bad(line, "missing the byte count");
  size_t n = 0;
  if (!parseInt(w[first], n)) return bad(line, "the byte count is not a number");
  if (w.size() - first - 1 != n) {
    return bad(line, "says " + std::to_string(n) + " bytes but has " + std::to_string(w.size() - first - 1));
  }
  std::vector<uint8_t> bytes;
  bytes.reserve(n);
  for (size_t i = first + 1; i < w.size(); ++i) {
    uint8_t b = 0;
    if (w[i].size() > 2 || !parseInt(w[i], b, 16)) return bad(line, "\"" + std::string(w[i].substr(0, 8)) + "\" is not a hex byte");
    bytes.push_back(b);
  }
  return bytes;
}

}  // namespace

Result<HidRecording> parseHidRecord(std::string_view text) {
  HidRecording rec;
  std::optional<int> firstDevice;
  int device = 0;
  bool haveDescriptor = false;
  bool haveId = false;
  size_t lineNo = 0;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.size() < 2 || line[1] != ':') continue;
    const char kind = line[0];
    const std::string_view body = line.substr(2);
    if (kind == 'D') {
      const auto w = splitWords(body);
      if (w.empty() || !parseInt(w[0], device) || device < 0) return bad(lineNo, "D: needs a device number");
      if (!firstDevice) firstDevice = device;
      continue;
    }
    if (!firstDevice) firstDevice = device;
    if (device != *firstDevice) continue;
    switch (kind) {
      case 'R': {
        auto bytes = lengthAndBytes(splitWords(body), 0, lineNo);
        if (!bytes) return Error{bytes.error()};
        if (haveDescriptor && *bytes != rec.descriptor) return bad(lineNo, "a second, different R: descriptor for the same device");
        rec.descriptor = std::move(*bytes);
        haveDescriptor = true;
        break;
      }
      case 'N': {
        std::string_view n = body;
        while (!n.empty() && n.front() == ' ') n.remove_prefix(1);
        rec.name = std::string(n);
        break;
      }
      case 'P': {
        std::string_view p = body;
        while (!p.empty() && p.front() == ' ') p.remove_prefix(1);
        rec.phys = std::string(p);
        break;
      }
      case 'I': {
        const auto w = splitWords(body);
        uint16_t v[3] = {0, 0, 0};
        if (w.size() < 3) return bad(lineNo, "I: needs bus vendor product");
        for (int i = 0; i < 3; ++i) {
          if (!parseInt(w[static_cast<size_t>(i)], v[i], 16)) return bad(lineNo, "I: values must be hex");
        }
        if (haveId && (v[1] != rec.vendorId || v[2] != rec.productId)) return bad(lineNo, "a second, different I: line for the same device");
        rec.bus = v[0];
        rec.vendorId = v[1];
        rec.productId = v[2];
        haveId = true;
        break;
      }
      case 'E': {
        const auto w = splitWords(body);
        if (w.empty()) return bad(lineNo, "E: needs a time stamp");
        HidRecordReport r;
        if (!parseTime(w[0], r.time_s)) return bad(lineNo, "E: bad time stamp");
        auto bytes = lengthAndBytes(w, 1, lineNo);
        if (!bytes) return Error{bytes.error()};
        r.bytes = std::move(*bytes);
        rec.reports.push_back(std::move(r));
        break;
      }
      default:
        break;
    }
  }
  if (!haveDescriptor) return fail("the capture has no R: (report descriptor) line; it is not a hid-recorder capture");
  return rec;
}

Result<HidRecording> loadHidRecord(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail("cannot read " + path.string() + ": no such file or no permission");
  std::stringstream ss;
  ss << in.rdbuf();
  auto rec = parseHidRecord(ss.str());
  if (!rec) return fail(path.string() + ": " + rec.error());
  return rec;
}

Result<std::vector<PenSample>> decodeHidRecording(const HidRecording& recording) {
  auto decoder = makePenDecoder(recording.vendorId, recording.productId, recording.descriptor);
  if (!decoder) return Error{decoder.error()};
  std::vector<PenSample> out;
  for (const auto& r : recording.reports) {
    if (auto s = (*decoder)->decode(r.bytes, r.time_s)) out.push_back(*s);
  }
  return out;
}

}  // namespace emboss
