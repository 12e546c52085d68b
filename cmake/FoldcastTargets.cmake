# Compile options shared by every foldcast target: warnings (our code only: third-party
# headers come in through imported targets and are treated as system headers) and the
# optional sanitizers.
add_library(foldcast_options INTERFACE)
target_compile_options(foldcast_options INTERFACE -Wall -Wextra -Wpedantic)
if(FOLDCAST_WERROR)
  target_compile_options(foldcast_options INTERFACE -Werror)
endif()
if(FOLDCAST_FUZZ)
  # Instrument every library for libFuzzer's coverage; fuzz targets add -fsanitize=fuzzer.
  target_compile_options(foldcast_options INTERFACE
    -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(foldcast_options INTERFACE -fsanitize=address,undefined)
endif()
if(FOLDCAST_SANITIZE)
  target_compile_options(foldcast_options INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(foldcast_options INTERFACE -fsanitize=address,undefined)
endif()

# The test programs' own code (fixtures, assertions, reference sums) is compiled with this
# optimisation, after the build type's flags; the code under test is in the libraries, built as
# configured.  -O1 compiles a test a third faster than Release's -O3 for no measurable change
# in the suite's time.  Not -O0: the tests inline Eigen and OpenCV, and ran minutes longer.
set(FOLDCAST_TEST_OPTIMIZATION "-O1" CACHE STRING "Optimisation flag for the test programs' own code")

# foldcast_module(NAME SOURCES... [DEPS ...]): a library foldcast_NAME with its public
# headers in NAME/include.
function(foldcast_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(foldcast_${name} STATIC ${ARG_SOURCES})
  add_library(foldcast::${name} ALIAS foldcast_${name})
  target_include_directories(foldcast_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
                                              PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(foldcast_${name} PUBLIC ${ARG_PUBLIC_DEPS}
                                         PRIVATE foldcast_options ${ARG_PRIVATE_DEPS})
endfunction()

# foldcast_test(NAME SOURCES... LIBS... [LABELS ...] [SLOW_TESTS ...] [ENVIRONMENT ...]): a GoogleTest
# executable whose tests are registered one by one with CTest.  Tests run from the source tree's
# tests/ folder so they can find tests/data; FOLDCAST_SHARED_DATA points at ../shared/data when
# present.  SLOW_TESTS names tests (Suite.Name) labelled `slow` instead of LABELS: measurements
# that run code the executable's other tests already run, at a larger size or with more samples,
# which CI's sanitizer stage leaves out.
function(foldcast_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS;LABELS;SLOW_TESTS;ENVIRONMENT" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_compile_options(${name} PRIVATE ${FOLDCAST_TEST_OPTIMIZATION})
  target_link_libraries(${name} PRIVATE foldcast_options ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)
  target_compile_definitions(${name} PRIVATE
    FOLDCAST_TEST_DATA="${PROJECT_SOURCE_DIR}/tests/data"
    FOLDCAST_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    FOLDCAST_BINARY_DIR="${PROJECT_BINARY_DIR}")
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  gtest_discover_tests(${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}/tests
                       TEST_LIST ${name}_TESTS DISCOVERY_TIMEOUT 60)
  # Labels and environment are set by a script of our own that CTest reads after the
  # discovered tests: gtest_discover_tests' PROPERTIES flattens list values, so a second
  # label (`hostile slow`) became a stray property name and was lost.
  set(properties_script ${CMAKE_CURRENT_BINARY_DIR}/${name}_properties.cmake)
  set(environment "")
  if(ARG_ENVIRONMENT)
    set(environment " ENVIRONMENT [==[${ARG_ENVIRONMENT}]==]")
  endif()
  # A name in SLOW_TESTS that the executable does not hold (renamed, removed) stops CTest, so
  # that a test does not silently go back to the sanitizer stage.
  set(slow_tests "")
  foreach(test IN LISTS ARG_SLOW_TESTS)
    string(APPEND slow_tests
           "  list(FIND ${name}_TESTS [==[${test}]==] found)\n"
           "  if(found LESS 0)\n    message(FATAL_ERROR [==[${name} has no test ${test} (SLOW_TESTS)]==])\n  endif()\n"
           "  set_tests_properties([==[${test}]==] PROPERTIES LABELS slow)\n")
  endforeach()
  file(GENERATE OUTPUT ${properties_script} CONTENT
       "if(${name}_TESTS)\n  set_tests_properties(\${${name}_TESTS} PROPERTIES LABELS [==[${ARG_LABELS}]==]${environment})\n${slow_tests}endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${properties_script})
endfunction()
