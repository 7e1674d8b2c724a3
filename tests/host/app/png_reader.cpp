#include "png_reader.hpp"

#include <cstring>
#include <fstream>
#include <iterator>

namespace cathbox::app::testing {
namespace {
std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}
}  // namespace

std::optional<Image> decode_png(const std::vector<std::uint8_t>& bytes, std::string& error) {
  static const std::uint8_t kSig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSig, 8) != 0) {
    error = "bad signature";
    return std::nullopt;
  }
  Image img;
  std::vector<std::uint8_t> z;
  std::size_t at = 8;
  bool ended = false;
  while (!ended) {
    if (at + 12 > bytes.size()) {
      error = "truncated chunk at byte " + std::to_string(at);
      return std::nullopt;
    }
    const std::uint32_t len = be32(&bytes[at]);
    if (len > bytes.size() - at - 12) {
      error = "chunk length past the end at byte " + std::to_string(at);
      return std::nullopt;
    }
    const std::uint8_t* type = &bytes[at + 4];
    const std::uint8_t* data = type + 4;
    if (PngWriter::crc32(std::span<const std::uint8_t>(type, len + 4)) != be32(data + len)) {
      error = "bad CRC at byte " + std::to_string(at);
      return std::nullopt;
    }
    if (std::memcmp(type, "IHDR", 4) == 0 && len == 13) {
      img.width = static_cast<int>(be32(data));
      img.height = static_cast<int>(be32(data + 4));
      if (data[8] != 8 || (data[9] != 2 && data[9] != 6) || data[12] != 0) {
        error = "unsupported IHDR";
        return std::nullopt;
      }
      img.channels = data[9] == 6 ? 4 : 3;
    } else if (std::memcmp(type, "IDAT", 4) == 0) {
      z.insert(z.end(), data, data + len);
    } else if (std::memcmp(type, "IEND", 4) == 0) {
      ended = true;
    }
    at += 12 + len;
  }
  if (img.width <= 0 || img.height <= 0 || img.width > 16384 || img.height > 16384 || z.size() < 6 ||
      z[0] != 0x78 || ((z[0] << 8) | z[1]) % 31 != 0) {
    error = "bad header or zlib stream";
    return std::nullopt;
  }
  std::vector<std::uint8_t> raw;
  std::size_t p = 2;
  bool final_block = false;
  while (!final_block) {
    if (p + 5 > z.size() || (z[p] & 0x06) != 0) {
      error = "not a stored deflate block at " + std::to_string(p);
      return std::nullopt;
    }
    final_block = (z[p] & 1) != 0;
    const std::size_t len = z[p + 1] | (z[p + 2] << 8);
    const std::size_t nlen = z[p + 3] | (z[p + 4] << 8);
    if ((len ^ 0xFFFFU) != nlen || p + 5 + len > z.size()) {
      error = "bad stored block length";
      return std::nullopt;
    }
    raw.insert(raw.end(), z.begin() + static_cast<std::ptrdiff_t>(p + 5),
               z.begin() + static_cast<std::ptrdiff_t>(p + 5 + len));
    p += 5 + len;
  }
  if (p + 4 != z.size() || be32(&z[p]) != PngWriter::adler32(raw)) {
    error = "bad Adler-32";
    return std::nullopt;
  }
  const std::size_t row = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.channels);
  if (raw.size() != (row + 1) * static_cast<std::size_t>(img.height)) {
    error = "pixel data size";
    return std::nullopt;
  }
  img.pixels.reserve(row * static_cast<std::size_t>(img.height));
  for (int y = 0; y < img.height; ++y) {
    const std::size_t r = (row + 1) * static_cast<std::size_t>(y);
    if (raw[r] != 0) {
      error = "unsupported filter";
      return std::nullopt;
    }
    img.pixels.insert(img.pixels.end(), raw.begin() + static_cast<std::ptrdiff_t>(r + 1),
                      raw.begin() + static_cast<std::ptrdiff_t>(r + 1 + row));
  }
  return img;
}

std::optional<Image> read_png(const std::string& path, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open";
    return std::nullopt;
  }
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return decode_png(bytes, error);
}

}  // namespace cathbox::app::testing
