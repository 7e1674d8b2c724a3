/* Bare runner (the emulated Cortex-M4 under QEMU, semihosting): runs every case, prints the
 * failures, exits with the number of failed cases (0 = pass). */
#include <stdio.h>

#include "cbx_test.h"

static unsigned failures_in_case;

static void on_fail(const char* file, int line, const char* message) {
  printf("  %s:%d: %s\n", file, line, message);
  failures_in_case++;
}

int main(void) {
  unsigned cases = 0, failed = 0;
  cbx_test_on_fail = on_fail;
  for (unsigned s = 0; s < cbx_test_suite_count; ++s) {
    for (const cbx_test_case* c = cbx_test_suites[s].cases; c->name != NULL; ++c) {
      failures_in_case = 0;
      c->run();
      cases++;
      if (failures_in_case) {
        failed++;
        printf("FAIL %s.%s\n", cbx_test_suites[s].name, c->name);
      }
    }
  }
  printf("firmware core tests: %u cases, %u failed\n", cases, failed);
  return failed > 255u ? 255 : (int)failed;
}
