#include "app/png_writer.hpp"

#include <gtest/gtest.h>

#include <string_view>

#include "png_reader.hpp"

namespace cathbox::app {
namespace {

TEST(PngWriter, RoundTripsRgbAndRgba) {
  for (int channels : {3, 4}) {
    Image img;
    img.width = 301;  // odd width, more than 64 KiB of pixels
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
  img.channels = 3;
  const base::Status<> written = PngWriter::write_file("/nonexistent-dir/x.png", img);
  ASSERT_FALSE(written);
  EXPECT_NE(written.error().message.find("/nonexistent-dir/x.png"), std::string::npos);
}

TEST(PngWriter, ACorruptedByteIsDetectedByTheReader) {
  Image img{4, 4, 3, std::vector<std::uint8_t>(48, 0x40)};
  std::vector<std::uint8_t> png = PngWriter::encode(img);
  // A byte of the pixel chunk's CRC (libpng, like the PNG spec, only warns about ancillary
  // chunks, and a flipped data byte may first break the zlib stream).
  const std::string_view text(reinterpret_cast<const char*>(png.data()), png.size());
  const std::size_t idat = text.find("IDAT");
  ASSERT_TRUE(idat != std::string_view::npos && idat >= 4);
  const std::size_t length = (std::size_t{png[idat - 4]} << 24) | (std::size_t{png[idat - 3]} << 16) |
                             (std::size_t{png[idat - 2]} << 8) | std::size_t{png[idat - 1]};
  ASSERT_LT(idat + 4 + length + 3, png.size());
  png[idat + 4 + length + 3] ^= 0x01;
  std::string error;
  EXPECT_FALSE(testing::decode_png(png, error));
  EXPECT_NE(error.find("CRC"), std::string::npos);
}

}  // namespace
}  // namespace cathbox::app
