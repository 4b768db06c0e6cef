/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* bench_crossing.c - the textbook even-odd crossing-number test (no ON class), a speed baseline for bench_pointclass. */
#include <stdint.h>

#include "bench_crossing.h"

/* For each point, count the edges crossed by the rightward horizontal ray (half-open
 * rule on y) and report the parity: 1 inside, 0 outside.  Floating point, no tolerance. */
void bench_crossing_classify(const double *xy, int64_t n, const double *pts, int64_t npoints,
                             uint8_t *out)
{
    for (int64_t i = 0; i < npoints; ++i) {
        const double px = pts[2 * i], py = pts[2 * i + 1];
        int inside = 0;
        double ax = xy[2 * (n - 1)], ay = xy[2 * (n - 1) + 1];
        for (int64_t k = 0; k < n; ++k) {
            const double bx = xy[2 * k], by = xy[2 * k + 1];
            if ((by > py) != (ay > py)) {
                const double xcross = bx + (py - by) * (ax - bx) / (ay - by);
                if (px < xcross)
                    inside = !inside;
            }
            ax = bx;
            ay = by;
        }
        out[i] = (uint8_t)inside;
    }
}
