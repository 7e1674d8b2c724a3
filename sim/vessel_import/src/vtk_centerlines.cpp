// The VTK half of the VTK importer: reads the polydata and copies its lines and arrays out.
// Built on its own as the module libcathbox_vessel_import_vtk.so, which vtk_module_loader.cpp
// opens when a VTK file is imported: this file and CMake are the only places that know VTK, and
// no program maps VTK's libraries (11 MB resident, their start-up) unless it reads a VTK file.
#include "vessel_import/vtk_centerlines.hpp"

#include <algorithm>
#include <filesystem>
#include <charconv>

#include "base/result.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkSmartPointer.h>
#include <vtkStringOutputWindow.h>
#include <vtkXMLPolyDataReader.h>

namespace cathbox::vessel_import {

VtkRead read_vtk_with_vtk(const std::string& path, const std::string& radius_array, bool xml);

namespace {

// VTK reports problems through its output window (to stderr by default); while a file is read
// they go to a string instead, and the last error becomes our one-line message.
class CapturedMessages {
 public:
  CapturedMessages() : previous_(vtkOutputWindow::GetInstance()) {
    // VTK 9 also logs every error and warning to stderr through vtkLogger; the string window
    // gets them all the same.
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
    previous_->Register(nullptr);
    vtkOutputWindow::SetInstance(window_);
  }
  ~CapturedMessages() {
    vtkOutputWindow::SetInstance(previous_);
    previous_->UnRegister(nullptr);
  }
  CapturedMessages(const CapturedMessages&) = delete;
  CapturedMessages& operator=(const CapturedMessages&) = delete;

  [[nodiscard]] std::string text() { return window_->GetOutput(); }
  // Readers report malformed files as errors or, for data that ends early, as warnings.
  [[nodiscard]] bool any() { return !text().empty(); }

  // The reader's message without VTK's own source location and the file name ("ERROR: In
  // .../vtkDataReader.cxx, line 391\nvtkPolyDataReader (0x55..): Unrecognized file type: x for
  // file: f.vtk" -> "VTK: Unrecognized file type: x"), and the file's line when the XML parser
  // gave one.
  void last_error(ImportError& e) {
    const std::string all = text();
    // "ERROR: In <source>, line <n>\n<object> (0x...): <message>\n" or
    // "Generic Warning: In <source>, line <n>\n<message>\n": the first one's message (the cause;
    // the pipeline's own complaints follow it).
    const std::size_t error_at = all.find("ERROR:");
    const std::size_t warning_at = all.find("Warning:");
    const std::size_t at = std::min(error_at, warning_at);
    if (at == std::string::npos) return;
    std::size_t begin = all.find('\n', at);
    while (begin < all.size() && all[begin] == '\n') ++begin;
    if (begin >= all.size()) return;
    std::string message = all.substr(begin, all.find('\n', begin) - begin);
    if (const std::size_t object = message.find("): "); object != std::string::npos) message = message.substr(object + 3);
    if (const std::size_t suffix = message.find(" for file: "); suffix != std::string::npos) message.resize(suffix);
    while (!message.empty() && message.back() == ' ') message.pop_back();
    if (const std::size_t at_line = message.find("at line "); at_line != std::string::npos) {
      const char* digits = message.c_str() + at_line + 8;
      int line = 0;
      const auto [end, ec] = std::from_chars(digits, message.c_str() + message.size(), line);
      if (ec == std::errc() && end != digits) e.line = line;
    }
    if (!message.empty()) e.message = "VTK: " + message;
  }

