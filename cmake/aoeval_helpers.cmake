# aoeval_test(NAME SOURCES... LIBS ...): a GoogleTest binary registered with ctest, test by test.
include(GoogleTest)
function(aoeval_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
    AOEVAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    AOEVAL_BINARY="$<TARGET_FILE_DIR:aoeval>/aoeval")
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
endfunction()
