#ifndef CBX_TEST_H
#define CBX_TEST_H
/* A tiny C test framework for the firmware core tests, so that the same test bodies run on the
 * host (wrapped as GoogleTest cases, one CTest entry each) and on the emulated Cortex-M4 (a
 * bare runner under QEMU, semihosting exit code). */
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  const char* name; /* NULL terminates a suite */
  void (*run)(void);
} cbx_test_case;

typedef struct {
  const char* name;
  const cbx_test_case* cases;
} cbx_test_suite;

extern const cbx_test_suite cbx_test_suites[];
extern const unsigned cbx_test_suite_count;

/* Where failures go: the runner (or the GoogleTest wrapper) installs it. */
typedef void (*cbx_test_fail_fn)(const char* file, int line, const char* message);
extern cbx_test_fail_fn cbx_test_on_fail;
void cbx_test_fail(const char* file, int line, const char* format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#define CBX_CHECK(c)                                                   \
  do {                                                                 \
    if (!(c)) cbx_test_fail(__FILE__, __LINE__, "CHECK(%s)", #c);      \
  } while (0)
#define CBX_CHECK_EQ(a, b)                                                                   \
  do {                                                                                       \
    const long long cbx_a_ = (long long)(a), cbx_b_ = (long long)(b);                        \
    if (cbx_a_ != cbx_b_)                                                                    \
      cbx_test_fail(__FILE__, __LINE__, "%s == %s (%lld vs %lld)", #a, #b, cbx_a_, cbx_b_); \
  } while (0)
#define CBX_CHECK_NEAR(a, b, tol)                                                             \
  do {                                                                                        \
    const long long cbx_a_ = (long long)(a), cbx_b_ = (long long)(b);                         \
    const long long cbx_d_ = cbx_a_ > cbx_b_ ? cbx_a_ - cbx_b_ : cbx_b_ - cbx_a_;             \
    if (cbx_d_ > (long long)(tol))                                                            \
      cbx_test_fail(__FILE__, __LINE__, "%s ~ %s within %s (%lld vs %lld)", #a, #b, #tol,     \
                    cbx_a_, cbx_b_);                                                          \
  } while (0)
#define CBX_CHECK_RANGE(v, lo, hi)                                                          \
  do {                                                                                      \
    const long long cbx_v_ = (long long)(v);                                                \
    if (cbx_v_ < (long long)(lo) || cbx_v_ > (long long)(hi))                               \
      cbx_test_fail(__FILE__, __LINE__, "%s in [%s, %s] (%lld)", #v, #lo, #hi, cbx_v_);     \
  } while (0)

#ifdef __cplusplus
}
#endif
#endif
