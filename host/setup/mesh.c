/* mesh.c — closed triangle meshes as scene shapes (see mesh.h). */
#include "mesh.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Triangles a mesh may have: a part for an SPH run is a few hundred
 * thousand at most; the bound keeps a malformed file from asking for
 * gigabytes. */
#define SPH_MESH_MAX_TRIANGLES 5000000
/* leaves of the bounding-volume hierarchy hold at most this many triangles */
#define BVH_LEAF 4

typedef struct {
    double lo[3], hi[3];
    int left, right;  /* children, -1 for a leaf */
    int first, count; /* a leaf's triangles: order[first .. first + count) */
} bvh_node;

struct sph_mesh {
    int nv, nt;
    double *v;  /* 3 nv: vertex positions */
    int *t;     /* 3 nt: vertex indices, counter-clockwise seen from outside */
    double *fn; /* 3 nt: unit face normals */
    double *en; /* 9 nt: pseudonormal of edge k (vertex k to k + 1): sum of its faces' normals */
    double *vn; /* 3 nv: angle-weighted vertex pseudonormals */
    double lower[3], upper[3], volume;
    bvh_node *nodes;
    int *order;
};

static void sub(const double *a, const double *b, double *r) {
    for (int k = 0; k < 3; k++) r[k] = a[k] - b[k];
}
static double dot(const double *a, const double *b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static void cross(const double *a, const double *b, double *r) {
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}
static const double *vert(const sph_mesh *m, int tri, int k) {
    return m->v + 3 * m->t[3 * tri + k];
}

void sph_mesh_free(sph_mesh *m) {
    if (!m) return;
    free(m->v);
    free(m->t);
    free(m->fn);
    free(m->en);
    free(m->vn);
    free(m->nodes);
    free(m->order);
    free(m);
}

/* ---- reading and welding ------------------------------------------------ */

/* a vertex and its index, sorted by position to weld equal ones */
typedef struct {
    float p[3];
    int i;
} weld_rec;

static int cmp_position(const void *pa, const void *pb) {
    const weld_rec *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->p[k] != b->p[k]) return a->p[k] < b->p[k] ? -1 : 1;
    return a->i - b->i;
}

/* The scene's triangles into m->v (welded by exact position) and m->t. */
static bool gather(const struct aiScene *sc, sph_mesh *m, char *why, size_t len) {
    long nv = 0, nt = 0;
    for (unsigned k = 0; k < sc->mNumMeshes; k++) {
        const struct aiMesh *me = sc->mMeshes[k];
        nv += me->mNumVertices;
        for (unsigned f = 0; f < me->mNumFaces; f++) nt += me->mFaces[f].mNumIndices == 3;
    }
    if (nt == 0) {
        snprintf(why, len, "holds no triangles (%u meshes, %ld vertices)", sc->mNumMeshes, nv);
        return false;
    }
    if (nt > SPH_MESH_MAX_TRIANGLES) {
        snprintf(why, len, "holds %ld triangles, more than the %d a mesh may have", nt,
                 SPH_MESH_MAX_TRIANGLES);
        return false;
    }
    weld_rec *raw = malloc(sizeof(weld_rec) * (size_t)(nv > 0 ? nv : 1));
    int *first = malloc(sizeof(int) * (sc->mNumMeshes + 1));
    int *id = malloc(sizeof(int) * (size_t)(nv > 0 ? nv : 1));
    m->t = malloc(sizeof(int) * 3 * (size_t)nt);
    m->v = malloc(sizeof(double) * 3 * (size_t)(nv > 0 ? nv : 1));
    bool ok = raw && first && id && m->t && m->v;
    if (!ok) snprintf(why, len, "out of memory for %ld vertices", nv);
    long base = 0;
    for (unsigned k = 0; ok && k < sc->mNumMeshes; k++) {
        const struct aiMesh *me = sc->mMeshes[k];
        first[k] = (int)base;
        for (unsigned i = 0; i < me->mNumVertices; i++) {
            const float p[3] = {me->mVertices[i].x, me->mVertices[i].y, me->mVertices[i].z};
            for (int a = 0; a < 3; a++) {
                if (!isfinite(p[a])) {
                    snprintf(why, len, "vertex %u of mesh %u is not finite", i, k);
                    ok = false;
                }
                raw[base + i].p[a] = p[a];
            }
            raw[base + i].i = (int)(base + i);
        }
        base += me->mNumVertices;
    }
    if (ok) {
        /* weld: vertices at exactly the same position are one (STL stores
         * each triangle's corners apart, OBJ may split them by normal) */
        qsort(raw, (size_t)nv, sizeof(weld_rec), cmp_position);
        int n = 0;
        for (long s = 0; s < nv; s++) {
            if (s == 0 || raw[s].p[0] != raw[s - 1].p[0] || raw[s].p[1] != raw[s - 1].p[1] ||
                raw[s].p[2] != raw[s - 1].p[2]) {
                for (int a = 0; a < 3; a++) m->v[3 * n + a] = raw[s].p[a];
                ++n;
            }
            id[raw[s].i] = n - 1;
        }
        m->nv = n;
        long t = 0;
        for (unsigned k = 0; k < sc->mNumMeshes; k++) {
            const struct aiMesh *me = sc->mMeshes[k];
            for (unsigned f = 0; f < me->mNumFaces; f++) {
                if (me->mFaces[f].mNumIndices != 3) continue;
                for (int c = 0; c < 3; c++) {
                    const unsigned vi = me->mFaces[f].mIndices[c];
                    if (vi >= me->mNumVertices) {
                        snprintf(why, len, "face %u of mesh %u refers to vertex %u of %u", f, k, vi,
                                 me->mNumVertices);
                        ok = false;
                        break;
                    }
                    m->t[3 * t + c] = id[first[k] + (int)vi];
                }
                if (!ok) break;
                ++t;
            }
            if (!ok) break;
        }
        m->nt = (int)t;
    }
    free(raw);
    free(first);
    free(id);
    return ok;
}

