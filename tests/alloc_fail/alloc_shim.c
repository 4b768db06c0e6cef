/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* alloc_shim.c - a malloc family that can be told to fail its N-th call: linked into the
 * test executable, it interposes on every allocation of libmfgeom (and of libc on its
 * behalf, e.g. qsort's buffer), so the library itself carries no test hook.
 * glibc only: the real allocator is reached through its __libc_* entry points (dlsym
 * would itself allocate).  Single-threaded use; not for sanitizer builds, whose runtime
 * owns malloc. */
#include <errno.h>
#include <stddef.h>
#include <stdlib.h>

#include "alloc_shim.h"

extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t size);
extern void __libc_free(void *p);
extern void *__libc_memalign(size_t align, size_t size);

static int armed;
static long fail_at;
static alloc_shim_stats st;

void alloc_shim_arm(long n)
{
    st.attempts = st.failed = st.net = 0;
    fail_at = n;
    armed = 1;
}

alloc_shim_stats alloc_shim_disarm(void)
{
    armed = 0;
    return st;
}

/* Counts one attempt; 1 when it is the one to fail. */
static int should_fail(void)
{
    if (!armed)
        return 0;
    st.attempts++;
    if (st.attempts == fail_at) {
        st.failed++;
        return 1;
    }
    return 0;
}

static void *counted(void *p)
{
    if (armed && p)
        st.net++;
    return p;
}

void *malloc(size_t size)
{
    if (should_fail()) {
        errno = ENOMEM;
        return NULL;
    }
    return counted(__libc_malloc(size));
}

void *calloc(size_t n, size_t size)
{
    if (should_fail()) {
        errno = ENOMEM;
        return NULL;
    }
    return counted(__libc_calloc(n, size));
}

void *realloc(void *p, size_t size)
{
    if (!p)
        return malloc(size);
    if (size == 0) { /* glibc: frees p */
        free(p);
        return NULL;
    }
    if (should_fail()) {
        errno = ENOMEM;
        return NULL; /* p stays valid, as with a real failure */
    }
    return __libc_realloc(p, size); /* one block before and after */
}

void free(void *p)
{
    if (armed && p)
        st.net--;
    __libc_free(p);
}

void *aligned_alloc(size_t align, size_t size)
{
    if (should_fail()) {
        errno = ENOMEM;
        return NULL;
    }
    return counted(__libc_memalign(align, size));
}

void *memalign(size_t align, size_t size);
void *memalign(size_t align, size_t size) { return aligned_alloc(align, size); }

int posix_memalign(void **out, size_t align, size_t size)
{
    if (align < sizeof(void *) || (align & (align - 1)))
        return EINVAL;
    void *p = aligned_alloc(align, size);
    if (!p)
        return ENOMEM;
    *out = p;
    return 0;
}
