#include "kernel_bytes.h"

#include "embedded_sources.h"

#include <ctype.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The declarations are read from the embedded device sources at run time,
 * the very text the OpenCL compiler (and, through #include, the C compiler of
 * the native backend) sees: a table generated at build time would be a
 * second copy with its own build step, and the text is parsed once per
 * profiled phase at the end of a run only.  tests/test_kernel_bytes.py
 * checks that every declaration names exactly its kernel's global pointer
 * arguments. */

#define DECL_TAG   "/* buffers of "
#define MAX_NAME   48
#define MAX_SEEN   96
#define MAX_TOKENS 160

typedef enum { ACCESS_NONE, ACCESS_READ, ACCESS_WRITE, ACCESS_UPDATE } access_kind;

sph_status sph_bytes_sizes_measure(sph_backend *be, sph_bytes_sizes *out, sph_error *err) {
    out->pair_slots = 0.0;
    out->grid_cells = (double)be->grid_cells;
    out->padded_n = (double)be->n;
    out->substeps = be->substeps;
    /* the sort's keys hold npad entries on OpenCL (a power of two for the
     * bitonic sort); the native backend keeps n and records no "keys" */
    for (int k = 0; k < be->nbuffers; ++k)
        if (strcmp(be->buffers[k].name, "keys") == 0)
            out->padded_n = (double)(be->buffers[k].bytes / sizeof(uint64_t));
    sph_neighbour_lists lists = {0};
    const sph_status st = be->ops->download_neighbours(be, &lists, err);
    if (st) return st;
    double slots = 0.0;
    for (int i = 0; i < lists.n; ++i) slots += (double)lists.count[i];
    out->pair_slots = slots;
    sph_neighbour_lists_free(&lists);
    return SPH_OK;
}

/* The argument list of `kernel` in the OpenCL program's description
 * (be->program_kernels, "name(a, b, ...)" per line); NULL if not there. */
static const char *program_args(const char *kernels, const char *kernel, size_t *len) {
    const size_t klen = strlen(kernel);
    for (const char *p = kernels; *p;) {
        const char *nl = strchr(p, '\n');
        const size_t n = nl ? (size_t)(nl - p) : strlen(p);
        if (n > klen && strncmp(p, kernel, klen) == 0 && p[klen] == '(') {
            *len = n - klen - 1;
            return p + klen + 1;
        }
        p += n + (nl ? 1 : 0);
    }
    return NULL;
}

static bool has_word(const char *list, size_t len, const char *word) {
    const size_t wlen = strlen(word);
    for (size_t k = 0; k + wlen <= len; ++k) {
        if (strncmp(list + k, word, wlen) != 0) continue;
        const bool start = k == 0 || !(isalnum((unsigned char)list[k - 1]) || list[k - 1] == '_');
        const bool end =
            k + wlen == len || !(isalnum((unsigned char)list[k + wlen]) || list[k + wlen] == '_');
        if (start && end) return true;
    }
    return false;
}

static int field_index(const sph_backend *be, const char *name) {
    for (int f = 0; f < FIELD_COUNT; ++f)
        if (be->fields[f].name && strcmp(be->fields[f].name, name) == 0) return f;
    return -1;
}

/* Whether this run's kernel has the buffer.  OpenCL: the compiled kernel's
 * arguments (the feature switches drop the others).  Native: the backend
 * compiles every feature in and passes NULL for the fields a scene lacks;
 * of the other buffers it always stores the pair geometry (no shifted
 * positions), takes dt as a value (no device step clock), sorts on the host
 * (no keys_sorted, no counter of finished blocks) and allocates pair_w for
 * TLSPH only (backend_cpu.c, alloc_pairs). */
static bool buffer_present(const sph_backend *be, const char *args, size_t args_len,
                           const char *name) {
    if (args) return has_word(args, args_len, name);
    const int f = field_index(be, name);
    if (f >= 0) return be->fields[f].present;
    static const char *const native_absent[] = {"pair_pos", "step_clock", "keys_sorted",
                                                "blocks_done"};
    for (size_t k = 0; k < sizeof native_absent / sizeof native_absent[0]; ++k)
        if (strcmp(name, native_absent[k]) == 0) return false;
    if (strcmp(name, "pair_w") == 0) return be->features.formulation == SPH_FORMULATION_TLSPH;
    return true;
}