 private:
  vtkOutputWindow* previous_;
  vtkNew<vtkStringOutputWindow> window_;
};

[[nodiscard]] std::string array_names(vtkPointData* data) {
  std::string out;
  for (int i = 0; i < data->GetNumberOfArrays(); ++i) {
    const char* name = data->GetArrayName(i);
    out += (out.empty() ? "" : ", ") + std::string(name ? name : "(unnamed)");
  }
  return out.empty() ? "none" : out;
}

// A surface: the points and the polygon cells (strips split into triangles, alternating
// winding as VTK's strips do). False when the polydata has neither.
bool copy_surface(vtkPolyData& data, PolylineArrays& out) {
  vtkCellArray* polys = data.GetPolys();
  vtkCellArray* strips = data.GetStrips();
  const vtkIdType n_polys = polys ? polys->GetNumberOfCells() : 0;
  const vtkIdType n_strips = strips ? strips->GetNumberOfCells() : 0;
  if (n_polys + n_strips == 0) return false;
  const vtkIdType n_points = data.GetNumberOfPoints();
  out.points.reserve(static_cast<std::size_t>(n_points));
  for (vtkIdType i = 0; i < n_points; ++i) {
    double p[3];
    data.GetPoint(i, p);
    out.points.emplace_back(p[0], p[1], p[2]);
  }
  out.polygons.reserve(static_cast<std::size_t>(n_polys));
  for (vtkIdType c = 0; c < n_polys; ++c) {
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    polys->GetCellAtId(c, size, ids);
    out.polygons.emplace_back(ids, ids + size);
  }
  for (vtkIdType c = 0; c < n_strips; ++c) {
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    strips->GetCellAtId(c, size, ids);
    for (vtkIdType k = 0; k + 2 < size; ++k) {
      if (k % 2 == 0) {
        out.polygons.push_back({ids[k], ids[k + 1], ids[k + 2]});
      } else {
        out.polygons.push_back({ids[k + 1], ids[k], ids[k + 2]});
      }
    }
  }
  return true;
}

// Reads the polydata (XML or legacy) with VTK's messages captured; on failure the message (and
// the file's line when VTK gave one, in `error`).
base::Result<vtkSmartPointer<vtkPolyData>> read_polydata(const std::string& path, bool xml, CapturedMessages& messages,
                                                          ImportError& error) {
  const auto failed = [&](const char* fallback) {
    messages.last_error(error);
    return base::Error{error.message.empty() ? std::string(fallback) : error.message};
  };
  if (xml) {
    vtkNew<vtkXMLPolyDataReader> reader;
    if (!reader->CanReadFile(path.c_str())) return failed("not a VTK XML PolyData file (.vtp)");
    reader->SetFileName(path.c_str());
    reader->Update();
    if (reader->GetErrorCode() != 0 || messages.any()) return failed("cannot read the XML PolyData");
    return vtkSmartPointer<vtkPolyData>(reader->GetOutput());
  }
  vtkNew<vtkPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  if (!reader->IsFilePolyData()) return failed("not a legacy VTK POLYDATA file");
  reader->ReadAllScalarsOn();
  reader->ReadAllVectorsOn();
  reader->ReadAllFieldsOn();
  reader->Update();
  if (reader->GetErrorCode() != 0 || messages.any()) return failed("cannot read the POLYDATA");
  return vtkSmartPointer<vtkPolyData>(reader->GetOutput());
}

// The radius array: the one named, or the first of the default names; its name into `out`.
base::Result<vtkDataArray*> find_radius_array(vtkPointData* point_data, const std::string& radius_array, PolylineArrays& out) {
  vtkDataArray* radius = nullptr;
  if (!radius_array.empty()) {
    radius = point_data->GetArray(radius_array.c_str());
    if (!radius) return base::Error{"no point array '" + radius_array + "' (point arrays: " + array_names(point_data) + ")"};
    out.radius_array = radius_array;
  } else {
    for (const std::string& name : default_radius_arrays()) {
      radius = point_data->GetArray(name.c_str());
      if (radius) {
        out.radius_array = name;
        break;
      }
    }
    if (!radius) {
      std::string tried;
      for (const std::string& name : default_radius_arrays()) tried += (tried.empty() ? "" : ", ") + name;
      return base::Error{"no radius array (tried " + tried + "; point arrays: " + array_names(point_data) +
                         "); name one with --radius-array"};
    }
  }
  if (radius->GetNumberOfComponents() != 1) {
    return base::Error{"point array '" + out.radius_array + "' has " + std::to_string(radius->GetNumberOfComponents()) +
                       " components, not 1"};
  }
  return radius;
}

// The points with their radii, the line cells and, when both are there, VMTK's CenterlineIds
// and TractIds per line.
void copy_centerlines(vtkPolyData& data, vtkCellArray& lines, vtkDataArray& radius, PolylineArrays& out) {
  const vtkIdType n_points = data.GetNumberOfPoints();
  out.points.reserve(static_cast<std::size_t>(n_points));
  out.radius.reserve(static_cast<std::size_t>(n_points));
  for (vtkIdType i = 0; i < n_points; ++i) {
    double p[3];
    data.GetPoint(i, p);
    out.points.emplace_back(p[0], p[1], p[2]);
    out.radius.push_back(i < radius.GetNumberOfTuples() ? radius.GetTuple1(i) : 0.0);
  }
  const vtkIdType n_lines = lines.GetNumberOfCells();
  for (vtkIdType c = 0; c < n_lines; ++c) {
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    lines.GetCellAtId(c, size, ids);
    out.lines.emplace_back(ids, ids + size);
  }
  // Cell data run over vertices, then lines, then polygons, then strips.
  vtkCellData* cell_data = data.GetCellData();
  vtkDataArray* centerline_ids = cell_data->GetArray("CenterlineIds");
  vtkDataArray* tract_ids = cell_data->GetArray("TractIds");
  const vtkIdType first_line = data.GetNumberOfVerts();
  if (centerline_ids && tract_ids && centerline_ids->GetNumberOfComponents() == 1 && tract_ids->GetNumberOfComponents() == 1 &&
      centerline_ids->GetNumberOfTuples() >= first_line + n_lines && tract_ids->GetNumberOfTuples() >= first_line + n_lines) {
    for (vtkIdType c = 0; c < n_lines; ++c) {
      out.centerline_ids.push_back(static_cast<std::int64_t>(centerline_ids->GetTuple1(first_line + c)));
      out.tract_ids.push_back(static_cast<std::int64_t>(tract_ids->GetTuple1(first_line + c)));
    }
  }
}

}  // namespace

VtkRead read_vtk_with_vtk(const std::string& path, const std::string& radius_array, bool xml) {
  VtkRead out;
  ImportError error{path, 0, 0, ""};
  const auto fail = [&](std::string message) {
    error.message = std::move(message);
    out.errors.push_back(error);
    return out;
  };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return fail("cannot open file");

  CapturedMessages messages;
  base::Result<vtkSmartPointer<vtkPolyData>> data = read_polydata(path, xml, messages, error);
  if (!data) return fail(data.error().message);
  if (!*data || (*data)->GetNumberOfPoints() == 0) return fail("no points");
  vtkCellArray* lines = (*data)->GetLines();
  if (!lines || lines->GetNumberOfCells() == 0) {
    if (copy_surface(**data, out.arrays)) return out;
    return fail("no line cells (centrelines are polylines) and no polygons (a surface)");
  }
  const base::Result<vtkDataArray*> radius = find_radius_array((*data)->GetPointData(), radius_array, out.arrays);
  if (!radius) return fail(radius.error().message);
  copy_centerlines(**data, *lines, **radius, out.arrays);
  return out;
}

}  // namespace cathbox::vessel_import

// The module's entry point (C linkage: looked up by name with dlsym).
extern "C" __attribute__((visibility("default"))) void cathbox_vessel_import_read_vtk(
    const std::string* path, const std::string* radius_array, bool xml, cathbox::vessel_import::VtkRead* out) {
  *out = cathbox::vessel_import::read_vtk_with_vtk(*path, *radius_array, xml);
}
