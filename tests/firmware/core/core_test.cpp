// Host runner: every C test case of the firmware core becomes a GoogleTest case
// (FirmwareCore_<suite>.<case>), so CTest lists and runs them one by one.
#include <gtest/gtest.h>

#include <string>

#include "cbx_test.h"

namespace {

void report_failure(const char* file, int line, const char* message) {
  ADD_FAILURE_AT(file, line) << message;
}

class CoreCase : public testing::Test {
 public:
  explicit CoreCase(void (*run)()) : run_(run) {}
  void TestBody() override {
    cbx_test_on_fail = report_failure;
    run_();
    cbx_test_on_fail = nullptr;
  }

 private:
  void (*run_)();
};

const bool registered = [] {
  for (unsigned s = 0; s < cbx_test_suite_count; ++s) {
    const cbx_test_suite& suite = cbx_test_suites[s];
    const std::string suite_name = std::string("FirmwareCore_") + suite.name;
    for (const cbx_test_case* c = suite.cases; c->name != nullptr; ++c) {
      void (*run)() = c->run;
      testing::RegisterTest(suite_name.c_str(), c->name, nullptr, nullptr, __FILE__, __LINE__,
                            [run]() -> testing::Test* { return new CoreCase(run); });
    }
  }
  return true;
}();

}  // namespace
