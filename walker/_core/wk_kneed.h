/* The kneed walker's locked phase (the knee locked: q3 = q2 and qd3 = qd2 kept exactly), as
 * model_kneed.c and model_kneed_coulomb.c both write it: the 6-entry state (q1, q2, q3, qd1,
 * qd2, qd3) from the two locked coordinates (q1, q2) and their rates. */
#ifndef WK_KNEED_H
#define WK_KNEED_H

/* out = (a[0], a[1], a[1], b[0], b[1], b[1]): the state (a the locked coordinates, b their
 * rates) or its rate of change (a the rates, b the accelerations). */
static inline void wk_kneed_locked_state(const double *a, const double *b, double *out)
{
    out[0] = a[0];
    out[1] = a[1];
    out[2] = a[1];
    out[3] = b[0];
    out[4] = b[1];
    out[5] = b[1];
}

/* The locked phase's J (6 x 6, zeroed by the caller) from a, the accelerations' Jacobian with
 * respect to (q1, q2, qd1, qd2) in 2 rows of `stride` entries: the rows of q3 and qd3 copy
 * those of q2 and qd2, the columns of q3 and qd3 are 0. */
static inline void wk_kneed_locked_jac(const double *a, int stride, double *J)
{
    J[0 * 6 + 3] = 1.0;
    J[1 * 6 + 4] = 1.0;
    J[2 * 6 + 4] = 1.0;
    for (int i = 0; i < 2; i++) {
        J[(3 + i) * 6 + 0] = a[i * stride + 0];
        J[(3 + i) * 6 + 1] = a[i * stride + 1];
        J[(3 + i) * 6 + 3] = a[i * stride + 2];
        J[(3 + i) * 6 + 4] = a[i * stride + 3];
    }
    for (int j = 0; j < 6; j++) J[5 * 6 + j] = J[4 * 6 + j];
}

#endif
