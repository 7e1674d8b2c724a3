#include "server/zstd_codec.hpp"

#include <zstd.h>

#include <memory>

namespace cathbox::server {

std::string zstd_compress(std::string_view bytes, int level) {
  std::string out(ZSTD_compressBound(bytes.size()), '\0');
  const std::size_t n = ZSTD_compress(out.data(), out.size(), bytes.data(), bytes.size(), level);
  if (ZSTD_isError(n)) return {};  // cannot happen with a bound-sized buffer
  out.resize(n);
  return out;
}

Result<std::string> zstd_decompress(std::string_view frame, std::size_t max_bytes) {
  const std::unique_ptr<ZSTD_DStream, decltype(&ZSTD_freeDStream)> stream(ZSTD_createDStream(), ZSTD_freeDStream);
  ZSTD_initDStream(stream.get());
  std::string out;
  ZSTD_inBuffer in{frame.data(), frame.size(), 0};
  std::string chunk(ZSTD_DStreamOutSize(), '\0');
  std::size_t last = 1;
  while (in.pos < in.size || last != 0) {
    ZSTD_outBuffer o{chunk.data(), chunk.size(), 0};
    const std::size_t before = in.pos;
    last = ZSTD_decompressStream(stream.get(), &o, &in);
    if (ZSTD_isError(last)) {
      return make_error(422, "zstd: byte " + std::to_string(in.pos) + ": " + ZSTD_getErrorName(last));
    }
    if (out.size() + o.pos > max_bytes) {
      return make_error(413, "zstd: content larger than " + std::to_string(max_bytes) + " bytes");
    }
    out.append(chunk.data(), o.pos);
    if (in.pos == in.size && o.pos == 0 && before == in.pos && last != 0) {
      return make_error(422, "zstd: byte " + std::to_string(in.size) + ": frame truncated");
    }
  }
  return out;
}

}  // namespace cathbox::server
