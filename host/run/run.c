#include "run.h"

#include "build_commit.h"
#include "checkpoint.h"
#include "kernel_bytes.h"
#include "output.h"
#include "snapshot.h"
#include "wall_clock.h"
#include "work_estimate.h"

#include <json-c/json.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#define LOCK_FILE ".sphsolid.lock"

/* fcntl errors that say the filesystem keeps no locks, not that another
 * process holds this one: a run there goes on without the guard. */
static bool no_locks_here(int e) {
    return e == ENOLCK || e == EINVAL || e == ENOSYS || e == EOPNOTSUPP;
}

/* POSIX record locks (fcntl), not flock(2), which _POSIX_C_SOURCE hides:
 * the same guarantees here (the kernel drops them when the process dies),
 * and F_GETLK names the holder's pid.  They belong to the process: closing
 * any descriptor of the file drops them, so a process opens each directory's
 * lock file once (a restart in place takes one lock, sph_simulation_open). */
sph_status sph_dir_lock_take(sph_dir_lock *lock, const char *dir, sph_dir_lock_mode mode,
                             const char *label, sph_error *err) {
    memset(lock, 0, sizeof *lock);
    lock->fd = -1;
    if (mode == SPH_DIR_LOCK_RUN) {
        const sph_status st = sph_output_make_dirs(dir, err);
        if (st) return st;
    }
    char path[PATH_MAX];
    if (snprintf(path, sizeof path, "%s/%s", dir, LOCK_FILE) >= (int)sizeof path)
        return sph_fail(err, SPH_ERR_INPUT, "%s %s: path too long", label, dir);
    const bool exclusive = mode != SPH_DIR_LOCK_SOURCE;
    int fd = open(path, O_RDWR | O_CLOEXEC | (mode == SPH_DIR_LOCK_IF_USED ? 0 : O_CREAT), 0666);
    if (fd < 0 && mode == SPH_DIR_LOCK_SOURCE) fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        /* a restart's source where no lock file can be made (read-only,
         * missing: the checkpoint read then says why), or a relax --out
         * directory no run has used: nothing to keep out */
        if (mode != SPH_DIR_LOCK_RUN) return SPH_OK;
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot create %s: %s", path, strerror(errno));
    }
    for (int tries = 0;; ++tries) {
        struct flock fl = {.l_type = exclusive ? F_WRLCK : F_RDLCK, .l_whence = SEEK_SET};
        if (fcntl(fd, F_SETLK, &fl) == 0) {
            lock->fd = fd;
            lock->held = true;
            lock->exclusive = exclusive;
            return SPH_OK;
        }
        const int e = errno;
        if (e == EINTR) continue;
        if (no_locks_here(e)) {
            close(fd);
            return SPH_OK;
        }
        if (e != EACCES && e != EAGAIN) {
            close(fd);
            return sph_fail(err, SPH_ERR_RUNTIME, "cannot lock %s: %s", path, strerror(e));
        }
        const bool known = fcntl(fd, F_GETLK, &fl) == 0;
        if (known && fl.l_type == F_UNLCK && tries < 3) continue; /* released meanwhile */
        close(fd);
        char pid[48] = "";
        if (known && fl.l_type != F_UNLCK && fl.l_pid > 0)
            snprintf(pid, sizeof pid, " (pid %ld)", (long)fl.l_pid);
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "%s %s is in use by another sphsolid process%s: wait for it to finish or "
                        "choose another directory",
                        label, dir, pid);
    }
}

void sph_dir_lock_release(sph_dir_lock *lock) {
    if (lock->held) close(lock->fd);
    lock->held = false;
    lock->fd = -1;
}

/* Whether two paths name one directory ("a" and "./a"): a restart there is
 * in place and takes one lock. */
