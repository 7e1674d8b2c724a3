#pragma once
// The case file's reader (parse_case): one statement per line, each checked as it is read, the
// case as a whole checked after the last. Its statements are defined by topic: the case's own
// (case_parser.cpp), a tool's between `tool` and `end` (case_tool_statements.cpp), the blood
// flow's and the clots' (case_flow_statements.cpp).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/text_lines.hpp"
#include "scenario/case_file.hpp"

namespace cathbox::tool::detail {

inline constexpr std::size_t kMaxTools = ToolLimits::kMaxTools;
inline constexpr std::size_t kMaxTubes = 200000;
inline constexpr std::size_t kMaxSections = ToolLimits::kMaxSections;
inline constexpr double kMaxToolLength_mm = ToolLimits::kMaxLength_mm;
inline constexpr double kMaxNodes = ToolLimits::kMaxNodes;
inline constexpr std::size_t kMaxFlowSettings = 100000;
inline constexpr std::size_t kMaxViews = 16;
inline constexpr std::size_t kMaxClots = 16;

class CaseParser {
 public:
  CaseParser(std::string_view text, std::string_view file) : lines_(text), file_(file) {}

  CaseParse run();

 private:
  // Which once-only keywords were given.
  struct Seen {
    bool header = false, name = false, entry = false, target = false, realistic = false, valve = false, threshold = false,
         aneurysm = false, wall = false;
  };

  // A line between `tool NAME KIND` and its `end`.
  bool in_tool_statement(const std::vector<std::string_view>& w);

  // A line outside a tool: its keyword's statement.
  bool statement(const std::vector<std::string_view>& w);
  bool header_statement(const std::vector<std::string_view>& w);
  bool name_statement(const std::vector<std::string_view>& w);
  bool threshold_statement(const std::vector<std::string_view>& w);
  bool valve_statement(const std::vector<std::string_view>& w);
  bool realistic_statement(const std::vector<std::string_view>& w);
  bool case_flow_statement(const std::vector<std::string_view>& w) { return flow_statement(c_.flow, w); }
  bool case_clot_statement(const std::vector<std::string_view>& w) { return clot_statement(c_, w); }

  // `vessel FILE` or `surface FILE`: the path relative to the case file's folder.
  bool path_statement(const std::vector<std::string_view>& w);
  bool tube_statement(const std::vector<std::string_view>& w);
  bool entry_statement(const std::vector<std::string_view>& w);
  bool target_statement(const std::vector<std::string_view>& w);

  // `tool NAME KIND`: a new tool, whose lines follow up to its `end`.
  bool tool_header(const std::vector<std::string_view>& w);
  bool aneurysm_statement(const std::vector<std::string_view>& w);
  bool view_statement(const std::vector<std::string_view>& w);
  bool wall_statement(const std::vector<std::string_view>& w);

  // After the last line: a vessel in one form, and what a surface needs.
  bool check_vessel();

  // Every `inside NAME`: a known catheter other than the tool, no cycle, and room for the tool.
  bool check_coaxial();
  bool check_aspiration();
  bool tool_statement(ToolSpec& t, const std::vector<std::string_view>& w);

  // `KEY VALUE` with VALUE in [lo, hi]: into `out`, else `message`.
  bool bounded_value(const std::vector<std::string_view>& w, double lo, double hi, const char* message, double& out);
  bool section_statement(ToolSpec& t, const std::vector<std::string_view>& w);
  bool next_coil_statement(ToolSpec& t, const std::vector<std::string_view>& w);

  // `spacing MAX_MM TIP_MM [TIP_ZONE_MM]`.
  bool spacing_statement(ToolSpec& t, const std::vector<std::string_view>& w);

  // Which of a section's required keys were given.
  struct SectionKeys {
    bool od = false, ei = false, gj = false;
  };

  // `section` and `next_coil`: LENGTH od=MM ei=N.mm2 gj=N.mm2 [curve=DEG] [shape=... loop=MM].
  bool section_words(const std::vector<std::string_view>& w, ToolKind kind, ToolSection& s);

  // One KEY=VALUE of a section.
  bool section_key(const std::string& verb, std::string_view k, std::string_view value, ToolSection& s, SectionKeys& given);

  // `clot SEG FROM_MM LENGTH_MM [red=PCT] [fibrin=PCT] [open=F]`.
  bool clot_statement(Case& c, const std::vector<std::string_view>& w);

