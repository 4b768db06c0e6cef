/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mesh_repair.c - The rounded boundary of an exact arrangement made a clean closed
 * 2-manifold: welds, needles, touching sheets (mesh_repair.h says what and why). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/hashmap.h"
#include "common/mfg_internal.h"
#include "common/vec3.h"
#include "mesh/mesh.h"
#include "mesh/mesh_repair.h"

/* ---- 1. Welds ------------------------------------------------------------------------- */

typedef struct tri_key {
    int64_t s[3]; /* sorted vertices */
    int64_t t;    /* the triangle */
    int sign;     /* +1: its order is an even permutation of s */
} tri_key;

static int cmp_tri_key(const void *pa, const void *pb)
{
    const tri_key *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->s[k] != b->s[k])
            return a->s[k] < b->s[k] ? -1 : 1;
    return a->t < b->t ? -1 : a->t > b->t;
}

static int weld(mfg_rmesh *m, double eps, int chain)
{
    int64_t nv = m->nv, nt = m->nt;
    int64_t *uf = malloc((size_t)(nv + 1) * sizeof *uf);
    int64_t *next = malloc((size_t)(nv + 1) * sizeof *next);
    tri_key *keys = malloc((size_t)(nt + 1) * sizeof *keys);
    int64_t *keep = malloc((size_t)(nt + 1) * sizeof *keep);
    hmap grid;
    memset(&grid, 0, sizeof grid);
    int ok = uf && next && keys && keep && hmap_init(&grid, nv + 1);
    for (int64_t i = 0; ok && i < nv; i++) {
        uf[i] = i;
        hkey key = hmap_cell_key(m->x + 3 * i, eps, 13);
        next[i] = hmap_get(&grid, &key);
        ok = hmap_put(&grid, &key, i);
    }
    for (int64_t i = 0; ok && i < nv; i++)
        for (int d = 0; d < 27; d++) {
            hkey key = hmap_cell_key(m->x + 3 * i, eps, d);
            for (int64_t j = hmap_get(&grid, &key); j >= 0; j = next[j])
                if (j > i && fabs(m->x[3 * j] - m->x[3 * i]) <= eps &&
                    fabs(m->x[3 * j + 1] - m->x[3 * i + 1]) <= eps &&
                    fabs(m->x[3 * j + 2] - m->x[3 * i + 2]) <= eps)
                    mfg_uf_union(uf, i, j);
        }
    if (!ok) {
        free(uf);
        free(next);
        free(keys);
        free(keep);
        hmap_free(&grid);
        return 0;
    }
    hmap_free(&grid);
    int64_t n = 0;
    for (int64_t t = 0; t < nt; t++) {
        int64_t v[3];
        for (int k = 0; k < 3; k++)
            v[k] = m->t[3 * t + k] = mfg_uf_find(uf, m->t[3 * t + k]);
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
            continue;
        int sign = 1;
        for (int i = 0; i < 2; i++) /* sort, counting swaps for the orientation */
            for (int j = 0; j < 2 - i; j++)
                if (v[j] > v[j + 1]) {
                    int64_t tmp = v[j];
                    v[j] = v[j + 1];
                    v[j + 1] = tmp;
                    sign = -sign;
                }
        memcpy(keys[n].s, v, sizeof v);
        keys[n].t = t;
        keys[n].sign = sign;
        n++;
    }
    if (n > 1)
        qsort(keys, (size_t)n, sizeof *keys, cmp_tri_key);
    int64_t nk = 0;
    for (int64_t i = 0; i < n;) {
        int64_t j = i, net = 0;
        while (j < n && !memcmp(keys[j].s, keys[i].s, sizeof keys[i].s))
            net += keys[j++].sign;
        /* the net orientation survives: once on a surface, |net| times in a chain (a
         * triangle counted twice is a sheet of multiplicity two) */
        int64_t want = net == 0 ? 0 : chain ? (net > 0 ? net : -net) : 1;
        for (int64_t q = i; q < j && want > 0; q++)
            if (keys[q].sign == (net > 0 ? 1 : -1)) {
                keep[nk++] = keys[q].t;
                want--;
            }
        i = j;
    }
    if (nk > 1)
        qsort(keep, (size_t)nk, sizeof *keep, mfg_cmp_i64); /* the original order */
    for (int64_t i = 0; i < nk; i++) {
        memmove(m->t + 3 * i, m->t + 3 * keep[i], 3 * sizeof *m->t);
        if (m->g)
            m->g[i] = m->g[keep[i]];
    }
    m->nt = nk;
    free(uf);
    free(next);
    free(keys);
    free(keep);
    return 1;
}

