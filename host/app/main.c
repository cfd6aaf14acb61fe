/* main.c — the sphsolid command line.
 *
 *   sphsolid run SCENE [--set key=value]... [--backend opencl|cpu] [--device N]
 *                      [--precision double|single|mixed] [--out DIR] [--quiet] [--profile]
 *                      [--checkpoint-every T] [--checkpoint-wall S] [--progress-interval S]
 *                      [--plot] [--pair-geometry auto|stored|recomputed] [--no-work-limit]
 *                      [--step-clock auto|device|host] [--substeps-per-launch N]
 *                      [--reduction auto|blocks|tree]
 *   sphsolid run --restart DIR [--set time.end=T]... [same options]
 *   sphsolid compare RUN_A RUN_B [--rtol X] [--atol X] [--fields a,b]
 *   sphsolid relax SCENE [--set key=value]... [--out FILE] [--force]
 *   sphsolid kernel-study [--out DIR] [--dp X] [--kappas list] [--kernels list]
 *   sphsolid scene-keys [SECTION]
 *   sphsolid devices
 *   sphsolid bandwidth [--backend cpu|opencl] [--device N] [--size-mb M] [--repeat K] [--json]
 *
 * Exit status: 0 success, 2 bad input (scene file, flags), 1 runtime failure,
 * 3 (compare) differences beyond the tolerance, 4 stopped by the instability
 * monitor (results kept, summary.json status "unstable").
 */
#include "bandwidth.h"
#include "compare.h"
#include "kernel_study.h"
#include "opencl_runtime.h"
#include "plot.h"
#include "particles.h"
#include "run.h"
#include "scene_schema.h"

#include <errno.h>
#include <stdbool.h>
#include <math.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(FILE *f) {
    fprintf(
        f,
        "usage: sphsolid run SCENE [--set key=value]... [--backend opencl|cpu] [--device N]\n"
        "                          [--precision double|single|mixed] [--out DIR] [--quiet] "
        "[--profile]\n"
        "                          [--checkpoint-every T] [--checkpoint-wall S]\n"
        "                          [--progress-interval S] [--plot] [--no-work-limit]\n"
        "                          [--pair-geometry auto|stored|recomputed]\n"
        "                          [--step-clock auto|device|host] [--substeps-per-launch N]\n"
        "                          [--reduction auto|blocks|tree]\n"
        "       sphsolid run --restart DIR [--set time.end=T] [options as above]\n"
        "       sphsolid compare RUN_A RUN_B [--rtol X] [--atol X] [--fields a,b,...]\n"
        "       sphsolid relax SCENE [--set key=value]... [--out FILE] [--force]\n"
        "       sphsolid kernel-study [--out DIR] [--dp X] [--kappas list] [--kernels list]\n"
        "                             [--steps N] [--seed S] [--exclude E]\n"
        "       sphsolid scene-keys [SECTION]\n"
        "       sphsolid devices\n"
        "       sphsolid bandwidth [--backend cpu|opencl] [--device N] [--size-mb M] [--repeat K]\n"
        "                          [--json]\n"
        "       sphsolid --version\n"
        "\n"
        "run       simulate a scene file (see docs/scene-format.md); results go to DIR\n"
        "          (default: runs/<scene directory name>): timeseries.csv, summary.json,\n"
        "          snapshots (VTKHDF, open snapshots.hdf.series in ParaView); one process\n"
        "          at a time in DIR: a second run (or restart, relax --out) there is refused\n"
        "--set     override any scene value, e.g. --set resolution.ratio=30\n"
        "--backend opencl: an OpenCL device (--device N, see `sphsolid devices`);\n"
        "          cpu: the native backend.  Default: an OpenCL GPU if present, else cpu\n"
        "--profile time every phase (device kernels, host steps) into summary.json\n"
        "--checkpoint-every T  write DIR/checkpoint/checkpoint.h5 every T simulated seconds\n"
        "--checkpoint-wall S   ... or every S seconds of wall time\n"
        "--restart DIR         continue the run in DIR from its checkpoint (in DIR, or --out),\n"
        "                      writing checkpoints as it did unless the flags above are given\n"
        "--progress-interval S seconds between progress lines when stderr is not a terminal\n"
        "--no-work-limit  run even when the predicted work is absurd (more substeps,\n"
        "          particle-substeps or outputs than its limits, a material faster than\n"
        "          sound in any solid, more output than the free disk): warn instead\n"
        "          (docs/scene-format.md, \"Predicted work\")\n"
        "--plot    write PNG plots into DIR/plots after the run (tools/plot_run.py)\n"
        "--pair-geometry  OpenCL: the acoustic passes read the frozen pair geometry from\n"
        "          per-pair arrays (stored) or recompute it (recomputed); auto (default):\n"
        "          recomputed on GPUs, stored on CPU devices (docs/benchmarks.md);\n"
        "          TLSPH always stores its reference geometry\n"
        "--step-clock  who sizes the acoustic substeps: OpenCL: the device (auto, where it\n"
        "          has double precision), enqueuing an advection step's substeps without a\n"
        "          read after each, or the host, reading max |v| after every substep;\n"
        "          native: the thread team in one parallel region per advection step\n"
        "          (auto), or the host between substeps; all give the same steps\n"
        "--substeps-per-launch  OpenCL: 1 launches each pass of each substep; N > 1 runs up\n"
        "          to N substeps per launch in one work-group (the substep loop, small\n"
        "          scenes); 0 (default): chosen by the particle count and the device; the\n"
        "          same steps bit for bit (docs/backends.md)\n"
        "--reduction  OpenCL: the reductions' first stage by blocks of particles (auto on\n"
        "          CPU devices) or by a tree over each work-group (auto on GPUs)\n"
        "relax     relax the particles of the bodies with placement = \"relaxed\" ahead of a\n"
        "          run, save them to their relaxation.file and print the residuals;\n"
        "          --out FILE saves the one relaxed body to FILE, --force relaxes even\n"
        "          when the file matches\n"
        "kernel-study  004's kernel study (Tables 1-4, Fig. 2): a disc D = 2 relaxed with\n"
        "          each kernel at each kappa = h/dp (h = 1.3 X, X = --dp, default 1/60);\n"
        "          df/dx errors and relaxation residues into DIR/kernel_study.json\n"
        "          (default DIR: runs/kernel-study; docs/kernel-study.md)\n"
        "scene-keys  the scene schema: every key a scene file may hold, its type, default,\n"
        "          range and meaning, as the Markdown tables of docs/scene-format.md (one\n"
        "          SECTION: `method`, `shapes.box`, ...; \"\" for the top level)\n"
        "compare   per-field maximum differences of two runs' snapshots and time series\n"
        "bandwidth the device's memory bandwidth: a streaming copy, GB/s (read + write)\n"
        "exit status: 0 success, 2 bad input, 1 runtime failure, 3 compare: beyond tolerance,\n"
        "             4 stopped by the instability monitor (results kept)\n");
}

