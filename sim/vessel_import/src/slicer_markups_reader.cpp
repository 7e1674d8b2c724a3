#include "vessel_import/slicer_markups_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

namespace cathbox::vessel_import {
namespace {

constexpr std::size_t kMaxDepth = 64;
constexpr std::size_t kMaxErrors = 100;

// A JSON value with the byte offset where the parser met it (what nlohmann's own tree does not
// keep), built from nlohmann's SAX events.
struct Node {
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };
  Kind kind = Kind::kNull;
  double number = 0.0;
  bool boolean = false;
  std::string text;
  std::vector<std::string> keys;  // objects: the members' names, in file order
  std::vector<Node> items;        // arrays: the items; objects: the members' values
  std::size_t at = 0;             // byte offset

  [[nodiscard]] const Node* member(std::string_view key) const {
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] == key) return &items[i];
    }
    return nullptr;
  }
};

// The iterator nlohmann reads through: it remembers the last byte read, which is where the
// parser is when it reports a value.
class TrackedIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  TrackedIterator() = default;
  TrackedIterator(const char* p, const char** last_read) : p_(p), last_read_(last_read) {}
  reference operator*() const {
    *last_read_ = p_;
    return *p_;
  }
  TrackedIterator& operator++() {
    ++p_;
    return *this;
  }
  TrackedIterator operator++(int) {
    TrackedIterator before = *this;
    ++p_;
    return before;
  }
  friend bool operator==(const TrackedIterator& a, const TrackedIterator& b) { return a.p_ == b.p_; }

 private:
  const char* p_ = nullptr;
  const char** last_read_ = nullptr;
};

class TreeBuilder {
 public:
  using json = nlohmann::json;
  TreeBuilder(const char* begin, const char** last_read) : begin_(begin), last_read_(last_read) {}

  bool null() { return value(Node::Kind::kNull); }
  bool boolean(bool v) {
    Node* n = add(Node::Kind::kBool);
    if (n) n->boolean = v;
    return n != nullptr;
  }
  bool number_integer(json::number_integer_t v) { return number(static_cast<double>(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return number(static_cast<double>(v)); }
  bool number_float(json::number_float_t v, const json::string_t&) { return number(v); }
  bool string(json::string_t& v) {
    Node* n = add(Node::Kind::kString);
    if (n) n->text = std::move(v);
    return n != nullptr;
  }
  bool binary(json::binary_t&) { return value(Node::Kind::kNull); }
  bool start_object(std::size_t) { return open(Node::Kind::kObject); }
  bool key(json::string_t& k) {
    key_ = std::move(k);
    return true;
  }
  bool end_object() { return close(); }
  bool start_array(std::size_t) { return open(Node::Kind::kArray); }
  bool end_array() { return close(); }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
    error_at_ = position;
    error_ = e.what();
    // nlohmann's message: "[json.exception.parse_error.101] parse error at line 3, column 5: ..."
    if (const std::size_t colon = error_.find(": "); colon != std::string::npos) error_ = error_.substr(colon + 2);
    return false;
  }

  Node root;
  std::string error_;
  std::size_t error_at_ = 0;  // 1-based byte of a syntax error (nlohmann's position)

 private:
  [[nodiscard]] std::size_t here() const { return *last_read_ ? static_cast<std::size_t>(*last_read_ - begin_) : 0; }
  Node* add(Node::Kind kind) {
    Node* n = nullptr;
    if (stack_.empty()) {
      n = &root;
    } else {
      if (stack_.back()->kind == Node::Kind::kObject) stack_.back()->keys.push_back(std::move(key_));
      stack_.back()->items.emplace_back();
      n = &stack_.back()->items.back();
    }
    n->kind = kind;
    n->at = here();
    return n;
  }
  bool value(Node::Kind kind) { return add(kind) != nullptr; }
  bool number(double v) {
    Node* n = add(Node::Kind::kNumber);
    n->number = v;
    return true;
  }
  bool open(Node::Kind kind) {
    if (stack_.size() >= kMaxDepth) {
      error_ = "nested deeper than " + std::to_string(kMaxDepth) + " levels";
      error_at_ = here() + 1;
      return false;
    }
    stack_.push_back(add(kind));
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }

  const char* begin_;
  const char** last_read_;
  std::vector<Node*> stack_;  // containers being filled (their addresses stay: a container's
                              // own vector only grows while it is on top of the stack)
  std::string key_;
};

[[nodiscard]] std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

class CurveReader {
 public:
  CurveReader(std::string_view text, std::string_view file, std::string_view radius_name, double unit_override_mm,
              SlicerRead& out)
      : text_(text), file_(file), radius_name_(lower(radius_name)), unit_override_mm_(unit_override_mm), out_(out) {}

