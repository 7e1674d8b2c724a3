# The build identifier every firmware image (and the emulator's factory image) carries in its
# image info block and reports in its device info: the short commit of the tree, with "+" when
# it has uncommitted changes, or "nogit" outside a git checkout. Regenerated at every build
# (not only at configure time), so an image never carries a stale identifier.
#   target_link_libraries(x PRIVATE cathbox_build_id)  ->  #include "cbx_build_id.h": CBX_BUILD_ID
set(_cbx_build_id_dir ${CMAKE_BINARY_DIR}/generated/build_id)
add_custom_target(cathbox_build_id_header
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DOUT=${_cbx_build_id_dir}/cbx_build_id.h
          -P ${CMAKE_CURRENT_LIST_DIR}/GenBuildId.cmake
  BYPRODUCTS ${_cbx_build_id_dir}/cbx_build_id.h
  COMMENT "Build identifier"
  VERBATIM)
add_library(cathbox_build_id INTERFACE)
target_include_directories(cathbox_build_id INTERFACE ${_cbx_build_id_dir})
add_dependencies(cathbox_build_id cathbox_build_id_header)
