/* test_neighbours.c — the configuration rebuild (cell keys, sort, permutation,
 * cell ranges, neighbour gathering) gives exactly the brute-force neighbour
 * sets on a random cloud, in 2D and 3D, including a cloud that forces the
 * neighbour capacity to grow and one spread so wide that the grid coarsens.
 * Run once per backend. */
#include "test_support.h"

#include <math.h>

/* cloud: n points, uniform in a box of side `extent`, plus `cluster` points
 * packed in a tiny ball (to exceed the initial neighbour capacity) */
static void check_cloud(test_counts *t, sph_backend_kind kind, int dim, int n, double extent,
                        int cluster, const char *label) {
    const double dp = 0.01;
    sph_particles p;
    if (test_random_cloud(&p, n, dim, dp, extent, cluster, 2024u + (unsigned)dim)) {
        CHECK(t, 0, "allocation");
        return;
    }
    sph_features f;
    test_feature_set(&f, dim, true, SPH_ROTATION_AVERAGED);
    sph_params_f64 prm[1];
    test_params(prm, dim, dp, n);
    sph_backend *be = NULL;
    sph_error err = {0};
    sph_rebuild_info info;
    sph_neighbour_lists nl = {0};
    double *x = malloc((size_t)n * dim * sizeof(double));
    double *v = malloc((size_t)n * dim * sizeof(double));
    int32_t *id = malloc((size_t)n * sizeof(int32_t));
    sph_status st = test_backend(kind, &f, prm, n, &be, &err);
    const int initial_cap = sph_initial_neighbour_capacity(dim, 2.6);
    if (!st) st = be->ops->upload(be, &p, &err);
    if (!st) st = be->ops->rebuild(be, &info, &err);
    if (!st) st = be->ops->download_neighbours(be, &nl, &err);
    if (!st) st = be->ops->download(be, FIELD_POS, x, &err);
    if (!st) st = be->ops->download(be, FIELD_VEL, v, &err);
    if (!st) st = be->ops->download(be, FIELD_ID, id, &err);
    CHECK(t, st == SPH_OK, "%s: rebuild failed: %s", label, err.msg);
    if (st) goto done;

    /* every field moved with its particle: position and velocity match the
     * initial values of the particle's id */
    int moved_wrong = 0;
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < dim; ++a)
            if (x[(size_t)a * n + i] != p.pos[(size_t)a * n + id[i]] ||
                v[(size_t)a * n + i] != p.vel[(size_t)a * n + id[i]])
                ++moved_wrong;
    CHECK(t, moved_wrong == 0, "%s: %d field values did not follow their particle", label,
          moved_wrong);

    /* brute force with the kernel's own arithmetic: d = x_i - x_j, r2 = d.d */
    const double cutoff2 = prm->cutoff * prm->cutoff;
    int *brute = malloc((size_t)n * sizeof(int));
    long mismatched = 0, pairs = 0;
    int max_count = 0;
    for (int i = 0; i < n; ++i) {
        int m = 0;
        for (int j = 0; j < n; ++j) {
            if (j == i) continue;
            double r2 = 0.0;
            for (int a = 0; a < dim; ++a) {
                const double d = x[(size_t)a * n + i] - x[(size_t)a * n + j];
                r2 += d * d;
            }
            if (r2 < cutoff2 && r2 > 0.0) brute[m++] = j;
        }
        pairs += m;
        if (m > max_count) max_count = m;
        const int c = nl.count[i];
        int *got = nl.j + (size_t)i * nl.cap;
        qsort(got, (size_t)c, sizeof(int), test_cmp_int);
        qsort(brute, (size_t)m, sizeof(int), test_cmp_int);
        if (c != m || memcmp(got, brute, (size_t)m * sizeof(int)) != 0) ++mismatched;
    }
    free(brute);
    CHECK(t, mismatched == 0, "%s: %ld of %d particles have a wrong neighbour set", label,
          mismatched, n);
    printf("%s: %d particles, %ld pairs, max %d neighbours, capacity %d (initial %d)\n", label, n,
           pairs, max_count, nl.cap, initial_cap);
    if (cluster > 0)
        CHECK(t, max_count > initial_cap && nl.cap >= max_count,
              "%s: the cluster must force the capacity to grow (max %d, initial cap %d, cap %d)",
              label, max_count, initial_cap, nl.cap);
done:
    sph_neighbour_lists_free(&nl);
    free(x);
    free(v);
    free(id);
    sph_backend_destroy(be);
    sph_particles_free(&p);
}

int main(int argc, char **argv) {
    test_counts t = {0};
    const sph_backend_kind kind = test_backend_kind(argc, argv);
    check_cloud(&t, kind, 2, 3000, 0.5, 0, "2D random cloud");
    check_cloud(&t, kind, 2, 3000, 0.5, 300, "2D cloud with a dense cluster");
    check_cloud(&t, kind, 3, 4000, 0.15, 0, "3D random cloud");
    check_cloud(&t, kind, 3, 4000, 0.15, 400, "3D cloud with a dense cluster");
    /* spread: a grid of cut-off cells would have ~1e8 cells; it coarsens */
    check_cloud(&t, kind, 2, 1000, 300.0, 500, "2D sparse cloud (coarsened grid)");
    return test_summary("test_neighbours", &t);
}
