# cathbox_find_pybind11(): Python's development files and pybind11 for the Python modules
# (host/python's _cathbox, host/app's _fluoro). Debian's python3 (/usr/bin/python3) is the one with
# numpy and pybind11 unless -DPython_EXECUTABLE= says otherwise. Sets Python_FOUND, pybind11_FOUND.
macro(cathbox_find_pybind11)
  if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the module is built for")
  endif()
  find_package(Python 3.9 COMPONENTS Interpreter Development.Module)
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 2.10 CONFIG QUIET)
endmacro()
