/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* medial_find.h - the medial tests' look-ups of boundary elements by their geometry (the
 * private md_elements of medial/medial.h): one copy for every stage's test. */
#ifndef MEDIAL_FIND_H
#define MEDIAL_FIND_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "medial/medial.h"

/* The face with outward unit normal n and offset delta (exactly, as the axis-aligned test
 * solids give), or -1. */
static inline int64_t face_with(const md_elements *el, double nx, double ny, double nz,
                                double delta)
{
    for (int64_t f = 0; f < el->nfaces; f++) {
        const double *p = el->face_plane + 4 * f;
        if (fabs(p[0] - nx) < 1e-15 && fabs(p[1] - ny) < 1e-15 && fabs(p[2] - nz) < 1e-15 &&
            fabs(p[3] - delta) < 1e-12)
            return f;
    }
    return -1;
}

/* The edge element with ends a, b (either order), or -1. */
static inline int64_t edge_with(const md_elements *el, const double *a, const double *b)
{
    for (int64_t i = 0; i < el->nedges; i++) {
        const double *A = el->edge_seg + 6 * i, *B = A + 3;
        if ((!memcmp(A, a, 24) && !memcmp(B, b, 24)) || (!memcmp(A, b, 24) && !memcmp(B, a, 24)))
            return el->nfaces + i;
    }
    return -1;
}

#endif
