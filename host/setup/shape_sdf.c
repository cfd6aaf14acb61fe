/* shape_sdf.c — signed distance and outward normal of the scene's shapes
 * (see shape_sdf.h). */
#include "shape_sdf.h"

#include "mesh.h"

#include <math.h>
#include <string.h>

/* The box-like combination of per-direction distances q[k] along the unit
 * directions dir[k] (k < m): outside (some q > 0) the Euclidean norm of the
 * positive parts, inside the largest q (the nearest face).  A box is this
 * with the signed axis directions; a cylinder with its radial and axial
 * directions. */
static double combine(int m, const double *q, const double dir[][3], double normal[3]) {
    double out2 = 0.0, inside = -INFINITY;
    int nearest = 0;
    for (int k = 0; k < m; k++) {
        if (q[k] > 0.0) out2 += q[k] * q[k];
        if (q[k] > inside) inside = q[k], nearest = k;
    }
    if (out2 > 0.0) {
        const double len = sqrt(out2);
        if (normal) {
            for (int a = 0; a < 3; a++) normal[a] = 0.0;
            for (int k = 0; k < m; k++)
                if (q[k] > 0.0)
                    for (int a = 0; a < 3; a++) normal[a] += q[k] / len * dir[k][a];
        }
        return len;
    }
    if (normal)
        for (int a = 0; a < 3; a++) normal[a] = dir[nearest][a];
    return inside;
}

double sph_shape_sdf(const sph_scene *scene, int shape, const double x[3], double normal[3]) {
    const sph_shape *sh = &scene->shapes[shape];
    const int dim = scene->dim;
    switch (sh->type) {
    case SPH_SHAPE_BOX: {
        double q[3], dir[3][3];
        memset(dir, 0, sizeof dir);
        for (int a = 0; a < dim; a++) {
            const double centre = 0.5 * (sh->lower[a] + sh->upper[a]);
            const double half = 0.5 * (sh->upper[a] - sh->lower[a]);
            const double d = x[a] - centre;
            q[a] = fabs(d) - half;
            dir[a][a] = d < 0.0 ? -1.0 : 1.0;
        }
        return combine(dim, q, dir, normal);
    }
    case SPH_SHAPE_SPHERE: {
        double u[3] = {0, 0, 0}, r2 = 0.0;
        for (int a = 0; a < dim; a++) {
            u[a] = x[a] - sh->centre[a];
            r2 += u[a] * u[a];
        }
        const double r = sqrt(r2);
        if (r > 0.0)
            for (int a = 0; a < dim; a++) u[a] /= r;
        else
            u[0] = 1.0; /* the centre: any direction */
        const double outer = r - sh->outer_radius;
        const double inner = sh->inner_radius > 0.0 ? sh->inner_radius - r : -INFINITY;
        const bool to_inner = inner > outer;
        if (normal)
            for (int a = 0; a < 3; a++) normal[a] = to_inner ? -u[a] : u[a];
        return to_inner ? inner : outer;
    }
    case SPH_SHAPE_CYLINDER: {
        double d[3], s = 0.0, radial[3], rho2 = 0.0;
        for (int a = 0; a < 3; a++) {
            d[a] = x[a] - sh->centre[a];
            s += d[a] * sh->axis[a];
        }
        for (int a = 0; a < 3; a++) {
            radial[a] = d[a] - s * sh->axis[a];
            rho2 += radial[a] * radial[a];
        }
        const double rho = sqrt(rho2);
        double dir[2][3];
        if (rho > 0.0) {
            for (int a = 0; a < 3; a++) dir[0][a] = radial[a] / rho;
        } else {
            /* on the axis: any direction perpendicular to it */
            const int k = fabs(sh->axis[0]) < 0.9 ? 0 : 1;
            double e[3] = {0, 0, 0}, len = 0.0;
            e[k] = 1.0;
            for (int a = 0; a < 3; a++) {
                dir[0][a] = e[a] - sh->axis[k] * sh->axis[a];
                len += dir[0][a] * dir[0][a];
            }
            for (int a = 0; a < 3; a++) dir[0][a] /= sqrt(len);
        }
        const double ds = s - 0.5 * sh->length;
        for (int a = 0; a < 3; a++) dir[1][a] = ds < 0.0 ? -sh->axis[a] : sh->axis[a];
        const double q[2] = {rho - sh->outer_radius, fabs(ds) - 0.5 * sh->length};
        return combine(2, q, (const double(*)[3])dir, normal);
    }
    case SPH_SHAPE_MESH:
        return sph_mesh_sdf(sh->mesh, x, normal);
    case SPH_SHAPE_UNION: {
        double best = INFINITY, n[3];
        for (int i = 0; i < sh->nparts; i++) {
            const double phi = sph_shape_sdf(scene, sh->parts[i], x, normal ? n : NULL);
            if (i == 0 || phi < best) {
                best = phi;
                if (normal) memcpy(normal, n, sizeof n);
            }
        }
        return best;
    }
    case SPH_SHAPE_DIFFERENCE: {
        double n[3];
        double phi = sph_shape_sdf(scene, sh->parts[0], x, normal);
        for (int i = 1; i < sh->nparts; i++) {
            const double cut = -sph_shape_sdf(scene, sh->parts[i], x, normal ? n : NULL);
            if (cut > phi) {
                phi = cut;
                if (normal)
                    for (int a = 0; a < 3; a++) normal[a] = -n[a];
            }
        }
        return phi;
    }
    }
    if (normal) normal[0] = 1.0, normal[1] = normal[2] = 0.0;
    return INFINITY;
}

static uint64_t fnv(uint64_t h, const void *data, size_t len) {
    const unsigned char *p = data;
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

static uint64_t hash_shape(const sph_scene *scene, int shape, uint64_t h) {
    const sph_shape *sh = &scene->shapes[shape];
    const int32_t type = (int32_t)sh->type, nparts = sh->nparts;
    h = fnv(h, &type, sizeof type);
    switch (sh->type) {
    case SPH_SHAPE_BOX:
        h = fnv(h, sh->lower, (size_t)scene->dim * sizeof sh->lower[0]);
        h = fnv(h, sh->upper, (size_t)scene->dim * sizeof sh->upper[0]);
        break;
    case SPH_SHAPE_SPHERE:
    case SPH_SHAPE_CYLINDER:
        /* only the components the shape has (2D shapes leave z unused) */
        h = fnv(h, sh->centre, (size_t)scene->dim * sizeof sh->centre[0]);
        h = fnv(h, &sh->inner_radius, sizeof sh->inner_radius);
        h = fnv(h, &sh->outer_radius, sizeof sh->outer_radius);
        if (sh->type == SPH_SHAPE_CYLINDER) {
            h = fnv(h, sh->axis, sizeof sh->axis);
            h = fnv(h, &sh->length, sizeof sh->length);
        }
        break;
    case SPH_SHAPE_MESH:
        h = sph_mesh_hash(sh->mesh, h);
        break;
    case SPH_SHAPE_UNION:
    case SPH_SHAPE_DIFFERENCE:
        h = fnv(h, &nparts, sizeof nparts);
        for (int i = 0; i < sh->nparts; i++) h = hash_shape(scene, sh->parts[i], h);
        break;
    }
    return h;
}

uint64_t sph_shape_hash(const sph_scene *scene, int shape) {
    const int32_t dim = scene->dim;
    return hash_shape(scene, shape, fnv(14695981039346656037ULL, &dim, sizeof dim));
}
