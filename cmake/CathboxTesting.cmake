# Test helpers. Every GoogleTest case becomes its own CTest entry (gtest_discover_tests).
find_package(GTest REQUIRED)
include(GoogleTest)

# cathbox_add_test(NAME n SOURCES ... [LIBS ...] [LABELS unit|integration|slow ...] [TIMEOUT s])
function(cathbox_add_test)
  cmake_parse_arguments(A "" "NAME;TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT CATHBOX_BUILD_TESTS)
    return()
  endif()
  if(NOT A_LABELS)
    set(A_LABELS unit)
  endif()
  if(NOT A_TIMEOUT)
    set(A_TIMEOUT 300)
  endif()
  add_executable(${A_NAME} ${A_SOURCES})
  target_link_libraries(${A_NAME} PRIVATE ${A_LIBS} GTest::gtest GTest::gmock GTest::gtest_main)
  target_compile_definitions(${A_NAME} PRIVATE
    CATHBOX_SOURCE_DIR="${PROJECT_SOURCE_DIR}" CATHBOX_BINARY_DIR="${PROJECT_BINARY_DIR}")
  cathbox_target_warnings(${A_NAME})
  gtest_discover_tests(${A_NAME}
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
    PROPERTIES TIMEOUT ${A_TIMEOUT}
    DISCOVERY_TIMEOUT 60)
  # The labels are set after discovery, from the list of discovered tests: a list given through
  # gtest_discover_tests' PROPERTIES is flattened into name/value pairs ("slow;long" gave LABELS
  # slow and a property named "long"), so every label but the first was lost.
  set(labels_file ${CMAKE_CURRENT_BINARY_DIR}/${A_NAME}_labels.cmake)
  file(WRITE ${labels_file}
    "if(${A_NAME}_TESTS)\n  set_tests_properties(\${${A_NAME}_TESTS} PROPERTIES LABELS \"${A_LABELS}\")\nendif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${labels_file})
endfunction()

# cathbox_add_fuzzer(NAME n SOURCES ... [LIBS ...] [CORPUS dir ...])
# The sources define LLVMFuzzerTestOneInput. With CATHBOX_FUZZ (clang, the asan preset) this is
# a libFuzzer binary (the rest of that tree is compiled -fsanitize=fuzzer-no-link; only these
# link libFuzzer's main); otherwise it is linked with a replay driver. Either way a CTest entry
# replays every file of the seed corpora (libFuzzer's -runs=0 runs the given corpora once), so
# each fuzz target is compiled and exercised on every build.
function(cathbox_add_fuzzer)
  cmake_parse_arguments(A "" "NAME" "SOURCES;LIBS;CORPUS" ${ARGN})
  set(target fuzz_${A_NAME})
  add_executable(${target} ${A_SOURCES})
  target_link_libraries(${target} PRIVATE ${A_LIBS})
  cathbox_target_warnings(${target})
  if(CATHBOX_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer)
    target_link_options(${target} PRIVATE -fsanitize=fuzzer)
    add_test(NAME fuzz_replay.${A_NAME} COMMAND ${target} -runs=0 ${A_CORPUS})
  else()
    # The replay driver, compiled once for every fuzz target.
    if(NOT TARGET cathbox_fuzz_replay_main)
      add_library(cathbox_fuzz_replay_main OBJECT ${PROJECT_SOURCE_DIR}/tests/fuzz/replay_main.cpp)
      cathbox_target_warnings(cathbox_fuzz_replay_main)
    endif()
    target_link_libraries(${target} PRIVATE cathbox_fuzz_replay_main)
    add_test(NAME fuzz_replay.${A_NAME} COMMAND ${target} ${A_CORPUS})
  endif()
  set_tests_properties(fuzz_replay.${A_NAME} PROPERTIES LABELS unit TIMEOUT 120)
  string(REPLACE ";" "," corpus_list "${A_CORPUS}")
  set_property(GLOBAL APPEND PROPERTY CATHBOX_FUZZERS "${target}|${corpus_list}")
endfunction()