/* ---- 2. Needles ------------------------------------------------------------------------ */

/* The height of the triangle (a, b, c) over its longest side. */
static double tri_height(const mfg_rmesh *m, int64_t a, int64_t b, int64_t c)
{
    const double *p[3] = {m->x + 3 * a, m->x + 3 * b, m->x + 3 * c};
    double best = 0, e1[3], e2[3], n[3];
    for (int i = 0; i < 3; i++)
        best = fmax(best, mfg_dist3(p[i], p[(i + 1) % 3]));
    mfg_sub3(p[1], p[0], e1);
    mfg_sub3(p[2], p[0], e2);
    mfg_cross3(e1, e2, n);
    return best > 0 ? mfg_norm3(n) / best : 0;
}

/* The longest side of triangle t (0 .. 2: from corner k to corner k + 1) and its height
 * over that side. */
static int longest_side(const mfg_rmesh *m, int64_t t, double *height)
{
    const int64_t *V = m->t + 3 * t;
    double best = -1;
    int k = 0;
    for (int i = 0; i < 3; i++) {
        double d = mfg_dist3(m->x + 3 * V[i], m->x + 3 * V[(i + 1) % 3]);
        if (d > best) {
            best = d;
            k = i;
        }
    }
    *height = tri_height(m, V[0], V[1], V[2]);
    return k;
}

static int add_triangle(mfg_rmesh *m, int64_t a, int64_t b, int64_t c, int64_t g)
{
    if (m->nt >= m->capt) {
        int64_t cap = mfg_grown_cap(m->capt, m->nt + 1, 64);
        int64_t *nt = realloc(m->t, (size_t)cap * 3 * sizeof *nt);
        if (!nt)
            return 0;
        m->t = nt;
        if (m->g) {
            int64_t *ng = realloc(m->g, (size_t)cap * sizeof *ng);
            if (!ng)
                return 0;
            m->g = ng;
        }
        m->capt = cap;
    }
    m->t[3 * m->nt] = a;
    m->t[3 * m->nt + 1] = b;
    m->t[3 * m->nt + 2] = c;
    if (m->g)
        m->g[m->nt] = g;
    m->nt++;
    return 1;
}

/* The directed sides of the live triangles: the map holds, per directed side, the last
 * triangle given it, and prev[3 t + k] the triangle that held that side before t (-1: none)
 * - a side of a non-manifold edge (sheets touching) belongs to two or more triangles, and
 * a needle along such an edge must still find a live neighbour (2026-12-06: with one
 * triangle per side, a cube's sweep kept 55 needles of height 4e-16 along an edge of four
 * triangles, which the turn to the caller's axes folded into 188 crossing pairs). */
typedef struct side_map {
    hmap dir;
    int64_t *prev;
    int64_t cap;
} side_map;

/* A live triangle with directed side a -> b, or -1. */
static int64_t with_side(const mfg_rmesh *m, const side_map *S, const uint8_t *dead, int64_t a, int64_t b)
{
    hkey key = mkkey(a, b, 0, 0);
    for (int64_t t = hmap_get(&S->dir, &key); t >= 0;) {
        int k = 0;
        while (k < 3 && !(m->t[3 * t + k] == a && m->t[3 * t + (k + 1) % 3] == b))
            k++;
        if (k == 3)
            return -1; /* not reached: triangles are never rewritten while mapped */
        if (!dead[t])
            return t;
        t = S->prev[3 * t + k];
    }
    return -1;
}

