/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* status.c - status names, the thread-local error detail and the version string. */
#include <stdarg.h>
#include <stdio.h>

#include "mfg_internal.h"

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
    }
    return "unknown status";
}

#define MFG_STR2(x) #x
#define MFG_STR(x) MFG_STR2(x)

const char *mfg_version(void)
{
    return MFG_STR(MFG_VERSION_MAJOR) "." MFG_STR(MFG_VERSION_MINOR) "." MFG_STR(MFG_VERSION_PATCH);
}
