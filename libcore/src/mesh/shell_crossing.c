/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* shell_crossing.c - the last test of the closed-solid check (issue 22): shells that cross
 * or nest wrongly.  A closed, consistently oriented 2-manifold mesh may still not bound a
 * solid: two overlapping boxes pass every edge test (volume 4 against a union of 3.75),
 * and a box inside a box facing the same way counts its inside twice.  The medial surface
 * then takes the inner faces for boundary without a word.
 *
 * Crossing, exactly: a bounding-volume tree over the triangles of non-zero area, traversed
 * against itself; two triangles that share no vertex index cross when an edge of one
 * passes through the other (its ends strictly on both sides of the plane, the piercing
 * point strictly inside: orient3d signs) or, coplanar, when their interiors overlap
 * (orient2d in the plane's dominant projection: edges crossing properly, or a vertex or
 * the centroid of one strictly inside the other).  Strict tests: shells that only touch
 * (a vertex on a face) are not reported.
 *
 * Flat shells: a connected shell whose signed volume is zero within rounding encloses no
 * solid (a folded-flat tetrahedron: its faces overlap, but share vertices, so the crossing
 * test does not see them) and has no inside or outside.  Refused by name.
 *
 * Nesting (shells that do not cross): each shell's signed volume and the winding number,
 * with respect to the other shells, of the centroid of its largest triangle (an interior
 * point of a triangle: another shell can only touch it by crossing, which was refused,
 * or by one of its vertices landing there exactly - then the number is not near an integer
 * and the shell's first triangle's centroid is tried).  Only shells whose box holds the
 * point count.  A shell facing out must lie outside all others (winding 0), a cavity
 * facing in inside exactly one (winding 1).  Skipped beyond MAX_NEST_SHELLS shells.
 *
 * (A vertex was the first choice of point: where a full-turn sweep's shells touch, it lies
 * on the other shell and its winding number is anything from 0 to 1.) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"
#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "common/vec3.h"

#define LEAF_TRIS 4
/* beyond this many shells the nesting test is skipped (its box filter is shells^2) */
#define MAX_NEST_SHELLS 4096
/* the rounding bound of a compensated sum of 3x3 determinants relative to their permanent
 * (mesh.c's VOLUME_BOUND: the same argument per shell) */
#define SHELL_VOLUME_BOUND 0x1p-47

typedef struct tnode {
    double lo[3], hi[3];
    int64_t left, right; /* children, or -1 for a leaf */
    int64_t first, count; /* leaf: ids[first .. first + count) */
} tnode;

typedef struct tree {
    tnode *n;
    int64_t nn;
    int64_t *ids;
    const double *xyz;
    const int64_t *tris;
    double *cen; /* 3 per triangle id: the centroid */
    double *box; /* 6 per triangle id: lo, hi */
} tree;

static void tri_box(const tree *T, int64_t t, double lo[3], double hi[3])
{
    memcpy(lo, T->box + 6 * t, 3 * sizeof(double));
    memcpy(hi, T->box + 6 * t + 3, 3 * sizeof(double));
}

/* Builds the node over ids[first .. first + count): split at the middle of the centroids'
 * extent on its longest axis (in-place partition, O(count)); half by count when that
 * puts everything on one side. */
