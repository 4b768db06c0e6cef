/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* status.c - status names, the thread-local error detail and the version string. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "common/mfg_internal.h"

/* The only mutable state of the library, and it is per thread: callers on different
 * threads never see each other's messages. */
static _Thread_local char mfg_error_text[512];

mfg_status mfg_fail(mfg_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(mfg_error_text, sizeof mfg_error_text, fmt, ap);
    va_end(ap);
    return status;
}

void mfg_clear_error(void)
{
    mfg_error_text[0] = '\0';
}

const char *mfg_last_error(void)
{
    return mfg_error_text;
}

const char *mfg_status_str(mfg_status status)
{
    switch (status) {
    case MFG_OK: return "ok";
    case MFG_ERR_NULL: return "null argument";
    case MFG_ERR_INVALID: return "invalid argument";
    case MFG_ERR_DEGENERATE: return "degenerate input";
    case MFG_ERR_NOMEM: return "out of memory";
    case MFG_ERR_INTERNAL: return "internal error";
    case MFG_ERR_CANCELLED: return "cancelled";
    }
    return "unknown status";
}

void mfg_prog_init(mfg_prog *p, const mfg_progress *progress, const char *call)
{
    memset(p, 0, sizeof *p);
    p->fn = progress ? progress->callback : NULL;
    p->user = progress ? progress->user : NULL;
    p->call = call;
    p->stage = "";
    p->every = 1;
    atomic_init(&p->stop, 0);
}

int mfg_prog_report(mfg_prog *p, double done, double total)
{
    if (!p->fn)
        return 1;
    p->left = p->every;
    if (atomic_load_explicit(&p->stop, memory_order_relaxed))
        return 0;
    double q = total > 0 && done > 0 ? done / total : 0;
    q = q < 1 ? q : 1;
    double f = p->lo + p->span * q;
    f = f < 1 ? f : 1;
    if (!(f >= p->last)) /* also NaN */
        f = p->last;
    p->last = f;
    p->reports++;
    if (p->fn(p->user, f, p->stage)) {
        atomic_store_explicit(&p->stop, 1, memory_order_relaxed);
        return 0;
    }
    return 1;
}

int mfg_prog_stage(mfg_prog *p, const char *stage, double lo, double hi, int64_t every)
{
    if (!p->fn)
        return 1;
    p->stage = stage;
    p->lo = lo > p->last ? lo : p->last;
    p->span = hi > p->lo ? hi - p->lo : 0;
    p->every = every > 0 ? every : 1;
    return mfg_prog_report(p, 0, 1);
}

mfg_status mfg_prog_fail(const mfg_prog *p)
{
    return mfg_fail(MFG_ERR_CANCELLED, "%s: cancelled in stage \"%s\"", p->call, p->stage);
}

#define MFG_STR2(x) #x
#define MFG_STR(x) MFG_STR2(x)

const char *mfg_version(void)
{
    return MFG_STR(MFG_VERSION_MAJOR) "." MFG_STR(MFG_VERSION_MINOR) "." MFG_STR(MFG_VERSION_PATCH);
}
