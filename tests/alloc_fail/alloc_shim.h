/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* alloc_shim.h - control of the failing allocator (alloc_shim.c) used by the allocation-
 * failure driver: make the N-th allocation fail and count live blocks inside a window. */
#ifndef ALLOC_SHIM_H
#define ALLOC_SHIM_H

typedef struct alloc_shim_stats {
    long attempts; /* allocation calls in the window (malloc, calloc, realloc, aligned) */
    long failed;   /* of which were made to fail */
    long net;      /* blocks allocated minus blocks freed in the window */
} alloc_shim_stats;

/* Opens a window: counts from zero, and the fail_at-th allocation attempt (1-based)
 * returns NULL (fail_at <= 0: none fails). */
void alloc_shim_arm(long fail_at);
/* Closes the window and returns what happened in it. */
alloc_shim_stats alloc_shim_disarm(void);

#endif
