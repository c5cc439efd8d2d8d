// Names each test case on stderr as it starts, and makes doctest's report unbuffered: when the
// suite is stopped from outside (ctest's time-out kills it), its output still says which case
// was running and every check that had failed.
#include <doctest/doctest.h>

#include <cstdio>
#include <iostream>

namespace {

struct progress_listener : doctest::IReporter {
  explicit progress_listener(const doctest::ContextOptions&) {}
  void report_query(const doctest::QueryData&) override {}
  void test_run_start() override { std::cout << std::unitbuf; }
  void test_run_end(const doctest::TestRunStats&) override {}
  void test_case_start(const doctest::TestCaseData& in) override {
    std::fprintf(stderr, "cli test case: %s\n", in.m_name);
  }
  void test_case_reenter(const doctest::TestCaseData&) override {}
  void test_case_end(const doctest::CurrentTestCaseStats&) override {}
  void test_case_exception(const doctest::TestCaseException&) override {}
  void subcase_start(const doctest::SubcaseSignature&) override {}
  void subcase_end() override {}
  void log_assert(const doctest::AssertData&) override {}
  void log_message(const doctest::MessageData&) override {}
  void test_case_skipped(const doctest::TestCaseData&) override {}
};

REGISTER_LISTENER("progress", 1, progress_listener);

}  // namespace
