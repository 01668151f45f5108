/* The exported entry point of wk_sincos.h for its accuracy test (tests/test_sincos.py calls
 * it through ctypes): s[i], c[i] = wk_sincos(x[i]) for i < n. */
#include <stdint.h>
#include "wk_sincos.h"

void wk_sincos_check(const double *x, double *s, double *c, int64_t n);

void wk_sincos_check(const double *x, double *s, double *c, int64_t n)
{
    for (int64_t i = 0; i < n; i++) wk_sincos(x[i], s + i, c + i);
}