static int64_t build(tree *T, int64_t first, int64_t count)
{
    int64_t me = T->nn++;
    tnode *nd = &T->n[me];
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < 3; k++) {
        nd->lo[k] = INFINITY;
        nd->hi[k] = -INFINITY;
    }
    for (int64_t i = first; i < first + count; i++) {
        double lo[3], hi[3];
        int64_t t = T->ids[i];
        tri_box(T, t, lo, hi);
        for (int k = 0; k < 3; k++) {
            nd->lo[k] = fmin(nd->lo[k], lo[k]);
            nd->hi[k] = fmax(nd->hi[k], hi[k]);
            clo[k] = fmin(clo[k], T->cen[3 * t + k]);
            chi[k] = fmax(chi[k], T->cen[3 * t + k]);
        }
    }
    nd->first = first;
    nd->count = count;
    nd->left = nd->right = -1;
    if (count <= LEAF_TRIS)
        return me;
    int ax = 0;
    for (int k = 1; k < 3; k++)
        if (chi[k] - clo[k] > chi[ax] - clo[ax])
            ax = k;
    double mid = 0.5 * (clo[ax] + chi[ax]);
    int64_t i = first, j = first + count - 1;
    while (i <= j) {
        if (T->cen[3 * T->ids[i] + ax] < mid) {
            i++;
        } else {
            int64_t x = T->ids[i];
            T->ids[i] = T->ids[j];
            T->ids[j--] = x;
        }
    }
    int64_t nl = i - first;
    if (nl == 0 || nl == count)
        nl = count / 2;
    int64_t l = build(T, first, nl), r = build(T, first + nl, count - nl);
    T->n[me].left = l; /* T->n is not reallocated: room for 2 count nodes */
    T->n[me].right = r;
    return me;
}

static int boxes_meet(const tnode *a, const tnode *b)
{
    for (int k = 0; k < 3; k++)
        if (a->hi[k] < b->lo[k] || b->hi[k] < a->lo[k])
            return 0;
    return 1;
}

/* Does segment pq pass through triangle abc: p and q strictly on both sides of its plane
 * and the piercing point strictly inside it? */
static int segment_pierces(const double *p, const double *q, const double *a, const double *b,
                           const double *c)
{
    int sp = mfg_orient3d(a, b, c, p), sq = mfg_orient3d(a, b, c, q);
    if (sp == 0 || sq == 0 || sp == sq)
        return 0;
    int o1 = mfg_orient3d(p, q, a, b), o2 = mfg_orient3d(p, q, b, c), o3 = mfg_orient3d(p, q, c, a);
    return o1 != 0 && o1 == o2 && o2 == o3;
}

/* Is point p strictly inside the 2-D triangle abc (either orientation)? */
static int inside2(const double p[2], const double a[2], const double b[2], const double c[2])
{
    int o1 = mfg_orient2d(a[0], a[1], b[0], b[1], p[0], p[1]);
    int o2 = mfg_orient2d(b[0], b[1], c[0], c[1], p[0], p[1]);
    int o3 = mfg_orient2d(c[0], c[1], a[0], a[1], p[0], p[1]);
    return o1 != 0 && o1 == o2 && o2 == o3;
}

/* Do coplanar triangles A and B (2-D, projected) overlap in their interiors? */
static int coplanar_overlap(double A[3][2], double B[3][2])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            const double *a = A[i], *b = A[(i + 1) % 3], *c = B[j], *d = B[(j + 1) % 3];
            int s1 = mfg_orient2d(a[0], a[1], b[0], b[1], c[0], c[1]);
            int s2 = mfg_orient2d(a[0], a[1], b[0], b[1], d[0], d[1]);
            int s3 = mfg_orient2d(c[0], c[1], d[0], d[1], a[0], a[1]);
            int s4 = mfg_orient2d(c[0], c[1], d[0], d[1], b[0], b[1]);
            if (s1 * s2 < 0 && s3 * s4 < 0)
                return 1;
        }
    double ca[2] = {0, 0}, cb[2] = {0, 0};
    for (int i = 0; i < 3; i++) {
        if (inside2(B[i], A[0], A[1], A[2]) || inside2(A[i], B[0], B[1], B[2]))
            return 1;
        for (int k = 0; k < 2; k++) {
            ca[k] += A[i][k] / 3;
            cb[k] += B[i][k] / 3;
        }
    }
    return inside2(ca, B[0], B[1], B[2]) || inside2(cb, A[0], A[1], A[2]);
}