/* Bytes of one declared buffer over its extent; -1 if not known. */
static double entry_bytes(const sph_backend *be, const sph_bytes_sizes *s, const char *name,
                          const char *shape) {
    if (!shape) {
        const int f = field_index(be, name);
        if (f < 0) return -1.0;
        const sph_field_info *info = &be->fields[f];
        return (double)be->n * info->components *
               (double)sph_field_element_size(info->type, &be->features);
    }
    if (strcmp(shape, "host") == 0) return -1.0;
    if (strcmp(shape, "small") == 0) {
        /* a few values (reduction rows, results, the clock, flags): as the
         * backend allocated it, where it records one under this name */
        for (int k = 0; k < be->nbuffers; ++k)
            if (strcmp(be->buffers[k].name, name) == 0) return (double)be->buffers[k].bytes;
        return 0.0;
    }
    char buf[64];
    snprintf(buf, sizeof buf, "%s", shape);
    double bytes = 0.0;
    bool first = true;
    for (char *save = NULL, *t = strtok_r(buf, "*", &save); t; t = strtok_r(NULL, "*", &save)) {
        double x;
        if (first) {
            first = false;
            if (strcmp(t, "int") == 0 || strcmp(t, "uint") == 0)
                x = 4;
            else if (strcmp(t, "ulong") == 0 || strcmp(t, "double") == 0)
                x = 8;
            else if (strcmp(t, "u8") == 0)
                x = 1;
            else if (strcmp(t, "real") == 0)
                x = (double)sph_field_element_size(FIELD_TYPE_REAL, &be->features);
            else if (strcmp(t, "hreal") == 0)
                x = (double)sph_field_element_size(FIELD_TYPE_HREAL, &be->features);
            else
                return -1.0;
            bytes = x;
            continue;
        }
        if (strcmp(t, "n") == 0)
            x = be->n;
        else if (strcmp(t, "npad") == 0)
            x = s->padded_n;
        else if (strcmp(t, "pairs") == 0)
            x = s->pair_slots;
        else if (strcmp(t, "cells") == 0)
            x = s->grid_cells;
        else if (strcmp(t, "d") == 0)
            x = be->features.dim;
        else if (isdigit((unsigned char)t[0]))
            x = atof(t);
        else
            return -1.0;
        bytes *= x;
    }
    return first ? -1.0 : bytes;
}

/* Bytes of one call of `kernel` by its declarations (a kernel with several
 * definitions, the alternatives of a feature switch, has one declaration
 * each; a buffer named by more than one counts once).  -1: undeclared, or a
 * buffer of unknown size. */
