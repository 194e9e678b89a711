# hos_library(name SOURCES ... DEPS ...): a static library of one subsystem.
function(hos_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  target_compile_options(${name} PRIVATE -Wall -Wextra -Wno-unused-parameter)
endfunction()

# hos_executable(name SOURCES ... DEPS ...): a thin main over a library call.
function(hos_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  target_compile_options(${name} PRIVATE -Wall -Wextra -Wno-unused-parameter)
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

# hos_test(name SOURCES ... DEPS ...): one gtest binary per module; every TEST
# becomes its own ctest entry so `ctest -R Suite.Case` works.
function(hos_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} hos_test_support GTest::gmock GTest::gtest_main)
  target_compile_options(${name} PRIVATE -Wall -Wextra -Wno-unused-parameter)
  include(GoogleTest)
  # gtest_discover_tests splits every ';' of PROPERTIES again (even escaped
  # ones), so ENVIRONMENT holds a single variable: HOS_BIN_DIR is not needed
  # because the tests run in the build folder and bin_dir() falls back to
  # ./bin. LABELS is only passed when given: an empty value would make the
  # next keyword its value.
  set(test_properties TIMEOUT ${ARG_TIMEOUT} ENVIRONMENT "HOS_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
  if(ARG_LABELS)
    list(APPEND test_properties LABELS "${ARG_LABELS}")
  endif()
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
    PROPERTIES ${test_properties}
    DISCOVERY_TIMEOUT 60)
endfunction()