static void transform(sph_mesh *m, const sph_mesh_transform *tf) {
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int axis = 0; axis < 3; axis++) {
        const double a = tf->rotate_deg[axis] * (3.14159265358979323846 / 180.0);
        const double c = cos(a), s = sin(a);
        double q[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        const int i = (axis + 1) % 3, j = (axis + 2) % 3;
        q[i][i] = c, q[i][j] = -s, q[j][i] = s, q[j][j] = c;
        double p[3][3];
        for (int u = 0; u < 3; u++)
            for (int w = 0; w < 3; w++)
                p[u][w] = q[u][0] * r[0][w] + q[u][1] * r[1][w] + q[u][2] * r[2][w];
        memcpy(r, p, sizeof r);
    }
    for (int i = 0; i < m->nv; i++) {
        double x[3];
        for (int a = 0; a < 3; a++) x[a] = tf->scale * m->v[3 * i + a];
        for (int a = 0; a < 3; a++)
            m->v[3 * i + a] = tf->translate[a] + r[a][0] * x[0] + r[a][1] * x[1] + r[a][2] * x[2];
    }
}

/* ---- checks and normals ------------------------------------------------- */

typedef struct {
    int lo, hi;  /* vertex indices, lo < hi */
    int forward; /* 1 if the triangle runs lo -> hi */
    int tri, k;  /* triangle and its edge (vertex k to k + 1) */
} edge_rec;

static int cmp_edge(const void *pa, const void *pb) {
    const edge_rec *a = pa, *b = pb;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return a->tri - b->tri;
}

