#pragma once
// What the case picker shows of a case file without opening it as a session: its title, its
// description (the file's first block of comment lines) and its anatomy (the centreline pieces
// with their radii, and the target) for the thumbnail (case_thumbnail.hpp). Reads the case and
// its HCLM only: no surface is meshed, so the whole cases folder is summed up in milliseconds.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "app/case_thumbnail.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::app {

struct CaseSummary {
  std::string title;        // the case's `name`, else the file name
  std::string description;  // the case file's first comment block, one paragraph, less a leading repeat of the
                            // title; for a bare vessel file, what it holds
  std::string error;        // the case or its vessel does not load: one line (then no anatomy)
  std::vector<ThumbnailTube> tubes;
  std::optional<glm::dvec3> target_mm;
};

// A `.case` file, or a bare `.hclm` vessel file (the default guidewire, no target).
[[nodiscard]] CaseSummary read_case_summary(const std::string& path);

// The first run of consecutive `#` lines, without the `#` and joined into one paragraph; empty
// when the text has no comment.
[[nodiscard]] std::string first_comment_block(std::string_view text);

// Every centreline piece of the model (point to point, each segment's radii).
[[nodiscard]] std::vector<ThumbnailTube> centreline_tubes(const vessel::VesselModel& model);

}  // namespace cathbox::app
