# The WebAssembly build (preset `wasm`, Debian's emscripten): protocol/, sim/ but the importer,
# host/device's protocol half, host/session and host/wasm. Emscripten's compiler must not see
# /usr/include (glibc's headers), so the header-only libraries the modules use are staged here
# one folder each, and zstd and zlib are compiled from Debian's own source packages (the
# versions of the native libraries: a record compresses to the same bytes), as is Google
# Benchmark for bench/wasm. Each is given the
# target name the modules link (glm::glm, Eigen3::Eigen, PkgConfig::XXHASH, PkgConfig::ZSTD,
# ZLIB::ZLIB) before the modules' find calls, which then keep them.
set(CATHBOX_WASM_SOURCES "${CMAKE_BINARY_DIR}/debian-sources" CACHE PATH
    "zstd, zlib and Google Benchmark sources for the WebAssembly build (scripts/wasm-sources fills it)")
if(NOT EXISTS "${CATHBOX_WASM_SOURCES}/zstd/lib/zstd.h" OR NOT EXISTS "${CATHBOX_WASM_SOURCES}/zlib/crc32.c"
   OR NOT EXISTS "${CATHBOX_WASM_SOURCES}/benchmark/src/benchmark.cc")
  execute_process(COMMAND ${CMAKE_SOURCE_DIR}/scripts/wasm-sources ${CATHBOX_WASM_SOURCES} RESULT_VARIABLE fetched)
  if(NOT fetched EQUAL 0)
    message(FATAL_ERROR "scripts/wasm-sources ${CATHBOX_WASM_SOURCES} failed: zstd, zlib and benchmark sources are needed")
  endif()
endif()

# Every object of the build, third-party ones too, with the same threads model: the recorder's
# writer is a thread (a Web Worker in the browser, a worker thread in node).
add_compile_options(-pthread)
add_link_options(-pthread)

set(stage "${CMAKE_BINARY_DIR}/wasm-include")
file(MAKE_DIRECTORY ${stage}/glm ${stage}/eigen ${stage}/xxhash)
file(CREATE_LINK /usr/include/glm ${stage}/glm/glm SYMBOLIC)
file(CREATE_LINK /usr/include/eigen3/Eigen ${stage}/eigen/Eigen SYMBOLIC)
file(CREATE_LINK /usr/include/xxhash.h ${stage}/xxhash/xxhash.h SYMBOLIC)

add_library(glm::glm INTERFACE IMPORTED GLOBAL)
target_include_directories(glm::glm SYSTEM INTERFACE ${stage}/glm)
add_library(Eigen3::Eigen INTERFACE IMPORTED GLOBAL)
target_include_directories(Eigen3::Eigen SYSTEM INTERFACE ${stage}/eigen)
# xxhash.h carries its implementation: inlined, nothing to link.
add_library(PkgConfig::XXHASH INTERFACE IMPORTED GLOBAL)
target_include_directories(PkgConfig::XXHASH SYSTEM INTERFACE ${stage}/xxhash)
target_compile_definitions(PkgConfig::XXHASH INTERFACE XXH_INLINE_ALL)

set(zstd ${CATHBOX_WASM_SOURCES}/zstd/lib)
file(GLOB zstd_sources ${zstd}/common/*.c ${zstd}/compress/*.c ${zstd}/decompress/*.c)
add_library(cathbox_wasm_zstd STATIC ${zstd_sources})
target_include_directories(cathbox_wasm_zstd SYSTEM PUBLIC ${zstd})
target_compile_definitions(cathbox_wasm_zstd PRIVATE ZSTD_DISABLE_ASM XXH_NAMESPACE=ZSTD_ ZSTD_MULTITHREAD=0)
target_compile_options(cathbox_wasm_zstd PRIVATE -O3)
add_library(PkgConfig::ZSTD ALIAS cathbox_wasm_zstd)

set(zlib ${CATHBOX_WASM_SOURCES}/zlib)
add_library(cathbox_wasm_zlib STATIC
  ${zlib}/adler32.c ${zlib}/compress.c ${zlib}/crc32.c ${zlib}/deflate.c ${zlib}/infback.c ${zlib}/inffast.c
  ${zlib}/inflate.c ${zlib}/inftrees.c ${zlib}/trees.c ${zlib}/uncompr.c ${zlib}/zutil.c)
target_include_directories(cathbox_wasm_zlib SYSTEM PUBLIC ${zlib})
target_compile_options(cathbox_wasm_zlib PRIVATE -O3)
add_library(ZLIB::ZLIB ALIAS cathbox_wasm_zlib)
set(ZLIB_INCLUDE_DIR ${zlib} CACHE PATH "" FORCE)
set(ZLIB_LIBRARY cathbox_wasm_zlib CACHE STRING "" FORCE)

# Google Benchmark for bench/wasm (the same bench source as the native bench_wasm).
set(gbench ${CATHBOX_WASM_SOURCES}/benchmark)
file(GLOB gbench_sources ${gbench}/src/*.cc)
list(FILTER gbench_sources EXCLUDE REGEX "benchmark_main\\.cc$")
add_library(cathbox_wasm_benchmark STATIC ${gbench_sources})
target_include_directories(cathbox_wasm_benchmark SYSTEM PUBLIC ${gbench}/include)
target_compile_definitions(cathbox_wasm_benchmark PUBLIC BENCHMARK_STATIC_DEFINE PRIVATE HAVE_STD_REGEX HAVE_STEADY_CLOCK)

# find_package(glm) and find_package(Eigen3) find the staged targets above (cmake/wasm/).
set(glm_DIR ${CMAKE_SOURCE_DIR}/cmake/wasm CACHE PATH "" FORCE)
set(Eigen3_DIR ${CMAKE_SOURCE_DIR}/cmake/wasm CACHE PATH "" FORCE)
