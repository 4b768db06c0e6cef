/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mfg_test.h - a minimal assertion harness for the C unit tests (counts, never aborts). */
#ifndef MFG_TEST_H
#define MFG_TEST_H
#include <stdio.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static int mfg_test_failures = 0;
static int mfg_test_checks = 0;

#define CHECK(cond)                                                                    \
    do {                                                                               \
        mfg_test_checks++;                                                             \
        if (!(cond)) {                                                                 \
            mfg_test_failures++;                                                       \
            if (mfg_test_failures < 50)                                                \
                fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
        }                                                                              \
    } while (0)

#define CHECK_EQ_INT(a, b)                                                             \
    do {                                                                               \
        long long va_ = (long long)(a), vb_ = (long long)(b);                          \
        mfg_test_checks++;                                                             \
        if (va_ != vb_) {                                                              \
            mfg_test_failures++;                                                       \
            if (mfg_test_failures < 50)                                                \
                fprintf(stderr, "%s:%d: %s == %lld, expected %s == %lld\n", __FILE__,  \
                        __LINE__, #a, va_, #b, vb_);                                   \
        }                                                                              \
    } while (0)

static inline int mfg_test_report(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, mfg_test_checks, mfg_test_failures);
    return mfg_test_failures ? 1 : 0;
}

/* Deterministic xorshift generator: tests must not depend on rand()'s implementation. */
static unsigned long long mfg_rng_state = 88172645463325252ULL;
static inline unsigned long long rng_next(void)
{
    mfg_rng_state ^= mfg_rng_state << 13;
    mfg_rng_state ^= mfg_rng_state >> 7;
    mfg_rng_state ^= mfg_rng_state << 17;
    return mfg_rng_state;
}
static inline double rng_uniform(double lo, double hi)
{
    return lo + (hi - lo) * ((double)(rng_next() >> 11) * 0x1p-53);
}
static inline long rng_int(long lo, long hi) /* inclusive */
{
    return lo + (long)(rng_next() % (unsigned long long)(hi - lo + 1));
}
#endif
