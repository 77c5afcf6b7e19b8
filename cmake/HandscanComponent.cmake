# Helpers that keep each component's CMakeLists.txt short and uniform.

# Adds every immediate sub-folder of the given folders that has a CMakeLists.txt (one level deep
# and, for folders that group components such as drivers/, two levels deep).
function(handscan_add_component_dirs)
  foreach(top IN LISTS ARGN)
    # A top folder that is one component itself (ui/) owns its CMakeLists.txt.
    if(EXISTS ${CMAKE_SOURCE_DIR}/${top}/CMakeLists.txt)
      add_subdirectory(${CMAKE_SOURCE_DIR}/${top} ${CMAKE_BINARY_DIR}/${top})
      continue()
    endif()
    file(GLOB children LIST_DIRECTORIES true RELATIVE ${CMAKE_SOURCE_DIR}
         ${CMAKE_SOURCE_DIR}/${top}/*)
    list(SORT children)
    foreach(child IN LISTS children)
      if(child STREQUAL "firmware/core" OR child STREQUAL "firmware/cli")
        continue()
      endif()
      if(IS_DIRECTORY ${CMAKE_SOURCE_DIR}/${child} AND EXISTS ${CMAKE_SOURCE_DIR}/${child}/CMakeLists.txt)
        add_subdirectory(${CMAKE_SOURCE_DIR}/${child} ${CMAKE_BINARY_DIR}/${child})
      endif()
    endforeach()
  endforeach()
endfunction()

# handscan_library(<name> [SOURCES ...] [PUBLIC_LIBS ...] [PRIVATE_LIBS ...] [INTERFACE])
# Public headers live in include/handscan/<name>/, sources in src/. Creates handscan_<name> and
# the ALIAS handscan::<name>.
function(handscan_library name)
  cmake_parse_arguments(ARG "INTERFACE" "" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  set(target handscan_${name})
  if(ARG_INTERFACE)
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_link_libraries(${target} INTERFACE ${ARG_PUBLIC_LIBS})
  else()
    add_library(${target} STATIC ${ARG_SOURCES})
    target_include_directories(${target} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
                                         PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
    handscan_set_warnings(${target})
  endif()
  add_library(handscan::${name} ALIAS ${target})
endfunction()

# handscan_test(<name> SOURCES ... LIBS ... [LABELS ...] [TIMEOUT s] [RUN_SERIAL])
# A GoogleTest executable registered with CTest test-by-test. RUN_SERIAL: its tests run alone
# (real-time processes against fake devices, which two at a time on two cores under ASan starve).
function(handscan_test name)
  cmake_parse_arguments(ARG "RUN_SERIAL" "TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gmock GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
      HANDSCAN_SHARED_DATA_DIR="${HANDSCAN_SHARED_DATA_DIR}"
      HANDSCAN_TEST_DATA_DIR="${HANDSCAN_TEST_DATA_DIR}"
      HANDSCAN_BINARY_DIR="${CMAKE_BINARY_DIR}"
      HANDSCAN_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  handscan_set_warnings(${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 120)
  endif()
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  set(serial FALSE)
  if(ARG_RUN_SERIAL)
    set(serial TRUE)
  endif()
  gtest_discover_tests(${name} DISCOVERY_MODE PRE_TEST
                       PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "${ARG_LABELS}" RUN_SERIAL ${serial})
endfunction()

# handscan_benchmark(<name> SOURCES ... LIBS ...): a Google Benchmark executable (not a test).
function(handscan_benchmark name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  if(NOT HANDSCAN_BUILD_BENCHMARKS)
    return()
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} benchmark::benchmark benchmark::benchmark_main)
  target_compile_definitions(${name} PRIVATE
      HANDSCAN_SHARED_DATA_DIR="${HANDSCAN_SHARED_DATA_DIR}"
      HANDSCAN_TEST_DATA_DIR="${HANDSCAN_TEST_DATA_DIR}")
  handscan_set_warnings(${name})
endfunction()

# handscan_fuzz_target(fuzz_<name> SOURCES ... LIBS ...): a libFuzzer executable, built only with
# HANDSCAN_FUZZ=ON (clang). tools/fuzz finds it through build/asan/fuzz_targets/<name>.path and
# seeds it from tests/data/fuzz/<name>/.
function(handscan_fuzz_target name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  if(NOT HANDSCAN_FUZZ)
    return()
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS})
  target_link_options(${name} PRIVATE -fsanitize=fuzzer)
  handscan_set_warnings(${name})
  file(GENERATE OUTPUT ${CMAKE_BINARY_DIR}/fuzz_targets/${name}.path CONTENT "$<TARGET_FILE:${name}>\n")
endfunction()
