#pragma once
// What the assignment and result handlers share (api_work.cpp, api_result_upload.cpp,
// api_results.cpp): a path id, and a result's metrics by name.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "api_call.hpp"

namespace cathbox::server::api {

// A positive id from a path segment; 400 otherwise.
Result<std::int64_t> id_param(const std::string& text);

std::map<std::string, double> metric_map(const std::vector<MetricValue>& metrics);

}  // namespace cathbox::server::api
