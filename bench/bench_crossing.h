/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* bench_crossing.h - declares the textbook crossing-number baseline used by bench_pointclass. */
#ifndef MFG_BENCH_CROSSING_H
#define MFG_BENCH_CROSSING_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Even-odd crossing test of npoints points against one closed ring of n vertices;
 * out[i] = 1 inside, 0 outside (points on the boundary get an arbitrary answer). */
void bench_crossing_classify(const double *xy, int64_t n, const double *pts, int64_t npoints,
                             uint8_t *out);

#ifdef __cplusplus
}
#endif

#endif
