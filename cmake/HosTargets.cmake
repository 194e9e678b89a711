# hos_warnings(target): the warning flags of every hos target; with
# HOS_WERROR (CI) a warning fails the build.
function(hos_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-unused-parameter)
  if(HOS_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# hos_light_code(target): code that does little work of its own (tests, the
# programs' command lines, the bench drivers) compiles with -O1 instead of
# the build type's -O3. The work runs in the libraries, still at -O3; for
# this code -O1 takes about 40% less compile time than -O3, and the tests'
# run time stays the same (docs/developing.md).
function(hos_light_code target)
  if(CMAKE_BUILD_TYPE STREQUAL "Release")
    target_compile_options(${target} PRIVATE -O1)
  endif()
endfunction()

# hos_library(name SOURCES ... DEPS ...): a static library of one subsystem.
function(hos_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  hos_warnings(${name})
endfunction()

# hos_executable(name SOURCES ... DEPS ...): a thin main over a library call.
function(hos_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  hos_warnings(${name})
  hos_light_code(${name})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bin)
endfunction()

# hos_optional_executable(name source deps...): hos_executable when every
# target of deps exists, so a partial module selection still configures.
function(hos_optional_executable name source)
  foreach(dep IN LISTS ARGN)
    if(NOT TARGET ${dep})
      return()
    endif()
  endforeach()
  hos_executable(${name} SOURCES ${source} DEPS ${ARGN})
endfunction()

# hos_test(name SOURCES ... DEPS ... [LABELS ...] [SLOW_TESTS Suite.Case ...]
#          [ONE_PROCESS Suite.Case ...] [TIMEOUT s]): one gtest binary per
# module; every TEST becomes its own ctest entry so `ctest -R Suite.Case`
# works. LABELS label every test of the binary; SLOW_TESTS (gtest filter
# patterns) label those tests `slow`, so `ctest -LE slow` runs the fast ones.
# ONE_PROCESS (test names) run as one ctest entry, labelled `slow` and named
# by all of them joined with '+' (so `ctest -R Suite.Case` still finds each):
# tests that share one expensive result (a function-local static) compute it
# once instead of once per process.
function(hos_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS;SLOW_TESTS;ONE_PROCESS" ${ARGN})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} hos_test_support GTest::gmock GTest::gtest_main)
  hos_warnings(${name})
  hos_light_code(${name})
  include(GoogleTest)
  # gtest_discover_tests splits every ';' of PROPERTIES again (even escaped
  # ones), so ENVIRONMENT holds a single variable: HOS_BIN_DIR is not needed
  # because the tests run in the build folder and bin_dir() falls back to
  # ./bin. LABELS is only passed when given: an empty value would make the
  # next keyword its value.
  set(test_properties TIMEOUT ${ARG_TIMEOUT} ENVIRONMENT "HOS_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
  set(fast_properties ${test_properties})
  if(ARG_LABELS)
    list(APPEND fast_properties LABELS "${ARG_LABELS}")
  endif()
  # The ONE_PROCESS tests: one entry, left out of the per-test discovery.
  set(fast_filter "")
  if(ARG_ONE_PROCESS)
    list(JOIN ARG_ONE_PROCESS ":" one_process_filter)
    list(JOIN ARG_ONE_PROCESS "+" one_process_name)
    add_test(NAME ${one_process_name} COMMAND ${name} --gtest_filter=${one_process_filter}
             WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
    set_tests_properties(${one_process_name} PROPERTIES ${test_properties} LABELS slow)
    set(fast_filter "-${one_process_filter}")
  endif()
  if(NOT ARG_SLOW_TESTS)
    gtest_discover_tests(${name}
      WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
      TEST_FILTER "${fast_filter}"
      PROPERTIES ${fast_properties}
      DISCOVERY_TIMEOUT 60)
    return()
  endif()
  # Discovered twice: the slow tests with the label, the others without.
  list(JOIN ARG_SLOW_TESTS ":" slow_filter)
  if(ARG_ONE_PROCESS)
    set(fast_filter "-${slow_filter}:${one_process_filter}")
    set(slow_filter "${slow_filter}-${one_process_filter}")
  else()
    set(fast_filter "-${slow_filter}")
  endif()
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
    TEST_FILTER "${fast_filter}"
    PROPERTIES ${fast_properties}
    DISCOVERY_TIMEOUT 60)
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
    TEST_FILTER "${slow_filter}"
    PROPERTIES ${test_properties} LABELS slow
    DISCOVERY_TIMEOUT 60)
endfunction()
