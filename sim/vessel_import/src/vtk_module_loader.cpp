// read_vtk_centerlines(): opens the VTK reader module (vtk_centerlines.cpp, linked with VTK) on
// first use and calls it. Looked for next to the program (../lib/ and the program's own folder,
// as the build tree lays them out), then on the loader's usual path.
#include <dlfcn.h>

#include <filesystem>
#include <mutex>

#include "vessel_import/vtk_centerlines.hpp"

namespace cathbox::vessel_import {
namespace {

constexpr const char* kModule = "libcathbox_vessel_import_vtk.so";
constexpr const char* kEntry = "cathbox_vessel_import_read_vtk";
using Entry = void (*)(const std::string*, const std::string*, bool, VtkRead*);

struct Module {
  Entry entry = nullptr;
  std::string error;
};

const Module& module() {
  static Module m;
  static std::once_flag once;
  std::call_once(once, [] {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    std::vector<std::string> candidates;
    if (!ec) {
      candidates.push_back((exe.parent_path().parent_path() / "lib" / kModule).string());
      candidates.push_back((exe.parent_path() / kModule).string());
    }
    candidates.emplace_back(kModule);
    std::string tried;
    for (const std::string& path : candidates) {
      void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        tried += (tried.empty() ? "" : "; ") + std::string(dlerror());
        continue;
      }
      m.entry = reinterpret_cast<Entry>(dlsym(handle, kEntry));
      if (m.entry) return;
      tried += (tried.empty() ? "" : "; ") + path + ": no " + kEntry;
    }
    m.error = "the VTK reader module is missing (" + tried + ")";
  });
  return m;
}

}  // namespace

VtkRead read_vtk_centerlines(const std::string& path, const std::string& radius_array, bool xml) {
  const Module& m = module();
  VtkRead out;
  if (!m.entry) {
    out.errors.push_back({path, 0, 0, m.error});
    return out;
  }
  m.entry(&path, &radius_array, xml, &out);
  return out;
}

}  // namespace cathbox::vessel_import
