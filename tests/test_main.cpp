#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "test_support.hpp"

// A test executable whose cases all need ../shared reports "skipped" to ctest (exit 77) when
// the folder is missing, instead of passing silently.
int main(int argc, char** argv) {
  doctest::Context context(argc, argv);
  const int result = context.run();
  if (context.shouldExit()) return result;
  if (result == 0 && areamatch_test::skipped_for_missing_shared()) return 77;
  return result;
}
