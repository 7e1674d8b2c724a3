#include "server/iso_time.hpp"

#include <cstdio>
#include <ctime>

namespace cathbox::server {

std::string iso_time(std::int64_t us) {
  std::int64_t seconds = us / 1'000'000;
  std::int64_t micros = us % 1'000'000;
  if (micros < 0) {
    micros += 1'000'000;
    seconds -= 1;
  }
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%06dZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour,
                tm.tm_min, tm.tm_sec, static_cast<int>(micros));
  return buf;
}

std::optional<std::int64_t> parse_iso_time(std::string_view text) {
  auto digits = [&](std::size_t at, std::size_t n, int& out) {
    if (at + n > text.size()) return false;
    out = 0;
    for (std::size_t i = at; i < at + n; ++i) {
      if (text[i] < '0' || text[i] > '9') return false;
      out = out * 10 + (text[i] - '0');
    }
    return true;
  };
  std::tm tm{};
  int year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0, micros = 0;
  if (!digits(0, 4, year) || text.size() < 10 || text[4] != '-' || !digits(5, 2, month) || text[7] != '-' || !digits(8, 2, day)) {
    return std::nullopt;
  }
  if (month < 1 || month > 12 || day < 1 || day > 31) return std::nullopt;
  std::size_t at = 10;
  if (text.size() > 10) {
    if ((text[10] != 'T' && text[10] != ' ') || !digits(11, 2, hour) || text.size() < 19 || text[13] != ':' || !digits(14, 2, minute) ||
        text[16] != ':' || !digits(17, 2, second)) {
      return std::nullopt;
    }
    if (hour > 23 || minute > 59 || second > 60) return std::nullopt;
    at = 19;
    if (at < text.size() && text[at] == '.') {
      std::size_t n = 0;
      ++at;
      int scale = 100000;
      while (at < text.size() && text[at] >= '0' && text[at] <= '9' && n < 6) {
        micros += (text[at] - '0') * scale;
        scale /= 10;
        ++at;
        ++n;
      }
      if (n == 0) return std::nullopt;
    }
    if (at >= text.size() || text[at] != 'Z') return std::nullopt;
    ++at;
  }
  if (at != text.size()) return std::nullopt;
  tm.tm_year = year - 1900;
  tm.tm_mon = month - 1;
  tm.tm_mday = day;
  tm.tm_hour = hour;
  tm.tm_min = minute;
  tm.tm_sec = second;
  const std::time_t t = timegm(&tm);
  return static_cast<std::int64_t>(t) * 1'000'000 + micros;
}

}  // namespace cathbox::server
