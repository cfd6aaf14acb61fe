#include "work_estimate.h"

#include "physics.h"

#include "particles.h" /* sph_format_bytes: the memory messages' units */

#include "sph_constants.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

/* Snapshot size model, from the plate's VTKHDF snapshots (deflate level 4):
 * about 32 KiB of metadata and provenance (the resolved scene, the
 * parameters) whatever the particle count, plus about half the raw bytes of
 * each particle's arrays (2D plate, 12 572 particles: 64 of 121 raw bytes;
 * 3D plate, 44 652 particles: 68 of 150).  The first snapshot, at rest or
 * close to it, compresses better; the estimate is for the others. */
#define SNAPSHOT_FIXED_BYTES   32768.0
#define SNAPSHOT_COMPRESSION   0.5
#define CSV_BYTES_PER_COLUMN   15.0 /* "%.12g," of the diagnostics, measured ~14.5 */
#define SERIES_BYTES_PER_ENTRY 72.0 /* a line of snapshots.hdf.series */

/* ---------------------------------------------------------------- naming */

/* Where `key` got its value (sph_scene_key_where): whether it is given. */
static bool where_of_key(const sph_scene *sc, const sph_work_request *rq, const char *key,
                         char *buf, size_t size) {
    return sph_scene_key_where(sc, rq->overrides, rq->noverrides, key, buf, size);
}

/* ------------------------------------------------------------ estimating */

/* Free bytes for the output directory: statvfs of it, or of its nearest
 * existing ancestor before the run creates it, plus the old snapshot files
 * a fresh run there removes first (a rerun into the same directory; not
 * for a restart).
 * SPHSOLID_TEST_FREE_BYTES replaces the filesystem's figure (tests). */
static double free_bytes(const char *out_dir, bool restart) {
    const char *test = getenv("SPHSOLID_TEST_FREE_BYTES");
    if (test && *test) return strtod(test, NULL);
    char path[4096];
    snprintf(path, sizeof path, "%s", out_dir);
    struct statvfs vfs;
    while (statvfs(path, &vfs) != 0) {
        if (errno != ENOENT && errno != ENOTDIR) return NAN;
        char *slash = strrchr(path, '/');
        if (!slash) {
            snprintf(path, sizeof path, ".");
        } else if (slash == path) {
            path[1] = '\0';
        } else {
            *slash = '\0';
        }
        if (strcmp(path, ".") == 0 || strcmp(path, "/") == 0) {
            if (statvfs(path, &vfs) != 0) return NAN;
            break;
        }
    }
    double room = (double)vfs.f_bavail * (double)vfs.f_frsize;
    char sub[4200];
    snprintf(sub, sizeof sub, "%s/snapshots", out_dir);
    /* a restart keeps the snapshots its checkpoint lists */
    DIR *d = restart ? NULL : opendir(sub);
    if (d) {
        for (struct dirent *e = readdir(d); e; e = readdir(d)) {
            if (strncmp(e->d_name, "snapshot_", 9) != 0) continue;
            char file[4500];
            struct stat st;
            snprintf(file, sizeof file, "%s/%s", sub, e->d_name);
            if (stat(file, &st) == 0 && S_ISREG(st.st_mode)) room += (double)st.st_size;
        }
        closedir(d);
    }
    return room;
}

/* Raw bytes of one particle's snapshot arrays (host/io/snapshot.c): points
 * (3 components, float in single precision), the chosen point data, and
 * the VTK connectivity, offset and type of its vertex cell. */
static double particle_snapshot_bytes(const sph_scene *sc, bool double_precision) {
    const double real = double_precision ? 8.0 : 4.0;
    double b = 3.0 * real + 8.0 + 8.0 + 1.0;
    static const int comps[SPH_OUT_COUNT] = {
        [SPH_OUT_VELOCITY] = 3,    [SPH_OUT_DISPLACEMENT] = 3, [SPH_OUT_DENSITY] = 1,
        [SPH_OUT_PRESSURE] = 1,    [SPH_OUT_VON_MISES] = 1,    [SPH_OUT_SHEAR_STRESS] = 6,
        [SPH_OUT_BODY_ID] = 1,     [SPH_OUT_PARTICLE_ID] = 1,  [SPH_OUT_PLASTIC_STRAIN] = 1,
        [SPH_OUT_MATERIAL_ID] = 1,
    };
    for (int k = 0; k < SPH_OUT_COUNT; ++k) {
        if (!sc->output_field[k]) continue;
        const bool integer =
            k == SPH_OUT_BODY_ID || k == SPH_OUT_PARTICLE_ID || k == SPH_OUT_MATERIAL_ID;
        b += comps[k] * (integer ? 4.0 : real);
    }
    return b;
}

