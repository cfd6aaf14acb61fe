/* hdf5_file.h — HDF5 files that appear complete or not at all.
 *
 * A file is created as `<path>.partial` and renamed to `<path>` only after
 * every dataset is written and the file is closed (and, for checkpoints,
 * synced), so a run killed mid-write leaves the previous file of that name
 * untouched.  The HDF5 file is built in memory (the core driver, no backing
 * store) and written to `<path>.partial` by sph_h5_commit with plain write
 * calls: a full disk or any other write error is then an errno for the
 * message, and HDF5 never holds a file it cannot flush (which it would try
 * to close again, and crash, at exit).  The helpers wrap the numbered HDF5
 * calls with sph_status errors that name the file; HDF5's own error-stack
 * printing is switched off.
 */
#ifndef SPH_HDF5_FILE_H
#define SPH_HDF5_FILE_H

#include "sph_error.h"

#include <hdf5.h>
#include <stdbool.h>
#include <stdint.h>

typedef struct {
    hid_t file;         /* the file, in memory */
    int fd;             /* `partial`, open from create to commit */
    char path[1100];    /* the final name */
    char partial[1200]; /* where it is written */
} sph_h5_writer;

/* Create `<path>.partial` (an error names it if it cannot be) and start the
 * file in memory. */
sph_status sph_h5_create(sph_h5_writer *w, const char *path, sph_error *err);
/* Write the file to `<path>.partial`, optionally fsync, close and rename
 * into place; on failure remove the partial file. */
sph_status sph_h5_commit(sph_h5_writer *w, bool sync, sph_error *err);
/* Close and remove the partial file (after an error). */
void sph_h5_abandon(sph_h5_writer *w);

/* Fault injection for tests/test_bad_input.py where no small filesystem can
 * be mounted: true when SPHSOLID_TEST_DISK_FULL is set and `path` contains
 * its value; the run's writers then fail that file with ENOSPC. */
bool sph_test_disk_full(const char *path);

/* A dataset of `rank` <= 2 dimensions from `data` in memory type `memtype`,
 * stored as `filetype`; chunked and compressed (shuffle + deflate) when it
 * holds more than 4096 values. */
sph_status sph_h5_write(const sph_h5_writer *w, hid_t loc, const char *name, hid_t memtype,
                        hid_t filetype, int rank, const hsize_t *dims, const void *data,
                        sph_error *err);
sph_status sph_h5_attr_string(const sph_h5_writer *w, hid_t loc, const char *name,
                              const char *value, sph_error *err);
sph_status sph_h5_attr_double(const sph_h5_writer *w, hid_t loc, const char *name, double value,
                              sph_error *err);
sph_status sph_h5_attr_int64s(const sph_h5_writer *w, hid_t loc, const char *name,
                              const int64_t *values, int count, sph_error *err);
/* A new group (closed by the caller with H5Gclose). */
sph_status sph_h5_group(const sph_h5_writer *w, hid_t loc, const char *name, hid_t *out,
                        sph_error *err);

/* Reading (checkpoints, compare). */
sph_status sph_h5_open_read(const char *path, hid_t *file, sph_error *err);
/* Read a whole dataset converted to `memtype`; `count` must equal its size. */
sph_status sph_h5_read(hid_t loc, const char *path, const char *name, hid_t memtype, void *out,
                       size_t count, sph_error *err);
/* Number of elements of a dataset (0 with an error when absent). */
sph_status sph_h5_size(hid_t loc, const char *path, const char *name, size_t *count,
                       sph_error *err);
sph_status sph_h5_read_attr_double(hid_t loc, const char *path, const char *name, double *out,
                                   sph_error *err);
sph_status sph_h5_read_attr_int64(hid_t loc, const char *path, const char *name, int64_t *out,
                                  sph_error *err);
/* A string attribute, malloc'ed (caller frees). */
sph_status sph_h5_read_attr_string(hid_t loc, const char *path, const char *name, char **out,
                                   sph_error *err);

#endif