  void read(const Node& root) {
    if (root.kind != Node::Kind::kObject) return fail(root, "expected a JSON object with a \"markups\" array");
    const Node* markups = root.member("markups");
    if (!markups || markups->kind != Node::Kind::kArray) return fail(root, "no \"markups\" array");
    for (std::size_t i = 0; i < markups->items.size() && out_.errors.size() < kMaxErrors; ++i) markup(markups->items[i], i);
    if (out_.ok() && out_.curves.empty()) {
      fail(*markups, "no curve among the " + std::to_string(markups->items.size()) + " markups (types Curve, ClosedCurve)");
    }
  }

 private:
  void fail(const Node& at, std::string message) {
    if (out_.errors.size() < kMaxErrors) out_.errors.push_back({std::string(file_), line_of(text_, at.at), 0, std::move(message)});
  }

  // fail(), for steps that return whether they succeeded.
  bool reject(const Node& at, std::string message) {
    fail(at, std::move(message));
    return false;
  }

  [[nodiscard]] const Node* string_member(const Node& object, std::string_view key, const std::string& what) {
    const Node* n = object.member(key);
    if (n && n->kind != Node::Kind::kString) {
      fail(*n, what + ": \"" + std::string(key) + "\" is not a string");
      return nullptr;
    }
    return n;
  }

  void markup(const Node& m, std::size_t index) {
    std::string what = "markup " + std::to_string(index);
    if (m.kind != Node::Kind::kObject) return fail(m, what + " is not an object");
    const Node* type = string_member(m, "type", what);
    if (!type) {
      if (!m.member("type")) fail(m, what + " has no \"type\"");
      return;
    }
    const Node* name = string_member(m, "name", what);
    if (name) what += " '" + name->text + "'";
    if (type->text != "Curve" && type->text != "ClosedCurve") {
      ++out_.skipped_markups;
      return;
    }
    const std::optional<bool> ras = is_ras(m, what);
    if (!ras) return;
    const std::optional<double> unit_mm = unit_in_mm(m, what);
    if (!unit_mm) return;
    const Node* points = m.member("controlPoints");
    if (!points || points->kind != Node::Kind::kArray) return fail(m, what + " has no \"controlPoints\" array");
    const Node* radii = radius_values(m, what, points->items.size());
    if (!radii) return;
    Polyline line;
    line.name = name ? name->text : type->text;
    line.where = what;
    const PointFrame frame{*ras, *unit_mm};
    for (std::size_t j = 0; j < points->items.size(); ++j) {
      if (!control_point(points->items[j], radii->items[j], j, what, frame, line)) return;
    }
    if (type->text == "ClosedCurve" && line.points.size() >= 3) line.points.push_back(line.points.front());
    if (line.points.size() < 2) return fail(m, what + " has fewer than 2 defined control points");
    out_.curves.push_back(std::move(line));
  }

  // Coordinates: LPS or RAS (true); nothing after a failure.
  std::optional<bool> is_ras(const Node& m, const std::string& what) {
    bool ras = false;
    if (const Node* system = string_member(m, "coordinateSystem", what)) {
      if (system->text == "RAS") {
        ras = true;
      } else if (system->text != "LPS") {
        fail(*system, what + ": coordinateSystem '" + system->text + "' is neither LPS nor RAS");
        return std::nullopt;
      }
      if (out_.coordinate_system.empty()) out_.coordinate_system = system->text;
    }
    if (out_.coordinate_system.empty()) out_.coordinate_system = "LPS";
    return ras;
  }

  // The coordinates' unit, mm or um (the caller's override wins); nothing after a failure.
  std::optional<double> unit_in_mm(const Node& m, const std::string& what) {
    double unit_mm = 1.0;
    if (const Node* units = m.member("coordinateUnits")) {
      const Node* code = units->kind == Node::Kind::kArray && !units->items.empty() ? &units->items.front() : units;
      if (code->kind != Node::Kind::kString || (code->text != "mm" && code->text != "um")) {
        if (unit_override_mm_ <= 0.0) {
          fail(*units, what + ": coordinateUnits must be \"mm\" or \"um\"");
          return std::nullopt;
        }
      } else {
        unit_mm = code->text == "um" ? 1e-3 : 1.0;
      }
    }
    if (unit_override_mm_ > 0.0) unit_mm = unit_override_mm_;
    return unit_mm;
  }