/* Do triangles s and t (sharing no vertex index) cross? */
static int triangles_cross(const double *xyz, const int64_t *tris, int64_t s, int64_t t)
{
    const double *P[3], *Q[3];
    for (int c = 0; c < 3; c++) {
        P[c] = xyz + 3 * tris[3 * s + c];
        Q[c] = xyz + 3 * tris[3 * t + c];
    }
    int o0 = mfg_orient3d(P[0], P[1], P[2], Q[0]), o1 = mfg_orient3d(P[0], P[1], P[2], Q[1]);
    int o2 = mfg_orient3d(P[0], P[1], P[2], Q[2]);
    if (o0 == 0 && o1 == 0 && o2 == 0) { /* coplanar: the plane's dominant projection */
        double n[3], u[3], v[3];
        mfg_sub3(P[1], P[0], u);
        mfg_sub3(P[2], P[0], v);
        mfg_cross3(u, v, n);
        int ax = 0;
        for (int k = 1; k < 3; k++)
            if (fabs(n[k]) > fabs(n[ax]))
                ax = k;
        int i0 = (ax + 1) % 3, i1 = (ax + 2) % 3;
        double A[3][2], B[3][2];
        for (int c = 0; c < 3; c++) {
            A[c][0] = P[c][i0], A[c][1] = P[c][i1];
            B[c][0] = Q[c][i0], B[c][1] = Q[c][i1];
        }
        return coplanar_overlap(A, B);
    }
    if ((o0 > 0 && o1 > 0 && o2 > 0) || (o0 < 0 && o1 < 0 && o2 < 0))
        return 0; /* B wholly on one side of A's plane */
    for (int c = 0; c < 3; c++)
        if (segment_pierces(P[c], P[(c + 1) % 3], Q[0], Q[1], Q[2]) ||
            segment_pierces(Q[c], Q[(c + 1) % 3], P[0], P[1], P[2]))
            return 1;
    return 0;
}

static int share_vertex(const int64_t *tris, int64_t s, int64_t t)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (tris[3 * s + i] == tris[3 * t + j])
                return 1;
    return 0;
}

typedef struct crossing {
    int64_t count, a, b; /* how many pairs cross; the first pair (a < b, smallest) */
} crossing;

static void test_pair(const tree *T, int64_t s, int64_t t, crossing *cr)
{
    if (s == t || share_vertex(T->tris, s, t) || !triangles_cross(T->xyz, T->tris, s, t))
        return;
    int64_t a = s < t ? s : t, b = s < t ? t : s;
    if (cr->count++ == 0 || a < cr->a || (a == cr->a && b < cr->b))
        cr->a = a, cr->b = b;
}

/* Every crossing pair, by the tree against itself (a stack of node pairs). */
static int self_collide(const tree *T, crossing *cr)
{
    int64_t *st = NULL, cap = 0, n = 0;
    if (!mfg_grow((void **)&st, &cap, 2, sizeof *st))
        return 0;
    st[n++] = 0;
    st[n++] = 0;
    while (n > 0) {
        int64_t b = st[--n], a = st[--n];
        const tnode *A = &T->n[a], *B = &T->n[b];
        if (a != b && !boxes_meet(A, B))
            continue;
        int64_t push[6];
        int np = 0;
        if (A->left < 0 && B->left < 0) {
            for (int64_t i = 0; i < A->count; i++)
                for (int64_t j = a == b ? i + 1 : 0; j < B->count; j++) {
                    int64_t s = T->ids[A->first + i], t = T->ids[B->first + j];
                    double lo1[3], hi1[3], lo2[3], hi2[3];
                    tri_box(T, s, lo1, hi1);
                    tri_box(T, t, lo2, hi2);
                    int meet = 1;
                    for (int k = 0; k < 3; k++)
                        meet &= !(hi1[k] < lo2[k] || hi2[k] < lo1[k]);
                    if (meet)
                        test_pair(T, s, t, cr);
                }
            continue;
        }
        if (a == b) {
            push[np++] = A->left, push[np++] = A->left;
            push[np++] = A->right, push[np++] = A->right;
            push[np++] = A->left, push[np++] = A->right;
        } else if (B->left < 0 || (A->left >= 0 && A->count >= B->count)) {
            push[np++] = A->left, push[np++] = b;
            push[np++] = A->right, push[np++] = b;
        } else {
            push[np++] = a, push[np++] = B->left;
            push[np++] = a, push[np++] = B->right;
        }
        if (!mfg_grow((void **)&st, &cap, n + np, sizeof *st)) {
            free(st);
            return 0;
        }
        for (int k = 0; k < np; k++)
            st[n++] = push[k];
    }
    free(st);
    return 1;
}

