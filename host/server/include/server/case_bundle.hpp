#pragma once
// What a case download carries: the case file and its HCLM file, verbatim, as one JSON object
// compressed with zstd (the trainer meshes locally, so no mesh travels):
//   {"format": "cathbox-case-bundle 1",
//    "case_file": "neuro.case", "case": "cathbox-case 1\n...",
//    "hclm_file": "neuro.hclm", "hclm": "s 37\n..."}
// The server stores the compressed bytes once and sends them with Content-Encoding: zstd; the
// library name and version travel in the URL (and the X-Cathbox-Case headers), not the bundle,
// and the content hash (SHA-256 of this JSON text) is the download's ETag.
#include <string>

#include "server/result.hpp"

namespace cathbox::server {

inline constexpr std::size_t kMaxBundleBytes = 16 * 1024 * 1024;

struct CaseBundle {
  std::string case_file;
  std::string case_text;
  std::string hclm_file;  // empty for cases made of analytic tubes
  std::string hclm_text;
};

// The JSON text (compact, keys in a fixed order, so equal files give equal hashes).
[[nodiscard]] std::string bundle_json(const CaseBundle& b);
// Parses the (already decompressed) JSON text; 422 with the field on error.
[[nodiscard]] Result<CaseBundle> parse_bundle_json(const std::string& json_text);
// Writes case_file and hclm_file into `folder` (created); the path of the case file.
[[nodiscard]] Result<std::string> write_bundle_files(const CaseBundle& b, const std::string& folder);

}  // namespace cathbox::server
