#include "app/png_writer.hpp"

#include <gtest/gtest.h>

#include <string_view>

#include "png_reader.hpp"

namespace cathbox::app {
namespace {

std::span<const std::uint8_t> bytes_of(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

TEST(PngWriter, Crc32MatchesTheStandardCheckValue) {
  EXPECT_EQ(PngWriter::crc32(bytes_of("123456789")), 0xCBF43926U);
  EXPECT_EQ(PngWriter::crc32(bytes_of("")), 0U);
}

TEST(PngWriter, Adler32MatchesKnownValues) {
  EXPECT_EQ(PngWriter::adler32(bytes_of("Wikipedia")), 0x11E60398U);
  EXPECT_EQ(PngWriter::adler32(bytes_of("")), 1U);
  // Long runs exercise the deferred modulo.
  std::vector<std::uint8_t> ff(100000, 0xFF);
  std::uint32_t a = 1;
  std::uint32_t b = 0;
  for (std::uint8_t v : ff) {
    a = (a + v) % 65521;
    b = (b + a) % 65521;
  }
  EXPECT_EQ(PngWriter::adler32(ff), (b << 16) | a);
}

TEST(PngWriter, RoundTripsRgbAndRgbaAcrossSeveralStoredBlocks) {
  for (int channels : {3, 4}) {
    Image img;
    img.width = 301;  // odd width, and more than 64 KiB of data: several deflate blocks
    img.height = 97;
    img.channels = channels;
    img.pixels.resize(static_cast<std::size_t>(img.width * img.height * channels));
    for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = static_cast<std::uint8_t>(i * 7 + i / 301);
    const std::vector<std::uint8_t> png = PngWriter::encode(img);
    ASSERT_FALSE(png.empty());
    std::string error;
    const auto back = testing::decode_png(png, error);
    ASSERT_TRUE(back) << error;
    EXPECT_EQ(back->width, img.width);
    EXPECT_EQ(back->height, img.height);
    EXPECT_EQ(back->channels, channels);
    EXPECT_EQ(back->pixels, img.pixels);
  }
}

TEST(PngWriter, RefusesMalformedImages) {
  Image img;
  EXPECT_TRUE(PngWriter::encode(img).empty());  // 0 x 0
  img.width = 2;
  img.height = 2;
  img.channels = 3;
  img.pixels.resize(11);  // one byte short
  EXPECT_TRUE(PngWriter::encode(img).empty());
  img.pixels.resize(12);
  img.channels = 2;
  EXPECT_TRUE(PngWriter::encode(img).empty());
  std::string error;
  img.channels = 3;
  EXPECT_FALSE(PngWriter::write_file("/nonexistent-dir/x.png", img, error));
  EXPECT_NE(error.find("/nonexistent-dir/x.png"), std::string::npos);
}

TEST(PngWriter, ACorruptedByteIsDetectedByTheReader) {
  Image img{4, 4, 3, std::vector<std::uint8_t>(48, 0x40)};
  std::vector<std::uint8_t> png = PngWriter::encode(img);
  png[png.size() / 2] ^= 0x01;
  std::string error;
  EXPECT_FALSE(testing::decode_png(png, error));
  EXPECT_NE(error.find("CRC"), std::string::npos);
}

}  // namespace
}  // namespace cathbox::app
