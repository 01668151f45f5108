/* Sine and cosine of a bounded argument, for the generated kernels of the structural
 * variants (walker/_generated/<module>_<variant>.c, printed by walker/symbolic/codegen_c.py).
 *
 * For |x| <= pi/4 (every angle of a walking gait: leg and joint angles, the slope) the two
 * come from their Taylor polynomials, no argument reduction: sin to the x^17 term, cos to
 * the x^16 term, whose truncation errors at pi/4 (8e-20 and 2e-18 relative) are far below
 * half an ulp.  Odd and even exactly (sin(-x) = -sin(x), cos(-x) = cos(x)), sin(0) = 0,
 * cos(0) = 1.  Beyond pi/4, and for NaN and infinities, libm's sin and cos.
 *
 * Accuracy: within 1 ulp of the exact values over |x| <= pi/4, checked against mpmath by
 * tests/test_sincos.py (wk_sincos_check below is its entry point).  About three times
 * faster than libm's sincos on the kernels' arguments (issue 30: sincos was a quarter of a
 * kneed stride's time).  The build disables contraction into fused multiply-adds
 * (setup.py), so the results do not depend on the compiler. */
#ifndef WK_SINCOS_H
#define WK_SINCOS_H

#include <math.h>

#define WK_SINCOS_BOUND 0.78539816339744828 /* pi/4, rounded down to a double */

/* Taylor coefficients: (-1)^k / (2k+1)! for sin, (-1)^k / (2k)! for cos, rounded to
 * double. */
#define WK_S1 (-1.0 / 6.0)
#define WK_S2 (1.0 / 120.0)
#define WK_S3 (-1.0 / 5040.0)
#define WK_S4 (1.0 / 362880.0)
#define WK_S5 (-1.0 / 39916800.0)
#define WK_S6 (1.0 / 6227020800.0)
#define WK_S7 (-1.0 / 1307674368000.0)
#define WK_S8 (1.0 / 355687428096000.0)
#define WK_C2 (1.0 / 24.0)
#define WK_C3 (-1.0 / 720.0)
#define WK_C4 (1.0 / 40320.0)
#define WK_C5 (-1.0 / 3628800.0)
#define WK_C6 (1.0 / 479001600.0)
#define WK_C7 (-1.0 / 87178291200.0)
#define WK_C8 (1.0 / 20922789888000.0)

/* sin x for |x| <= pi/4: x + x^3 S(x^2). */
static inline double wk_sin_small(double x, double z)
{
    const double p =
        WK_S1 +
        z * (WK_S2 + z * (WK_S3 + z * (WK_S4 + z * (WK_S5 + z * (WK_S6 + z * (WK_S7 + z * WK_S8))))));
    return x + (x * z) * p;
}

/* cos x for |x| <= pi/4: 1 - z/2 + z^2 C(z), the rounding of w = 1 - z/2 carried into the
 * small terms ((1 - w) - z/2 is exact: w lies in [0.69, 1]). */
static inline double wk_cos_small(double z)
{
    const double hz = 0.5 * z;
    const double w = 1.0 - hz;
    const double c =
        WK_C2 + z * (WK_C3 + z * (WK_C4 + z * (WK_C5 + z * (WK_C6 + z * (WK_C7 + z * WK_C8)))));
    return w + (((1.0 - w) - hz) + (z * z) * c);
}

static inline void wk_sincos(double x, double *s, double *c)
{
    if (fabs(x) <= WK_SINCOS_BOUND) {
        const double z = x * x;
        *s = wk_sin_small(x, z);
        *c = wk_cos_small(z);
        return;
    }
    *s = sin(x);
    *c = cos(x);
}

static inline double wk_sin(double x)
{
    return fabs(x) <= WK_SINCOS_BOUND ? wk_sin_small(x, x * x) : sin(x);
}

static inline double wk_cos(double x)
{
    return fabs(x) <= WK_SINCOS_BOUND ? wk_cos_small(x * x) : cos(x);
}

#endif
