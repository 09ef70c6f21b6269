# tests/golden/golden.cmake — fortu's own golden suites, run by `fortu golden` under CTest:
# hand-checked models, the examples and every RANOK script (see the README, "Golden tests").
# Included by tests/CMakeLists.txt when the fortu binary is built.
foreach(suite models examples ranok)
  add_test(NAME golden_${suite}
           COMMAND fortu golden ${CMAKE_CURRENT_LIST_DIR}/${suite} --jobs 2)
  set_tests_properties(golden_${suite} PROPERTIES  # exit status 0 iff every test passes
    ENVIRONMENT "FORTU_SHARED_DIR=${FORTU_SHARED_DIR}"
    TIMEOUT 120)
endforeach()