/* Solid angle of triangle abc seen from p (Van Oosterom & Strackee), in units of 4 pi. */
static double solid_angle(const double *p, const double *a, const double *b, const double *c)
{
    double A[3], B[3], C[3];
    mfg_sub3(a, p, A);
    mfg_sub3(b, p, B);
    mfg_sub3(c, p, C);
    double la = mfg_norm3(A), lb = mfg_norm3(B), lc = mfg_norm3(C), bc[3];
    mfg_cross3(B, C, bc);
    double num = mfg_dot3(A, bc);
    double den = la * lb * lc + mfg_dot3(A, B) * lc + mfg_dot3(A, C) * lb + mfg_dot3(B, C) * la;
    return atan2(num, den) / (2 * 3.14159265358979323846);
}

int64_t mfg_mesh_shells(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt,
                        int64_t *shell_of, mfg_shell_info **out)
{
    *out = NULL;
    int64_t *comp = malloc((size_t)(nv + 1) * sizeof *comp), *num = malloc((size_t)(nv + 1) * sizeof *num);
    if (!comp || !num) {
        free(comp);
        free(num);
        return -1;
    }
    for (int64_t v = 0; v < nv; v++) {
        comp[v] = v;
        num[v] = -1;
    }
    for (int64_t t = 0; t < nt; t++) {
        mfg_uf_union(comp, tris[3 * t], tris[3 * t + 1]);
        mfg_uf_union(comp, tris[3 * t], tris[3 * t + 2]);
    }
    int64_t ns = 0;
    for (int64_t t = 0; t < nt; t++) {
        int64_t r = mfg_uf_find(comp, tris[3 * t]);
        if (num[r] < 0)
            num[r] = ns++;
        shell_of[t] = num[r];
    }
    free(comp);
    free(num);
    mfg_shell_info *S = calloc((size_t)ns + 1, sizeof *S);
    double *comp_sum = calloc((size_t)ns + 1, sizeof *comp_sum);
    if (!S || !comp_sum) {
        free(S);
        free(comp_sum);
        return -1;
    }
    /* volumes about the mesh's box centre, as mesh.c sums the whole (rounding bound) */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, o[3];
    for (int64_t t = 0; t < 3 * nt; t++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], xyz[3 * tris[t] + k]);
            hi[k] = fmax(hi[k], xyz[3 * tris[t] + k]);
        }
    for (int k = 0; k < 3; k++)
        o[k] = lo[k] * 0.5 + hi[k] * 0.5;
    for (int64_t s = 0; s < ns; s++) {
        S[s].first = -1;
        S[s].largest = -1;
        for (int k = 0; k < 3; k++) {
            S[s].lo[k] = INFINITY;
            S[s].hi[k] = -INFINITY;
        }
    }
    for (int64_t t = 0; t < nt; t++) {
        mfg_shell_info *sh = &S[shell_of[t]];
        const int64_t *tv = tris + 3 * t;
        sh->ntriangles++;
        if (sh->first < 0)
            sh->first = t;
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = xyz[3 * tv[0] + k] - o[k];
            b[k] = xyz[3 * tv[1] + k] - o[k];
            c[k] = xyz[3 * tv[2] + k] - o[k];
            sh->lo[k] = fmin(sh->lo[k], fmin(a[k], fmin(b[k], c[k])) + o[k]);
            sh->hi[k] = fmax(sh->hi[k], fmax(a[k], fmax(b[k], c[k])) + o[k]);
        }
        if (tv[0] == tv[1] || tv[1] == tv[2] || tv[0] == tv[2])
            continue;
        double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
        sh->volume6_bound += SHELL_VOLUME_BOUND *
                             (fabs(a[0]) * (fabs(b[1] * c[2]) + fabs(b[2] * c[1])) +
                              fabs(a[1]) * (fabs(b[2] * c[0]) + fabs(b[0] * c[2])) +
                              fabs(a[2]) * (fabs(b[0] * c[1]) + fabs(b[1] * c[0])));
        double x = sh->volume6 + det; /* Neumaier's compensated sum */
        comp_sum[shell_of[t]] += fabs(sh->volume6) >= fabs(det) ? (sh->volume6 - x) + det
                                                                : (det - x) + sh->volume6;
        sh->volume6 = x;
        double u[3], w[3], n[3];
        mfg_sub3(b, a, u);
        mfg_sub3(c, a, w);
        mfg_cross3(u, w, n);
        double area2 = mfg_norm3(n);
        if (area2 > sh->largest_area2) {
            sh->largest_area2 = area2;
            sh->largest = t;
        }
    }
    for (int64_t s = 0; s < ns; s++)
        S[s].volume6 += comp_sum[s];
    free(comp_sum);
    *out = S;
    return ns;
}