/* The index of `value` in the NULL-terminated list `names`, or -1. */
static int choice_index(const char *value, const char *const *names) {
    for (int k = 0; names[k]; ++k)
        if (strcmp(value, names[k]) == 0) return k;
    return -1;
}

static int input_error(const char *fmt, const char *arg) {
    fprintf(stderr, "sphsolid: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(run `sphsolid --help` for usage)\n");
    return SPH_ERR_INPUT;
}

/* sphsolid scene-keys [SECTION]: the schema's key tables (scene_schema.h). */
static int cmd_scene_keys(int argc, char **argv) {
    const char *sections[SK_COUNT];
    const int n = sph_scene_key_sections(sections, SK_COUNT);
    if (argc > 1) return input_error("scene-keys takes one SECTION, got '%s' too", argv[1]);
    if (argc == 1) {
        if (sph_scene_keys_markdown(stdout, argv[0])) return 0;
        fprintf(stderr, "sphsolid: scene-keys: no section '%s'; the sections:", argv[0]);
        for (int i = 0; i < n; i++) fprintf(stderr, " \"%s\"", sections[i]);
        fprintf(stderr, "\n");
        return SPH_ERR_INPUT;
    }
    for (int i = 0; i < n; i++) {
        printf("%s### %s\n\n", i ? "\n" : "", sections[i][0] ? sections[i] : "(top level)");
        sph_scene_keys_markdown(stdout, sections[i]);
    }
    return 0;
}

/* Default output directory: runs/<name of the scene's directory or stem>. */
static void default_out_dir(const char *scene, char *buf, size_t len) {
    char tmp[PATH_MAX];
    snprintf(tmp, sizeof tmp, "%s", scene);
    char *slash = strrchr(tmp, '/');
    const char *name = tmp;
    if (slash) {
        *slash = '\0';
        char *parent = strrchr(tmp, '/');
        name = parent ? parent + 1 : tmp;
        if (strcmp(name, ".") == 0 || *name == '\0') name = slash + 1;
    } else {
        char *dot = strrchr(tmp, '.');
        if (dot) *dot = '\0';
    }
    sph_format(buf, len, "runs/%s", name);
}

