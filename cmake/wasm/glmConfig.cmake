# The WebAssembly build's glm (cmake/CathboxWasm.cmake defines glm::glm).
if(NOT TARGET glm::glm)
  message(FATAL_ERROR "glm::glm comes from cmake/CathboxWasm.cmake")
endif()
