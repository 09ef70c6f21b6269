# cmake/install.cmake — `cmake --install` and `cpack -G DEB`: the layout an installed fortu
# finds its parts in, relative to its own executable (cli/data_paths.hpp,
# runtime/plugin_loader.hpp), so any prefix and any copy of the tree works:
#   bin/fortu
#   LIBDIR/fortu/libfortu_image.so, libfortu_vdb.so, the plug-ins (lib/fortu, or
#     libfortu_hdf5.so, libfortu_mpi.so              lib/x86_64-linux-gnu/fortu for /usr)
#   share/fortu/stdlib, examples, bench/models        the data folders
#   share/man/man1/fortu.1.gz                         help2man on the built binary + every command's --help
#                                                    (gzip -9n, as Debian's policy has installed man pages)
#   share/bash-completion/completions/fortu, share/zsh/vendor-completions/_fortu
# The man page and completions are generated from the binary's own help (cli/shell/generate.py),
# which its option tables write, so they cannot drift from what it accepts.
install(TARGETS fortu RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS fortu_image LIBRARY DESTINATION ${FORTU_PLUGIN_INSTALL_DIR})
foreach(plugin fortu_vdb fortu_hdf5 fortu_mpi)
  if(TARGET ${plugin})
    install(TARGETS ${plugin} LIBRARY DESTINATION ${FORTU_PLUGIN_INSTALL_DIR})
  endif()
endforeach()

find_package(Python3 COMPONENTS Interpreter)
find_program(FORTU_HELP2MAN help2man)
set(FORTU_SHELL_DIR ${CMAKE_BINARY_DIR}/shell)
if(Python3_Interpreter_FOUND)
  add_custom_command(OUTPUT ${FORTU_SHELL_DIR}/fortu.bash ${FORTU_SHELL_DIR}/_fortu ${FORTU_SHELL_DIR}/commands.h2m
    COMMAND ${CMAKE_COMMAND} -E make_directory ${FORTU_SHELL_DIR}
    COMMAND Python3::Interpreter ${CMAKE_SOURCE_DIR}/cli/shell/generate.py $<TARGET_FILE:fortu> ${FORTU_SHELL_DIR}
    DEPENDS fortu ${CMAKE_SOURCE_DIR}/cli/shell/generate.py
    COMMENT "shell completion from fortu's --help" VERBATIM)
  set(FORTU_SHELL_FILES ${FORTU_SHELL_DIR}/fortu.bash ${FORTU_SHELL_DIR}/_fortu)
  install(FILES ${FORTU_SHELL_DIR}/fortu.bash DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
          RENAME fortu)
  install(FILES ${FORTU_SHELL_DIR}/_fortu DESTINATION ${CMAKE_INSTALL_DATADIR}/zsh/vendor-completions)
  if(FORTU_HELP2MAN)
    add_custom_command(OUTPUT ${FORTU_SHELL_DIR}/fortu.1
      COMMAND ${FORTU_HELP2MAN} --no-info --no-discard-stderr --section=1 --locale=C.UTF-8
              "--name=evaluate FORTU R-function models (RANOK scripts) on 2D/3D grids"
              --include=${FORTU_SHELL_DIR}/commands.h2m --output=${FORTU_SHELL_DIR}/fortu.1 $<TARGET_FILE:fortu>
      DEPENDS fortu ${FORTU_SHELL_DIR}/commands.h2m
      COMMENT "man page from fortu --help (help2man)" VERBATIM)
    find_program(FORTU_GZIP gzip REQUIRED)
    add_custom_command(OUTPUT ${FORTU_SHELL_DIR}/fortu.1.gz
      COMMAND ${FORTU_GZIP} -9nkf ${FORTU_SHELL_DIR}/fortu.1
      DEPENDS ${FORTU_SHELL_DIR}/fortu.1
      COMMENT "man page compressed (gzip -9n)" VERBATIM)
    list(APPEND FORTU_SHELL_FILES ${FORTU_SHELL_DIR}/fortu.1.gz)
    install(FILES ${FORTU_SHELL_DIR}/fortu.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
  else()
    message(STATUS "help2man not found: no man page (apt-get install help2man)")
  endif()
  add_custom_target(fortu_shell_files ALL DEPENDS ${FORTU_SHELL_FILES})
else()
  message(STATUS "python3 not found: no shell completion or man page")
endif()

# The Debian package: in a build folder configured with -DCMAKE_INSTALL_PREFIX=/usr (so that
# GNUInstallDirs and the Python module pick Debian's folders), `cpack -G DEB` gives
# fortu_VERSION_ARCH.deb, its dependencies computed by dpkg-shlibdeps from the binary and plug-ins.
set(CPACK_PACKAGE_NAME fortu)
set(CPACK_PACKAGE_VENDOR "fortu")
set(CPACK_PACKAGE_CONTACT "fortu maintainers <fortu@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "interpreter for FORTU R-function models (RANOK scripts)")
string(CONCAT CPACK_PACKAGE_DESCRIPTION
  "fortu parses FORTU scripts (the language of the RANOK R-function modelling systems),\n"
  "evaluates them on 2D/3D grids with the classic and functional-voxel engines, and writes\n"
  "pictures, M-images, values, contours, meshes and volumes.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The Python module (python3 -c 'import fortu') needs the interpreter and numpy, which no
# library dependency names.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3, python3-numpy")
if(NOT CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  message(STATUS "cpack -G DEB: configure a build folder with -DCMAKE_INSTALL_PREFIX=/usr for the package")
endif()
include(CPack)