static int cmd_run(int argc, char **argv) {
    sph_run_options opt = {0};
    opt.backend.kind = SPH_BACKEND_AUTO;
    opt.backend.device_index = -1;
    opt.precision = SPH_PRECISION_DOUBLE;
    const char **overrides = calloc((size_t)argc, sizeof(char *));
    if (!overrides) return SPH_ERR_RUNTIME;
    int noverrides = 0;
    const char *out_dir = NULL;
    bool plot = false;
    for (int k = 0; k < argc; ++k) {
        const char *a = argv[k];
        const char *value = k + 1 < argc ? argv[k + 1] : NULL;
        if (strcmp(a, "--set") == 0 || strcmp(a, "--backend") == 0 || strcmp(a, "--device") == 0 ||
            strcmp(a, "--precision") == 0 || strcmp(a, "--out") == 0 ||
            strcmp(a, "--pair-geometry") == 0 || strcmp(a, "--step-clock") == 0 ||
            strcmp(a, "--substeps-per-launch") == 0 || strcmp(a, "--reduction") == 0 ||
            strcmp(a, "--restart") == 0 || strcmp(a, "--checkpoint-every") == 0 ||
            strcmp(a, "--checkpoint-wall") == 0 || strcmp(a, "--progress-interval") == 0) {
            if (!value) {
                free(overrides);
                return input_error("%s needs a value", a);
            }
            ++k;
        }
        if (strcmp(a, "--set") == 0) {
            overrides[noverrides++] = value;
        } else if (strcmp(a, "--backend") == 0) {
            if (strcmp(value, "cpu") == 0)
                opt.backend.kind = SPH_BACKEND_CPU;
            else if (strcmp(value, "opencl") == 0)
                opt.backend.kind = SPH_BACKEND_OPENCL;
            else {
                free(overrides);
                return input_error("--backend %s: expected opencl or cpu", value);
            }
        } else if (strcmp(a, "--device") == 0) {
            char *end;
            errno = 0;
            const long d = strtol(value, &end, 10);
            if (errno || *end || d < 0 || d > 1000) {
                free(overrides);
                return input_error("--device %s: expected a device number (see `sphsolid devices`)",
                                   value);
            }
            opt.backend.device_index = (int)d;
            if (opt.backend.kind == SPH_BACKEND_AUTO) opt.backend.kind = SPH_BACKEND_OPENCL;
        } else if (strcmp(a, "--precision") == 0) {
            if (!sph_precision_parse(value, &opt.precision)) {
                free(overrides);
                return input_error("--precision %s: expected double, single or mixed", value);
            }
        } else if (strcmp(a, "--pair-geometry") == 0 || strcmp(a, "--step-clock") == 0) {
            /* in the order of sph_pair_geometry and sph_step_clock_mode */
            static const char *const geometry_names[] = {"auto", "stored", "recomputed", NULL};
            static const char *const clock_names[] = {"auto", "device", "host", NULL};
            const bool geometry = strcmp(a, "--pair-geometry") == 0;
            const int choice = choice_index(value, geometry ? geometry_names : clock_names);
            if (choice < 0) {
                free(overrides);
                return input_error(geometry
                                       ? "--pair-geometry %s: expected auto, stored or recomputed"
                                       : "--step-clock %s: expected auto, device or host",
                                   value);
            }
            if (geometry)
                opt.backend.pair_geometry = (sph_pair_geometry)choice;
            else
                opt.backend.step_clock = (sph_step_clock_mode)choice;
        } else if (strcmp(a, "--substeps-per-launch") == 0) {
            char *end;
            errno = 0;
            const long count = strtol(value, &end, 10);
            if (errno || *end || end == value || count < 0 || count > 1000000) {
                free(overrides);
                return input_error("--substeps-per-launch %s: expected a whole number from 0 "
                                   "(chosen by the run) to 1000000",
                                   value);
            }
            opt.backend.substeps_per_launch = count;
        } else if (strcmp(a, "--reduction") == 0) {
            static const char *const reduction_names[] = {"auto", "blocks", "tree", NULL};
            const int choice = choice_index(value, reduction_names);
            if (choice < 0) {
                free(overrides);
                return input_error("--reduction %s: expected auto, blocks or tree", value);
            }
            opt.backend.reduction = (sph_reduction_mode)choice;
        } else if (strcmp(a, "--out") == 0) {
            out_dir = value;
        } else if (strcmp(a, "--restart") == 0) {
            opt.restart_dir = value;
        } else if (strcmp(a, "--checkpoint-every") == 0 || strcmp(a, "--checkpoint-wall") == 0 ||
                   strcmp(a, "--progress-interval") == 0) {
            char *end;
            errno = 0;
            const double x = strtod(value, &end);
            if (errno || *end || !(x > 0) || !isfinite(x)) {
                free(overrides);
                fprintf(stderr, "sphsolid: %s %s: expected a positive number of seconds\n", a,
                        value);
                return SPH_ERR_INPUT;
            }
            if (strcmp(a, "--checkpoint-every") == 0)
                opt.checkpoint_every = x;
            else if (strcmp(a, "--checkpoint-wall") == 0)
                opt.checkpoint_wall = x;
            else
                opt.progress_interval = x;
        } else if (strcmp(a, "--plot") == 0) {
            plot = true;
        } else if (strcmp(a, "--no-work-limit") == 0) {
            opt.no_work_limit = true;
        } else if (strcmp(a, "--quiet") == 0) {
            opt.quiet = true;
        } else if (strcmp(a, "--profile") == 0) {
            opt.backend.profile = true;
        } else if (a[0] == '-') {
            free(overrides);
            return input_error("unknown option %s", a);
        } else if (!opt.scene_path) {
            opt.scene_path = a;
        } else {
            free(overrides);
            return input_error("unexpected argument %s (one scene per run)", a);
        }
    }
    if (!opt.scene_path && !opt.restart_dir) {
        free(overrides);
        return input_error("%s", "run needs a scene file (or --restart DIR)");
    }
    if (opt.scene_path && opt.restart_dir) {
        free(overrides);
        return input_error("--restart %s continues the scene stored in its checkpoint: give no "
                           "scene file (change the end time with --set time.end=...)",
                           opt.restart_dir);
    }
    if (opt.backend.kind == SPH_BACKEND_CPU && opt.backend.device_index >= 0) {
        free(overrides);
        return input_error("%s",
                           "--device selects an OpenCL device; it does not go with --backend cpu");
    }
    char default_dir[PATH_MAX];
    if (!out_dir && opt.restart_dir) out_dir = opt.restart_dir;
    if (!out_dir) {
        default_out_dir(opt.scene_path, default_dir, sizeof default_dir);
        out_dir = default_dir;
    }
    opt.overrides = overrides;
    opt.noverrides = noverrides;
    opt.out_dir = out_dir;
    opt.backend.quiet = opt.quiet;

    sph_simulation sim;
    sph_error err = {0};
    sph_status st = sph_simulation_open(&sim, &opt, &err);
    if (!st) st = sph_simulation_run(&sim, &err);
    if (st) {
        fprintf(stderr, "sphsolid: %s\n", err.msg);
    } else if (!opt.quiet) {
        fprintf(stderr,
                "sphsolid: done: %d particles, %ld acoustic / %ld advection steps, %.2f s wall "
                "(%.3g M particle-substeps/s); results in %s\n",
                sim.particles.n, sim.stats.acoustic_steps, sim.stats.advection_steps,
                sim.stats.wall_seconds, sim.stats.particle_substeps_per_second / 1e6, out_dir);
        if (isfinite(sim.metrics.first_period))
            fprintf(stderr, "sphsolid: first period %.5f s\n", sim.metrics.first_period);
        if (isfinite(sim.metrics.max_angular_momentum_error))
            fprintf(stderr, "sphsolid: max angular-momentum error %.3f %%\n",
                    100.0 * sim.metrics.max_angular_momentum_error);
        else if (sim.metrics.angular_momentum_not_conserved[0])
            fprintf(stderr, "sphsolid: angular momentum not conserved (%s): no error reported\n",
                    sim.metrics.angular_momentum_not_conserved);
    }
    if (!st && plot) {
        sph_error perr = {0};
        st = sph_plot_run(out_dir, opt.quiet, &perr);
        if (st) fprintf(stderr, "sphsolid: %s\n", perr.msg);
    }
    /* after the plots: the directory stays this run's until they are in it */
    sph_simulation_close(&sim);
    free(overrides);
    return (int)st;
}

