#pragma once
// zstd (Debian's libzstd) for case bundles and queued uploads. Decompression is bounded: a
// frame that would grow past `max_bytes` is refused, so a small hostile input cannot make a
// large allocation.
#include <string>
#include <string_view>

#include "server/result.hpp"

namespace cathbox::server {

[[nodiscard]] std::string zstd_compress(std::string_view bytes, int level = 19);
// 422 "zstd: ..." on a corrupt frame or one larger than max_bytes.
[[nodiscard]] Result<std::string> zstd_decompress(std::string_view frame, std::size_t max_bytes);

}  // namespace cathbox::server
