/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mfg_internal.h - private helpers shared by every algorithm family (errors, limits). */
#ifndef MFG_INTERNAL_H
#define MFG_INTERNAL_H

#include "mfgeom.h"

/* Records the detail text for the calling thread and returns status, so that a
 * failure path reads `return mfg_fail(MFG_ERR_INVALID, "...", ...);`. */
mfg_status mfg_fail(mfg_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Clears the thread's detail text (called on success paths of public entry points). */
void mfg_clear_error(void);

/* True when v is finite and |v| <= MFG_MAX_COORD. */
static inline int mfg_coord_ok(double v)
{
    return v >= -MFG_MAX_COORD && v <= MFG_MAX_COORD; /* false for NaN */
}

#endif
