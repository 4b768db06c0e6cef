/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/bvh.c - A bounding-box hierarchy over the arrangement's triangles: the pairs
 * whose boxes overlap (the candidates of the pair stage) and the boxes an axis-parallel
 * ray may meet (the winding numbers).  Boxes only prune; every decision is exact. */
#include "arrange/arrange.h"

/* Boxes per leaf. */
#define LEAF_MAX 4
/* A rounded ray origin lies within a few ulps of the exact one, and boxes hold their
 * triangles' exact corners: this padding (unit scale, coordinates at most
 * ARR_COORD_MAX) keeps a rounding from dropping a box. */
#define RAY_PAD 0x1p-36

typedef struct node {
    double lo[3], hi[3];
    int64_t right; /* internal: the right child (the left is the next node); leaf: first */
    int32_t count; /* leaf: its boxes; internal: 0 */
} node;

struct arr_bvh {
    node *nodes;
    int64_t nnodes;
    int64_t *idx;   /* box ids in leaf order */
    const double *boxes;
    double *own;    /* a copy of the boxes (the caller's may go away) */
};

typedef struct build_ctx {
    arr_bvh *h;
    double *cen;    /* centre of each box, 3 per box */
    int64_t *tmp;
} build_ctx;

static void box_of(const arr_bvh *h, int64_t b, int64_t e, node *n)
{
    for (int k = 0; k < 3; k++) {
        n->lo[k] = INFINITY;
        n->hi[k] = -INFINITY;
    }
    for (int64_t i = b; i < e; i++) {
        const double *bx = h->boxes + 6 * h->idx[i];
        for (int k = 0; k < 3; k++) {
            n->lo[k] = fmin(n->lo[k], bx[k]);
            n->hi[k] = fmax(n->hi[k], bx[3 + k]);
        }
    }
}

/* Partitions idx[b, e) about the median centre along axis k (nth element). */
static void split_median(build_ctx *bc, int64_t b, int64_t e, int k)
{
    int64_t *a = bc->h->idx;
    int64_t lo = b, hi = e - 1, m = (b + e) / 2;
    while (lo < hi) {
        double piv = bc->cen[3 * a[(lo + hi) / 2] + k];
        int64_t i = lo, j = hi;
        while (i <= j) {
            while (bc->cen[3 * a[i] + k] < piv)
                i++;
            while (bc->cen[3 * a[j] + k] > piv)
                j--;
            if (i <= j) {
                int64_t t = a[i];
                a[i] = a[j];
                a[j] = t;
                i++;
                j--;
            }
        }
        if (m <= j)
            hi = j;
        else if (m >= i)
            lo = i;
        else
            break;
    }
}

/* Builds the subtree over idx[b, e) at node slot *next; iterative over the right spine
 * would save stack, but the depth is at most ~log2(n) + a few (median splits). */
static void build(build_ctx *bc, int64_t b, int64_t e)
{
    arr_bvh *h = bc->h;
    int64_t me = h->nnodes++;
    node *n = &h->nodes[me];
    box_of(h, b, e, n);
    if (e - b <= LEAF_MAX) {
        n->right = b;
        n->count = (int32_t)(e - b);
        return;
    }
    int k = 0;
    double ext = -1;
    for (int d = 0; d < 3; d++)
        if (n->hi[d] - n->lo[d] > ext) {
            ext = n->hi[d] - n->lo[d];
            k = d;
        }
    split_median(bc, b, e, k);
    int64_t m = (b + e) / 2;
    h->nodes[me].count = 0;
    build(bc, b, m);
    h->nodes[me].right = h->nnodes;
    build(bc, m, e);
}

arr_bvh *arr_bvh_build(const double *boxes, int64_t n)
{
    arr_bvh *h = calloc(1, sizeof *h);
    build_ctx bc = {h, NULL, NULL};
    if (!h)
        return NULL;
    h->own = malloc((size_t)(6 * n + 6) * sizeof *h->own);
    h->idx = malloc((size_t)(n + 1) * sizeof *h->idx);
    h->nodes = malloc((size_t)(2 * n + 2) * sizeof *h->nodes);
    bc.cen = malloc((size_t)(3 * n + 3) * sizeof *bc.cen);
    if (!h->own || !h->idx || !h->nodes || !bc.cen) {
        free(bc.cen);
        arr_bvh_free(h);
        return NULL;
    }
    memcpy(h->own, boxes, (size_t)(6 * n) * sizeof *boxes);
    h->boxes = h->own;
    for (int64_t i = 0; i < n; i++) {
        h->idx[i] = i;
        for (int k = 0; k < 3; k++)
            bc.cen[3 * i + k] = 0.5 * (boxes[6 * i + k] + boxes[6 * i + 3 + k]);
    }
    if (n > 0)
        build(&bc, 0, n);
    free(bc.cen);
    return h;
}