static bool check_and_normals(sph_mesh *m, char *why, size_t len) {
    for (int a = 0; a < 3; a++) m->lower[a] = INFINITY, m->upper[a] = -INFINITY;
    for (int i = 0; i < m->nv; i++)
        for (int a = 0; a < 3; a++) {
            m->lower[a] = fmin(m->lower[a], m->v[3 * i + a]);
            m->upper[a] = fmax(m->upper[a], m->v[3 * i + a]);
        }
    double diag2 = 0.0;
    for (int a = 0; a < 3; a++) diag2 += (m->upper[a] - m->lower[a]) * (m->upper[a] - m->lower[a]);
    if (!(diag2 > 0.0) || !isfinite(diag2)) {
        snprintf(why, len, "its vertices span no volume (bounding box diagonal %g)", sqrt(diag2));
        return false;
    }
    m->fn = malloc(sizeof(double) * 3 * (size_t)m->nt);
    m->en = calloc(9 * (size_t)m->nt, sizeof(double));
    m->vn = calloc(3 * (size_t)m->nv, sizeof(double));
    edge_rec *e = malloc(sizeof(edge_rec) * 3 * (size_t)m->nt);
    if (!m->fn || !m->en || !m->vn || !e) {
        free(e);
        snprintf(why, len, "out of memory for %d triangles", m->nt);
        return false;
    }
    /* degenerate triangles: a repeated vertex or an area below 1e-12 of the
     * bounding box's diagonal squared */
    int degenerate = 0, first_bad = -1;
    double volume = 0.0;
    for (int t = 0; t < m->nt; t++) {
        const double *p0 = vert(m, t, 0), *p1 = vert(m, t, 1), *p2 = vert(m, t, 2);
        double u[3], w[3], n[3];
        sub(p1, p0, u);
        sub(p2, p0, w);
        cross(u, w, n);
        const double area2 = sqrt(dot(n, n));
        volume += dot(p0, n) / 6.0;
        if (!(area2 > 1e-12 * diag2)) {
            if (first_bad < 0) first_bad = t;
            ++degenerate;
            continue;
        }
        for (int a = 0; a < 3; a++) m->fn[3 * t + a] = n[a] / area2;
    }
    if (degenerate) {
        const double *p = vert(m, first_bad, 0);
        snprintf(why, len,
                 "has %d degenerate triangle%s (zero area or a repeated vertex), the first "
                 "(triangle %d) at (%g, %g, %g)",
                 degenerate, degenerate == 1 ? "" : "s", first_bad, p[0], p[1], p[2]);
        free(e);
        return false;
    }
    /* edges: each must be shared by exactly two triangles running along it
     * in opposite directions */
    for (int t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            const int a = m->t[3 * t + k], b = m->t[3 * t + (k + 1) % 3];
            e[3 * t + k] = (edge_rec){a < b ? a : b, a < b ? b : a, a < b, t, k};
        }
    qsort(e, 3 * (size_t)m->nt, sizeof(edge_rec), cmp_edge);
    int open = 0, crowded = 0, flipped = 0;
    const edge_rec *first_open = NULL, *first_crowded = NULL, *first_flipped = NULL;
    for (long s = 0; s < 3L * m->nt;) {
        long r = s + 1;
        while (r < 3L * m->nt && e[r].lo == e[s].lo && e[r].hi == e[s].hi) ++r;
        const long count = r - s;
        if (count == 1) {
            if (!open++) first_open = &e[s];
        } else if (count > 2) {
            if (!crowded++) first_crowded = &e[s];
        } else if (e[s].forward == e[s + 1].forward) {
            if (!flipped++) first_flipped = &e[s];
        } else {
            for (int q = 0; q < 2; q++) {
                const edge_rec *x = &e[s + q], *y = &e[s + 1 - q];
                for (int a = 0; a < 3; a++)
                    m->en[9 * x->tri + 3 * x->k + a] =
                        m->fn[3 * x->tri + a] + m->fn[3 * y->tri + a];
            }
        }
        s = r;
    }
    const edge_rec *bad = first_open ? first_open : first_crowded ? first_crowded : first_flipped;
    if (bad) {
        const double *p = m->v + 3 * bad->lo, *q = m->v + 3 * bad->hi;
        if (open)
            snprintf(why, len,
                     "is not closed: %d boundary edge%s (used by one triangle), the first from "
                     "(%g, %g, %g) to (%g, %g, %g); a body needs a watertight surface",
                     open, open == 1 ? "" : "s", p[0], p[1], p[2], q[0], q[1], q[2]);
        else if (crowded)
            snprintf(why, len,
                     "is not a manifold: %d edge%s shared by more than two triangles, the first "
                     "from (%g, %g, %g) to (%g, %g, %g)",
                     crowded, crowded == 1 ? "" : "s", p[0], p[1], p[2], q[0], q[1], q[2]);
        else
            snprintf(why, len,
                     "has inverted triangles: %d edge%s whose two triangles run the same way "
                     "(inconsistent winding), the first from (%g, %g, %g) to (%g, %g, %g)",
                     flipped, flipped == 1 ? "" : "s", p[0], p[1], p[2], q[0], q[1], q[2]);
        free(e);
        return false;
    }
    free(e);
    if (!(volume > 0.0)) {
        snprintf(why, len,
                 "is inside out: its triangles face inward (enclosed volume %g < 0); reverse "
                 "their winding",
                 volume);
        return false;
    }
    m->volume = volume;
    /* angle-weighted vertex pseudonormals */
    for (int t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            const double *p = vert(m, t, k), *q = vert(m, t, (k + 1) % 3),
                         *r = vert(m, t, (k + 2) % 3);
            double u[3], w[3];
            sub(q, p, u);
            sub(r, p, w);
            const double c = dot(u, w) / sqrt(dot(u, u) * dot(w, w));
            const double angle = acos(fmax(-1.0, fmin(1.0, c)));
            for (int a = 0; a < 3; a++) m->vn[3 * m->t[3 * t + k] + a] += angle * m->fn[3 * t + a];
        }
    return true;
}

