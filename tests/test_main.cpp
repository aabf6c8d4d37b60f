#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "test_support.hpp"

#include <cstdio>

namespace {

/// Counts the test cases that ran. ctest runs one test file at a time through a filter
/// (--source-file); a filter that selects nothing (a file renamed, a typo) must fail, not pass.
struct RunCounter : doctest::IReporter {
  static int& ran() {
    static int count = 0;  // test-only state, one run per process
    return count;
  }
  explicit RunCounter(const doctest::ContextOptions&) {}
  void report_query(const doctest::QueryData&) override {}
  void test_run_start() override {}
  void test_run_end(const doctest::TestRunStats&) override {}
  void test_case_start(const doctest::TestCaseData&) override { ++ran(); }
  void test_case_reenter(const doctest::TestCaseData&) override {}
  void test_case_end(const doctest::CurrentTestCaseStats&) override {}
  void test_case_exception(const doctest::TestCaseException&) override {}
  void subcase_start(const doctest::SubcaseSignature&) override {}
  void subcase_end() override {}
  void log_assert(const doctest::AssertData&) override {}
  void log_message(const doctest::MessageData&) override {}
  void test_case_skipped(const doctest::TestCaseData&) override {}
};
REGISTER_LISTENER("run_counter", 1, RunCounter);

}  // namespace

// A test file whose cases all need ../shared reports "skipped" to ctest (exit 77) when the folder
// is missing, instead of passing silently.
int main(int argc, char** argv) {
  doctest::Context context(argc, argv);
  const int result = context.run();
  if (context.shouldExit()) return result;
  if (RunCounter::ran() == 0) {
    std::fprintf(stderr, "no test case matched the filters given\n");
    return 1;
  }
  if (result == 0 && areamatch_test::skipped_for_missing_shared()) return 77;
  return result;
}