void sph_work_estimate_compute(const sph_scene *sc, const sph_particles *p,
                               const sph_params_f64 *prm, const sph_work_request *rq,
                               sph_work_estimate *e) {
    memset(e, 0, sizeof *e);
    /* the fastest material a body or a region uses */
    int row_of[SPH_MAX_MATERIALS];
    sph_scene_material_rows(sc, row_of);
    e->material = sc->bodies[0].material;
    for (int m = 0; m < sc->nmaterials && m < SPH_MAX_MATERIALS; ++m)
        if (row_of[m] >= 0 && sc->materials[m].sound_speed > sc->materials[e->material].sound_speed)
            e->material = m;
    e->sound_speed = sc->materials[e->material].sound_speed;
    /* the compressible fluid's sound speed is each particle's own,
     * sqrt(gamma p / rho) (device/sph_eulerian.h): its largest at the start */
    if (sc->formulation == SPH_FORMULATION_EULERIAN_COMPRESSIBLE && p->pressure) {
        const sph_physics *k = sph_physics_for(p->dim, true);
        for (int i = 0; i < p->n; ++i)
            e->sound_speed =
                fmax(e->sound_speed, k->ideal_gas_sound_speed(p->pressure[i], p->rho[i],
                                                              sc->materials[e->material].gamma));
    }
    double v2 = 0.0;
    for (int i = 0; i < p->n; ++i) {
        double s = 0.0;
        for (int d = 0; d < p->dim; ++d) {
            const double v = p->vel[(size_t)d * p->n + i];
            s += v * v;
        }
        v2 = fmax(v2, s);
    }
    e->max_speed = sqrt(v2);
    e->h = prm->h;
    /* the solver's own steps (sph_step_clock.h, solver.c) at the start */
    e->dt_acoustic = sc->cfl_acoustic * e->h / (e->sound_speed + e->max_speed);
    const double u = fmax(e->max_speed, sc->has_reference_speed ? sc->reference_speed : 0.0);
    e->dt_advection = sc->stepping == SPH_STEPPING_SINGLE ? e->dt_acoustic
                      : u > 0.0                           ? sc->cfl_advection * e->h / u
                                                          : INFINITY;
    const double span = fmax(sc->end_time - rq->start_time, 0.0);
    e->outputs = ceil(span / sc->output_interval);
    /* every output time is landed on by a substep of its own */
    e->substeps = fmax(span / e->dt_acoustic, e->outputs);
    e->particle_substeps = (double)p->n * e->substeps;
    if (sc->snapshot_every > 0) {
        /* every snapshot_every-th output, the last output, and t = 0 */
        const double every = (double)sc->snapshot_every;
        e->snapshots = floor(e->outputs / every) + (fmod(e->outputs, every) != 0.0 ? 1.0 : 0.0) +
                       (rq->start_time > 0 ? 0.0 : 1.0);
        e->snapshot_bytes =
            SNAPSHOT_FIXED_BYTES +
            SNAPSHOT_COMPRESSION * (double)p->n * particle_snapshot_bytes(sc, rq->double_precision);
    }
    const double columns =
        1.0 + 3.0 + sc->dim + sph_spin_components(sc->dim) + 2.0 + sc->nobservers * sc->dim;
    e->bytes = e->snapshots * (e->snapshot_bytes + SERIES_BYTES_PER_ENTRY) +
               e->outputs * columns * CSV_BYTES_PER_COLUMN;
    e->free_bytes = rq->out_dir ? free_bytes(rq->out_dir, rq->start_time > 0) : NAN;
}

/* -------------------------------------------------------------- judging */

/* The key that makes the substep count large, for the message: an acoustic
 * CFL far below its default, initial speeds beyond the sound speed, or
 * else simply the length of the run. */