static int map_sides(side_map *S, const mfg_rmesh *m, int64_t t)
{
    if (3 * t + 3 > S->cap) {
        int64_t cap = mfg_grown_cap(S->cap, 3 * t + 3, 64);
        int64_t *n = realloc(S->prev, (size_t)cap * sizeof *n);
        if (!n)
            return 0;
        S->prev = n;
        S->cap = cap;
    }
    for (int k = 0; k < 3; k++) {
        hkey key = mkkey(m->t[3 * t + k], m->t[3 * t + (k + 1) % 3], 0, 0);
        int64_t before = hmap_get(&S->dir, &key);
        S->prev[3 * t + k] = before == t ? -1 : before;
        if (!hmap_put(&S->dir, &key, t))
            return 0;
    }
    return 1;
}

/* How often an edge may be taken away by flips and made again (remove_needles). */
#define FLIP_AGAIN 2

/* Removes the triangles t with drop[t] (and their labels), keeping the others' order. */
static void drop_triangles(mfg_rmesh *m, const uint8_t *drop)
{
    int64_t n = 0;
    for (int64_t t = 0; t < m->nt; t++) {
        if (drop[t])
            continue;
        memmove(m->t + 3 * n, m->t + 3 * t, 3 * sizeof *m->t);
        if (m->g)
            m->g[n] = m->g[t];
        n++;
    }
    m->nt = n;
}

static int remove_needles(mfg_rmesh *m, double eps)
{
    side_map S = {{0}, NULL, 0};
    hmap gone = {0}; /* the edges flips took away (smaller id first) */
    int64_t cap = 2 * m->nt + 16, top = 0;
    uint8_t *dead = calloc((size_t)cap, 1);
    int64_t *stack = malloc((size_t)cap * sizeof *stack);
    if (!dead || !stack || !hmap_init(&S.dir, 3 * m->nt + 1) || !hmap_init(&gone, 64)) {
        hmap_free(&S.dir);
        free(dead);
        free(stack);
        return 0;
    }
    int ok = 1;
    for (int64_t t = 0; t < m->nt && ok; t++) {
        ok = map_sides(&S, m, t);
        stack[top++] = t;
    }
    /* every operation removes a needle and makes two triangles of its neighbour: bound the
     * work in case rounding keeps making new ones */
    int64_t budget = 4 * m->nt + 64;
    while (ok && top > 0 && budget-- > 0) {
        int64_t t = stack[--top];
        if (dead[t])
            continue;
        double h;
        int k = longest_side(m, t, &h);
        if (h > eps)
            continue;
        int64_t a = m->t[3 * t + k], b = m->t[3 * t + (k + 1) % 3], c = m->t[3 * t + (k + 2) % 3];
        int64_t u = with_side(m, &S, dead, b, a);
        if (u < 0)
            continue;
        int j = 0;
        while (m->t[3 * u + j] != b)
            j++;
        int64_t d = m->t[3 * u + (j + 2) % 3];
        if (d == c) {
            /* a flat pocket: u is t reversed, every side of one cancels a side of the
             * other, so both go and the mesh stays closed (a run of needles along an
             * edge of touching sheets leaves these behind) */
            dead[t] = 1;
            dead[u] = 1;
            continue;
        }
        /* an edge that flips took away FLIP_AGAIN times is not made again: each edge
         * goes at most that often, so the loop ends by itself.  (2026-12-06: a needle of
         * height 8e-17 whose neighbour's apex lay on its line too flipped into one of
         * 6e-13 and back until the budget was spent, and the 37 other needles of that
         * mesh were never reached; never making an edge again left a crossing in the
         * arrangement test's turned boxes that one more flip resolves.) */
        hkey cd = mkkey(c < d ? c : d, c < d ? d : c, 0, 0);
        if (hmap_get(&gone, &cd) >= FLIP_AGAIN)
            continue;
        hkey ab = mkkey(a < b ? a : b, a < b ? b : a, 0, 0);
        int64_t times = hmap_get(&gone, &ab);
        if (!hmap_put(&gone, &ab, times < 0 ? 1 : times + 1)) {
            ok = 0;
            break;
        }
        /* t = (a, b, c) and u = (b, a, d) go, (b, c, d) and (c, a, d) come: appended, not
         * written over u, so that the side map's chains through u stay valid */
        if (m->nt + 2 > cap) {
            int64_t nc = 2 * cap;
            uint8_t *nd = realloc(dead, (size_t)nc);
            int64_t *ns = nd ? realloc(stack, (size_t)nc * sizeof *ns) : NULL;
            if (nd)
                dead = nd;
            if (!ns) {
                ok = 0;
                break;
            }
            stack = ns;
            memset(dead + cap, 0, (size_t)(nc - cap));
            cap = nc;
        }
        dead[t] = 1;
        dead[u] = 1;
        int64_t g = m->g ? m->g[u] : 0;
        int64_t v = m->nt, w = m->nt + 1;
        ok = add_triangle(m, b, c, d, g) && add_triangle(m, c, a, d, g) && map_sides(&S, m, v) &&
             map_sides(&S, m, w);
        if (ok && top + 2 <= cap) {
            stack[top++] = v;
            stack[top++] = w;
        }
    }
    if (ok)
        drop_triangles(m, dead);
    hmap_free(&S.dir);
    hmap_free(&gone);
    free(S.prev);
    free(dead);
    free(stack);
    return ok;
}