int mfg_shell_is_flat(const mfg_shell_info *s)
{
    return !(fabs(s->volume6) > s->volume6_bound);
}

/* The winding number about p of the shells other than `self` whose box holds p
 * (tri_of: the triangles sorted by shell, start[s] .. start[s + 1] those of shell s). */
static double winding_of_others(const double *p, int64_t self, int64_t ns, const mfg_shell_info *S,
                                const double *xyz, const int64_t *tris, const int64_t *tri_of,
                                const int64_t *start)
{
    double w = 0;
    for (int64_t s = 0; s < ns; s++) {
        if (s == self)
            continue;
        int in = 1;
        for (int k = 0; k < 3; k++)
            in &= p[k] >= S[s].lo[k] && p[k] <= S[s].hi[k];
        if (!in)
            continue; /* a closed shell's winding number is 0 outside its box */
        for (int64_t i = start[s]; i < start[s + 1]; i++) {
            const int64_t *tv = tris + 3 * tri_of[i];
            w += solid_angle(p, xyz + 3 * tv[0], xyz + 3 * tv[1], xyz + 3 * tv[2]);
        }
    }
    return w;
}

static void centroid(const double *xyz, const int64_t *tris, int64_t t, double p[3])
{
    for (int k = 0; k < 3; k++)
        p[k] = (xyz[3 * tris[3 * t] + k] + xyz[3 * tris[3 * t + 1] + k] + xyz[3 * tris[3 * t + 2] + k]) / 3;
}

