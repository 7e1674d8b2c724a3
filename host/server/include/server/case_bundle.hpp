#pragma once
// What a case download carries: the case file and its HCLM file, verbatim, as one JSON object
// compressed with zstd (the trainer meshes locally, so no mesh travels):
//   {"format": "cathbox-case-bundle 1",
//    "case_file": "neuro.case", "case": "cathbox-case 1\n...",
//    "hclm_file": "neuro.hclm", "hclm": "s 37\n...",
//    "surface_file": "lumen.cbxmesh", "surface_hex": "4342..."}   (only for a `surface FILE` case)
// The server stores the compressed bytes once and sends them with Content-Encoding: zstd; the
// library name and version travel in the URL (and the X-Cathbox-Case headers), not the bundle,
// and the content hash (SHA-256 of this JSON text) is the download's ETag.
#include <optional>
#include <string>
#include <string_view>

#include "server/result.hpp"

namespace cathbox::server {

inline constexpr std::size_t kMaxBundleBytes = 16 * 1024 * 1024;

struct CaseBundle {
  std::string case_file;
  std::string case_text;
  std::string hclm_file;  // empty for cases made of analytic tubes
  std::string hclm_text;
  std::string surface_file;   // a case's own wall (`surface FILE`); empty: meshed from the HCLM
  std::string surface_bytes;  // its CBXMESH2 bytes, verbatim (in JSON as lowercase hex)
};

// Lowercase hex of `bytes`, and back (nullopt on an odd length or a non-hex character).
[[nodiscard]] std::string hex_of(std::string_view bytes);
[[nodiscard]] std::optional<std::string> bytes_of_hex(std::string_view hex);

// The JSON text (compact, keys in a fixed order, so equal files give equal hashes).
[[nodiscard]] std::string bundle_json(const CaseBundle& b);
// Parses the (already decompressed) JSON text; 422 with the field on error.
[[nodiscard]] Result<CaseBundle> parse_bundle_json(const std::string& json_text);
// Writes case_file and hclm_file into `folder` (created); the path of the case file.
[[nodiscard]] Result<std::string> write_bundle_files(const CaseBundle& b, const std::string& folder);

}  // namespace cathbox::server