/* ---- 3. Touching sheets ----------------------------------------------------------------- */

typedef struct side_ref {
    int64_t s;      /* triangle * 3 + corner: the side from corner k to corner k + 1 */
    double angle;
    int dir;        /* +1: the side runs from the smaller vertex id to the larger */
} side_ref;

static int cmp_angle(const void *pa, const void *pb)
{
    const side_ref *a = pa, *b = pb;
    if (a->angle != b->angle)
        return a->angle < b->angle ? -1 : 1;
    return a->s < b->s ? -1 : a->s > b->s;
}

static int cmp_i64_pair(const void *pa, const void *pb)
{
    const int64_t *a = pa, *b = pb;
    if (a[0] != b[0])
        return a[0] < b[0] ? -1 : 1;
    return a[1] < b[1] ? -1 : a[1] > b[1];
}

/* Pairs the 2k sides round one edge (lo < hi its vertices) so that each pair bounds a
 * wedge of the solid: round the edge by increasing angle (right-handed about lo -> hi),
 * a side running hi -> lo has the solid after it, up to the next side. */
static void pair_round_edge(const mfg_rmesh *m, side_ref *r, int64_t n, int64_t lo, int64_t hi,
                            int64_t *partner, int64_t *partner_scratch)
{
    const double *a = m->x + 3 * lo, *b = m->x + 3 * hi;
    double e[3], ref[3] = {0, 0, 0}, ref2[3];
    mfg_sub3(b, a, e);
    double ee = mfg_dot3(e, e);
    for (int64_t i = 0; i < n; i++) {
        int64_t t = r[i].s / 3;
        int k = (int)(r[i].s % 3);
        const double *c = m->x + 3 * m->t[3 * t + (k + 2) % 3];
        double d[3];
        mfg_sub3(c, a, d);
        double f = ee > 0 ? mfg_dot3(d, e) / ee : 0;
        for (int q = 0; q < 3; q++)
            d[q] -= f * e[q];
        if (i == 0) {
            mfg_unit3(d, ref);
            double eu[3];
            mfg_unit3(e, eu);
            mfg_cross3(eu, ref, ref2);
        }
        double ang = atan2(mfg_dot3(d, ref2), mfg_dot3(d, ref));
        r[i].angle = ang < 0 ? ang + MFG_TWO_PI : ang;
    }
    if (n > 1)
        qsort(r, (size_t)n, sizeof *r, cmp_angle);
    /* A side running hi -> lo opens a wedge, the next side running lo -> hi closes it:
     * matched as brackets round the circle, starting after the lowest running balance,
     * every side gets a partner.  In the exact angular order that is pairing each
     * opener with the side after it; where rounding misorders sides whose triangles lie
     * within ulps of each other (sheets touching at grazing angles) it still pairs every
     * side, so the mesh stays closed (pairing only neighbours left two sides of such an
     * edge unpaired: 2026-12-06, a cube's sweep "not closed: 3 boundary edges" after the
     * first rounding, then its passes multiplied the crossings and the call refused). */
    int64_t balance = 0, low = 0, start = 0;
    for (int64_t i = 0; i < n; i++) {
        balance += r[i].dir < 0 ? 1 : -1;
        if (balance < low) {
            low = balance;
            start = i + 1;
        }
    }
    if (balance != 0)
        return; /* not a chain round this edge: its sides stay unpaired (the check says so) */
    int64_t *open = partner_scratch, nopen = 0;
    for (int64_t q = 0; q < n; q++) {
        int64_t i = (start + q) % n;
        if (r[i].dir < 0) {
            open[nopen++] = i;
        } else if (nopen > 0) {
            int64_t j = open[--nopen];
            partner[r[i].s] = r[j].s;
            partner[r[j].s] = r[i].s;
        }
    }
}

