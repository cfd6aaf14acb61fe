#include "hdf5_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define COMPRESS_ABOVE 4096
#define CHUNK_VALUES   65536

static void quiet_hdf5(void) {
    /* errors are reported through sph_status, naming the file */
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

/* An HDF5 call on the in-memory file failed: HDF5 then ran out of memory
 * (disk errors come only from sph_h5_commit). */
static sph_status write_failed(const sph_h5_writer *w, const char *what, sph_error *err) {
    return sph_fail(err, SPH_ERR_RUNTIME, "cannot build %s (%s): HDF5 error (out of memory?)",
                    w->path, what);
}

bool sph_test_disk_full(const char *path) {
    const char *s = getenv("SPHSOLID_TEST_DISK_FULL");
    return s && *s && strstr(path, s) != NULL;
}

sph_status sph_h5_create(sph_h5_writer *w, const char *path, sph_error *err) {
    quiet_hdf5();
    w->file = -1;
    snprintf(w->path, sizeof w->path, "%s", path);
    snprintf(w->partial, sizeof w->partial, "%s.partial", path);
    w->fd = open(w->partial, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (w->fd < 0)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", w->partial, strerror(errno));
    /* in memory, grown 4 MiB at a time; nothing is written through HDF5 */
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    if (fapl >= 0 && H5Pset_fapl_core(fapl, (size_t)4 << 20, 0) >= 0)
        w->file = H5Fcreate(w->partial, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    if (fapl >= 0) H5Pclose(fapl);
    if (w->file < 0) {
        const sph_status st = write_failed(w, "create", err);
        sph_h5_abandon(w);
        return st;
    }
    return SPH_OK;
}

/* Fault injection for the kill-during-write test (tests/test_restart.py):
 * hold a checkpoint open and incomplete for SPHSOLID_TEST_CHECKPOINT_DELAY
 * seconds, so that the test can kill the run mid-write. */
static void test_write_delay(void) {
    const char *s = getenv("SPHSOLID_TEST_CHECKPOINT_DELAY");
    if (!s) return;
    const double seconds = atof(s);
    if (seconds <= 0) return;
    struct timespec ts = {(time_t)seconds, (long)((seconds - (double)(time_t)seconds) * 1e9)};
    nanosleep(&ts, NULL);
}

static bool write_all(int fd, const char *buf, size_t len) {
    while (len > 0) {
        const ssize_t got = write(fd, buf, len);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) {
            if (got == 0) errno = EIO;
            return false;
        }
        buf += got;
        len -= (size_t)got;
    }
    return true;
}

sph_status sph_h5_commit(sph_h5_writer *w, bool sync, sph_error *err) {
    if (sync) test_write_delay();
    /* the image of the finished file */
    char *image = NULL;
    ssize_t size =
        H5Fflush(w->file, H5F_SCOPE_GLOBAL) < 0 ? -1 : H5Fget_file_image(w->file, NULL, 0);
    if (size > 0) image = malloc((size_t)size);
    if (!image || H5Fget_file_image(w->file, image, (size_t)size) != size) {
        free(image);
        const sph_status st = write_failed(w, "image", err);
        sph_h5_abandon(w);
        return st;
    }
    H5Fclose(w->file);
    w->file = -1;
    bool ok;
    if (sph_test_disk_full(w->path)) {
        errno = ENOSPC;
        ok = false;
    } else {
        ok = write_all(w->fd, image, (size_t)size) && (!sync || fsync(w->fd) == 0);
    }
    free(image);
    const int write_errno = errno;
    const int closed = close(w->fd);
    w->fd = -1;
    if (!ok || closed != 0) {
        const sph_status st = sph_fail(err, SPH_ERR_RUNTIME, "cannot write %s: %s", w->partial,
                                       strerror(ok ? errno : write_errno));
        unlink(w->partial);
        return st;
    }
    if (rename(w->partial, w->path) != 0) {
        const sph_status st = sph_fail(err, SPH_ERR_RUNTIME, "cannot rename %s to %s: %s",
                                       w->partial, w->path, strerror(errno));
        unlink(w->partial);
        return st;
    }
    return SPH_OK;
}

void sph_h5_abandon(sph_h5_writer *w) {
    if (w->file >= 0) H5Fclose(w->file);
    w->file = -1;
    if (w->fd >= 0) close(w->fd);
    w->fd = -1;
    unlink(w->partial);
}

sph_status sph_h5_write(const sph_h5_writer *w, hid_t loc, const char *name, hid_t memtype,
                        hid_t filetype, int rank, const hsize_t *dims, const void *data,
                        sph_error *err) {
    hsize_t total = 1;
    for (int k = 0; k < rank; ++k) total *= dims[k];
    errno = 0;
    const hid_t space = H5Screate_simple(rank, dims, NULL);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (space < 0 || dcpl < 0) {
        if (space >= 0) H5Sclose(space);
        if (dcpl >= 0) H5Pclose(dcpl);
        return write_failed(w, name, err);
    }
    /* no modification time in the object headers: two runs that compute the
     * same values write the same bytes, whenever they run */
    H5Pset_obj_track_times(dcpl, 0);
    if (total > COMPRESS_ABOVE) {
        /* chunks of whole rows, about CHUNK_VALUES values each */
        hsize_t chunk[2] = {dims[0], rank > 1 ? dims[1] : 1};
        const hsize_t row = rank > 1 ? dims[1] : 1;
        const hsize_t rows = CHUNK_VALUES / row > 0 ? CHUNK_VALUES / row : 1;
        if (chunk[0] > rows) chunk[0] = rows;
        H5Pset_chunk(dcpl, rank, chunk);
        H5Pset_shuffle(dcpl);
        H5Pset_deflate(dcpl, 4);
    }
    const hid_t ds = H5Dcreate2(loc, name, filetype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    herr_t rc = ds < 0 ? -1 : H5Dwrite(ds, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
    if (ds >= 0 && H5Dclose(ds) < 0) rc = -1;
    H5Pclose(dcpl);
    H5Sclose(space);
    return rc < 0 ? write_failed(w, name, err) : SPH_OK;
}

static sph_status write_attr(const sph_h5_writer *w, hid_t loc, const char *name, hid_t type,
                             hid_t space, const void *data, sph_error *err) {
    errno = 0;
    const hid_t a = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = a < 0 ? -1 : H5Awrite(a, type, data);
    if (a >= 0 && H5Aclose(a) < 0) rc = -1;
    return rc < 0 ? write_failed(w, name, err) : SPH_OK;
}

sph_status sph_h5_attr_string(const sph_h5_writer *w, hid_t loc, const char *name,
                              const char *value, sph_error *err) {
    /* fixed-length ASCII: what VTK's HDF reader expects for Type */
    const size_t len = strlen(value);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, len > 0 ? len : 1);
    H5Tset_strpad(type, H5T_STR_NULLPAD);
    const hid_t space = H5Screate(H5S_SCALAR);
    const sph_status st = write_attr(w, loc, name, type, space, len > 0 ? value : "", err);
    H5Sclose(space);
    H5Tclose(type);
    return st;
}

sph_status sph_h5_attr_double(const sph_h5_writer *w, hid_t loc, const char *name, double value,
                              sph_error *err) {
    const hid_t space = H5Screate(H5S_SCALAR);
    const sph_status st = write_attr(w, loc, name, H5T_NATIVE_DOUBLE, space, &value, err);
    H5Sclose(space);
    return st;
}

sph_status sph_h5_attr_int64s(const sph_h5_writer *w, hid_t loc, const char *name,
                              const int64_t *values, int count, sph_error *err) {
    const hsize_t dims[1] = {(hsize_t)count};
    const hid_t space = count == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, dims, NULL);
    const sph_status st = write_attr(w, loc, name, H5T_NATIVE_INT64, space, values, err);
    H5Sclose(space);
    return st;
}

sph_status sph_h5_group(const sph_h5_writer *w, hid_t loc, const char *name, hid_t *out,
                        sph_error *err) {
    errno = 0;
    /* no modification time (sph_h5_write) */
    const hid_t gcpl = H5Pcreate(H5P_GROUP_CREATE);
    if (gcpl >= 0) H5Pset_obj_track_times(gcpl, 0);
    *out = H5Gcreate2(loc, name, H5P_DEFAULT, gcpl >= 0 ? gcpl : H5P_DEFAULT, H5P_DEFAULT);
    if (gcpl >= 0) H5Pclose(gcpl);
    return *out < 0 ? write_failed(w, name, err) : SPH_OK;
}

/* ---------------------------------------------------------------- reading */

sph_status sph_h5_open_read(const char *path, hid_t *file, sph_error *err) {
    quiet_hdf5();
    if (access(path, R_OK) != 0)
        return sph_fail(err, SPH_ERR_INPUT, "cannot read %s: %s", path, strerror(errno));
    *file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (*file < 0) return sph_fail(err, SPH_ERR_INPUT, "%s is not a readable HDF5 file", path);
    return SPH_OK;
}

sph_status sph_h5_size(hid_t loc, const char *path, const char *name, size_t *count,
                       sph_error *err) {
    *count = 0;
    const hid_t ds = H5Dopen2(loc, name, H5P_DEFAULT);
    if (ds < 0) return sph_fail(err, SPH_ERR_INPUT, "%s: no dataset '%s'", path, name);
    const hid_t space = H5Dget_space(ds);
    const hssize_t n = space < 0 ? -1 : H5Sget_simple_extent_npoints(space);
    if (space >= 0) H5Sclose(space);
    H5Dclose(ds);
    if (n < 0) return sph_fail(err, SPH_ERR_INPUT, "%s: cannot read dataset '%s'", path, name);
    *count = (size_t)n;
    return SPH_OK;
}

sph_status sph_h5_read(hid_t loc, const char *path, const char *name, hid_t memtype, void *out,
                       size_t count, sph_error *err) {
    size_t have = 0;
    sph_status st = sph_h5_size(loc, path, name, &have, err);
    if (st) return st;
    if (have != count)
        return sph_fail(err, SPH_ERR_INPUT, "%s: dataset '%s' has %zu values, expected %zu", path,
                        name, have, count);
    const hid_t ds = H5Dopen2(loc, name, H5P_DEFAULT);
    const herr_t rc = ds < 0 ? -1 : H5Dread(ds, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, out);
    if (ds >= 0) H5Dclose(ds);
    if (rc < 0) return sph_fail(err, SPH_ERR_INPUT, "%s: cannot read dataset '%s'", path, name);
    return SPH_OK;
}

static hid_t open_attr(hid_t loc, const char *path, const char *name, sph_error *err) {
    const hid_t a = H5Aopen_by_name(loc, ".", name, H5P_DEFAULT, H5P_DEFAULT);
    if (a < 0) sph_fail(err, SPH_ERR_INPUT, "%s: no attribute '%s'", path, name);
    return a;
}

/* Whether attribute a holds one value (H5Aread fills as many as it holds:
 * an array where one value is read would overrun the reader's buffer). */
static bool holds_one(hid_t a, const char *path, const char *name, sph_error *err) {
    const hid_t space = H5Aget_space(a);
    const hssize_t count = space < 0 ? -1 : H5Sget_simple_extent_npoints(space);
    if (space >= 0) H5Sclose(space);
    if (count != 1)
        sph_fail(err, SPH_ERR_INPUT, "%s: attribute '%s' holds %lld values, not one", path, name,
                 (long long)count);
    return count == 1;
}

static sph_status read_attr(hid_t loc, const char *path, const char *name, hid_t memtype, void *out,
                            sph_error *err) {
    const hid_t a = open_attr(loc, path, name, err);
    if (a < 0) return SPH_ERR_INPUT;
    if (!holds_one(a, path, name, err)) {
        H5Aclose(a);
        return SPH_ERR_INPUT;
    }
    const herr_t rc = H5Aread(a, memtype, out);
    H5Aclose(a);
    return rc < 0 ? sph_fail(err, SPH_ERR_INPUT, "%s: cannot read attribute '%s'", path, name)
                  : SPH_OK;
}

sph_status sph_h5_read_attr_double(hid_t loc, const char *path, const char *name, double *out,
                                   sph_error *err) {
    return read_attr(loc, path, name, H5T_NATIVE_DOUBLE, out, err);
}

sph_status sph_h5_read_attr_int64(hid_t loc, const char *path, const char *name, int64_t *out,
                                  sph_error *err) {
    return read_attr(loc, path, name, H5T_NATIVE_INT64, out, err);
}

sph_status sph_h5_read_attr_string(hid_t loc, const char *path, const char *name, char **out,
                                   sph_error *err) {
    *out = NULL;
    const hid_t a = open_attr(loc, path, name, err);
    if (a < 0) return SPH_ERR_INPUT;
    if (!holds_one(a, path, name, err)) {
        H5Aclose(a);
        return SPH_ERR_INPUT;
    }
    const hid_t ftype = H5Aget_type(a);
    const bool fixed =
        ftype >= 0 && H5Tget_class(ftype) == H5T_STRING && !H5Tis_variable_str(ftype);
    const size_t len = fixed ? H5Tget_size(ftype) : 0;
    if (ftype >= 0) H5Tclose(ftype);
    if (!fixed) {
        H5Aclose(a);
        return sph_fail(err, SPH_ERR_INPUT, "%s: attribute '%s' is not a fixed-length string", path,
                        name);
    }
    char *buf = calloc(len + 1, 1);
    /* one more byte: the memory type is NUL-terminated, the file's padded */
    const hid_t mtype = H5Tcopy(H5T_C_S1);
    H5Tset_size(mtype, len + 1);
    const herr_t rc = buf ? H5Aread(a, mtype, buf) : -1;
    H5Tclose(mtype);
    H5Aclose(a);
    if (rc < 0) {
        free(buf);
        return sph_fail(err, SPH_ERR_INPUT, "%s: cannot read attribute '%s'", path, name);
    }
    *out = buf;
    return SPH_OK;
}
