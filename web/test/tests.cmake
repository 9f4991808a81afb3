# The WebAssembly decoder and the viewer page, tested from the native build
# against the WebAssembly build in DTM_WEB_BUILD (scripts/test.sh makes both;
# scripts/build_web.sh the second). node runs the tests (node --test);
# Playwright drives Debian's chromium for the page.
find_program(NODE node REQUIRED)
set(web_dist ${DTM_WEB_BUILD}/dist)
set(web_streams ${CMAKE_BINARY_DIR}/web-streams)
set(web_artifacts ${CMAKE_BINARY_DIR}/web-artifacts)
set(web_environment
  DTM_WEB_DIST=${web_dist}
  DTM_LEVEL_SUMMARY=$<TARGET_FILE:level_summary>
  DTM_MESHDEC=$<TARGET_FILE:meshdec>
  DTM_MESHINFO=$<TARGET_FILE:meshinfo>
  DTM_WEB_STREAMS=${web_streams}
  DTM_SOURCE_DIR=${PROJECT_SOURCE_DIR}
  DTM_WEB_ARTIFACTS=${web_artifacts})

# The corpus streams every web test decodes (a fixture: made once per run).
add_test(NAME web_streams
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/test/make_streams.sh $<TARGET_FILE:meshenc> ${web_streams})
set_tests_properties(web_streams PROPERTIES FIXTURES_SETUP web_streams)

# Fails, naming the command to run, when the WebAssembly build is missing.
add_test(NAME web_build_present
         COMMAND ${CMAKE_COMMAND} -DDIST=${web_dist} -P ${CMAKE_CURRENT_SOURCE_DIR}/test/check_dist.cmake)
set_tests_properties(web_build_present PROPERTIES FIXTURES_SETUP web_dist)

foreach(test wasm_equivalence cells viewer gltf)
  add_test(NAME web_${test} COMMAND ${NODE} --test --test-reporter=spec ${CMAKE_CURRENT_SOURCE_DIR}/test/${test}.test.mjs)
  set_tests_properties(web_${test} PROPERTIES
    ENVIRONMENT "${web_environment}" FIXTURES_REQUIRED "web_streams;web_dist" TIMEOUT 900)
endforeach()
# The longest tests of the suite start first (ctest runs the costliest
# first), beside the others: Chromium's software rendering leaves a core's
# worth of room, and every wait in the page has a deadline of minutes.
set_tests_properties(web_viewer PROPERTIES COST 120)
set_tests_properties(web_gltf PROPERTIES COST 20)