static int separate_sheets(mfg_rmesh *m)
{
    int64_t nt = m->nt, ns = 3 * nt;
    int64_t *partner = malloc((size_t)(ns + 1) * sizeof *partner);
    int64_t *uf = malloc((size_t)(ns + 1) * sizeof *uf);
    side_ref *r = NULL;
    int64_t capr = 0, *open = NULL, capopen = 0;
    int ok = partner && uf;
    if (!ok)
        goto done;
    /* sides sorted by their edge: (min vertex, max vertex, side) records */
    int64_t *pairs = malloc((size_t)(3 * ns + 3) * sizeof *pairs);
    if (!pairs) {
        ok = 0;
        goto done;
    }
    for (int64_t s = 0; s < ns; s++) {
        int64_t a = m->t[s], b = m->t[s - s % 3 + (s % 3 + 1) % 3];
        pairs[3 * s] = a < b ? a : b;
        pairs[3 * s + 1] = a < b ? b : a;
        pairs[3 * s + 2] = s;
        partner[s] = -1;
        uf[s] = s;
    }
    if (ns > 1)
        qsort(pairs, (size_t)ns, 3 * sizeof *pairs, cmp_i64_pair);
    for (int64_t i = 0, j; i < ns && ok; i = j) {
        for (j = i + 1; j < ns && pairs[3 * j] == pairs[3 * i] && pairs[3 * j + 1] == pairs[3 * i + 1]; j++)
            ;
        int64_t n = j - i;
        if (n == 2) {
            partner[pairs[3 * i + 2]] = pairs[3 * i + 5];
            partner[pairs[3 * i + 5]] = pairs[3 * i + 2];
        } else if (n > 2) {
            if (!mfg_grow((void **)&r, &capr, n, sizeof *r) ||
                !mfg_grow((void **)&open, &capopen, n, sizeof *open)) {
                ok = 0;
                break;
            }
            for (int64_t q = 0; q < n; q++) {
                int64_t s = pairs[3 * (i + q) + 2];
                r[q].s = s;
                r[q].dir = m->t[s] == pairs[3 * i] ? 1 : -1;
            }
            pair_round_edge(m, r, n, pairs[3 * i], pairs[3 * i + 1], partner, open);
        }
    }
    free(pairs);
    if (!ok)
        goto done;
    /* corners joined through paired sides: corner (t, k) is slot 3 t + k */
    for (int64_t s = 0; s < ns; s++) {
        int64_t p = partner[s];
        if (p < 0)
            continue;
        int64_t t = s / 3, k = s % 3, u = p / 3, j = p % 3;
        int64_t a = m->t[s], b = m->t[3 * t + (k + 1) % 3];
        /* the partner runs b -> a (or a -> b, inconsistently oriented: join by vertex) */
        for (int q = 0; q < 3; q++) {
            int64_t slot = 3 * u + q, v = m->t[slot];
            if (v == a)
                mfg_uf_union(uf, s, slot);
            else if (v == b)
                mfg_uf_union(uf, 3 * t + (k + 1) % 3, slot);
        }
        (void)j;
    }
    /* one vertex per fan: the first fan (smallest corner) keeps the vertex */
    {
        int64_t *first = malloc((size_t)(m->nv + 1) * sizeof *first);
        int64_t *copy = malloc((size_t)(ns + 1) * sizeof *copy);
        if (!first || !copy) {
            free(first);
            free(copy);
            ok = 0;
            goto done;
        }
        for (int64_t v = 0; v < m->nv; v++)
            first[v] = -1;
        for (int64_t s = 0; s < ns; s++)
            copy[s] = -1;
        for (int64_t s = 0; s < ns && ok; s++) {
            int64_t v = m->t[s], root = mfg_uf_find(uf, s);
            if (first[v] < 0)
                first[v] = root;
            if (root == first[v])
                continue;
            if (copy[root] < 0) {
                if (m->nv >= m->capv) {
                    int64_t cap = mfg_grown_cap(m->capv, m->nv + 1, 64);
                    double *nx = realloc(m->x, (size_t)cap * 3 * sizeof *nx);
                    if (!nx) {
                        ok = 0;
                        break;
                    }
                    m->x = nx;
                    m->capv = cap;
                }
                memcpy(m->x + 3 * m->nv, m->x + 3 * v, 3 * sizeof *m->x);
                copy[root] = m->nv++;
            }
            m->t[s] = copy[root];
        }
        free(first);
        free(copy);
    }
done:
    free(partner);
    free(uf);
    free(r);
    free(open);
    return ok;
}