static double kernel_bytes(const sph_backend *be, const sph_bytes_sizes *s, const char *kernel) {
    size_t args_len = 0;
    const char *args = NULL;
    if (be->program_kernels[0]) {
        args = program_args(be->program_kernels, kernel, &args_len);
        if (!args) return -1.0; /* not in this run's program */
    }
    char seen[MAX_SEEN][MAX_NAME];
    int nseen = 0;
    bool declared = false;
    double total = 0.0;
    const size_t klen = strlen(kernel);
    for (const sph_embedded_file *file = sph_embedded_files; file->name; ++file) {
        for (const char *p = strstr(file->text, DECL_TAG); p; p = strstr(p + 1, DECL_TAG)) {
            const char *name = p + strlen(DECL_TAG);
            if (strncmp(name, kernel, klen) != 0 || name[klen] != ':') continue;
            const char *end = strstr(name, "*/");
            if (!end) return -1.0;
            declared = true;
            access_kind mode = ACCESS_NONE;
            for (const char *q = name + klen + 1; q < end;) {
                while (q < end && (isspace((unsigned char)*q) || *q == ';' || *q == ',')) ++q;
                const char *t = q;
                while (q < end && !isspace((unsigned char)*q) && *q != ';' && *q != ',') ++q;
                const size_t tlen = (size_t)(q - t);
                if (tlen == 0 || (tlen == 1 && *t == '*')) continue; /* a continued line */
                char tok[2 * MAX_NAME];
                if (tlen >= sizeof tok) return -1.0;
                memcpy(tok, t, tlen);
                tok[tlen] = '\0';
                if (strcmp(tok, "reads") == 0)
                    mode = ACCESS_READ;
                else if (strcmp(tok, "writes") == 0)
                    mode = ACCESS_WRITE;
                else if (strcmp(tok, "updates") == 0)
                    mode = ACCESS_UPDATE;
                if (strcmp(tok, "reads") == 0 || strcmp(tok, "writes") == 0 ||
                    strcmp(tok, "updates") == 0)
                    continue;
                if (mode == ACCESS_NONE) return -1.0;
                char *shape = strchr(tok, ':');
                if (shape) *shape++ = '\0';
                if (strlen(tok) >= MAX_NAME) return -1.0;
                bool dup = false;
                for (int k = 0; k < nseen && !dup; ++k) dup = strcmp(seen[k], tok) == 0;
                if (dup) continue;
                if (nseen == MAX_SEEN) return -1.0;
                snprintf(seen[nseen++], MAX_NAME, "%s", tok);
                if (!buffer_present(be, args, args_len, tok)) continue;
                const double b = entry_bytes(be, s, tok, shape);
                if (b < 0) return -1.0;
                total += mode == ACCESS_UPDATE ? 2.0 * b : b;
            }
        }
    }
    return declared ? total : -1.0;
}

static void append(char *out, size_t cap, const char *name) {
    const size_t len = strlen(out);
    snprintf(out + len, cap - len, "%s%s", len ? " + " : "", name);
}

double sph_phase_bytes(const sph_backend *be, const sph_profile_record *rec,
                       const sph_bytes_sizes *sizes, char *kernels, size_t cap) {
    kernels[0] = '\0';
    const bool native = be->program_kernels[0] == '\0';
    if ((native && strcmp(rec->name, "acoustic substep") == 0) ||
        (!native && strcmp(rec->name, "acoustic_substep_loop") == 0)) {
        /* the native substep runs the passes of the OpenCL kernels fused in
         * one parallel region (backend_cpu_kernels.c, solid_substep_passes,
         * tl_substep_passes), every substep of the run inside this phase,
         * and OpenCL's substep loop runs them in one work-group
         * (device/substep_loop.cl), the substeps of a launch in one call:
         * the passes' bytes per substep; the fluids' passes are not the
         * OpenCL kernels one for one: no count */
        const sph_features *f = &be->features;
        if (FORM_IS_EULERIAN((int)f->formulation) || rec->calls <= 0) return -1.0;
        const char *list[6];
        int nk = 0;
        if (f->formulation == SPH_FORMULATION_TLSPH) {
            list[nk++] = "tl_deformation";
            list[nk++] = "tl_acceleration";
            list[nk++] = "tl_update";
        } else {
            if (be->fields[FIELD_CONTACT_COUNT].present) list[nk++] = "acoustic_contact";
            list[nk++] = "acoustic_pressure";
            list[nk++] = "acoustic_velocity_terms";
            if (be->fields[FIELD_ACC_STRESS].present) list[nk++] = "acoustic_shear_force";
        }
        list[nk++] = "substep_reduce";
        double per_substep = 0.0;
        for (int k = 0; k < nk; ++k) {
            const double b = kernel_bytes(be, sizes, list[k]);
            if (b < 0) return -1.0;
            per_substep += b;
        }
        for (int k = 0; k < nk; ++k) append(kernels, cap, list[k]);
        return per_substep * (double)sizes->substeps / (double)rec->calls;
    }
    /* diagnostics_reduce has two definitions (fluids, solids): the native
     * backend's phase cannot say which by its arguments */
    if (native && strcmp(rec->name, "diagnostics_reduce") == 0) return -1.0;
    /* every other phase that is a kernel: that kernel (the native backend's
     * rebuild_reduce and build_neighbours run the kernels' code as they are) */
    const double b = kernel_bytes(be, sizes, rec->name);
    if (b >= 0) append(kernels, cap, rec->name);
    return b;
}
