#pragma once
// What the record header's codec shares (record_header.cpp, record_header_tool.cpp,
// record_header_device.cpp): the tag of an enum, the walk over tagged fields, the error of a
// field with a bad value, and the readers of one field's value.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "session/record_format.hpp"

namespace cathbox::session::record {

template <class Tag>
std::uint32_t t(Tag tag) {
  return static_cast<std::uint32_t>(tag);
}

// Walks the tagged fields of `data`, calling on_field(tag, value reader) for each; reports
// malformed fields and unknown ones (see record_format.hpp: tags 64..127 are skipped).
class Fields {
 public:
  Fields(std::span<const std::uint8_t> data, std::size_t base) : r_(data), base_(base) {}

  template <class Fn>
  bool each(const char* what, Fn&& on_field) {
    while (!r_.done()) {
      const std::size_t at = r_.position();
      std::uint64_t tag = 0;
      std::uint64_t length = 0;
      std::span<const std::uint8_t> value;
      if (!r_.varint(tag) || !r_.varint(length) || length > r_.left() || !r_.bytes(length, value)) {
        return fail(at, std::string(what) + ": a field runs past its end");
      }
      const int known = on_field(tag, value, base_ + at);
      if (known < 0) return false;  // on_field set the error
      if (known == 0 && !(tag >= 64 && tag < 128)) {
        return fail(at, std::string(what) + ": unknown field " + std::to_string(tag));
      }
    }
    return true;
  }
  bool fail(std::size_t at, std::string what) {
    what_ = std::move(what);
    offset_ = base_ + at;
    return false;
  }
  std::string what_;
  std::size_t offset_ = 0;

 private:
  ByteReader r_;
  std::size_t base_;
};

// The error of a field with a bad value: its offset and what (empty: none yet).
struct FieldError {
  std::string what;
  std::size_t at = 0;
  int bad(std::size_t offset, std::string msg) {
    what = std::move(msg);
    at = offset;
    return -1;
  }
  // A nested walk that failed: its own error unless a field inside it already set one.
  int nested(const Fields& f) { return what.empty() ? bad(f.offset_, f.what_) : -1; }
};

inline bool get_f64(std::span<const std::uint8_t> v, double& out) {
  ByteReader r(v);
  return v.size() == 8 && r.f64(out) && std::isfinite(out);
}

inline bool get_u64(std::span<const std::uint8_t> v, std::uint64_t& out) {
  ByteReader r(v);
  return v.size() == 8 && r.u64(out);
}

inline std::string text_of(std::span<const std::uint8_t> v) { return {reinterpret_cast<const char*>(v.data()), v.size()}; }

}  // namespace cathbox::session::record