#ifdef ARR_DEBUG
#include <stdio.h>
static void say_closed(const mfg_rmesh *m, const char *after)
{
    mfg_mesh_report r;
    mfg_status s = mfg_mesh_check_closed(m->x, m->nv, m->t, m->nt, &r);
    fprintf(stderr, "  repair: after %s: %lld triangles, %s\n", after, (long long)m->nt,
            s == MFG_OK ? "closed" : mfg_last_error());
}
#define SAY(m, what) say_closed(m, what)
#else
#define SAY(m, what) ((void)0)
#endif

int mfg_mesh_repair(mfg_rmesh *m, double eps)
{
    if (!weld(m, eps, 0))
        return 0;
    SAY(m, "weld");
    if (!remove_needles(m, eps))
        return 0;
    SAY(m, "needles");
    if (!separate_sheets(m))
        return 0;
    SAY(m, "sheets");
    return 1;
}

int mfg_mesh_separate_sheets(mfg_rmesh *m)
{
    return separate_sheets(m);
}

int mfg_chain_weld(mfg_rmesh *m, double eps)
{
    return weld(m, eps, 1);
}

/* ---- 4. Flat shells ------------------------------------------------------------------- */

int mfg_mesh_drop_flat_shells(mfg_rmesh *m)
{
    int64_t *shell_of = malloc((size_t)(m->nt + 1) * sizeof *shell_of);
    mfg_shell_info *S = NULL;
    int64_t ns = shell_of ? mfg_mesh_shells(m->x, m->nv, m->t, m->nt, shell_of, &S) : -1;
    if (ns < 0) {
        free(shell_of);
        return 0;
    }
    uint8_t *flat = malloc((size_t)m->nt + 1);
    if (flat) {
        for (int64_t t = 0; t < m->nt; t++)
            flat[t] = (uint8_t)mfg_shell_is_flat(&S[shell_of[t]]);
        drop_triangles(m, flat);
    }
    free(flat);
    free(shell_of);
    free(S);
    return flat != NULL;
}
