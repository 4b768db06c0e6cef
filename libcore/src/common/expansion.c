/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* expansion.c - the expansion arithmetic routines of expansion.h (the algorithms of
 * Shewchuk 1997, written for mfgeom with zero elimination; no code copied). */
#include <math.h>

#include "common/expansion.h"

int expn_grow(int elen, const double *e, double b, double *h)
{
    /* Carry b upwards through e; each step leaves its exact rounding error behind. */
    double q = b;
    int hlen = 0;
    for (int i = 0; i < elen; i++) {
        double sum, err;
        expn_two_sum(q, e[i], &sum, &err);
        q = sum;
        if (err != 0.0)
            h[hlen++] = err;
    }
    if (q != 0.0 || hlen == 0)
        h[hlen++] = q;
    return hlen;
}

/* The merge of expn_sum and expn_diff_expansions: fsign is +1 or -1 (the sign applied to
 * f's components), so a difference needs no negated copy of f. */
static int merge_sum(int elen, const double *e, int flen, const double *f, double fsign,
                     double *h)
{
    /* Take the components of e and f in increasing magnitude and carry their running sum
     * q: adding each next component to q is exact as q + error (TwoSum), and the errors
     * come out non-overlapping and increasing.  Round-to-even keeps the result strongly
     * non-overlapping when e and f are (Shewchuk's Theorem 13). */
    int i = 0, j = 0, hlen = 0;
    double q;
    if (elen + flen == 0) {
        h[0] = 0.0;
        return 1;
    }
    if (j >= flen || (i < elen && fabs(e[i]) <= fabs(f[j])))
        q = e[i++];
    else
        q = fsign * f[j++];
    while (i < elen || j < flen) {
        double g, sum, err;
        if (j >= flen || (i < elen && fabs(e[i]) <= fabs(f[j])))
            g = e[i++];
        else
            g = fsign * f[j++];
        expn_two_sum(q, g, &sum, &err);
        q = sum;
        if (err != 0.0)
            h[hlen++] = err;
    }
    if (q != 0.0 || hlen == 0)
        h[hlen++] = q;
    return hlen;
}

int expn_sum(int elen, const double *e, int flen, const double *f, double *h)
{
    return merge_sum(elen, e, flen, f, 1.0, h);
}

int expn_diff_expansions(int elen, const double *e, int flen, const double *f, double *h)
{
    return merge_sum(elen, e, flen, f, -1.0, h);
}

int expn_scale(int elen, const double *e, double b, double *h)
{
    /* Each component times b is an exact (product, error) pair; the pairs are folded into
     * a running sum q from the smallest component up (Shewchuk's Theorem 19). */
    double q, hh, prod, perr, sum;
    int hlen = 0;
    expn_two_product(e[0], b, &q, &hh);
    if (hh != 0.0)
        h[hlen++] = hh;
    for (int i = 1; i < elen; i++) {
        expn_two_product(e[i], b, &prod, &perr);
        expn_two_sum(q, perr, &sum, &hh);
        if (hh != 0.0)
            h[hlen++] = hh;
        expn_two_sum(prod, sum, &q, &hh);
        if (hh != 0.0)
            h[hlen++] = hh;
    }
    if (q != 0.0 || hlen == 0)
        h[hlen++] = q;
    return hlen;
}

int expn_mul(int elen, const double *e, int flen, const double *f, double *h, double *s1,
             double *s2)
{
    /* Scale the longer expansion by each component of the shorter one: fewer (and longer)
     * partial products, so fewer passes of the quadratic accumulation. */
    if (flen > elen) {
        const double *t = e;
        e = f;
        f = t;
        int n = elen;
        elen = flen;
        flen = n;
    }
    double *acc = h, *spare = s2;
    int alen = expn_scale(elen, e, f[0], acc);
    for (int j = 1; j < flen; j++) {
        if (f[j] == 0.0)
            continue;
        int plen = expn_scale(elen, e, f[j], s1);
        int n = expn_sum(alen, acc, plen, s1, spare);
        double *t = acc;
        acc = spare;
        spare = t;
        alen = n;
    }
    if (acc != h)
        for (int i = 0; i < alen; i++)
            h[i] = acc[i];
    return alen;
}

int expn_compress(int elen, double *e)
{
    /* Top-down pass: sum from the largest component down, keeping each partial sum that
     * no longer absorbs the next component, stored from the top of the array.  Bottom-up
     * pass: sum those back from the smallest, emitting the non-zero errors from the
     * bottom.  The result is non-adjacent and its largest component is within one ulp of
     * the value (Shewchuk's Theorem 23).  Writing index never passes the reading index,
     * so the work is done in place. */
    if (elen < 1) {
        e[0] = 0.0;
        return 1;
    }
    if (elen == 1)
        return 1;
    int bottom = elen - 1;
    double q = e[elen - 1];
    for (int i = elen - 2; i >= 0; i--) {
        double sum, err;
        expn_two_sum(q, e[i], &sum, &err);
        if (err != 0.0) {
            e[bottom--] = sum;
            q = err;
        } else {
            q = sum;
        }
    }
    e[bottom] = q;
    int top = 0;
    for (int i = bottom + 1; i < elen; i++) {
        double sum, err;
        expn_two_sum(e[i], q, &sum, &err);
        if (err != 0.0)
            e[top++] = err;
        q = sum;
    }
    e[top++] = q;
    return top;
}