  // `aspiration pump|syringe` in a catheter with a lumen.
  bool aspiration_statement(Case& c, const ToolSpec& t, const std::vector<std::string_view>& w);

  // `balloon length=MM from_tip=MM nominal=ATM burst=ATM chart=P:D,P:D,...` on a catheter.
  bool balloon_statement(ToolSpec& t, const std::vector<std::string_view>& w);

  // `stent_retriever diameter=MM length=MM [embed=S]` on a push wire (a guidewire tool).
  bool stent_statement(ToolSpec& t, const std::vector<std::string_view>& w);

  // `flow KEY VALUES...`: the blood-flow model's settings (sim/flow/README.md). Segment ids are
  // checked against the vessel model when the flow network is built, naming this line.
  bool flow_statement(flow::FlowSettings& f, const std::vector<std::string_view>& w);

  // `flow KEY ...` has lo..hi values after its key.
  bool flow_args(const std::vector<std::string_view>& w, std::size_t lo, std::size_t hi);

  // Word i of a flow line, a number in the range (lo open or closed, hi closed).
  bool flow_value_in(const std::vector<std::string_view>& w, std::size_t i, double lo, double hi, bool lo_open, const char* range,
                     double& out);

  // `flow KEY VALUE`, once per case.
  bool flow_scalar(const std::vector<std::string_view>& w, double& field, double lo, double hi, bool lo_open, const char* range);

  // `flow inflow|outlet|closed SEG ...`: a segment given once as an outlet or closed (an
  // inflow may also be either), at most kMaxFlowSettings in all.
  bool flow_segment_setting(flow::FlowSettings& f, const std::vector<std::string_view>& w, std::vector<flow::SegmentSetting>& list,
                            double value);
  bool once_flow(std::string_view key);
  bool check_tool(const ToolSpec& t, std::size_t line);

  // The words w[first..] as key=NUMBER pairs, each handed to on_pair(key, value), which returns
  // false once it has reported an error. `what` names the statement in the errors.
  template <class OnPair>
  bool number_pairs(const std::vector<std::string_view>& w, std::size_t first, std::string_view what, OnPair on_pair) {
    for (std::size_t i = first; i < w.size(); ++i) {
      const std::size_t eq = w[i].find('=');
      if (eq == std::string_view::npos) return error_here(std::string(what) + ": expected key=value, got '" + std::string(w[i]) + "'");
      const std::string_view k = w[i].substr(0, eq);
      double v = 0.0;
      if (!number(w[i].substr(eq + 1), std::string(what) + " " + std::string(k), v) || !on_pair(k, v)) return false;
    }
    return true;
  }

  bool expect_args(const std::vector<std::string_view>& w, std::size_t n) {
    if (w.size() == n + 1) return true;
    return error_here(std::string(w[0]) + ": expected " + std::to_string(n) + " value" + (n == 1 ? "" : "s") + ", got " +
                      std::to_string(w.size() - 1));
  }
  bool once(bool& seen, std::string_view key) {
    if (seen) return error_here(std::string(key) + " given twice");
    seen = true;
    return true;
  }
  bool number(std::string_view word, const std::string& what, double& out) {
    const std::optional<double> v = base::text::parse_number(word);
    if (!v) return error_here(what + ": '" + std::string(word) + "' is not a finite number");
    out = *v;
    return true;
  }
  bool numbers(const std::vector<std::string_view>& w, std::size_t first, double* out, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!number(w[first + i], std::string(w[0]), out[i])) return false;
    }
    return true;
  }
  bool error_here(const std::string& message) { return error_at(lines_.line(), message); }
  bool error_at(std::size_t line, const std::string& message) {
    error_ = base::text::located(file_, line, message);
    return false;
  }
  CaseParse fail() { return base::Error{error_}; }
  CaseParse fail_here(const std::string& message) {
    error_here(message);
    return fail();
  }
  CaseParse fail_at(std::size_t line, const std::string& message) {
    error_at(line, message);
    return fail();
  }

  base::text::TextLines lines_;
  std::string_view file_;
  std::string error_;
  Case c_;
  Seen seen_;
  ToolSpec* tool_ = nullptr;  // the tool whose lines are being read (c_.tools' last), or none
  std::size_t tool_line_ = 0;
  std::vector<std::size_t> tool_lines_;  // each tool's `tool` line
  std::vector<std::string> flow_keys_;
  std::size_t stent_line_ = 0;  // the last stent_retriever statement
  std::size_t surface_line_ = 0;  // the `surface` statement
};

}  // namespace cathbox::tool::detail
