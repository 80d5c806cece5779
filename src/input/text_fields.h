// Small helpers for the line-oriented recording formats (evemu, hid-recorder): words, numbers, times.
#pragma once

#include <cctype>
#include <charconv>
#include <cstdint>
#include <string_view>
#include <vector>

namespace emboss::text {

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// The whitespace-separated words of a line (views into it).
inline std::vector<std::string_view> splitWords(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    const size_t start = i;
    while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

// The whole of `s` as an integer in `base` (a leading '+' allowed); false on anything else.
template <class T>
bool parseInt(std::string_view s, T& out, int base = 10) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto* end = s.data() + s.size();
  const auto r = std::from_chars(s.data(), end, out, base);
  return r.ec == std::errc() && r.ptr == end;
}

// A time stamp "sec" or "sec.fraction" (up to 9 digits, never negative) in seconds.
inline bool parseTime(std::string_view s, double& out) {
  if (!s.empty() && s.front() == '-') return false;
  const size_t dot = s.find('.');
  std::uint64_t sec = 0;
  std::uint64_t frac = 0;
  if (dot == std::string_view::npos) {
    if (!parseInt(s, sec)) return false;
    out = static_cast<double>(sec);
    return true;
  }
  const std::string_view fs = s.substr(dot + 1);
  if (!parseInt(s.substr(0, dot), sec) || fs.empty() || fs.size() > 9 || fs.front() == '-' || fs.front() == '+') return false;
  if (!parseInt(fs, frac)) return false;
  double scale = 1.0;
  for (size_t i = 0; i < fs.size(); ++i) scale *= 10.0;
  out = static_cast<double>(sec) + static_cast<double>(frac) / scale;
  return true;
}

}  // namespace emboss::text
