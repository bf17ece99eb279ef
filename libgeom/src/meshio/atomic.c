/* meshio atomic file output: a temporary file in the destination's
 * directory, renamed over the destination when complete (POSIX). */
#define _POSIX_C_SOURCE 200809L

#include "meshio/meshio_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static geom_status io_error(geom_diag *d, const char *path, int err, const char *what)
{
    char reason[128];
    geom__sys_reason(err, reason, sizeof reason);
    return geom_diag_set(d, GEOM_ERR_IO, path, 0, 0, "%s: %s", what, reason);
}

geom_status geom_meshio__atomic_open(mio_atomic *a, const char *path, const geom_allocator *al,
                                     geom_diag *diag)
{
    memset(a, 0, sizeof *a);
    a->fd = -1;
    a->alloc = al;
    size_t plen = strlen(path);
    if (plen == 0)
        return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "empty output path");
    if (path[plen - 1] == '/')
        return geom_diag_set(diag, GEOM_ERR_IO, path, 0, 0, "output path names a directory");
    a->path_size = plen + 1;
    a->path = geom_alloc(al, a->path_size);
    a->tmp_size = plen + 32;
    a->tmp = geom_alloc(al, a->tmp_size);
    if (!a->path || !a->tmp) {
        geom_free(al, a->path, a->path_size);
        geom_free(al, a->tmp, a->tmp_size);
        a->path = a->tmp = NULL;
        return geom_diag_set(diag, GEOM_ERR_NOMEM, path, 0, 0, "out of memory");
    }
    memcpy(a->path, path, plen + 1);
    const char *slash = strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0;
    const char *base = path + dirlen;

    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    uint64_t seed = geom_meshio__mix((uint64_t)ts.tv_nsec, (uint64_t)ts.tv_sec);
    seed = geom_meshio__mix(seed, (uint64_t)getpid());
    seed = geom_meshio__mix(seed, (uint64_t)(uintptr_t)&ts);
    static const char alphabet[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    int err = 0;
    for (int attempt = 0; attempt < 100; attempt++) {
        uint64_t r = geom_meshio__mix(seed, (uint64_t)attempt);
        char rnd[9];
        for (int i = 0; i < 8; i++) {
            rnd[i] = alphabet[r % 36];
            r /= 36;
        }
        rnd[8] = '\0';
        snprintf(a->tmp, a->tmp_size, "%.*s.%s.%s.tmp", (int)dirlen, path, base, rnd);
        int fd = open(a->tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd >= 0) {
            a->fd = fd;
            return GEOM_OK;
        }
        err = errno;
        if (err != EEXIST)
            break;
    }
    geom_status st = io_error(diag, path, err, "cannot create a temporary file next to it");
    geom_free(al, a->path, a->path_size);
    geom_free(al, a->tmp, a->tmp_size);
    a->path = a->tmp = NULL;
    return st;
}

geom_status geom_meshio__atomic_write(void *user, const void *data, size_t n, geom_diag *diag)
{
    mio_atomic *a = user;
    const char *p = data;
    while (n > 0) {
        ssize_t w = write(a->fd, p, n);
        if (w < 0) {
            if (errno == EINTR)
                continue;
            return io_error(diag, a->path, errno, "write failed");
        }
        if (w == 0)
            return geom_diag_set(diag, GEOM_ERR_IO, a->path, 0, 0, "write failed: no progress");
        p += w;
        n -= (size_t)w;
    }
    return GEOM_OK;
}

static void release(mio_atomic *a)
{
    geom_free(a->alloc, a->path, a->path_size);
    geom_free(a->alloc, a->tmp, a->tmp_size);
    a->path = a->tmp = NULL;
    a->fd = -1;
}

geom_status geom_meshio__atomic_commit(mio_atomic *a, geom_diag *diag)
{
    geom_status st = GEOM_OK;
    if (close(a->fd) != 0)
        st = io_error(diag, a->path, errno, "closing the temporary file failed");
    a->fd = -1;
    if (st == GEOM_OK && rename(a->tmp, a->path) != 0)
        st = io_error(diag, a->path, errno, "cannot rename the temporary file onto it");
    if (st != GEOM_OK)
        unlink(a->tmp);
    release(a);
    return st;
}

void geom_meshio__atomic_abort(mio_atomic *a)
{
    if (!a->tmp)
        return;
    if (a->fd >= 0)
        close(a->fd);
    unlink(a->tmp);
    release(a);
}
