/* sph_error.h — errors are return codes with a message.
 *
 * Every fallible library function returns SPH_OK or an sph_status code and,
 * on failure, writes one clear sentence into the caller's sph_error.  Nothing
 * in the library prints or exits; the CLI turns the code into the process
 * exit status (0 success, 2 bad input, 1 runtime failure, 4 stopped by the
 * instability monitor).
 */
#ifndef SPH_ERROR_H
#define SPH_ERROR_H

typedef enum {
    SPH_OK = 0,
    SPH_ERR_RUNTIME = 1, /* device, memory, I/O, numerical failure */
    SPH_ERR_INPUT = 2,   /* scene file, CLI flags */
    SPH_UNSTABLE = 4,    /* the instability monitor stopped the run (results kept) */
} sph_status;

#define SPH_ERROR_MSG_LEN 2048

typedef struct {
    sph_status code;
    char msg[SPH_ERROR_MSG_LEN];
} sph_error;

/* Record a failure; returns `code` so callers can `return sph_fail(...)`. */
sph_status sph_fail(sph_error *err, sph_status code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Prefix the recorded message with context ("while building ...: "). */
sph_status sph_error_prefix(sph_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* snprintf for messages and labels where truncation is acceptable. */
void sph_format(char *buf, unsigned long len, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#endif
