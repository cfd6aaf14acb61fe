#include "sph_error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

sph_status sph_fail(sph_error *err, sph_status code, const char *fmt, ...) {
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return code;
}

sph_status sph_error_prefix(sph_error *err, const char *fmt, ...) {
    if (!err) return SPH_ERR_RUNTIME;
    char prefix[SPH_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    char joined[SPH_ERROR_MSG_LEN];
    sph_format(joined, sizeof joined, "%s%s", prefix, err->msg);
    memcpy(err->msg, joined, sizeof joined);
    return err->code;
}

void sph_format(char *buf, unsigned long len, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, len, fmt, ap);
    va_end(ap);
}
