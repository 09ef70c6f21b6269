# tests/repl/repl.cmake — the interactive `fortu repl` test: a real pseudo-terminal under tmux
# (half-block picture, a syntax error, Ctrl-C, Ctrl-D, history). Included by tests/CMakeLists.txt;
# fails, rather than passes, when tmux is missing.
add_test(NAME repl_tmux COMMAND ${CMAKE_CURRENT_LIST_DIR}/repl_tmux_test.sh $<TARGET_FILE:fortu>)
set_tests_properties(repl_tmux PROPERTIES TIMEOUT 180)
