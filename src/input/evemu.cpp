// evemu recordings (.desc device descriptions, .events event streams) parsed and turned into PenSamples.
#include "input/evemu.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <sstream>

#include "input/text_fields.h"

namespace emboss {

namespace {

using text::parseInt;
using text::parseTime;
using text::splitWords;
using text::trim;

Error lineError(size_t line, std::string_view what, std::string_view text) {
  std::string t(text.substr(0, 80));
  return fail("evemu line " + std::to_string(line) + ": " + std::string(what) + " (\"" + t + "\")");
}

Result<std::string> readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return fail("cannot read " + p.string() + ": no such file or no permission");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> nameWords(std::string_view s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ' ' || c == '.' || c == '-' || c == '_' || c == '\t') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

bool isInterfaceWord(const std::string& w) {
  static const char* const kWords[] = {"pen", "stylus", "eraser", "pad", "finger", "touch", "mouse", "keyboard"};
  return std::any_of(std::begin(kWords), std::end(kWords), [&](const char* k) { return w == k; });
}

}  // namespace

bool EvemuDevice::hasKey(int code) const {
  const auto it = bits.find(evcode::kEvKey);
  if (it == bits.end() || code < 0) return false;
  const size_t byte = static_cast<size_t>(code) / 8;
  if (byte >= it->second.size()) return false;
  return (it->second[byte] >> (code % 8)) & 1;
}

Result<EvemuRecording> parseEvemu(std::string_view text) {
  EvemuRecording rec;
  size_t lineNo = 0;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.size() < 2 || line[1] != ':') continue;  // comments, blank lines, anything else
    const char kind = line[0];
    std::string_view body = line.substr(2);
    if (kind == 'N') {
      rec.device.name = std::string(trim(body));
      continue;
    }
    if (const size_t hash = body.find('#'); hash != std::string_view::npos) body = body.substr(0, hash);
    const auto w = splitWords(body);
    switch (kind) {
      case 'I': {
        uint16_t v[4] = {0, 0, 0, 0};
        if (w.size() < 4) return lineError(lineNo, "I: needs bus vendor product version", line);
        for (int i = 0; i < 4; ++i) {
          if (!parseInt(w[static_cast<size_t>(i)], v[i], 16)) return lineError(lineNo, "I: values must be hex", line);
        }
        rec.device.bus = v[0];
        rec.device.vendor = v[1];
        rec.device.product = v[2];
        rec.device.version = v[3];
        break;
      }
      case 'B': {
        if (w.empty()) return lineError(lineNo, "B: needs an event type", line);
        int type = 0;
        if (!parseInt(w[0], type, 16) || type < 0 || type > 0x1f) return lineError(lineNo, "B: bad event type", line);
        auto& bytes = rec.device.bits[type];
        for (size_t i = 1; i < w.size(); ++i) {
          uint8_t b = 0;
          if (!parseInt(w[i], b, 16)) return lineError(lineNo, "B: bytes must be hex", line);
          if (bytes.size() < 4096) bytes.push_back(b);
        }
        break;
      }
      case 'A': {
        if (w.size() < 5) return lineError(lineNo, "A: needs code min max fuzz flat [resolution]", line);
        int code = 0;
        AbsRange r;
        if (!parseInt(w[0], code, 16) || code < 0 || code > 0x3f) return lineError(lineNo, "A: bad axis code", line);
        if (!parseInt(w[1], r.min) || !parseInt(w[2], r.max) || !parseInt(w[3], r.fuzz) || !parseInt(w[4], r.flat) ||
            (w.size() > 5 && !parseInt(w[5], r.resolution))) {
          return lineError(lineNo, "A: values must be decimal integers", line);
        }
        rec.device.axes[code] = r;
        break;
      }
      case 'E': {
        if (w.size() < 4) return lineError(lineNo, "E: needs time type code value", line);
        EvemuEvent e;
        if (!parseTime(w[0], e.time_s)) return lineError(lineNo, "E: bad time stamp", line);
        if (!parseInt(w[1], e.type, 16) || !parseInt(w[2], e.code, 16) || e.type < 0 || e.code < 0 || e.type > 0xffff ||
            e.code > 0xffff) {
          return lineError(lineNo, "E: type and code must be hex", line);
        }
        if (!parseInt(w[3], e.value)) return lineError(lineNo, "E: value must be a decimal 32-bit integer", line);
        rec.events.push_back(e);
        break;
      }
      default:
        break;  // P: properties, S: and anything newer
    }
  }
  return rec;
}