static bool same_directory(const char *a, const char *b) {
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && S_ISDIR(sa.st_mode) &&
           sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* The output directory becomes this run's: nothing in it changes before the
 * lock is held (sph_output_open then removes the previous results). */
static sph_status lock_out_dir(sph_simulation *sim, sph_error *err) {
    const char *dir = sim->options.out_dir;
    sph_status st =
        sph_dir_lock_take(&sim->out_lock, dir, SPH_DIR_LOCK_RUN, "output directory", err);
    if (st) return st;
    /* only the lock's holder writes a checkpoint here: a .partial one now was
     * left by a run that died writing it, and would outlive this run */
    char ck[1200], partial[1300];
    sph_checkpoint_path(dir, ck, sizeof ck);
    snprintf(partial, sizeof partial, "%s.partial", ck);
    if (unlink(partial) != 0 && errno != ENOENT)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot remove %s: %s", partial, strerror(errno));
    return SPH_OK;
}

/* A restart's scene: the resolved text stored in the checkpoint, with the
 * overrides a continuation may change (a later end time, other output). */
static sph_status restart_scene(const sph_run_options *opt, sph_scene *scene, sph_error *err) {
    if (opt->scene_path)
        return sph_fail(err, SPH_ERR_INPUT,
                        "--restart %s continues the scene stored in its checkpoint: give no "
                        "scene file (change the end time with --set time.end=...)",
                        opt->restart_dir);
    for (int k = 0; k < opt->noverrides; ++k) {
        const char *o = opt->overrides[k];
        if (strncmp(o, "time.end=", 9) != 0 && strncmp(o, "output.", 7) != 0)
            return sph_fail(err, SPH_ERR_INPUT,
                            "--set %s: a restart may change only time.end and output.*; the "
                            "physics must stay that of the checkpoint",
                            o);
    }
    char *text = NULL;
    sph_status st = sph_checkpoint_read_scene(opt->restart_dir, &text, err);
    if (st) return st;
    char origin[1200];
    sph_checkpoint_path(opt->restart_dir, origin, sizeof origin);
    st = sph_scene_load_text(scene, origin, text, opt->overrides, opt->noverrides, err);
    free(text);
    /* relaxed bodies are relaxed again in memory (deterministic: the same
     * bits), not read from or written to a file next to the checkpoint,
     * where a relative relaxation.file of the stored scene would point */
    for (int b = 0; !st && b < scene->nbodies; b++) scene->bodies[b].relaxation.file[0] = '\0';
    return st;
}

/* A restart up to its scene: the locks, the checkpoint's time and settings,
 * the stored scene.  In place, the run's own lock comes before anything is
 * read; elsewhere the source is held shared, so that no run replaces the
 * checkpoint and snapshots this one reads and copies. */
static sph_status restart_open(sph_simulation *sim, sph_error *err) {
    sph_run_options *opt = &sim->options;
    const char *dir = opt->restart_dir;
    const bool in_place = opt->out_dir && same_directory(dir, opt->out_dir);
    sph_status st = in_place ? lock_out_dir(sim, err)
                             : sph_dir_lock_take(&sim->source_lock, dir, SPH_DIR_LOCK_SOURCE,
                                                 "restart directory", err);
    if (!st) st = restart_scene(opt, &sim->scene, err);
    if (st) return st;
    sim->scene_loaded = true;
    sph_checkpoint_info info;
    st = sph_checkpoint_read_info(dir, &info, err);
    if (st) return st;
    if (sim->scene.end_time < info.time) {
        char ck[1200];
        sph_checkpoint_path(dir, ck, sizeof ck);
        return sph_fail(err, SPH_ERR_INPUT,
                        "time.end = %.9g s is before the time of the checkpoint %s, t = %.9g s: a "
                        "restart continues from there (give --set time.end=%.9g or later)",
                        sim->scene.end_time, ck, info.time, info.time);
    }
    /* the run's checkpoints go on (a flag given now overrides its own one) */
    if (!(opt->checkpoint_every > 0)) opt->checkpoint_every = info.checkpoint_every;
    if (!(opt->checkpoint_wall > 0)) opt->checkpoint_wall = info.checkpoint_wall;
    return in_place || !opt->out_dir ? SPH_OK : lock_out_dir(sim, err);
}

sph_status sph_simulation_open(sph_simulation *sim, const sph_run_options *opt, sph_error *err) {
    memset(sim, 0, sizeof *sim);
    sim->options = *opt;
    sim->restart_time = NAN;
    const double t0 = sph_wall_seconds();
    sph_status st;
    if (opt->restart_dir) {
        st = restart_open(sim, err);
        if (st) return st;
    } else {
        st = sph_scene_load(&sim->scene, opt->scene_path, opt->overrides, opt->noverrides, err);
        if (st) return st;
        sim->scene_loaded = true;
        if (opt->out_dir) st = lock_out_dir(sim, err);
        if (st) return st;
    }
    st = sph_particles_generate(&sim->scene, &sim->particles, err);
    if (st) return st;
    for (int b = 0; b < sim->scene.nbodies && !opt->quiet; b++) {
        if (!sim->particles.relax[b].relaxed) continue;
        char line[4096];
        sph_relax_report_format(&sim->particles.relax[b], sim->scene.bodies[b].name,
                                sim->scene.bodies[b].relaxation.file, line, sizeof line);
        fprintf(stderr, "sphsolid: %s\n", line);
    }
    sph_features_from_scene(&sim->scene, &sim->particles, opt->precision, &sim->features);
    st = sph_params_fill(&sim->scene, &sim->particles, &sim->features, &sim->prm, err);
    if (!st) st = sph_observers_init(&sim->scene, &sim->particles, &sim->prm, &sim->observers, err);
    if (!st) st = sph_timeseries_init(&sim->series, sim->scene.dim, sim->scene.nobservers, err);
    if (st) return st;
    st = sph_backend_create(&opt->backend, &sim->features, &sim->prm, sim->particles.n,
                            &sim->backend, err);
    if (st) return st;
    if (!opt->quiet)
        fprintf(stderr, "sphsolid: backend %s on %s: %s\n", sim->backend->kind_name,
                sim->backend->device_name, sim->backend->choice_reason);
    sim->setup_seconds = sph_wall_seconds() - t0;
    return SPH_OK;
}

static json_object *num(double x) {
    /* JSON has no NaN: unknown values are null */
    return isfinite(x) ? json_object_new_double(x) : NULL;
}

static json_object *vector_json(const double *v, int dim) {
    json_object *a = json_object_new_array();
    for (int k = 0; k < dim; ++k) json_object_array_add(a, json_object_new_double(v[k]));
    return a;
}

/* The resolved parameters (summary.json "resolved"; snapshot provenance). */
static json_object *resolved_json(const sph_simulation *sim) {
    const sph_scene *sc = &sim->scene;
    json_object *res = json_object_new_object();
    json_object_object_add(res, "dimension", json_object_new_int(sc->dim));
    json_object_object_add(res, "dp", json_object_new_double(sc->dp));
    json_object_object_add(res, "smoothing_length", json_object_new_double(sim->prm.h));
    json_object_object_add(res, "cutoff", json_object_new_double(sim->prm.cutoff));
    json_object_object_add(res, "xi_e", json_object_new_double(sc->xi_e));
    json_object_object_add(res, "stepping", sph_json_string(sph_stepping_name(sc->stepping)));
    json_object_object_add(res, "cfl_advection", json_object_new_double(sc->cfl_advection));
    json_object_object_add(res, "cfl_acoustic", json_object_new_double(sc->cfl_acoustic));
    json_object_object_add(res, "reference_speed", num(sim->stats.reference_speed));
    json_object_object_add(res, "acceleration_criterion",
                           json_object_new_boolean(sc->acceleration_criterion));
    json_object_object_add(res, "riemann_limiter",
                           json_object_new_double(sc->riemann_limiter_slope));
    if (SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        json_object_object_add(res, "integrator",
                               sph_json_string(sc->fluid_integrator == SPH_FLUID_SSP_RK3 ? "ssp-rk3"
                                               : sc->fluid_integrator == SPH_FLUID_SSP_RK2
                                                   ? "ssp-rk2"
                                                   : "two-stage"));
    if (SPH_FORMULATION_IS_EULERIAN(sc->formulation))
        json_object_object_add(res, "viscous_regularization",
                               sph_json_string(sc->viscous_regularization == SPH_VISCOUS_LINEAR
                                                   ? "linear"
                                                   : "squared"));
    json_object_object_add(res, "end_time", json_object_new_double(sc->end_time));
    json_object_object_add(res, "output_interval", json_object_new_double(sc->output_interval));
    json_object_object_add(res, "gravity", vector_json(sc->gravity, sc->dim));
    json_object *mats = json_object_new_array();
    for (int m = 0; m < sc->nmaterials; ++m) {
        json_object *o = json_object_new_object();
        const sph_material *mt = &sc->materials[m];
        json_object_object_add(o, "name", sph_json_string(mt->name));
        json_object_object_add(o, "density", json_object_new_double(mt->density));
        json_object_object_add(o, "youngs_modulus", json_object_new_double(mt->youngs_modulus));
        json_object_object_add(o, "poisson_ratio", json_object_new_double(mt->poisson_ratio));
        json_object_object_add(o, "sound_speed", json_object_new_double(mt->sound_speed));
        json_object_object_add(o, "shear_modulus", json_object_new_double(mt->shear_modulus));
        json_object_object_add(o, "bulk_modulus", json_object_new_double(mt->bulk_modulus));
        json_object_array_add(mats, o);
    }
    json_object_object_add(res, "materials", mats);
    json_object *bodies = json_object_new_array();
    for (int b = 0; b < sc->nbodies; ++b) {
        json_object *o = json_object_new_object();
        json_object_object_add(o, "name", sph_json_string(sc->bodies[b].name));
        json_object_object_add(o, "particles", json_object_new_int(sim->particles.body_count[b]));
        /* its material, and those of its regions in order */
        const sph_body *body = &sc->bodies[b];
        json_object_object_add(o, "material", sph_json_string(sc->materials[body->material].name));
        if (body->nregions > 0) {
            json_object *regions = json_object_new_array();
            for (int k = 0; k < body->nregions; ++k)
                json_object_array_add(
                    regions, sph_json_string(sc->materials[body->regions[k].material].name));
            json_object_object_add(o, "region_materials", regions);
        }
        json_object_array_add(bodies, o);
    }
    json_object_object_add(res, "bodies", bodies);
    json_object_object_add(res, "fixed_particles", json_object_new_int(sim->particles.fixed_count));
    return res;
}

/* Every string goes in through sph_json_string (output.h): the title, the
 * scene path, the overrides and the resolved text are the user's bytes, and
 * json-c copies bytes that are not UTF-8 into the file unchanged. */
/* `sizes`: the sizes the kernels' buffer declarations refer to (profiled
 * runs; NULL: no byte counts in the profile) */
static json_object *summary_json(const sph_simulation *sim, const sph_bytes_sizes *sizes) {
    const sph_scene *sc = &sim->scene;
    const sph_backend *be = sim->backend;
    json_object *root = json_object_new_object();
    json_object_object_add(root, "sphsolid_version", sph_json_string(SPHSOLID_VERSION));
    json_object_object_add(root, "commit", sph_json_string(sph_build_commit()));
    const bool unstable = isfinite(sim->stats.instability_time) && sim->stats.instability_stopped;
    json_object_object_add(root, "status", sph_json_string(unstable ? "unstable" : "completed"));
    if (isfinite(sim->stats.instability_time)) {
        json_object *ins = json_object_new_object();
        json_object_object_add(ins, "time", json_object_new_double(sim->stats.instability_time));
        json_object_object_add(ins, "quantity", sph_json_string(sim->stats.instability_quantity));
        json_object_object_add(ins, "value", num(sim->stats.instability_value));
        json_object_object_add(ins, "threshold", num(sim->stats.instability_threshold));
        if (sim->stats.instability_field[0])
            json_object_object_add(ins, "field", sph_json_string(sim->stats.instability_field));
        if (sim->stats.instability_particle >= 0) {
            const int b = sim->stats.instability_body;
            json_object_object_add(ins, "particle",
                                   json_object_new_int64(sim->stats.instability_particle));
            json_object_object_add(ins, "body", sph_json_string(sc->bodies[b].name));
            json_object *x = json_object_new_array();
            for (int k = 0; k < sc->dim; ++k)
                json_object_array_add(x,
                                      json_object_new_double(sim->stats.instability_position[k]));
            json_object_object_add(ins, "position", x);
        }
        json_object_object_add(ins, "stopped", json_object_new_boolean(unstable));
        json_object_object_add(root, "instability", ins);
    }

    json_object *scene = json_object_new_object();
    json_object_object_add(scene, "path", sph_json_string(sc->path));
    json_object_object_add(scene, "title", sph_json_string(sc->title));
    json_object *ovr = json_object_new_array();
    for (int k = 0; k < sim->options.noverrides; ++k)
        json_object_array_add(ovr, sph_json_string(sim->options.overrides[k]));
    json_object_object_add(scene, "overrides", ovr);
    json_object_object_add(scene, "resolved_text",
                           sph_json_string(sc->resolved_text ? sc->resolved_text : ""));
    json_object_object_add(root, "scene", scene);

    json_object_object_add(root, "resolved", resolved_json(sim));

    json_object_object_add(root, "formulation",
                           sph_json_string(sph_formulation_name(sc->formulation)));
    json_object_object_add(root, "rotation", sph_json_string(sph_rotation_name(sc->rotation)));
    json_object_object_add(root, "kernel", sph_json_string(sph_kernel_name(sc->kernel)));
    json_object_object_add(root, "backend", sph_json_string(be->kind_name));
    json_object_object_add(root, "device", sph_json_string(be->device_name));
    json_object_object_add(root, "backend_choice", sph_json_string(be->choice_reason));
    json_object_object_add(root, "precision", sph_json_string(sph_precision_name(&sim->features)));
    json_object_object_add(root, "build_options", sph_json_string(be->build_options));
    /* OpenCL: 1, a launch per pass, or the substep loop's most per launch */
    if (be->substeps_per_launch > 0)
        json_object_object_add(root, "substeps_per_launch",
                               json_object_new_int64(be->substeps_per_launch));
    json_object *features = json_object_new_object();
    const sph_features *f = &sim->features;
    json_object_object_add(features, "dimension", json_object_new_int(f->dim));
    json_object_object_add(features, "formulation",
                           sph_json_string(sph_formulation_name(f->formulation)));
    json_object_object_add(features, "rotation", sph_json_string(sph_rotation_name(f->rotation)));
    json_object_object_add(features, "kernel", sph_json_string(sph_kernel_name(f->kernel)));
    json_object_object_add(
        features, "material_model",
        sph_json_string(f->plastic                                      ? "j2-plastic"
                        : f->elastic_model == ELASTIC_MODEL_NEO_HOOKEAN ? "neo-hookean"
                        : f->elastic_model == ELASTIC_MODEL_EXPONENTIAL ? "exponential"
                                                                        : "elastic"));
    json_object_object_add(features, "pairwise_damping", json_object_new_boolean(f->tl_damping));
    json_object_object_add(features, "clamp", json_object_new_boolean(f->has_clamp));
    json_object_object_add(features, "torque_projection",
                           json_object_new_boolean(f->torque_projection));
    json_object_object_add(features, "bodies", json_object_new_int(f->nbodies));
    json_object_object_add(features, "materials", json_object_new_int(f->materials));
    json_object_object_add(features, "contact", json_object_new_boolean(f->contact));
    json_object_object_add(features, "walls", json_object_new_int(f->walls));
    json_object_object_add(features, "precision", sph_json_string(sph_precision_name(f)));
    json_object_object_add(features, "stepping", sph_json_string(sph_stepping_name(f->stepping)));
    json_object_object_add(features, "snapshots",
                           json_object_new_boolean(sim->scene.snapshot_every > 0));
    json_object_object_add(root, "features", features);
    if (be->program_kernels[0]) {
        /* one entry per compiled kernel: "name(arg, ...)" */
        json_object *kernels = json_object_new_array();
        const char *p = be->program_kernels;
        while (*p) {
            const char *nl = strchr(p, '\n');
            const size_t n = nl ? (size_t)(nl - p) : strlen(p);
            json_object_array_add(kernels, sph_json_string_len(p, n));
            p += n + (nl ? 1 : 0);
        }
        json_object_object_add(root, "program_kernels", kernels);
    }
    json_object *mem = json_object_new_object();
    json_object_object_add(mem, "total_bytes",
                           json_object_new_int64((int64_t)sph_backend_total_bytes(be)));
    json_object *bufs = json_object_new_array();
    for (int k = 0; k < be->nbuffers; ++k) {
        json_object *o = json_object_new_object();
        json_object_object_add(o, "name", sph_json_string(be->buffers[k].name));
        json_object_object_add(o, "bytes", json_object_new_int64((int64_t)be->buffers[k].bytes));
        json_object_array_add(bufs, o);
    }
    json_object_object_add(mem, "buffers", bufs);
    json_object_object_add(root, "memory", mem);
    if (be->profiling) {
        json_object *prof = json_object_new_array();
        for (int k = 0; k < be->nprofile; ++k) {
            json_object *o = json_object_new_object();
            json_object_object_add(o, "phase", sph_json_string(be->profile[k].name));
            json_object_object_add(o, "calls", json_object_new_int64(be->profile[k].calls));
            json_object_object_add(o, "seconds", json_object_new_double(be->profile[k].seconds));
            /* the bytes one call moves by the kernels' own declarations
             * (kernel_bytes.h), absent for a phase that is no declared
             * kernel, and the bandwidth that gives */
            char kernels[256];
            const double bytes =
                sizes ? sph_phase_bytes(be, &be->profile[k], sizes, kernels, sizeof kernels) : -1;
            if (bytes >= 0) {
                json_object_object_add(o, "bytes_per_call", json_object_new_double(bytes));
                json_object_object_add(o, "bytes_of", sph_json_string(kernels));
                const double s = be->profile[k].seconds;
                if (s > 0)
                    json_object_object_add(
                        o, "gbs",
                        json_object_new_double(bytes * (double)be->profile[k].calls / s / 1e9));
            }
            json_object_array_add(prof, o);
        }
        json_object_object_add(root, "profile", prof);
        if (sizes) {
            json_object *z = json_object_new_object();
            json_object_object_add(z, "pair_slots", json_object_new_double(sizes->pair_slots));
            json_object_object_add(z, "grid_cells", json_object_new_double(sizes->grid_cells));
            json_object_object_add(z, "padded_particles", json_object_new_double(sizes->padded_n));
            json_object_object_add(root, "profile_sizes", z);
        }
    }

    json_object_object_add(root, "particle_count", json_object_new_int(sim->particles.n));
    /* how the relaxed bodies were placed (docs/scene-format.md, "Relaxed placement") */
    json_object *relaxed = json_object_new_array();
    for (int b = 0; b < sc->nbodies; ++b) {
        const sph_relax_report *r = &sim->particles.relax[b];
        if (!r->relaxed) continue;
        json_object *o = json_object_new_object();
        json_object_object_add(o, "body", sph_json_string(sc->bodies[b].name));
        json_object_object_add(o, "particles", json_object_new_int(r->particles));
        json_object_object_add(o, "steps", json_object_new_int(r->steps));
        json_object_object_add(o, "residual_mean", num(r->mean));
        json_object_object_add(o, "residual_max", num(r->max));
        json_object_object_add(o, "residual_start_mean", num(r->start_mean));
        json_object_object_add(o, "residual_lattice_mean", num(r->lattice_mean));
        json_object_object_add(o, "min_distance", num(r->min_distance));
        json_object_object_add(o, "file", sph_json_string(sc->bodies[b].relaxation.file));
        json_object_object_add(o, "reused", json_object_new_boolean(r->reused));
        json_object_array_add(relaxed, o);
    }
    json_object_object_add(root, "relaxed_bodies", relaxed);
    json_object_object_add(root, "snapshots", json_object_new_int(sim->snapshot_count));
    json_object *fields = json_object_new_array();
    for (int k = 0; k < SPH_OUT_COUNT; ++k)
        if (sc->output_field[k])
            json_object_array_add(fields,
                                  sph_json_string(sph_output_field_name((sph_output_field)k)));
    json_object_object_add(root, "snapshot_fields", fields);
    if (isfinite(sim->restart_time)) {
        json_object *r = json_object_new_object();
        json_object_object_add(r, "directory", sph_json_string(sim->options.restart_dir));
        json_object_object_add(r, "time", json_object_new_double(sim->restart_time));
        json_object_object_add(root, "restarted_from", r);
    }
    json_object_object_add(root, "acoustic_steps",
                           json_object_new_int64(sim->stats.acoustic_steps));
    json_object_object_add(root, "advection_steps",
                           json_object_new_int64(sim->stats.advection_steps));
    json_object_object_add(root, "simulated_time", json_object_new_double(sim->stats.end_time));
    json_object_object_add(root, "wall_time_s", json_object_new_double(sim->stats.wall_seconds));
    json_object_object_add(root, "setup_time_s", json_object_new_double(sim->setup_seconds));
    json_object_object_add(root, "particle_substeps_per_second",
                           json_object_new_double(sim->stats.particle_substeps_per_second));

    const sph_metrics *m = &sim->metrics;
    json_object *metrics = json_object_new_object();
    json_object_object_add(metrics, "initial_kinetic_energy", num(m->initial_kinetic_energy));
    json_object_object_add(metrics, "final_total_energy_ratio", num(m->final_total_energy_ratio));
    json_object_object_add(metrics, "max_linear_momentum_drift", num(m->max_linear_momentum_drift));
    json_object_object_add(metrics, "max_angular_momentum_error",
                           num(m->max_angular_momentum_error));
    /* null where angular momentum is conserved, else why the error is not
     * reported (a constraint, a wall, gravity) */
    json_object_object_add(metrics, "angular_momentum_not_conserved",
                           m->angular_momentum_not_conserved[0]
                               ? sph_json_string(m->angular_momentum_not_conserved)
                               : NULL);
    json_object_object_add(metrics, "initial_angular_momentum", num(m->initial_angular_momentum));
    if (sc->period_observer >= 0) {
        json_object_object_add(metrics, "first_period", num(m->first_period));
        json_object_object_add(metrics, "max_observer_displacement",
                               num(m->max_observer_displacement));
    }
    /* each traction observer's first pulse (analysis.h) */
    for (int o = 0; o < sc->nobservers; ++o) {
        if (sc->observers[o].quantity != SPH_OBSERVE_TRACTION) continue;
        char key[SPH_NAME_LEN + 16];
        snprintf(key, sizeof key, "%s_first_pulse", sc->observers[o].name);
        json_object_object_add(metrics, key, num(sph_first_pulse(&sim->series, sc, o)));
    }
    if (sc->wave_incident >= 0 && sc->wave_transmitted >= 0 &&
        sc->wave_incident != sc->wave_transmitted) {
        /* a pulse through an interface against the 1D relations (analysis.h) */
        const sph_wave_metrics *wm = &sim->wave_metrics;
        const struct {
            const char *name;
            double value;
        } wave[] = {{"incident_stress", wm->incident},
                    {"reflected_stress", wm->reflected},
                    {"transmitted_stress", wm->transmitted},
                    {"transmitted_stress_ratio", wm->transmitted_ratio},
                    {"transmitted_stress_ratio_theory", wm->transmitted_ratio_theory},
                    {"reflected_stress_ratio", wm->reflected_ratio},
                    {"reflected_stress_ratio_theory", wm->reflected_ratio_theory},
                    {"impedance_incident", wm->impedance_incident},
                    {"impedance_transmitted", wm->impedance_transmitted}};
        for (size_t k = 0; k < sizeof wave / sizeof wave[0]; ++k)
            json_object_object_add(metrics, wave[k].name, num(wave[k].value));
    }
    if (SPH_FORMULATION_IS_EULERIAN(sc->formulation)) {
        /* fluids: conservation, and the forces on the walls over the
         * trailing window (004 §4.3, Table 5) */
        const sph_fluid_metrics *fm = &sim->fluid_metrics;
        json_object_object_add(metrics, "max_mass_drift", num(fm->max_mass_drift));
        json_object_object_add(metrics, "max_total_energy_drift", num(fm->max_total_energy_drift));
        if (sc->has_forces) {
            json_object_object_add(metrics, "mean_drag_coefficient",
                                   num(fm->mean_drag_coefficient));
            json_object_object_add(metrics, "lift_amplitude", num(fm->lift_amplitude));
            json_object_object_add(metrics, "strouhal_number", num(fm->strouhal_number));
            json_object_object_add(metrics, "force_window_start", num(fm->force_window_start));
        }
    }
    json_object_object_add(root, "metrics", metrics);
    /* the physical scales `sphsolid compare` measures quantities that are
     * zero in theory against (docs/output-format.md, "summary.json") */
    json_object *scales = json_object_new_object();
    json_object_object_add(scales, "total_mass", num(m->total_mass));
    json_object_object_add(scales, "momentum", num(m->momentum_scale));
    json_object_object_add(scales, "angular_momentum", num(m->angular_momentum_scale));
    json_object_object_add(scales, "energy", num(m->energy_scale));
    json_object_object_add(root, "scales", scales);
    return root;
}

/* Copy the snapshots a restart keeps when it writes to another directory. */
static sph_status copy_kept_snapshots(const char *from, const char *to, int count, sph_error *err) {
    char sub[1100];
    snprintf(sub, sizeof sub, "%s/snapshots", to);
    if (mkdir(sub, 0777) != 0 && errno != EEXIST)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot create %s: %s", sub, strerror(errno));
    for (int k = 0; k < count; ++k) {
        char name[64], src[1200], dst[1200], tmp[1300];
        sph_snapshot_name(k, name, sizeof name);
        snprintf(src, sizeof src, "%s/%s", from, name);
        snprintf(dst, sizeof dst, "%s/%s", to, name);
        snprintf(tmp, sizeof tmp, "%s.partial", dst);
        FILE *in = fopen(src, "rb");
        if (!in)
            return sph_fail(err, SPH_ERR_INPUT,
                            "cannot read %s (a snapshot the checkpoint "
                            "lists): %s",
                            src, strerror(errno));
        FILE *out = fopen(tmp, "wb");
        if (!out) {
            fclose(in);
            return sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", tmp, strerror(errno));
        }
        char buf[65536];
        size_t got;
        int bad = 0;
        while (!bad && (got = fread(buf, 1, sizeof buf, in)) > 0)
            bad = fwrite(buf, 1, got, out) != got;
        bad = bad || ferror(in);
        fclose(in);
        if (fclose(out) != 0 || bad || rename(tmp, dst) != 0) {
            unlink(tmp);
            return sph_fail(err, SPH_ERR_RUNTIME, "cannot copy %s to %s: %s", src, dst,
                            strerror(errno));
        }
    }
    return SPH_OK;
}

sph_status sph_simulation_run(sph_simulation *sim, sph_error *err) {
    const sph_run_options *opt = &sim->options;
    sph_output out;
    sph_output *outp = NULL;
    sph_snapshots snaps;
    sph_snapshots *snapp = NULL;
    sph_checkpoint ck;
    bool resumed = false;
    char *parameters = NULL;
    sph_status st = SPH_OK;
    if (opt->restart_dir) {
        const sph_checkpoint_scene scene = {&sim->particles, sim->scene.output_interval};
        st = sph_checkpoint_read(opt->restart_dir, sim->backend, &scene, &ck, &sim->series, err);
        if (st) return st;
        resumed = true;
        sim->restart_time = ck.h.time;
        if (!opt->quiet) {
            fprintf(stderr, "sphsolid: restarting from t = %.9g s (%s)\n", ck.h.time,
                    opt->restart_dir);
            const bool same = strcmp(ck.backend, sim->backend->kind_name) == 0 &&
                              strcmp(ck.precision, sph_precision_name(&sim->features)) == 0;
            if (!same)
                fprintf(stderr,
                        "sphsolid: note: the checkpoint was written by the %s backend in %s "
                        "precision; continuing on another backend or precision is not bit-for-bit "
                        "the uninterrupted run\n",
                        ck.backend, ck.precision);
        }
    }
    if (!st) {
        /* the predicted work, before anything is written (work_estimate.h) */
        const sph_work_request work = {
            .start_time = resumed ? ck.h.time : 0.0,
            .out_dir = opt->out_dir,
            .overrides = opt->overrides,
            .noverrides = opt->noverrides,
            .checkpoint_every = opt->checkpoint_every,
            .double_precision = sim->features.double_precision,
            .no_limit = opt->no_work_limit,
            .quiet = opt->quiet,
        };
        st = sph_work_check(&sim->scene, &sim->particles, &sim->prm, &work, NULL, err);
    }
    if (!st && opt->out_dir) {
        st = sph_output_open(&out, opt->out_dir, &sim->scene, resumed ? &sim->series : NULL, err);
        if (!st) outp = &out;
    }
    if (!st && outp && sim->scene.snapshot_every > 0) {
        json_object *res = resolved_json(sim);
        parameters = strdup(json_object_to_json_string_ext(res, JSON_C_TO_STRING_PLAIN));
        json_object_put(res);
        const sph_snapshot_context ctx = {
            .scene = &sim->scene,
            .initial = &sim->particles,
            .prm = &sim->prm,
            .commit = sph_build_commit(),
            .backend = sim->backend->kind_name,
            .device = sim->backend->device_name,
            .build_options = sim->backend->build_options,
            .precision = sph_precision_name(&sim->features),
            .parameters_json = parameters ? parameters : "{}",
        };
        const int keep = resumed ? ck.h.nsnapshots : 0;
        if (keep > 0 && strcmp(opt->restart_dir, opt->out_dir) != 0)
            st = copy_kept_snapshots(opt->restart_dir, opt->out_dir, keep, err);
        if (!st)
            st = sph_snapshots_open(&snaps, opt->out_dir, &ctx, sim->particles.n,
                                    sim->features.double_precision, keep,
                                    resumed ? ck.h.snapshot_times : NULL, err);
        if (!st) snapp = &snaps;
    }
    const sph_solver_args args = {
        .scene = &sim->scene,
        .backend = sim->backend,
        .initial = &sim->particles,
        .prm = &sim->prm,
        .observers = &sim->observers,
        .output = outp,
        .snapshots = snapp,
        .run_dir = opt->out_dir,
        .checkpoint_every = opt->checkpoint_every,
        .checkpoint_wall = opt->checkpoint_wall,
        .resume = resumed ? &ck : NULL,
        .quiet = opt->quiet,
        .progress_interval = opt->progress_interval > 0 ? opt->progress_interval : 10.0,
        .max_acoustic_steps = opt->max_acoustic_steps,
    };
    if (!st) st = sph_solve(&args, &sim->series, &sim->stats, err);
    if (snapp) {
        sim->snapshot_count = snapp->count;
        sph_snapshots_close(snapp);
    }
    free(parameters);
    if (resumed) sph_checkpoint_free(&ck);
    /* the initial state's sums in double (the no-spin decision and the
     * momentum scales do not depend on the run's precision) and whether the
     * scene conserves angular momentum at all */
    sph_initial_sums initial;
    sph_initial_sums_compute(&sim->particles, &initial);
    char not_conserved[256];
    sph_angular_momentum_conserved(&sim->scene, not_conserved, sizeof not_conserved);
    sph_metrics_compute(&sim->series, sim->scene.period_observer, sim->scene.period_axis, &initial,
                        not_conserved, &sim->metrics);
    sph_fluid_metrics_compute(&sim->series, &sim->scene, &sim->fluid_metrics);
    sph_wave_metrics_compute(&sim->series, &sim->scene, &sim->wave_metrics);
    if (outp) {
        /* a run the instability monitor stopped keeps its results, marked
         * "unstable" in summary.json */
        const bool keep = st == SPH_OK || st == SPH_UNSTABLE;
        sph_error close_err;
        const sph_status cst = sph_output_close(outp, keep, &close_err);
        if (keep && cst) {
            *err = close_err;
            st = cst;
        }
        /* the profile's byte counts need the last rebuild's neighbour
         * counts (a download, profiled runs that completed only) */
        sph_bytes_sizes sizes;
        const bool counted = sim->backend->profiling && st == SPH_OK;
        if (counted) st = sph_bytes_sizes_measure(sim->backend, &sizes, err);
        if (st == SPH_OK || st == SPH_UNSTABLE) {
            json_object *summary = summary_json(sim, counted ? &sizes : NULL);
            sph_error werr;
            const sph_status wst =
                sph_output_write_json(opt->out_dir, "summary.json", summary, &werr);
            json_object_put(summary);
            if (wst) {
                *err = werr;
                st = wst;
            }
        }
    }
    return st;
}

void sph_simulation_close(sph_simulation *sim) {
    sph_backend_destroy(sim->backend);
    sph_observers_free(&sim->observers);
    sph_timeseries_free(&sim->series);
    sph_particles_free(&sim->particles);
    if (sim->scene_loaded) sph_scene_free(&sim->scene);
    sph_dir_lock_release(&sim->out_lock);
    sph_dir_lock_release(&sim->source_lock);
    memset(sim, 0, sizeof *sim);
}