/* ---- bounding-volume hierarchy ------------------------------------------ */

/* a triangle and its centroid's coordinate along the split axis */
typedef struct {
    double key;
    int tri;
} split_rec;

static int cmp_split(const void *pa, const void *pb) {
    const split_rec *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return a->tri - b->tri;
}

static int build_node(sph_mesh *m, const double *centroid, split_rec *tmp, int first, int count,
                      int *nnodes) {
    const int id = (*nnodes)++;
    bvh_node *nd = &m->nodes[id];
    for (int a = 0; a < 3; a++) nd->lo[a] = INFINITY, nd->hi[a] = -INFINITY;
    for (int s = first; s < first + count; s++)
        for (int k = 0; k < 3; k++) {
            const double *p = vert(m, m->order[s], k);
            for (int a = 0; a < 3; a++) {
                nd->lo[a] = fmin(nd->lo[a], p[a]);
                nd->hi[a] = fmax(nd->hi[a], p[a]);
            }
        }
    nd->first = first;
    nd->count = count;
    nd->left = nd->right = -1;
    if (count <= BVH_LEAF) return id;
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (nd->hi[a] - nd->lo[a] > nd->hi[axis] - nd->lo[axis]) axis = a;
    for (int s = 0; s < count; s++)
        tmp[s] = (split_rec){centroid[3 * m->order[first + s] + axis], m->order[first + s]};
    qsort(tmp, (size_t)count, sizeof(split_rec), cmp_split);
    for (int s = 0; s < count; s++) m->order[first + s] = tmp[s].tri;
    const int half = count / 2;
    const int left = build_node(m, centroid, tmp, first, half, nnodes);
    const int right = build_node(m, centroid, tmp, first + half, count - half, nnodes);
    m->nodes[id].left = left;
    m->nodes[id].right = right;
    return id;
}

static bool build_bvh(sph_mesh *m, char *why, size_t len) {
    m->nodes = malloc(sizeof(bvh_node) * 2 * (size_t)m->nt);
    m->order = malloc(sizeof(int) * (size_t)m->nt);
    double *centroid = malloc(sizeof(double) * 3 * (size_t)m->nt);
    split_rec *tmp = malloc(sizeof(split_rec) * (size_t)m->nt);
    if (!m->nodes || !m->order || !centroid || !tmp) {
        free(centroid);
        free(tmp);
        snprintf(why, len, "out of memory for the search tree of %d triangles", m->nt);
        return false;
    }
    for (int t = 0; t < m->nt; t++) {
        m->order[t] = t;
        for (int a = 0; a < 3; a++)
            centroid[3 * t + a] = (vert(m, t, 0)[a] + vert(m, t, 1)[a] + vert(m, t, 2)[a]) / 3.0;
    }
    int nnodes = 0;
    build_node(m, centroid, tmp, 0, m->nt, &nnodes);
    free(centroid);
    free(tmp);
    return true;
}

/* ---- self-intersection -------------------------------------------------- */

/* The pseudonormal's sign is exact only for a surface that does not meet
 * itself: a fold, a corner pulled through a face, or two overlapping parts
 * exported as one file would put points inside that are outside (and the
 * relaxation's surface where there is none), so such a mesh is refused.  Two
 * triangles of a closed manifold that does not meet itself share points only
 * where they share vertices: their common edge, their common vertex.  Every
 * pair whose bounding boxes overlap (through the hierarchy) is tested for a
 * common point elsewhere; distances below 1e-9 of the bounding box's
 * diagonal count as zero (SELF_MEET_TOLERANCE), so a surface that touches
 * itself (two parts sharing a face, a vertex on another face) is refused
 * too. */
#define SELF_MEET_TOLERANCE 1e-9

