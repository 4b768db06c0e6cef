/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sphere.c - the spherical smallest enclosing cap (Welzl), shared by the maximum
 * intersection (bounding caps, inscribed circles of regions) and any other user. */
#include <string.h>

#include "sphere/sphere.h"

/* Smallest cap with a and b on its boundary: centred on their midpoint. */
static void cap2(const double *a, const double *b, double c[3], double *cosr)
{
    double s[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
    if (!mfg_unit3(s, c)) { /* antipodal: any point of the bisecting circle */
        double t[3] = {a[1], -a[0], 0};
        if (!mfg_unit3(t, c)) {
            t[0] = 0, t[1] = a[2], t[2] = -a[1];
            mfg_unit3(t, c);
        }
    }
    *cosr = fmin(mfg_dot3(c, a), mfg_dot3(c, b));
}

/* The cap with a, b and p on its boundary: centred on the pole of their plane (on the
 * side of the points). */
static void cap3(const double *a, const double *b, const double *p, double c[3], double *cosr)
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]}, n[3];
    mfg_cross3(u, v, n);
    if (!mfg_unit3(n, c)) {
        cap2(a, b, c, cosr);
        return;
    }
    if (mfg_dot3(c, a) < 0)
        mfg_neg3(c, c);
    *cosr = fmin(mfg_dot3(c, a), fmin(mfg_dot3(c, b), mfg_dot3(c, p)));
}

void mfg_enclosing_cap(const double *pts, int64_t k, double c[3], double *cosr)
{
    const double eps = MFG_CAP_SLACK;
    /* Visit the points in scrambled order (index u -> u + stride mod k): points given
     * along a boundary would otherwise make nearly every one a new support point. */
    const int64_t stride = mfg_scramble_stride(k);
    memcpy(c, pts, 3 * sizeof(double));
    *cosr = 1.0;
    for (int64_t i = 1, ii = stride % k; i < k; i++, ii = (ii + stride) % k) {
        const double *pi = pts + 3 * ii;
        if (mfg_dot3(c, pi) >= *cosr - eps)
            continue;
        memcpy(c, pi, 3 * sizeof(double));
        *cosr = 1.0;
        for (int64_t j = 0, jj = 0; j < i; j++, jj = (jj + stride) % k) {
            const double *pj = pts + 3 * jj;
            if (mfg_dot3(c, pj) >= *cosr - eps)
                continue;
            cap2(pi, pj, c, cosr);
            for (int64_t l = 0, ll = 0; l < j; l++, ll = (ll + stride) % k) {
                const double *pl = pts + 3 * ll;
                if (mfg_dot3(c, pl) >= *cosr - eps)
                    continue;
                cap3(pi, pj, pl, c, cosr);
            }
        }
    }
}