  // The radius per control point: the measurement named radius_name_; null after a failure.
  const Node* radius_values(const Node& m, const std::string& what, std::size_t point_count) {
    const Node* radii = nullptr;
    if (const Node* measurements = m.member("measurements"); measurements && measurements->kind == Node::Kind::kArray) {
      for (const Node& meas : measurements->items) {
        const Node* mname = meas.kind == Node::Kind::kObject ? meas.member("name") : nullptr;
        if (!mname || mname->kind != Node::Kind::kString || lower(mname->text) != radius_name_) continue;
        radii = meas.member("controlPointValues");
        if (!radii || radii->kind != Node::Kind::kArray) {
          fail(meas, what + ": measurement '" + mname->text + "' has no \"controlPointValues\" array");
          return nullptr;
        }
        break;
      }
    }
    if (!radii) {
      fail(m, what + " has no per-point radius (a measurement named '" + radius_name_ + "' with \"controlPointValues\")");
      return nullptr;
    }
    if (radii->items.size() != point_count) {
      fail(*radii, what + ": " + std::to_string(radii->items.size()) + " radius values for " + std::to_string(point_count) +
                       " control points");
      return nullptr;
    }
    return radii;
  }

  struct PointFrame {
    bool ras = false;
    double unit_mm = 1.0;
  };

  // Control point j with its radius appended to `line` (LPS, mm), or skipped when undefined or a
  // preview; false after a failure.
  bool control_point(const Node& cp, const Node& r, std::size_t j, const std::string& what, const PointFrame& frame,
                     Polyline& line) {
    const std::string point_what = what + ", control point " + std::to_string(j);
    if (cp.kind != Node::Kind::kObject) return reject(cp, point_what + " is not an object");
    if (const Node* status = cp.member("positionStatus");
        status && status->kind == Node::Kind::kString && (status->text == "undefined" || status->text == "preview")) {
      ++out_.skipped_points;
      return true;
    }
    const Node* position = cp.member("position");
    if (!position) return reject(cp, point_what + " has no \"position\"");
    if (position->kind != Node::Kind::kArray || position->items.size() != 3) {
      return reject(*position, point_what + ": \"position\" must be 3 numbers");
    }
    double xyz[3];
    for (std::size_t k = 0; k < 3; ++k) {
      const Node& c = position->items[k];
      if (c.kind != Node::Kind::kNumber || !std::isfinite(c.number)) {
        return reject(c, point_what + ": \"position\" must be 3 finite numbers");
      }
      xyz[k] = c.number;
    }
    if (r.kind != Node::Kind::kNumber || !std::isfinite(r.number)) {
      return reject(r, what + ": radius of control point " + std::to_string(j) + " is not a finite number");
    }
    if (frame.ras) {
      xyz[0] = -xyz[0];
      xyz[1] = -xyz[1];
    }
    line.points.push_back({glm::dvec3(xyz[0], xyz[1], xyz[2]) * frame.unit_mm, r.number * frame.unit_mm});
    return true;
  }

  std::string_view text_;
  std::string_view file_;
  std::string radius_name_;
  double unit_override_mm_;
  SlicerRead& out_;
};

}  // namespace

SlicerRead parse_slicer_markups(std::string_view text, std::string_view file, std::string_view radius_name,
                                double unit_override_mm) {
  SlicerRead out;
  const char* last_read = nullptr;
  TreeBuilder builder(text.data(), &last_read);
  const TrackedIterator first(text.data(), &last_read);
  const TrackedIterator last(text.data() + text.size(), &last_read);
  const bool parsed = nlohmann::json::sax_parse(first, last, &builder);
  if (!parsed) {
    ImportError e{std::string(file), 0, builder.error_at_, builder.error_.empty() ? "not valid JSON" : builder.error_};
    if (builder.error_at_ > 0) e.line = line_of(text, builder.error_at_ - 1);
    out.errors.push_back(std::move(e));
    return out;
  }
  CurveReader(text, file, radius_name, unit_override_mm, out).read(builder.root);
  return out;
}

}  // namespace cathbox::vessel_import