/* Flat shells and wrong nesting (the file's comment). */
static mfg_status nesting_problem(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt)
{
    int64_t *shell_of = malloc((size_t)(nt + 1) * sizeof *shell_of);
    mfg_shell_info *S = NULL;
    int64_t ns = shell_of ? mfg_mesh_shells(xyz, nv, tris, nt, shell_of, &S) : -1;
    int64_t *tri_of = NULL, *start = NULL;
    mfg_status st = MFG_OK;
    if (ns < 0)
        goto nomem;
    for (int64_t s = 0; s < ns; s++)
        if (mfg_shell_is_flat(&S[s])) {
            st = mfg_fail(MFG_ERR_INVALID,
                          "flat shell: the shell of triangle %lld (%lld triangles) encloses no volume "
                          "(its faces fold onto each other); remove it",
                          (long long)S[s].first, (long long)S[s].ntriangles);
            goto done;
        }
    if (ns < 2 || ns > MAX_NEST_SHELLS)
        goto done;
    tri_of = malloc((size_t)(nt + 1) * sizeof *tri_of);
    start = calloc((size_t)ns + 2, sizeof *start);
    if (!tri_of || !start)
        goto nomem;
    for (int64_t t = 0; t < nt; t++) /* counting sort of the triangles by shell */
        start[shell_of[t] + 2]++;
    for (int64_t s = 0; s < ns; s++)
        start[s + 2] += start[s + 1];
    for (int64_t t = 0; t < nt; t++)
        tri_of[start[shell_of[t] + 1]++] = t;
    for (int64_t k = 0; k < ns; k++) {
        if (S[k].largest < 0)
            continue; /* every triangle of zero area: flat, refused above */
        double p[3], w;
        centroid(xyz, tris, S[k].largest, p);
        w = winding_of_others(p, k, ns, S, xyz, tris, tri_of, start);
        if (fabs(w - round(w)) > 0.25) { /* a vertex of another shell on the point */
            centroid(xyz, tris, S[k].first, p);
            w = winding_of_others(p, k, ns, S, xyz, tris, tri_of, start);
        }
        long wi = lround(w);
        if (fabs(w - (double)wi) > 0.25)
            continue; /* rounding too large to tell */
        long want = S[k].volume6 > 0 ? 0 : 1;
        if (wi != want) {
            st = mfg_fail(MFG_ERR_INVALID,
                          "nested shells: the shell of triangle %lld (%s) lies %s (winding number %ld): "
                          "a solid's shells must not overlap",
                          (long long)S[k].first, S[k].volume6 > 0 ? "facing out" : "a cavity facing in",
                          S[k].volume6 > 0 ? "inside another shell" : "outside every solid shell", wi);
            goto done;
        }
    }
    goto done;
nomem:
    st = mfg_fail(MFG_ERR_NOMEM, "out of memory checking the shells of %lld triangles", (long long)nt);
done:
    free(shell_of);
    free(S);
    free(tri_of);
    free(start);
    return st;
}

mfg_status mfg_mesh_shells_problem(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt)
{
    mfg_status st = MFG_OK;
    tree T;
    memset(&T, 0, sizeof T);
    T.xyz = xyz;
    T.tris = tris;
    T.ids = malloc((size_t)(nt + 1) * sizeof *T.ids);
    T.cen = malloc((size_t)(3 * nt + 1) * sizeof *T.cen);
    T.box = malloc((size_t)(6 * nt + 1) * sizeof *T.box);
    T.n = malloc((size_t)(2 * nt + 1) * sizeof *T.n);
    if (!T.ids || !T.cen || !T.box || !T.n) {
        st = mfg_fail(MFG_ERR_NOMEM, "out of memory checking the shells of %lld triangles", (long long)nt);
        goto done;
    }
    int64_t m = 0;
    for (int64_t t = 0; t < nt; t++) {
        const double *a = xyz + 3 * tris[3 * t], *b = xyz + 3 * tris[3 * t + 1], *c = xyz + 3 * tris[3 * t + 2];
        if (mfg_triangle_zero_area(a, b, c))
            continue;
        for (int k = 0; k < 3; k++) {
            T.cen[3 * t + k] = (a[k] + b[k] + c[k]) / 3;
            T.box[6 * t + k] = fmin(a[k], fmin(b[k], c[k]));
            T.box[6 * t + 3 + k] = fmax(a[k], fmax(b[k], c[k]));
        }
        T.ids[m++] = t;
    }
    crossing cr = {0, -1, -1};
    if (m > 1) {
        build(&T, 0, m);
        if (!self_collide(&T, &cr)) {
            st = mfg_fail(MFG_ERR_NOMEM, "out of memory checking the shells of %lld triangles", (long long)nt);
            goto done;
        }
    }
    if (cr.count) {
        st = mfg_fail(MFG_ERR_INVALID,
                      "shells cross: triangles %lld and %lld intersect (%lld crossing pairs; "
                      "overlapping or self-intersecting shells: unite them first)",
                      (long long)cr.a, (long long)cr.b, (long long)cr.count);
        goto done;
    }
    st = nesting_problem(xyz, nv, tris, nt);
done:
    free(T.ids);
    free(T.cen);
    free(T.box);
    free(T.n);
    return st;
}
