#include <algorithm>
#include <cctype>
#include <optional>
#include <string>
#include <string_view>

#include "vessel_import/importer.hpp"

namespace cathbox::vessel_import {
namespace {

[[nodiscard]] std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

[[nodiscard]] bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

}  // namespace

std::optional<Format> format_from_name(std::string_view name) {
  const std::string n = lower(name);
  if (n == "vtk") return Format::kVtkLegacy;
  if (n == "vtp") return Format::kVtkXml;
  if (n == "slicer" || n == "mrk.json" || n == "json") return Format::kSlicerMarkups;
  if (n == "swc") return Format::kSwc;
  if (n == "surface" || n == "stl" || n == "obj" || n == "ply" || n == "off") return Format::kSurface;
  return std::nullopt;
}

std::optional<Format> format_from_path(std::string_view path) {
  const std::string p = lower(path);
  if (ends_with(p, ".vtk")) return Format::kVtkLegacy;
  if (ends_with(p, ".vtp")) return Format::kVtkXml;
  if (ends_with(p, ".json")) return Format::kSlicerMarkups;
  if (ends_with(p, ".swc")) return Format::kSwc;
  for (const char* ext : {".stl", ".obj", ".ply", ".off"}) {
    if (ends_with(p, ext)) return Format::kSurface;
  }
  return std::nullopt;
}

const char* format_name(Format format) {
  switch (format) {
    case Format::kVtkLegacy: return "VTK legacy polydata";
    case Format::kVtkXml: return "VTK XML polydata";
    case Format::kSlicerMarkups: return "Slicer markups";
    case Format::kSwc: return "SWC";
    case Format::kSurface: return "surface";
  }
  return "?";
}

std::optional<double> unit_to_mm(std::string_view unit) {
  if (unit == "mm") return 1.0;
  if (unit == "cm") return 10.0;
  if (unit == "m") return 1000.0;
  if (unit == "um") return 1e-3;
  return std::nullopt;
}

}  // namespace cathbox::vessel_import
