/* Every suite of the firmware core tests, for both runners. */
#include "cbx_test.h"

extern const cbx_test_case cbx_tests_encoder[];
extern const cbx_test_case cbx_tests_render[];
extern const cbx_test_case cbx_tests_safety[];
extern const cbx_test_case cbx_tests_protocol[];

const cbx_test_suite cbx_test_suites[] = {
    {"encoder", cbx_tests_encoder},
    {"render", cbx_tests_render},
    {"safety", cbx_tests_safety},
    {"protocol", cbx_tests_protocol},
};
const unsigned cbx_test_suite_count = sizeof cbx_test_suites / sizeof cbx_test_suites[0];
