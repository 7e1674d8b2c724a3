#include "cbx_test.h"

#include <stdarg.h>
#include <stdio.h>

cbx_test_fail_fn cbx_test_on_fail = 0;

void cbx_test_fail(const char* file, int line, const char* format, ...) {
  char message[256];
  va_list args;
  va_start(args, format);
  vsnprintf(message, sizeof message, format, args);
  va_end(args);
  if (cbx_test_on_fail) cbx_test_on_fail(file, line, message);
}
