# Shared helpers for the project's own targets. Flags are set per target, never globally.

# Adds <dir> when it holds a CMakeLists.txt (modules appear as issues land).
function(cathbox_add_module dir)
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${dir}/CMakeLists.txt)
    add_subdirectory(${dir})
  endif()
endfunction()

# Adds every immediate subfolder of the current folder that holds a CMakeLists.txt.
function(cathbox_add_subdirs)
  file(GLOB children LIST_DIRECTORIES true RELATIVE ${CMAKE_CURRENT_SOURCE_DIR}
       ${CMAKE_CURRENT_SOURCE_DIR}/*)
  list(SORT children)
  foreach(child IN LISTS children)
    if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/${child}
       AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${child}/CMakeLists.txt)
      add_subdirectory(${child})
    endif()
  endforeach()
endfunction()

# Warnings for a project target: -Wall -Wextra -Wpedantic (+ -Werror unless disabled).
# Third-party headers come in through imported targets, which CMake marks SYSTEM.
function(cathbox_target_warnings target)
  set(flags -Wall -Wextra -Wpedantic -Wshadow -Wformat=2 -Wundef)
  if(CATHBOX_WERROR)
    list(APPEND flags -Werror)
  endif()
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:C>:${flags} -Wstrict-prototypes -Wmissing-prototypes>
    $<$<COMPILE_LANGUAGE:CXX>:${flags} -Wnon-virtual-dtor>)
endfunction()

# cathbox_add_library(NAME <module> [STATIC] SOURCES ... [PUBLIC_LIBS ...] [PRIVATE_LIBS ...])
# Target cathbox_<module>, alias cathbox::<module>, public headers in ./include.
function(cathbox_add_library)
  cmake_parse_arguments(A "" "NAME" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  set(target cathbox_${A_NAME})
  add_library(${target} STATIC ${A_SOURCES})
  add_library(cathbox::${A_NAME} ALIAS ${target})
  target_include_directories(${target} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(${target} PUBLIC ${A_PUBLIC_LIBS} PRIVATE ${A_PRIVATE_LIBS})
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  cathbox_target_warnings(${target})
endfunction()