typedef struct {
    double tol;         /* distances at most this are zero */
    int axis_u, axis_v; /* the plane of projection of the triangle tested against */
} meet_frame;

static double cross2(const double *a, const double *b, const meet_frame *f) {
    return a[f->axis_u] * b[f->axis_v] - a[f->axis_v] * b[f->axis_u];
}

/* the projection that keeps a plane of unit normal n least distorted: drop
 * its largest component */
static meet_frame frame_of(const double *n, double tol) {
    int drop = 0;
    for (int a = 1; a < 3; a++)
        if (fabs(n[a]) > fabs(n[drop])) drop = a;
    return (meet_frame){tol, (drop + 1) % 3, (drop + 2) % 3};
}

/* a point of the same plane within tol of the triangle (a, b, c) */
static bool in_triangle_2d(const double *p, const double *a, const double *b, const double *c,
                           const meet_frame *f) {
    const double *corner[3] = {a, b, c};
    double e[3], w[3];
    sub(b, a, e);
    sub(c, a, w);
    const double orientation = cross2(e, w, f) > 0.0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; k++) {
        const double *s = corner[k], *t = corner[(k + 1) % 3];
        sub(t, s, e);
        sub(p, s, w);
        /* the signed distance from the edge's line, inside positive */
        const double length = hypot(e[f->axis_u], e[f->axis_v]);
        if (orientation * cross2(e, w, f) < -f->tol * length) return false;
    }
    return true;
}

static bool far_from(const double *x, const double *excluded, double tol) {
    double d[3];
    if (!excluded) return true;
    sub(x, excluded, d);
    return dot(d, d) > tol * tol;
}

/* a common point of the segments pq and ab of one plane, other than
 * `excluded` (NULL: none), into at */
static bool segments_meet_2d(const double *p, const double *q, const double *a, const double *b,
                             const double *excluded, const meet_frame *f, double *at) {
    double r[3], s[3], ap[3];
    sub(q, p, r);
    sub(b, a, s);
    sub(a, p, ap);
    const double lr = hypot(r[f->axis_u], r[f->axis_v]), ls = hypot(s[f->axis_u], s[f->axis_v]);
    const double denom = cross2(r, s, f);
    if (fabs(denom) > 1e-12 * lr * ls) { /* not parallel */
        const double u = cross2(ap, s, f) / denom, v = cross2(ap, r, f) / denom;
        if (u < -f->tol / lr || u > 1.0 + f->tol / lr || v < -f->tol / ls || v > 1.0 + f->tol / ls)
            return false;
        for (int k = 0; k < 3; k++) at[k] = p[k] + u * r[k];
        return far_from(at, excluded, f->tol);
    }
    /* parallel: apart, or overlapping along one line */
    if (fabs(cross2(ap, r, f)) > f->tol * lr) return false;
    const double *ends[4] = {p, q, a, b};
    for (int k = 0; k < 4; k++) {
        /* an end of one segment on the other */
        const double *x = ends[k], *o0 = k < 2 ? a : p, *o1 = k < 2 ? b : q;
        double d[3], xo[3];
        sub(o1, o0, d);
        sub(x, o0, xo);
        const double l2 = d[f->axis_u] * d[f->axis_u] + d[f->axis_v] * d[f->axis_v];
        const double t = (xo[f->axis_u] * d[f->axis_u] + xo[f->axis_v] * d[f->axis_v]) / l2;
        const double slack = f->tol / sqrt(l2);
        if (t >= -slack && t <= 1.0 + slack && far_from(x, excluded, f->tol)) {
            memcpy(at, x, 3 * sizeof(double));
            return true;
        }
    }
    return false;
}

/* a common point of the segment pq and the triangle tri, other than
 * `excluded`, into at */
