#pragma once
// An assignment's pass criteria: conditions on a run's metrics, all of which must hold.
//   [{"metric": "target_reached", "op": "==", "value": 1},
//    {"metric": "fluoroscopy_time_s", "op": "<=", "value": 180},
//    {"metric": "peak_wall_force_mN", "op": "<=", "value": 200}]
// A metric the run did not measure fails its criterion (and says so).
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/result.hpp"

namespace cathbox::server {

struct Criterion {
  std::string metric;
  std::string op;  // "<", "<=", "==", ">=", ">"
  double value = 0.0;
};

struct CriterionOutcome {
  Criterion criterion;
  bool measured = false;
  double actual = 0.0;
  bool passed = false;
};

struct Evaluation {
  bool passed = true;
  std::vector<CriterionOutcome> outcomes;
};

class PassCriteria {
 public:
  // `known_metrics` empty: any well-formed name ([A-Za-z0-9_], 1-64) is accepted.
  [[nodiscard]] static Result<PassCriteria> parse(const nlohmann::json& array, const std::vector<std::string>& known_metrics);
  [[nodiscard]] static Result<PassCriteria> parse_text(const std::string& json_text);
  [[nodiscard]] nlohmann::json to_json() const;
  [[nodiscard]] Evaluation evaluate(const std::map<std::string, double>& metrics) const;
  [[nodiscard]] const std::vector<Criterion>& criteria() const { return criteria_; }

 private:
  std::vector<Criterion> criteria_;
};

[[nodiscard]] nlohmann::json evaluation_json(const Evaluation& e);

}  // namespace cathbox::server
