# Compiles SOURCE (syntax only) and requires it to fail with EXPECT in the compiler's output;
# with ONLY=1, as the only error. Run by ctest (tests/CMakeLists.txt): a policy that breaks the
# Matcher's contract must be told what is wrong in one readable message.
#   cmake -DCOMPILER=c++ -DSOURCE=bad.cpp -DINCLUDES="a|b" -DEXPECT="text" [-DONLY=1] -P check.cmake
string(REPLACE "|" ";" include_dirs "${INCLUDES}")
set(flags -std=c++17 -fsyntax-only)
foreach(dir IN LISTS include_dirs)
  if(dir)  # an empty entry (a target without include directories) must not swallow the source
    list(APPEND flags "-I${dir}")
  endif()
endforeach()
execute_process(COMMAND "${COMPILER}" ${flags} "${SOURCE}" RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(status EQUAL 0)
  message(FATAL_ERROR "${SOURCE} compiled, but it must not")
endif()
string(FIND "${out}" "${EXPECT}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${SOURCE}: the compiler did not say \"${EXPECT}\":\n${out}")
endif()
string(REGEX MATCHALL "error:" errors "${out}")
list(LENGTH errors count)
if(ONLY AND NOT count EQUAL 1)
  message(FATAL_ERROR "${SOURCE}: ${count} errors, only the policy's message expected:\n${out}")
endif()
message(STATUS "${SOURCE}: ${count} error(s), the expected message among them")