static bool segment_meets_triangle(const sph_mesh *m, const double *p, const double *q, int tri,
                                   const double *excluded, double tol, double *at) {
    const double *a = vert(m, tri, 0), *b = vert(m, tri, 1), *c = vert(m, tri, 2);
    const double *n = m->fn + 3 * tri;
    double ap[3], aq[3];
    sub(p, a, ap);
    sub(q, a, aq);
    const double dp = dot(n, ap), dq = dot(n, aq);
    if ((dp > tol && dq > tol) || (dp < -tol && dq < -tol)) return false;
    const meet_frame f = frame_of(n, tol);
    if (fabs(dp) <= tol && fabs(dq) <= tol) {
        /* in the triangle's plane: an end inside it, or a crossing of its edges */
        if (in_triangle_2d(p, a, b, c, &f) && far_from(p, excluded, tol)) {
            memcpy(at, p, sizeof(double) * 3);
            return true;
        }
        if (in_triangle_2d(q, a, b, c, &f) && far_from(q, excluded, tol)) {
            memcpy(at, q, sizeof(double) * 3);
            return true;
        }
        return segments_meet_2d(p, q, a, b, excluded, &f, at) ||
               segments_meet_2d(p, q, b, c, excluded, &f, at) ||
               segments_meet_2d(p, q, c, a, excluded, &f, at);
    }
    /* through the plane: where it crosses */
    const double s = dp / (dp - dq);
    for (int k = 0; k < 3; k++) at[k] = p[k] + s * (q[k] - p[k]);
    return in_triangle_2d(at, a, b, c, &f) && far_from(at, excluded, tol);
}

/* Triangles t and u meet other than along the edge or at the vertex they
 * share: a point common to both into at. */
static bool triangles_meet(const sph_mesh *m, int t, int u, double tol, double *at) {
    /* the corners of t and of u that the other shares, as bit masks */
    int shared = 0, shared_vertex = -1, t_shares = 0, u_shares = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (m->t[3 * t + i] == m->t[3 * u + j]) {
                ++shared, shared_vertex = m->t[3 * t + i];
                t_shares |= 1 << i, u_shares |= 1 << j;
            }
    if (shared == 3) { /* the same triangle twice */
        for (int a = 0; a < 3; a++)
            at[a] = (vert(m, t, 0)[a] + vert(m, t, 1)[a] + vert(m, t, 2)[a]) / 3.0;
        return true;
    }
    if (shared == 2) {
        /* two planes through one edge meet only there, unless they are one
         * plane and the triangles lie on the same side of the edge (a fold) */
        /* the corner each does not share */
        const int k = t_shares == 6 ? 0 : t_shares == 5 ? 1 : 2;
        const int l = u_shares == 6 ? 0 : u_shares == 5 ? 1 : 2;
        const double *c = vert(m, t, k), *d = vert(m, u, l);
        const double *e0 = vert(m, t, (k + 1) % 3), *e1 = vert(m, t, (k + 2) % 3);
        double edge[3], ec[3], ed[3], nc[3], nd[3];
        sub(e1, e0, edge);
        sub(c, e0, ec);
        sub(d, e0, ed);
        if (fabs(dot(m->fn + 3 * t, ed)) > tol) return false;
        cross(edge, ec, nc);
        cross(edge, ed, nd);
        if (!(dot(nc, nd) > 0.0)) return false;
        memcpy(at, d, sizeof(double) * 3);
        return true;
    }
    const double *excluded = shared == 1 ? m->v + 3 * shared_vertex : NULL;
    for (int pass = 0; pass < 2; pass++) {
        const int edges_of = pass ? u : t, against = pass ? t : u;
        for (int k = 0; k < 3; k++)
            if (segment_meets_triangle(m, vert(m, edges_of, k), vert(m, edges_of, (k + 1) % 3),
                                       against, excluded, tol, at))
                return true;
    }
    return false;
}

