# Run at every build (core/CMakeLists.txt, target firmament_revision): writes OUT, a header defining
# FIRMAMENT_REVISION as the source's git commit ("abc1234", "abc1234-dirty" with uncommitted changes,
# "unknown" outside a git checkout).  The file is rewritten only when that changes, so an unchanged
# revision recompiles nothing.
execute_process(COMMAND git -C "${SOURCE_DIR}" rev-parse --short=7 HEAD
                OUTPUT_VARIABLE revision OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE failed ERROR_QUIET)
if(failed OR revision STREQUAL "")
  set(revision unknown)
else()
  execute_process(COMMAND git -C "${SOURCE_DIR}" status --porcelain --untracked-files=no
                  OUTPUT_VARIABLE changes OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT changes STREQUAL "")
    string(APPEND revision -dirty)
  endif()
endif()
file(WRITE "${OUT}.new" "#define FIRMAMENT_REVISION \"${revision}\"\n")
configure_file("${OUT}.new" "${OUT}" COPYONLY)
