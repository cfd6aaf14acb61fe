#include "plot.h"

#include "embedded_sources.h"

#include <errno.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

sph_status sph_plot_run(const char *run_dir, bool quiet, sph_error *err) {
    const char *script = NULL;
    for (const sph_embedded_file *f = sph_embedded_files; f->name; ++f)
        if (strcmp(f->name, "plot_run.py") == 0) script = f->text;
    if (!script) return sph_fail(err, SPH_ERR_RUNTIME, "the plot script is not embedded");
    const char *python = getenv("SPHSOLID_PYTHON");
    if (!python || !*python) python = "/usr/bin/python3";

    int fds[2];
    if (pipe(fds) != 0)
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot start %s: %s", python, strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
    posix_spawn_file_actions_addclose(&actions, fds[1]);
    if (quiet) posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", 1, 0);
    char *const argv[] = {(char *)python, (char *)"-", (char *)run_dir, NULL};
    pid_t pid;
    const int rc = posix_spawn(&pid, python, &actions, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[0]);
    if (rc != 0) {
        close(fds[1]);
        return sph_fail(err, SPH_ERR_RUNTIME, "cannot run %s for the plots: %s", python,
                        strerror(rc));
    }
    /* a python that exits early closes the pipe: no SIGPIPE for us */
    void (*old)(int) = signal(SIGPIPE, SIG_IGN);
    const size_t len = strlen(script);
    size_t done = 0;
    while (done < len) {
        const ssize_t w = write(fds[1], script + done, len - done);
        if (w <= 0) break;
        done += (size_t)w;
    }
    close(fds[1]);
    signal(SIGPIPE, old);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return sph_fail(err, SPH_ERR_RUNTIME,
                        "the plots of %s failed (%s - %s exited with status %d; it needs Debian's "
                        "python3-matplotlib and python3-h5py)",
                        run_dir, python, run_dir, WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return SPH_OK;
}