/* sphsolid relax: the placement of a run without the run. */
static int cmd_relax(int argc, char **argv) {
    const char **overrides = calloc((size_t)argc + 1, sizeof(char *));
    if (!overrides) return SPH_ERR_RUNTIME;
    int noverrides = 0;
    const char *scene_path = NULL, *out = NULL;
    bool force = false;
    for (int k = 0; k < argc; ++k) {
        const char *a = argv[k];
        if (strcmp(a, "--set") == 0 || strcmp(a, "--out") == 0) {
            if (k + 1 >= argc) {
                free(overrides);
                return input_error("%s needs a value", a);
            }
            if (strcmp(a, "--set") == 0)
                overrides[noverrides++] = argv[++k];
            else
                out = argv[++k];
        } else if (strcmp(a, "--force") == 0) {
            force = true;
        } else if (a[0] == '-') {
            free(overrides);
            return input_error("unknown option %s", a);
        } else if (!scene_path) {
            scene_path = a;
        } else {
            free(overrides);
            return input_error("unexpected argument %s (one scene)", a);
        }
    }
    if (!scene_path) {
        free(overrides);
        return input_error("%s", "relax needs a scene file");
    }
    sph_scene *scene = malloc(sizeof *scene);
    sph_particles p;
    sph_error err = {0};
    sph_status st = scene ? sph_scene_load(scene, scene_path, overrides, noverrides, &err)
                          : sph_fail(&err, SPH_ERR_RUNTIME, "out of memory");
    free(overrides);
    if (st) {
        fprintf(stderr, "sphsolid: %s\n", err.msg);
        free(scene);
        return (int)st;
    }
    int relaxed = 0, which = -1;
    for (int b = 0; b < scene->nbodies; b++)
        if (scene->bodies[b].placement == SPH_PLACEMENT_RELAXED) relaxed++, which = b;
    if (relaxed == 0)
        st = sph_fail(&err, SPH_ERR_INPUT,
                      "%s: no body has placement = \"relaxed\" (e.g. --set "
                      "bodies.%s.placement=relaxed)",
                      scene_path, scene->bodies[0].name);
    else if (out && relaxed > 1)
        st = sph_fail(&err, SPH_ERR_INPUT,
                      "--out %s: the scene has %d bodies with placement = \"relaxed\"; --out "
                      "names the file of one (give each body its relaxation.file instead)",
                      out, relaxed);
    else if (out && strlen(out) >= sizeof scene->bodies[which].relaxation.file)
        st = sph_fail(&err, SPH_ERR_INPUT, "--out: the path is too long");
    if (!st && out)
        snprintf(scene->bodies[which].relaxation.file, sizeof scene->bodies[which].relaxation.file,
                 "%s", out);
    /* --out into a run's directory waits for no one: refused while a run or
     * a restart holds it (run.h, sph_dir_lock) */
    sph_dir_lock lock = {.fd = -1};
    if (!st && out) {
        char dir[PATH_MAX], label[PATH_MAX + 32];
        snprintf(dir, sizeof dir, "%s", out);
        char *slash = strrchr(dir, '/');
        if (!slash)
            snprintf(dir, sizeof dir, ".");
        else if (slash == dir)
            slash[1] = '\0';
        else
            *slash = '\0';
        snprintf(label, sizeof label, "--out %s: directory", out);
        st = sph_dir_lock_take(&lock, dir, SPH_DIR_LOCK_IF_USED, label, &err);
    }
    if (!st) st = sph_particles_generate_ex(scene, &p, force, &err);
    sph_dir_lock_release(&lock);
    if (st) {
        fprintf(stderr, "sphsolid: %s\n", err.msg);
    } else {
        for (int b = 0; b < scene->nbodies; b++) {
            if (!p.relax[b].relaxed) continue;
            char line[4096];
            sph_relax_report_format(&p.relax[b], scene->bodies[b].name,
                                    scene->bodies[b].relaxation.file, line, sizeof line);
            printf("%s\n", line);
        }
        sph_particles_free(&p);
    }
    sph_scene_free(scene);
    free(scene);
    return (int)st;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        usage(stderr);
        return SPH_ERR_INPUT;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
        strcmp(argv[1], "help") == 0) {
        usage(stdout);
        return 0;
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("sphsolid %s\n", SPHSOLID_VERSION);
        return 0;
    }
    if (strcmp(argv[1], "devices") == 0) {
        sph_opencl_print_devices(stdout);
        return 0;
    }
    if (strcmp(argv[1], "run") == 0) return cmd_run(argc - 2, argv + 2);
    if (strcmp(argv[1], "relax") == 0) return cmd_relax(argc - 2, argv + 2);
    if (strcmp(argv[1], "compare") == 0) return sph_compare_main(argc - 2, argv + 2);
    if (strcmp(argv[1], "kernel-study") == 0) return sph_kernel_study_main(argc - 2, argv + 2);
    if (strcmp(argv[1], "bandwidth") == 0) return sph_bandwidth_main(argc - 2, argv + 2);
    if (strcmp(argv[1], "scene-keys") == 0) return cmd_scene_keys(argc - 2, argv + 2);
    return input_error("unknown command '%s'", argv[1]);
}
