# Requires the case SOURCE to have failed to compile with EXPECT in the compiler's output, and with
# ONLY=1 as its only error: a policy that breaks the Matcher's contract must be told what is wrong
# in one readable message. Reads the output of compile_all.cmake (every case in one unit, compiled
# once) and keeps the errors that belong to SOURCE: those under an instantiation "required from
# here" in SOURCE (GCC: the context comes before the error), or followed by a note that SOURCE
# "requested" it (clang: after), or written at a line of SOURCE itself.
#   cmake -DSOURCE=bad.cpp -DOUTPUT=out.txt -DEXPECT="text" [-DONLY=1] -P check.cmake
if(NOT EXISTS "${OUTPUT}")
  message(FATAL_ERROR "${OUTPUT} is missing: the compile_fail_compile test (compile_all.cmake) did not run")
endif()
get_filename_component(case "${SOURCE}" NAME)
file(READ "${OUTPUT}" out)
# One list element per line (the messages hold semicolons, which CMake lists would split on).
string(REPLACE ";" "<semicolon>" text "${out}")
string(REPLACE "\n" ";" lines "${text}")
set(owner "")          # the case whose instantiation the compiler is in (GCC's context lines)
set(last_owner "")     # the case the last error was counted for
set(mine "")           # SOURCE's errors
set(last_error "")
foreach(line IN LISTS lines)
  if(line MATCHES "([A-Za-z0-9_]+\\.cpp):[0-9]+:[0-9]+: +required from here")
    set(owner "${CMAKE_MATCH_1}")
  elseif(line MATCHES "([A-Za-z0-9_]+\\.cpp):[0-9]+:[0-9]+: note: in instantiation of .* requested here")
    # clang names the case after the error: move the last error to that case.
    if(last_error AND NOT last_owner STREQUAL CMAKE_MATCH_1)
      if(last_owner STREQUAL case)
        list(REMOVE_AT mine -1)
      endif()
      set(last_owner "${CMAKE_MATCH_1}")
      if(last_owner STREQUAL case)
        list(APPEND mine "${last_error}")
      endif()
    endif()
  elseif(line MATCHES "error:")
    set(last_owner "${owner}")
    if(line MATCHES "^([^:]*/)?([A-Za-z0-9_]+\\.cpp):[0-9]+:[0-9]+: (fatal )?error:")
      set(last_owner "${CMAKE_MATCH_2}")
    endif()
    set(last_error "${line}")
    if(last_owner STREQUAL case)
      list(APPEND mine "${line}")
    endif()
  endif()
endforeach()
list(LENGTH mine count)
list(JOIN mine "\n" mine_text)
string(REPLACE "<semicolon>" ";" mine_text "${mine_text}")
if(count EQUAL 0)
  message(FATAL_ERROR "${case} compiled, but it must not (no error of its own in ${OUTPUT})")
endif()
string(FIND "${mine_text}" "${EXPECT}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${case}: the compiler did not say \"${EXPECT}\"; its errors:\n${mine_text}")
endif()
if(ONLY AND NOT count EQUAL 1)
  message(FATAL_ERROR "${case}: ${count} errors, only the policy's message expected:\n${mine_text}")
endif()
message(STATUS "${case}: ${count} error(s), the expected message among them")
