# The WebAssembly build's Eigen (cmake/CathboxWasm.cmake defines Eigen3::Eigen).
if(NOT TARGET Eigen3::Eigen)
  message(FATAL_ERROR "Eigen3::Eigen comes from cmake/CathboxWasm.cmake")
endif()