void arr_bvh_free(arr_bvh *h)
{
    if (!h)
        return;
    free(h->nodes);
    free(h->idx);
    free(h->own);
    free(h);
}

static int overlap(const double *alo, const double *ahi, const double *blo, const double *bhi)
{
    for (int k = 0; k < 3; k++)
        if (alo[k] > bhi[k] || blo[k] > ahi[k])
            return 0;
    return 1;
}

/* Pairs of boxes under nodes a and b (a == b: pairs within one subtree), by an explicit
 * stack of node pairs. */
int arr_bvh_pairs(const arr_bvh *h, int (*fn)(void *user, int64_t i, int64_t j), void *user)
{
    if (h->nnodes == 0)
        return 1;
    int64_t cap = 256, top = 0;
    int64_t *stack = malloc((size_t)cap * 2 * sizeof *stack);
    if (!stack)
        return -1;
    stack[top++] = 0;
    stack[top++] = 0;
    int ok = 1;
    while (top > 0 && ok == 1) {
        int64_t b = stack[--top], a = stack[--top];
        const node *A = &h->nodes[a], *B = &h->nodes[b];
        if (a != b && !overlap(A->lo, A->hi, B->lo, B->hi))
            continue;
        if (A->count && B->count) {
            for (int64_t i = A->right; i < A->right + A->count && ok == 1; i++) {
                int64_t j0 = a == b ? i + 1 : B->right;
                for (int64_t j = j0; j < B->right + B->count; j++) {
                    int64_t x = h->idx[i], y = h->idx[j];
                    const double *bx = h->boxes + 6 * x, *by = h->boxes + 6 * y;
                    if (!overlap(bx, bx + 3, by, by + 3))
                        continue;
                    if (!fn(user, x < y ? x : y, x < y ? y : x)) {
                        ok = 0;
                        break;
                    }
                }
            }
            continue;
        }
        if (top + 6 > 2 * cap) {
            int64_t *ns = realloc(stack, (size_t)cap * 4 * sizeof *ns);
            if (!ns) {
                ok = -1;
                break;
            }
            stack = ns;
            cap *= 2;
        }
        if (a == b) {
            int64_t l = a + 1, r = A->right;
            stack[top++] = l;
            stack[top++] = l;
            stack[top++] = r;
            stack[top++] = r;
            stack[top++] = l;
            stack[top++] = r;
        } else if (A->count || (!B->count && (B->hi[0] - B->lo[0]) > (A->hi[0] - A->lo[0]))) {
            /* descend into the internal (or the larger) one */
            stack[top++] = a;
            stack[top++] = b + 1;
            stack[top++] = a;
            stack[top++] = B->right;
        } else {
            stack[top++] = a + 1;
            stack[top++] = b;
            stack[top++] = A->right;
            stack[top++] = b;
        }
    }
    free(stack);
    return ok;
}

int arr_bvh_ray(const arr_bvh *h, const double o[3], int axis, int dir,
                int (*fn)(void *user, int64_t i), void *user)
{
    if (h->nnodes == 0)
        return 1;
    int64_t stack[256];
    int top = 0;
    stack[top++] = 0;
    int i1 = (axis + 1) % 3, i2 = (axis + 2) % 3;
    while (top > 0) {
        int64_t ni = stack[--top];
        const node *n = &h->nodes[ni];
        if (o[i1] < n->lo[i1] - RAY_PAD || o[i1] > n->hi[i1] + RAY_PAD ||
            o[i2] < n->lo[i2] - RAY_PAD || o[i2] > n->hi[i2] + RAY_PAD)
            continue;
        if (dir > 0 ? n->hi[axis] + RAY_PAD < o[axis] : n->lo[axis] - RAY_PAD > o[axis])
            continue;
        if (n->count) {
            for (int64_t i = n->right; i < n->right + n->count; i++) {
                int64_t b = h->idx[i];
                const double *bx = h->boxes + 6 * b;
                if (o[i1] < bx[i1] - RAY_PAD || o[i1] > bx[3 + i1] + RAY_PAD ||
                    o[i2] < bx[i2] - RAY_PAD || o[i2] > bx[3 + i2] + RAY_PAD)
                    continue;
                if (dir > 0 ? bx[3 + axis] + RAY_PAD < o[axis] : bx[axis] - RAY_PAD > o[axis])
                    continue;
                if (!fn(user, b))
                    return 0;
            }
            continue;
        }
        if (top + 2 > 256)
            return -1; /* cannot happen: the depth of median splits is ~log2(n) */
        stack[top++] = ni + 1;
        stack[top++] = n->right;
    }
    return 1;
}
