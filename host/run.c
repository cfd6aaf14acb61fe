#include "run.h"

#include "build_commit.h"
#include "checkpoint.h"
#include "output.h"
#include "snapshot.h"
#include "wall_clock.h"

#include <json-c/json.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

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

sph_status sph_simulation_open(sph_simulation *sim, const sph_run_options *opt, sph_error *err) {
    memset(sim, 0, sizeof *sim);
    sim->options = *opt;
    sim->restart_time = NAN;
    const double t0 = sph_wall_seconds();
    sph_status st;
    if (opt->restart_dir) {
        st = restart_scene(opt, &sim->scene, err);
    } else {
        st = sph_scene_load(&sim->scene, opt->scene_path, opt->overrides, opt->noverrides, err);
    }
    if (st) return st;
    sim->scene_loaded = true;
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
    st = sph_params_fill(&sim->scene, &sim->particles, &sim->features, sim->prm, err);
    if (!st) st = sph_observers_init(&sim->scene, &sim->particles, sim->prm, &sim->observers, err);
    if (!st) st = sph_timeseries_init(&sim->series, sim->scene.dim, sim->scene.nobservers, err);
    if (st) return st;
    st = sph_backend_create(&opt->backend, &sim->features, sim->prm, sim->particles.n,
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
    json_object_object_add(res, "smoothing_length", json_object_new_double(sim->prm[PRM_H]));
    json_object_object_add(res, "cutoff", json_object_new_double(sim->prm[PRM_CUTOFF]));
    json_object_object_add(res, "xi_e", json_object_new_double(sc->xi_e));
    json_object_object_add(res, "stepping",
                           json_object_new_string(sph_stepping_name(sc->stepping)));
    json_object_object_add(res, "cfl_advection", json_object_new_double(sc->cfl_advection));
    json_object_object_add(res, "cfl_acoustic", json_object_new_double(sc->cfl_acoustic));
    json_object_object_add(res, "reference_speed", num(sim->stats.reference_speed));
    json_object_object_add(res, "acceleration_criterion",
                           json_object_new_boolean(sc->acceleration_criterion));
    json_object_object_add(res, "riemann_limiter",
                           json_object_new_double(sc->riemann_limiter_slope));
    json_object_object_add(res, "end_time", json_object_new_double(sc->end_time));
    json_object_object_add(res, "output_interval", json_object_new_double(sc->output_interval));
    json_object_object_add(res, "gravity", vector_json(sc->gravity, sc->dim));
    json_object *mats = json_object_new_array();
    for (int m = 0; m < sc->nmaterials; ++m) {
        json_object *o = json_object_new_object();
        const sph_material *mt = &sc->materials[m];
        json_object_object_add(o, "name", json_object_new_string(mt->name));
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
        json_object_object_add(o, "name", json_object_new_string(sc->bodies[b].name));
        json_object_object_add(o, "particles", json_object_new_int(sim->particles.body_count[b]));
        json_object_array_add(bodies, o);
    }
    json_object_object_add(res, "bodies", bodies);
    json_object_object_add(res, "fixed_particles", json_object_new_int(sim->particles.fixed_count));
    return res;
}

static json_object *summary_json(const sph_simulation *sim) {
    const sph_scene *sc = &sim->scene;
    const sph_backend *be = sim->backend;
    json_object *root = json_object_new_object();
    json_object_object_add(root, "sphsolid_version", json_object_new_string(SPHSOLID_VERSION));
    json_object_object_add(root, "commit", json_object_new_string(sph_build_commit()));
    const bool unstable = isfinite(sim->stats.instability_time) && sim->stats.instability_stopped;
    json_object_object_add(root, "status",
                           json_object_new_string(unstable ? "unstable" : "completed"));
    if (isfinite(sim->stats.instability_time)) {
        json_object *ins = json_object_new_object();
        json_object_object_add(ins, "time", json_object_new_double(sim->stats.instability_time));
        json_object_object_add(ins, "quantity",
                               json_object_new_string(sim->stats.instability_quantity));
        json_object_object_add(ins, "value", num(sim->stats.instability_value));
        json_object_object_add(ins, "threshold", num(sim->stats.instability_threshold));
        if (sim->stats.instability_field[0])
            json_object_object_add(ins, "field",
                                   json_object_new_string(sim->stats.instability_field));
        if (sim->stats.instability_particle >= 0) {
            const int b = sim->stats.instability_body;
            json_object_object_add(ins, "particle",
                                   json_object_new_int64(sim->stats.instability_particle));
            json_object_object_add(ins, "body", json_object_new_string(sc->bodies[b].name));
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
    json_object_object_add(scene, "path", json_object_new_string(sc->path));
    json_object_object_add(scene, "title", json_object_new_string(sc->title));
    json_object *ovr = json_object_new_array();
    for (int k = 0; k < sim->options.noverrides; ++k)
        json_object_array_add(ovr, json_object_new_string(sim->options.overrides[k]));
    json_object_object_add(scene, "overrides", ovr);
    json_object_object_add(scene, "resolved_text",
                           json_object_new_string(sc->resolved_text ? sc->resolved_text : ""));
    json_object_object_add(root, "scene", scene);

    json_object_object_add(root, "resolved", resolved_json(sim));

    json_object_object_add(root, "formulation",
                           json_object_new_string(sph_formulation_name(sc->formulation)));
    json_object_object_add(root, "rotation",
                           json_object_new_string(sph_rotation_name(sc->rotation)));
    json_object_object_add(root, "kernel", json_object_new_string(sph_kernel_name(sc->kernel)));
    json_object_object_add(root, "backend", json_object_new_string(be->kind_name));
    json_object_object_add(root, "device", json_object_new_string(be->device_name));
    json_object_object_add(root, "backend_choice", json_object_new_string(be->choice_reason));
    json_object_object_add(root, "precision",
                           json_object_new_string(sph_precision_name(&sim->features)));
    json_object_object_add(root, "build_options", json_object_new_string(be->build_options));
    json_object *features = json_object_new_object();
    const sph_features *f = &sim->features;
    json_object_object_add(features, "dimension", json_object_new_int(f->dim));
    json_object_object_add(features, "formulation",
                           json_object_new_string(sph_formulation_name(f->formulation)));
    json_object_object_add(features, "rotation",
                           json_object_new_string(sph_rotation_name(f->rotation)));
    json_object_object_add(features, "kernel", json_object_new_string(sph_kernel_name(f->kernel)));
    json_object_object_add(features, "material_model",
                           json_object_new_string(f->plastic ? "j2-plastic" : "elastic"));
    json_object_object_add(features, "clamp", json_object_new_boolean(f->has_clamp));
    json_object_object_add(features, "torque_projection",
                           json_object_new_boolean(f->torque_projection));
    json_object_object_add(features, "bodies", json_object_new_int(f->nbodies));
    json_object_object_add(features, "contact", json_object_new_boolean(f->contact));
    json_object_object_add(features, "walls", json_object_new_int(f->walls));
    json_object_object_add(features, "precision", json_object_new_string(sph_precision_name(f)));
    json_object_object_add(features, "stepping",
                           json_object_new_string(sph_stepping_name(f->stepping)));
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
            json_object_array_add(kernels, json_object_new_string_len(p, (int)n));
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
        json_object_object_add(o, "name", json_object_new_string(be->buffers[k].name));
        json_object_object_add(o, "bytes", json_object_new_int64((int64_t)be->buffers[k].bytes));
        json_object_array_add(bufs, o);
    }
    json_object_object_add(mem, "buffers", bufs);
    json_object_object_add(root, "memory", mem);
    if (be->profiling) {
        json_object *prof = json_object_new_array();
        for (int k = 0; k < be->nprofile; ++k) {
            json_object *o = json_object_new_object();
            json_object_object_add(o, "phase", json_object_new_string(be->profile[k].name));
            json_object_object_add(o, "calls", json_object_new_int64(be->profile[k].calls));
            json_object_object_add(o, "seconds", json_object_new_double(be->profile[k].seconds));
            json_object_array_add(prof, o);
        }
        json_object_object_add(root, "profile", prof);
    }

    json_object_object_add(root, "particle_count", json_object_new_int(sim->particles.n));
    /* how the relaxed bodies were placed (docs/scene-format.md, "Relaxed placement") */
    json_object *relaxed = json_object_new_array();
    for (int b = 0; b < sc->nbodies; ++b) {
        const sph_relax_report *r = &sim->particles.relax[b];
        if (!r->relaxed) continue;
        json_object *o = json_object_new_object();
        json_object_object_add(o, "body", json_object_new_string(sc->bodies[b].name));
        json_object_object_add(o, "particles", json_object_new_int(r->particles));
        json_object_object_add(o, "steps", json_object_new_int(r->steps));
        json_object_object_add(o, "residual_mean", num(r->mean));
        json_object_object_add(o, "residual_max", num(r->max));
        json_object_object_add(o, "residual_start_mean", num(r->start_mean));
        json_object_object_add(o, "residual_lattice_mean", num(r->lattice_mean));
        json_object_object_add(o, "min_distance", num(r->min_distance));
        json_object_object_add(o, "file", json_object_new_string(sc->bodies[b].relaxation.file));
        json_object_object_add(o, "reused", json_object_new_boolean(r->reused));
        json_object_array_add(relaxed, o);
    }
    json_object_object_add(root, "relaxed_bodies", relaxed);
    json_object_object_add(root, "snapshots", json_object_new_int(sim->snapshot_count));
    json_object *fields = json_object_new_array();
    for (int k = 0; k < SPH_OUT_COUNT; ++k)
        if (sc->output_field[k])
            json_object_array_add(
                fields, json_object_new_string(sph_output_field_name((sph_output_field)k)));
    json_object_object_add(root, "snapshot_fields", fields);
    if (isfinite(sim->restart_time)) {
        json_object *r = json_object_new_object();
        json_object_object_add(r, "directory", json_object_new_string(sim->options.restart_dir));
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
    if (sc->period_observer >= 0) {
        json_object_object_add(metrics, "first_period", num(m->first_period));
        json_object_object_add(metrics, "max_observer_displacement",
                               num(m->max_observer_displacement));
    }
    json_object_object_add(root, "metrics", metrics);
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
        st = sph_checkpoint_read(opt->restart_dir, sim->backend, &ck, &sim->series, err);
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
    if (opt->out_dir) {
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
            .prm = sim->prm,
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
        .prm = sim->prm,
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
    /* scales for the momentum errors: the total |momentum| magnitude and
     * sum m |x - x_c| |v| about the centre of mass */
    const int np = sim->particles.n, dim = sim->scene.dim;
    double scale = 0.0, angular_scale = 0.0, total_mass = 0.0, centre[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < np; ++i) {
        total_mass += sim->particles.mass[i];
        for (int d = 0; d < dim; ++d)
            centre[d] += sim->particles.mass[i] * sim->particles.pos[(size_t)d * np + i];
    }
    for (int d = 0; d < dim && total_mass > 0.0; ++d) centre[d] /= total_mass;
    for (int i = 0; i < np; ++i) {
        double v2 = 0.0, r2 = 0.0;
        for (int d = 0; d < dim; ++d) {
            const double v = sim->particles.vel[(size_t)d * np + i];
            const double r = sim->particles.pos[(size_t)d * np + i] - centre[d];
            v2 += v * v;
            r2 += r * r;
        }
        scale += sim->particles.mass[i] * sqrt(v2);
        angular_scale += sim->particles.mass[i] * sqrt(r2 * v2);
    }
    sph_metrics_compute(&sim->series, sim->scene.period_observer, sim->scene.period_axis, scale,
                        angular_scale, &sim->metrics);
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
        if (st == SPH_OK || st == SPH_UNSTABLE) {
            json_object *summary = summary_json(sim);
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
    memset(sim, 0, sizeof *sim);
}
