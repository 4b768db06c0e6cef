/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* visibility.h - private to the visibility map (visibility.c, visibility_hull.c,
 * visibility_draft.c, visibility_batch.c): the cone of the normals and the functions
 * called across those files. */
#ifndef MFG_VISIBILITY_H
#define MFG_VISIBILITY_H

#include <stdint.h>

#include "common/mfg_internal.h"
#include "sphere/sphere.h"

typedef const double *vref; /* a normal: points into the caller's array */

enum cone_state { CONE_EMPTY, CONE_RAY, CONE_WEDGE, CONE_HULL, CONE_LINE };

typedef struct cone3 {
    enum cone_state state;
    vref a, b;   /* ray: a; wedge: from a counter-clockwise to b (about a x b) */
    vref *h;     /* hull vertices, counter-clockwise seen from outside */
    int *o;      /* scratch: orientation of p against each hull edge */
    vref *tmp;   /* scratch for rebuilding the hull */
    int64_t nh, cap;
    vref q;      /* CONE_LINE: q and -q both lie in the cone */
    double c[3], cos2_in; /* inscribed cap, cos^2 of its radius (floating point, only to
                           * skip inside points) */
    int have_cap;
} cone3;

/* Above this many hull vertices the remaining normals come in batches (visibility_batch.c). */
#define SMALL_HULL 48

/* visibility_hull.c */
mfg_status mfg_vm_hull_reserve(cone3 *k, int64_t n);
void mfg_vm_update_cap(cone3 *k);
int mfg_vm_in_inscribed_cap(const cone3 *k, vref p);
mfg_status mfg_vm_hull_add(cone3 *k, vref p);
mfg_status mfg_vm_low_add(cone3 *k, vref p);

/* visibility.c (output) */
mfg_status mfg_vm_spoly_new(int kind, int64_t n, mfg_spoly **out);
void mfg_vm_any_orthogonal(const double a[3], double out[3]);

/* visibility_draft.c */
mfg_status mfg_vm_apply_draft(const cone3 *k, double draft, mfg_spoly **map);

/* visibility_batch.c */
mfg_status mfg_vm_grow_in_batches(cone3 *k, const double *normals, int64_t m, int64_t step,
                                  int64_t idx, int64_t stride);

#endif