static bool check_self_intersection(const sph_mesh *m, char *why, size_t len) {
    double diag2 = 0.0;
    for (int a = 0; a < 3; a++) diag2 += (m->upper[a] - m->lower[a]) * (m->upper[a] - m->lower[a]);
    const double tol = SELF_MEET_TOLERANCE * sqrt(diag2);
    long pairs = 0;
    int first_t = -1, first_u = -1;
    double first_at[3] = {0, 0, 0};
    for (int t = 0; t < m->nt; t++) {
        double lo[3], hi[3];
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(vert(m, t, 0)[a], fmin(vert(m, t, 1)[a], vert(m, t, 2)[a])) - tol;
            hi[a] = fmax(vert(m, t, 0)[a], fmax(vert(m, t, 1)[a], vert(m, t, 2)[a])) + tol;
        }
        int stack[128], top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const bvh_node *nd = &m->nodes[stack[--top]];
            bool apart = false;
            for (int a = 0; a < 3; a++) apart = apart || nd->hi[a] < lo[a] || nd->lo[a] > hi[a];
            if (apart) continue;
            if (nd->left >= 0) {
                if (top + 2 > (int)(sizeof stack / sizeof stack[0]))
                    continue; /* depth ~ log2(nt) */
                stack[top++] = nd->left;
                stack[top++] = nd->right;
                continue;
            }
            for (int s = nd->first; s < nd->first + nd->count; s++) {
                const int u = m->order[s];
                double at[3];
                if (u <= t || !triangles_meet(m, t, u, tol, at)) continue;
                ++pairs;
                if (first_t < 0 || (t == first_t && u < first_u)) {
                    first_t = t, first_u = u;
                    memcpy(first_at, at, sizeof first_at);
                }
            }
        }
    }
    if (!pairs) return true;
    snprintf(why, len,
             "intersects itself: %ld pair%s of triangles meet away from a shared edge or vertex, "
             "the first triangles %d and %d at (%g, %g, %g); a body needs one closed surface "
             "that neither crosses nor touches itself (overlapping parts exported as one file: "
             "join them by a boolean union in the CAD or mesh tool, or give each part its own "
             "mesh shape and combine them with a \"union\" shape)",
             pairs, pairs == 1 ? "" : "s", first_t, first_u, first_at[0], first_at[1], first_at[2]);
    return false;
}

sph_mesh *sph_mesh_load(const char *path, const void *data, size_t size, const char *hint,
                        const sph_mesh_transform *tf, char *why, size_t len) {
    const unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices;
    const struct aiScene *sc = NULL;
    if (data) {
        if (size == 0 || size > 0x7fffffffu) {
            snprintf(why, len, "is empty or too large (%zu bytes)", size);
            return NULL;
        }
        if (!hint || (strcmp(hint, "stl") != 0 && strcmp(hint, "obj") != 0)) {
            snprintf(why, len, "format '%s' is not read (STL, OBJ)", hint ? hint : "");
            return NULL;
        }
        sc = aiImportFileFromMemory(data, (unsigned)size, flags, hint);
    } else {
        /* the formats a scene may name: STL and OBJ (by extension; assimp
         * would otherwise guess among its forty formats from the content) */
        const char *dot = strrchr(path, '.');
        const char *ext = dot && !strchr(dot, '/') ? dot + 1 : "";
        if (strcasecmp(ext, "stl") != 0 && strcasecmp(ext, "obj") != 0) {
            snprintf(why, len,
                     "is not an .stl or .obj file (the formats read: STL, ASCII or "
                     "binary, and OBJ)");
            return NULL;
        }
        FILE *f = fopen(path, "rb");
        if (!f) {
            snprintf(why, len, "cannot open it: %s", strerror(errno));
            return NULL;
        }
        fclose(f);
        sc = aiImportFile(path, flags);
    }
    if (!sc) {
        snprintf(why, len, "cannot read it as a mesh: %s", aiGetErrorString());
        return NULL;
    }
    sph_mesh *m = calloc(1, sizeof *m);
    bool ok = m != NULL;
    if (!ok) snprintf(why, len, "out of memory");
    ok = ok && gather(sc, m, why, len);
    aiReleaseImport(sc);
    if (ok) transform(m, tf);
    ok = ok && check_and_normals(m, why, len) && build_bvh(m, why, len) &&
         check_self_intersection(m, why, len);
    if (!ok) {
        sph_mesh_free(m);
        return NULL;
    }
    return m;
}

int sph_mesh_triangles(const sph_mesh *m) {
    return m->nt;
}

double sph_mesh_volume(const sph_mesh *m) {
    return m->volume;
}

void sph_mesh_bounds(const sph_mesh *m, double lower[3], double upper[3]) {
    for (int a = 0; a < 3; a++) lower[a] = m->lower[a], upper[a] = m->upper[a];
}

/* ---- queries ------------------------------------------------------------ */

/* The point of triangle t nearest x (Ericson, Real-Time Collision Detection
 * §5.1.5) into p; returns the feature: 0 the face, 1 + k vertex k, 4 + k the
 * edge from vertex k to k + 1. */
