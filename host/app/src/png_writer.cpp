#include "app/png_writer.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace cathbox::app {
namespace {

std::array<std::uint32_t, 256> make_crc_table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1U) ? (0xEDB88320U ^ (c >> 1)) : (c >> 1);
    table[n] = c;
  }
  return table;
}

void put_u32_be(std::vector<std::uint8_t>& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 24));
  out.push_back(static_cast<std::uint8_t>(v >> 16));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

void put_chunk(std::vector<std::uint8_t>& out, const char type[4],
               std::span<const std::uint8_t> data) {
  put_u32_be(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t type_at = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const std::uint32_t crc = PngWriter::crc32(
      std::span<const std::uint8_t>(out.data() + type_at, data.size() + 4));
  put_u32_be(out, crc);
}

}  // namespace

std::uint32_t PngWriter::crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc) {
  static const std::array<std::uint32_t, 256> table = make_crc_table();
  std::uint32_t c = crc ^ 0xFFFFFFFFU;
  for (std::uint8_t b : bytes) c = table[(c ^ b) & 0xFFU] ^ (c >> 8);
  return c ^ 0xFFFFFFFFU;
}

std::uint32_t PngWriter::adler32(std::span<const std::uint8_t> bytes) {
  constexpr std::uint32_t kMod = 65521;
  std::uint32_t a = 1;
  std::uint32_t b = 0;
  std::size_t i = 0;
  while (i < bytes.size()) {
    // 5552 bytes is the largest run whose sums cannot overflow 32 bits before the modulo.
    const std::size_t run = std::min<std::size_t>(5552, bytes.size() - i);
    for (std::size_t k = 0; k < run; ++k) {
      a += bytes[i + k];
      b += a;
    }
    a %= kMod;
    b %= kMod;
    i += run;
  }
  return (b << 16) | a;
}

std::vector<std::uint8_t> PngWriter::encode(const Image& image) {
  if (image.width <= 0 || image.height <= 0 || (image.channels != 3 && image.channels != 4) ||
      image.width > (1 << 16) || image.height > (1 << 16)) {
    return {};
  }
  const std::size_t row_bytes =
      static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.channels);
  if (image.pixels.size() != row_bytes * static_cast<std::size_t>(image.height)) return {};

  // Raw scanlines, each preceded by filter type 0 (none).
  std::vector<std::uint8_t> raw;
  raw.reserve((row_bytes + 1) * static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    raw.push_back(0);
    const auto* row = image.pixels.data() + row_bytes * static_cast<std::size_t>(y);
    raw.insert(raw.end(), row, row + row_bytes);
  }

  // zlib stream: header (deflate, 32K window, no dictionary), stored blocks, Adler-32.
  std::vector<std::uint8_t> z;
  z.reserve(raw.size() + raw.size() / 65535 * 5 + 16);
  z.push_back(0x78);
  z.push_back(0x01);
  std::size_t at = 0;
  do {
    const std::size_t len = std::min<std::size_t>(65535, raw.size() - at);
    const bool last = at + len == raw.size();
    z.push_back(last ? 1 : 0);  // BFINAL, BTYPE = 00 (stored)
    const auto len16 = static_cast<std::uint16_t>(len);
    const auto nlen16 = static_cast<std::uint16_t>(~len16);
    z.push_back(static_cast<std::uint8_t>(len16 & 0xFFU));
    z.push_back(static_cast<std::uint8_t>(len16 >> 8));
    z.push_back(static_cast<std::uint8_t>(nlen16 & 0xFFU));
    z.push_back(static_cast<std::uint8_t>(nlen16 >> 8));
    z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(at),
             raw.begin() + static_cast<std::ptrdiff_t>(at + len));
    at += len;
  } while (at < raw.size());
  put_u32_be(z, adler32(raw));

  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> ihdr;
  put_u32_be(ihdr, static_cast<std::uint32_t>(image.width));
  put_u32_be(ihdr, static_cast<std::uint32_t>(image.height));
  ihdr.push_back(8);                                // bit depth
  ihdr.push_back(image.channels == 4 ? 6 : 2);      // colour type: RGBA or RGB
  ihdr.push_back(0);                                // compression: deflate
  ihdr.push_back(0);                                // filter method 0
  ihdr.push_back(0);                                // no interlace
  put_chunk(png, "IHDR", ihdr);
  put_chunk(png, "IDAT", z);
  put_chunk(png, "IEND", {});
  return png;
}

bool PngWriter::write_file(const std::string& path, const Image& image, std::string& error) {
  const std::vector<std::uint8_t> png = encode(image);
  if (png.empty()) {
    error = "png: invalid image " + std::to_string(image.width) + "x" +
            std::to_string(image.height) + "x" + std::to_string(image.channels);
    return false;
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) {
    error = path + ": cannot open for writing";
    return false;
  }
  out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  if (!out) {
    error = path + ": write failed";
    return false;
  }
  return true;
}

}  // namespace cathbox::app