Result<std::filesystem::path> findEvemuDesc(const std::filesystem::path& events) {
  namespace fs = std::filesystem;
  const fs::path dir = events.has_parent_path() ? events.parent_path() : fs::path(".");
  const std::string stem = events.stem().string();
  const fs::path exact = dir / (stem + ".desc");
  std::error_code ec;
  if (fs::is_regular_file(exact, ec)) return exact;

  const auto eventWords = nameWords(stem);
  std::vector<std::string> seen;
  fs::path best;
  size_t bestWords = 0;
  bool bestIsPen = false;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().extension() != ".desc") continue;
    const std::string cand = it->path().stem().string();
    seen.push_back(it->path().filename().string());
    auto words = nameWords(cand);
    bool isPen = false;
    if (!words.empty() && isInterfaceWord(words.back())) {
      isPen = words.back() == "pen" || words.back() == "stylus";
      words.pop_back();
    }
    if (words.empty() || words.size() > eventWords.size()) continue;
    if (!std::equal(words.begin(), words.end(), eventWords.begin())) continue;
    if (words.size() > bestWords || (words.size() == bestWords && isPen && !bestIsPen)) {
      best = it->path();
      bestWords = words.size();
      bestIsPen = isPen;
    }
  }
  if (ec) return fail("cannot list " + dir.string() + " to find the .desc for " + events.filename().string() + ": " + ec.message());
  if (bestWords == 0) {
    std::string list;
    for (const auto& s : seen) list += (list.empty() ? "" : ", ") + s;
    return fail(events.filename().string() + " has no device description and no matching .desc was found in " +
                dir.string() + (seen.empty() ? " (no .desc files there)" : " (saw: " + list + ")") +
                "; pass the description with --desc FILE");
  }
  return best;
}

Result<EvemuRecording> loadEvemu(const std::filesystem::path& events, const std::optional<std::filesystem::path>& desc) {
  auto text = readFile(events);
  if (!text) return Error{text.error()};
  auto rec = parseEvemu(*text);
  if (!rec) return fail(events.string() + ": " + rec.error());
  if (rec->events.empty()) return fail(events.string() + " holds no E: event lines; is it a .desc file?");
  if (rec->device.hasAxes() && !desc) return rec;

  std::filesystem::path descPath;
  if (desc) {
    descPath = *desc;
  } else {
    auto found = findEvemuDesc(events);
    if (!found) return Error{found.error()};
    descPath = *found;
  }
  auto dtext = readFile(descPath);
  if (!dtext) return Error{dtext.error()};
  auto drec = parseEvemu(*dtext);
  if (!drec) return fail(descPath.string() + ": " + drec.error());
  if (!drec->device.hasAxes()) return fail(descPath.string() + " has no A: axis lines; it is not an evemu device description");
  rec->device = std::move(drec->device);
  return rec;
}

Result<std::vector<PenSample>> evemuToSamples(const EvemuRecording& recording) {
  const auto& dev = recording.device;
  for (int code : {evcode::kAbsX, evcode::kAbsY}) {
    const auto it = dev.axes.find(code);
    if (it == dev.axes.end()) {
      return fail(std::string("the recording has no ") + (code == evcode::kAbsX ? "ABS_X" : "ABS_Y") +
                  " range; an .events file without its description needs the matching .desc");
    }
    if (it->second.max <= it->second.min) {
      return fail(std::string(code == evcode::kAbsX ? "ABS_X" : "ABS_Y") + " has an empty range (max <= min)");
    }
  }
  // Capabilities from the B: bits; a description without them is judged by the events.
  bool toolKeys = false;
  bool touchKey = false;
  if (dev.bits.count(evcode::kEvKey)) {
    for (int c = evcode::kBtnToolPen; c <= evcode::kBtnToolAirbrush; ++c) toolKeys = toolKeys || dev.hasKey(c);
    touchKey = dev.hasKey(evcode::kBtnTouch);
  }
  for (const auto& e : recording.events) {
    if (e.type != evcode::kEvKey) continue;
    if (e.code >= evcode::kBtnToolPen && e.code <= evcode::kBtnToolAirbrush) toolKeys = true;
    if (e.code == evcode::kBtnTouch) touchKey = true;
  }
  EvdevPenState state(dev.axes, toolKeys, touchKey);
  std::vector<PenSample> out;
  for (const auto& e : recording.events) {
    if (auto s = state.feed(e.time_s, e.type, e.code, e.value)) out.push_back(*s);
  }
  return out;
}

std::vector<Stroke> splitStrokes(const std::vector<PenSample>& samples) {
  std::vector<Stroke> strokes;
  bool down = false;
  for (const auto& s : samples) {
    if (s.tip) {
      if (!down) strokes.emplace_back();
      strokes.back().push_back(s);
    }
    down = s.tip;
  }
  return strokes;
}

}  // namespace emboss
