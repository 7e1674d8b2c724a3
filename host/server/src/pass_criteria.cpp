#include "server/pass_criteria.hpp"

#include <algorithm>
#include <cmath>

#include "server/json_input.hpp"

namespace cathbox::server {

namespace {
constexpr const char* kOps[] = {"<", "<=", "==", ">=", ">"};
constexpr std::size_t kMaxCriteria = 32;

bool metric_name_ok(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'; }) &&
         s.front() != '_';
}

bool holds(const std::string& op, double actual, double value) {
  if (op == "<") return actual < value;
  if (op == "<=") return actual <= value;
  if (op == "==") return std::fabs(actual - value) <= 1e-9 * std::max(1.0, std::fabs(value));
  if (op == ">=") return actual >= value;
  return actual > value;
}
}  // namespace

Result<PassCriteria> PassCriteria::parse(const nlohmann::json& array, const std::vector<std::string>& known_metrics) {
  if (!array.is_array()) return make_error(400, std::string("field 'criteria': expected an array, got ") + array.type_name());
  if (array.size() > kMaxCriteria) {
    return make_error(400, "field 'criteria': at most " + std::to_string(kMaxCriteria) + " criteria");
  }
  PassCriteria out;
  for (std::size_t i = 0; i < array.size(); ++i) {
    FieldReader f(array[i], "criteria[" + std::to_string(i) + "].");
    Criterion c;
    c.metric = f.string("metric", 64);
    c.op = f.string("op", 2);
    c.value = f.number("value");
    f.only({"metric", "op", "value"});
    if (f.ok() && !metric_name_ok(c.metric)) f.fail("metric", "'" + c.metric + "' is not a metric name ([A-Za-z0-9_])");
    if (f.ok() && !known_metrics.empty() &&
        std::find(known_metrics.begin(), known_metrics.end(), c.metric) == known_metrics.end()) {
      std::string list;
      for (const std::string& k : known_metrics) list += (list.empty() ? "" : ", ") + k;
      f.fail("metric", "unknown metric '" + c.metric + "' (known: " + list + ")");
    }
    if (f.ok() && std::find(std::begin(kOps), std::end(kOps), c.op) == std::end(kOps)) {
      f.fail("op", "'" + c.op + "' is not one of < <= == >= >");
    }
    if (!f.ok()) return f.error();
    out.criteria_.push_back(std::move(c));
  }
  return out;
}

Result<PassCriteria> PassCriteria::parse_text(const std::string& json_text) {
  Result<nlohmann::json> parsed = parse_json(json_text, "criteria");
  if (!parsed) return parsed.error();
  return parse(parsed.value(), {});
}

nlohmann::json PassCriteria::to_json() const {
  nlohmann::json out = nlohmann::json::array();
  for (const Criterion& c : criteria_) out.push_back({{"metric", c.metric}, {"op", c.op}, {"value", c.value}});
  return out;
}

Evaluation PassCriteria::evaluate(const std::map<std::string, double>& metrics) const {
  Evaluation e;
  for (const Criterion& c : criteria_) {
    CriterionOutcome o{c, false, 0.0, false};
    const auto it = metrics.find(c.metric);
    if (it != metrics.end()) {
      o.measured = true;
      o.actual = it->second;
      o.passed = holds(c.op, o.actual, c.value);
    }
    e.passed = e.passed && o.passed;
    e.outcomes.push_back(o);
  }
  return e;
}

nlohmann::json evaluation_json(const Evaluation& e) {
  nlohmann::json out = {{"passed", e.passed}, {"criteria", nlohmann::json::array()}};
  for (const CriterionOutcome& o : e.outcomes) {
    nlohmann::json c = {{"metric", o.criterion.metric}, {"op", o.criterion.op}, {"value", o.criterion.value}, {"passed", o.passed}};
    c["actual"] = o.measured ? nlohmann::json(o.actual) : nlohmann::json(nullptr);
    out["criteria"].push_back(std::move(c));
  }
  return out;
}

}  // namespace cathbox::server
