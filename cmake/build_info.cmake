# Run at every build (cmake -P): the commit the sources are at and whether tracked files differ
# from it, into OUT. The file is rewritten only when they change, so only then is rtm relinked.
# Sources outside a git checkout of their own (a tarball) say "unknown".
# Inputs: SOURCE_DIR, VERSION, TEMPLATE, OUT.
set(commit "unknown")
set(modified "std::nullopt")
execute_process(COMMAND git -C "${SOURCE_DIR}" rev-parse --show-toplevel HEAD
                OUTPUT_VARIABLE lines RESULT_VARIABLE failed ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT failed)
  string(REPLACE "\n" ";" lines "${lines}")
  list(GET lines 0 top)
  list(GET lines 1 head)
  # A tarball unpacked inside some other repository is not that repository's commit.
  file(REAL_PATH "${top}" top)
  file(REAL_PATH "${SOURCE_DIR}" source)
  if(top STREQUAL source)
    set(commit "${head}")
    execute_process(COMMAND git -C "${SOURCE_DIR}" status --porcelain --untracked-files=no
                    OUTPUT_VARIABLE changes RESULT_VARIABLE failed ERROR_QUIET)
    if(NOT failed)
      if(changes STREQUAL "")
        set(modified "false")
      else()
        set(modified "true")
      endif()
    endif()
  endif()
endif()
configure_file("${TEMPLATE}" "${OUT}" @ONLY)
