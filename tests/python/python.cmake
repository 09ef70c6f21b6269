# tests/python/python.cmake — the Python module's pytest suite under CTest, with the Python
# the module was built for and the package from the build tree (cli/python/). Included by
# tests/CMakeLists.txt when the module is built.
add_test(NAME python_module
         COMMAND ${Python_EXECUTABLE} -m pytest -q -p no:cacheprovider ${CMAKE_CURRENT_LIST_DIR})
set_tests_properties(python_module PROPERTIES
  ENVIRONMENT "PYTHONPATH=${FORTU_PYTHON_DIR};FORTU_BINARY=${CMAKE_BINARY_DIR}/fortu;FORTU_SHARED_DIR=${FORTU_SHARED_DIR};FORTU_SOURCE_DIR=${PROJECT_SOURCE_DIR}"
  TIMEOUT 300)