static const char *substep_key(const sph_scene *sc, const sph_work_estimate *e, char *buf,
                               size_t size) {
    if (e->outputs >= 0.5 * e->substeps) return "time.output_interval";
    if (sc->cfl_acoustic < 0.01) return "time.cfl_acoustic";
    if (e->max_speed > e->sound_speed) {
        /* the body of the fastest particle is the first whose velocity is not zero */
        for (int b = 0; b < sc->nbodies; ++b)
            if (sc->bodies[b].velocity.type != SPH_VELOCITY_ZERO) {
                sph_format(buf, size, "bodies.%s.initial_velocity", sc->bodies[b].name);
                return buf;
            }
    }
    return "time.end";
}

/* The material key behind a sound speed beyond the limit: the given
 * sound_speed, a Poisson's ratio so close to 0.5 that the bulk modulus
 * dwarfs the shear modulus, a density below any solid's (aerogels: about
 * 1 kg/m^3), else Young's modulus. */
static const char *material_key(const sph_scene *sc, const sph_work_request *rq,
                                const sph_material *m, bool *has_speed) {
    char where[SPH_SCENE_WHERE_LEN];
    char key[SPH_NAME_LEN + 32];
    sph_format(key, sizeof key, "materials.%s.sound_speed", m->name);
    *has_speed = where_of_key(sc, rq, key, where, sizeof where);
    if (*has_speed) return "sound_speed";
    if (m->bulk_modulus > 1e3 * m->shear_modulus) return "poisson_ratio";
    if (m->density < 1.0) return "density";
    return "youngs_modulus";
}

/* Report one exceeded limit: the refusal, or with --no-work-limit the same
 * text as a warning. */
static sph_status exceeded(const sph_work_request *rq, const char *where, const char *what,
                           sph_error *err) {
    if (!rq->no_limit)
        return sph_fail(err, SPH_ERR_INPUT, "%s: %s; or run it anyway with --no-work-limit", where,
                        what);
    if (!rq->quiet)
        fprintf(stderr, "sphsolid: warning: %s: %s (--no-work-limit: running it anyway)\n", where,
                what);
    return SPH_OK;
}