static int closest_on_triangle(const sph_mesh *m, int t, const double *x, double *p) {
    const double *a = vert(m, t, 0), *b = vert(m, t, 1), *c = vert(m, t, 2);
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    sub(b, a, ab);
    sub(c, a, ac);
    sub(x, a, ap);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return memcpy(p, a, 3 * sizeof(double)), 1;
    sub(x, b, bp);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return memcpy(p, b, 3 * sizeof(double)), 2;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++) p[k] = a[k] + v * ab[k];
        return 4;
    }
    sub(x, c, cp);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return memcpy(p, c, 3 * sizeof(double)), 3;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++) p[k] = a[k] + w * ac[k];
        return 6; /* edge c -> a */
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++) p[k] = b[k] + w * (c[k] - b[k]);
        return 5;
    }
    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    for (int k = 0; k < 3; k++) p[k] = a[k] + ab[k] * v + ac[k] * w;
    return 0;
}

static double box_distance2(const bvh_node *nd, const double *x) {
    double d2 = 0.0;
    for (int a = 0; a < 3; a++) {
        const double d = x[a] < nd->lo[a]   ? nd->lo[a] - x[a]
                         : x[a] > nd->hi[a] ? x[a] - nd->hi[a]
                                            : 0.0;
        d2 += d * d;
    }
    return d2;
}

/* Within the mesh's bounding box (a closed surface lies inside it). */
static bool in_bounding_box(const sph_mesh *m, const double x[3]) {
    for (int a = 0; a < 3; a++)
        if (x[a] < m->lower[a] || x[a] > m->upper[a]) return false;
    return true;
}

double sph_mesh_sdf(const sph_mesh *m, const double x[3], double normal[3]) {
    double best = INFINITY, p[3] = {0, 0, 0};
    int best_tri = 0, best_feature = 0;
    int stack[128], top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *nd = &m->nodes[stack[--top]];
        if (box_distance2(nd, x) >= best) continue;
        if (nd->left < 0) {
            for (int s = nd->first; s < nd->first + nd->count; s++) {
                double q[3], d[3];
                const int feature = closest_on_triangle(m, m->order[s], x, q);
                sub(x, q, d);
                const double d2 = dot(d, d);
                if (d2 < best) {
                    best = d2, best_tri = m->order[s], best_feature = feature;
                    memcpy(p, q, sizeof p);
                }
            }
            continue;
        }
        /* the nearer child last, so that it is searched first */
        const double dl = box_distance2(&m->nodes[nd->left], x);
        const double dr = box_distance2(&m->nodes[nd->right], x);
        if (top + 2 > (int)(sizeof stack / sizeof stack[0])) continue; /* depth ~ log2(nt) */
        stack[top++] = dl < dr ? nd->right : nd->left;
        stack[top++] = dl < dr ? nd->left : nd->right;
    }
    /* the pseudonormal of the nearest feature signs the distance; a point
     * outside the bounding box is outside whatever the pseudonormal says (a
     * guard: it can say inside where a surface intersects itself, such as
     * the cube with one corner pulled through a face of
     * tests/fuzz/mesh_regressions, which check_self_intersection refuses) */
    const double *pn = best_feature == 0   ? m->fn + 3 * best_tri
                       : best_feature <= 3 ? m->vn + 3 * m->t[3 * best_tri + best_feature - 1]
                                           : m->en + 9 * best_tri + 3 * (best_feature - 4);
    double d[3];
    sub(x, p, d);
    const double dist = sqrt(best);
    const double sign = !in_bounding_box(m, x) || dot(d, pn) >= 0.0 ? 1.0 : -1.0;
    if (normal) {
        if (dist > 1e-12 * (m->upper[0] - m->lower[0] + m->upper[1] - m->lower[1])) {
            for (int a = 0; a < 3; a++) normal[a] = sign * d[a] / dist;
        } else {
            const double ln = sqrt(dot(pn, pn));
            for (int a = 0; a < 3; a++) normal[a] = pn[a] / ln;
        }
    }
    return sign * dist;
}

bool sph_mesh_contains(const sph_mesh *m, const double x[3]) {
    return in_bounding_box(m, x) && sph_mesh_sdf(m, x, NULL) <= 0.0;
}

uint64_t sph_mesh_hash(const sph_mesh *m, uint64_t h) {
    const unsigned char *p = (const unsigned char *)m->v;
    for (size_t i = 0; i < sizeof(double) * 3 * (size_t)m->nv; i++)
        h = (h ^ p[i]) * 1099511628211ULL;
    p = (const unsigned char *)m->t;
    for (size_t i = 0; i < sizeof(int) * 3 * (size_t)m->nt; i++) h = (h ^ p[i]) * 1099511628211ULL;
    return h;
}