sph_status sph_work_check(const sph_scene *sc, const sph_particles *p, const sph_params_f64 *prm,
                          const sph_work_request *rq, sph_work_estimate *out, sph_error *err) {
    sph_work_estimate local;
    sph_work_estimate *e = out ? out : &local;
    sph_work_estimate_compute(sc, p, prm, rq, e);
    const double span = fmax(sc->end_time - rq->start_time, 0.0);
    char where[SPH_SCENE_WHERE_LEN + 64], what[1800], key[SPH_NAME_LEN + 48];
    char steps[400];
    sph_format(steps, sizeof steps,
               "about %.3g acoustic substeps of %.3g s (CFL_ac h / (c0 + max |v|) with h = %.3g m, "
               "c0 = %.4g m/s, max |v| = %.3g m/s) for %.3g s of simulated time",
               e->substeps, e->dt_acoustic, e->h, e->sound_speed, e->max_speed, span);
    sph_status st = SPH_OK;

    /* a material no solid resembles: the most likely slip of a unit or a digit */
    if (e->sound_speed > SPH_WORK_MAX_SOUND_SPEED) {
        const sph_material *m = &sc->materials[e->material];
        bool has_speed;
        const char *leaf = material_key(sc, rq, m, &has_speed);
        sph_format(key, sizeof key, "materials.%s.%s", m->name, leaf);
        /* nu as written (0.49999999999), to all its digits where 15 round it */
        char nu[32];
        sph_format(nu, sizeof nu, "%.15g", m->poisson_ratio);
        if (strtod(nu, NULL) != m->poisson_ratio)
            sph_format(nu, sizeof nu, "%.17g", m->poisson_ratio);
        where_of_key(sc, rq, key, where, sizeof where);
        if (has_speed)
            sph_format(what, sizeof what,
                       "the sound speed c0 = %.4g m/s is beyond %.0e m/s, faster than sound in "
                       "any solid (SI units: m/s): %s",
                       e->sound_speed, SPH_WORK_MAX_SOUND_SPEED, steps);
        else
            sph_format(what, sizeof what,
                       "density %.6g, youngs_modulus %.6g and poisson_ratio %s give the sound "
                       "speed c0 = sqrt(E / (3 (1 - 2 nu) rho0)) = %.4g m/s (bulk modulus %.3g "
                       "times the shear modulus), beyond %.0e m/s, faster than sound in any solid "
                       "(SI units: Pa, kg/m^3): %s",
                       m->density, m->youngs_modulus, nu, e->sound_speed,
                       m->bulk_modulus / m->shear_modulus, SPH_WORK_MAX_SOUND_SPEED, steps);
        st = exceeded(rq, where, what, err);
    }
    if (!st && rq->out_dir && isfinite(e->free_bytes) && e->bytes > 0.5 * e->free_bytes) {
        /* the snapshots' own interval where they are most of it and the
         * scene gives one, else the output interval they follow */
        const double snap = e->snapshots * e->snapshot_bytes;
        bool given = false;
        if (snap > 0.5 * e->bytes) {
            given = where_of_key(sc, rq, "output.snapshot_interval", where, sizeof where);
        }
        if (!given) where_of_key(sc, rq, "time.output_interval", where, sizeof where);
        char total[32], each[32], room[32];
        sph_format_bytes(e->bytes, total, sizeof total);
        sph_format_bytes(e->snapshot_bytes, each, sizeof each);
        sph_format_bytes(e->free_bytes, room, sizeof room);
        char snaps[160] = "no snapshots";
        if (e->snapshots > 0)
            sph_format(snaps, sizeof snaps, "%.3g snapshots of about %s every %.3g s", e->snapshots,
                       each, sc->snapshot_interval);
        sph_format(what, sizeof what,
                   "the run would write about %s (%s, and a row of timeseries.csv at each of "
                   "%.3g output times %.3g s apart) to %s, whose filesystem has %s free",
                   total, snaps, e->outputs, sc->output_interval, rq->out_dir, room);
        if (e->bytes > e->free_bytes) {
            char more[2000];
            sph_format(more, sizeof more,
                       "%s; write less often (time.output_interval, output.snapshot_interval) or "
                       "to another disk (--out)",
                       what);
            st = exceeded(rq, where, more, err);
        } else if (!rq->quiet) {
            /* fits, but leaves less than half the room: say so and go on */
            fprintf(stderr, "sphsolid: warning: %s: %s\n", where, what);
        }
    }
    if (!st && e->outputs > SPH_WORK_MAX_OUTPUTS) {
        where_of_key(sc, rq, "time.output_interval", where, sizeof where);
        sph_format(what, sizeof what,
                   "%.3g output times (every %.3g s for %.3g s), beyond %.0e: each is a row of "
                   "the time series, held in memory and written to timeseries.csv",
                   e->outputs, sc->output_interval, span, SPH_WORK_MAX_OUTPUTS);
        st = exceeded(rq, where, what, err);
    }
    if (!st && e->substeps > SPH_WORK_MAX_SUBSTEPS) {
        where_of_key(sc, rq, substep_key(sc, e, key, sizeof key), where, sizeof where);
        sph_format(what, sizeof what, "the run would take %s, beyond %.0e substeps", steps,
                   SPH_WORK_MAX_SUBSTEPS);
        st = exceeded(rq, where, what, err);
    }
    /* (one of the two is enough to say) */
    if (!st && e->particle_substeps > SPH_WORK_MAX_PARTICLE_SUBSTEPS &&
        !(e->substeps > SPH_WORK_MAX_SUBSTEPS)) {
        where_of_key(sc, rq, substep_key(sc, e, key, sizeof key), where, sizeof where);
        sph_format(what, sizeof what,
                   "the run would take %.3g particle-substeps (%d particles, %s), beyond %.0e "
                   "(34 hours at the fastest rate measured, docs/benchmarks.md)",
                   e->particle_substeps, p->n, steps, SPH_WORK_MAX_PARTICLE_SUBSTEPS);
        st = exceeded(rq, where, what, err);
    }
    if (!st && !rq->quiet && rq->checkpoint_every > 0 && rq->checkpoint_every < e->dt_advection)
        fprintf(stderr,
                "sphsolid: note: --checkpoint-every %g s is shorter than an advection step (about "
                "%.3g s at the start): a checkpoint is written after every advection step\n",
                rq->checkpoint_every, e->dt_advection);
    return st;
}
