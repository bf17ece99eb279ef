/* meshio atomic file output (POSIX). A regular destination (or the regular
 * file a symbolic link points to) is replaced through a temporary file in
 * its directory, renamed over it when complete, keeping its mode (and owner
 * where permitted); anything else that can be opened for writing (a device
 * such as /dev/null, a FIFO) is written through, never replaced. The
 * temporary file is ".NAME.XXXXXXXX.geomtmp" (NAME cut so that the whole
 * fits NAME_MAX), so a stale one left by a killed process is recognisable. */
#define _XOPEN_SOURCE 700 /* realpath, with POSIX.1-2008 */

#include "meshio/meshio_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#ifndef NAME_MAX
#define NAME_MAX 255
#endif

static geom_status io_error(geom_diag *d, const char *path, int err, const char *what)
{
    char reason[128];
    geom__sys_reason(err, reason, sizeof reason);
    return geom_diag_set(d, GEOM_ERR_IO, path, 0, 0, "%s: %s", what, reason);
}

static char *dup_string(const geom_allocator *al, const char *s, size_t *size)
{
    *size = strlen(s) + 1;
    char *p = geom_alloc(al, *size);
    if (p)
        memcpy(p, s, *size);
    return p;
}

static void release(mio_atomic *a)
{
    geom_free(a->alloc, a->path, a->path_size);
    geom_free(a->alloc, a->dest, a->dest_size);
    geom_free(a->alloc, a->tmp, a->tmp_size);
    a->path = a->dest = a->tmp = NULL;
    a->fd = -1;
}

/* Length of the longest prefix of base (at most max bytes) that does not
 * end inside a UTF-8 sequence. */
static size_t cut_name(const char *base, size_t len, size_t max)
{
    if (len <= max)
        return len;
    size_t n = max;
    while (n > 0 && ((unsigned char)base[n] & 0xC0) == 0x80)
        n--;
    return n;
}

/* Create the temporary file next to a->dest. */
static geom_status open_temporary(mio_atomic *a, const struct stat *old, geom_diag *diag)
{
    static const char suffix[] = ".geomtmp";
    const char *dest = a->dest;
    const char *slash = strrchr(dest, '/');
    size_t dirlen = slash ? (size_t)(slash - dest) + 1 : 0;
    const char *base = dest + dirlen;
    size_t blen = strlen(base);
    /* "." NAME "." 8 random suffix */
    size_t room = NAME_MAX - (1 + 1 + 8 + (sizeof suffix - 1));
    size_t keep = cut_name(base, blen, room);
    a->tmp_size = dirlen + 1 + keep + 1 + 8 + sizeof suffix;
    a->tmp = geom_alloc(a->alloc, a->tmp_size);
    if (!a->tmp)
        return geom_diag_set(diag, GEOM_ERR_NOMEM, a->path, 0, 0, "out of memory");

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
        snprintf(a->tmp, a->tmp_size, "%.*s.%.*s.%s%s", (int)dirlen, dest, (int)keep, base, rnd,
                 suffix);
        int fd = open(a->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            a->fd = fd;
            if (old) { /* keep the replaced file's owner (where allowed) and mode */
                if (old->st_uid != geteuid() || old->st_gid != getegid()) {
                    if (fchown(fd, old->st_uid, old->st_gid) != 0) {
                        /* not permitted: the new file is ours */
                    }
                }
                if (fchmod(fd, old->st_mode & 07777) != 0) {
                    err = errno;
                    close(fd);
                    unlink(a->tmp);
                    a->fd = -1;
                    return io_error(diag, a->path, err, "cannot set the mode of the temporary file");
                }
            }
            return GEOM_OK;
        }
        err = errno;
        if (err != EEXIST)
            break;
    }
    return io_error(diag, a->path, err, "cannot create a temporary file next to it");
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
    a->path = dup_string(al, path, &a->path_size);
    if (!a->path)
        return geom_diag_set(diag, GEOM_ERR_NOMEM, path, 0, 0, "out of memory");

    struct stat lst, st;
    geom_status s = GEOM_OK;
    if (lstat(path, &lst) != 0) {
        if (errno != ENOENT) {
            s = io_error(diag, path, errno, "cannot open for writing");
            goto fail;
        }
        a->dest = dup_string(al, path, &a->dest_size); /* a new file */
        if (!a->dest)
            goto nomem;
        s = open_temporary(a, NULL, diag);
        if (s != GEOM_OK)
            goto fail;
        return GEOM_OK;
    }
    if (stat(path, &st) != 0) { /* a symbolic link that leads nowhere */
        s = errno == ENOENT ? geom_diag_set(diag, GEOM_ERR_IO, path, 0, 0,
                                            "not writing through a dangling symbolic link")
                            : io_error(diag, path, errno, "cannot open for writing");
        goto fail;
    }
    if (S_ISDIR(st.st_mode)) {
        s = geom_diag_set(diag, GEOM_ERR_IO, path, 0, 0, "is a directory");
        goto fail;
    }
    if (!S_ISREG(st.st_mode)) {
        /* A device, FIFO or socket: write through, never replace it. */
        int fd = open(path, O_WRONLY | O_NOCTTY | O_CLOEXEC);
        if (fd < 0) {
            s = io_error(diag, path, errno, "cannot open for writing");
            goto fail;
        }
        a->fd = fd;
        return GEOM_OK;
    }
    /* A regular file, maybe through symbolic links: refuse it as cp would
     * if we may not write it, then replace the file itself (the links stay). */
    if (faccessat(AT_FDCWD, path, W_OK, AT_EACCESS) != 0) {
        s = io_error(diag, path, errno, "cannot open for writing");
        goto fail;
    }
    if (S_ISLNK(lst.st_mode)) {
        char *real = realpath(path, NULL);
        if (!real) {
            s = io_error(diag, path, errno, "cannot resolve the symbolic link");
            goto fail;
        }
        a->dest = dup_string(al, real, &a->dest_size);
        free(real);
    } else {
        a->dest = dup_string(al, path, &a->dest_size);
    }
    if (!a->dest)
        goto nomem;
    s = open_temporary(a, &st, diag);
    if (s != GEOM_OK)
        goto fail;
    return GEOM_OK;
nomem:
    s = geom_diag_set(diag, GEOM_ERR_NOMEM, path, 0, 0, "out of memory");
fail:
    release(a);
    return s;
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

geom_status geom_meshio__atomic_commit(mio_atomic *a, geom_diag *diag)
{
    geom_status st = GEOM_OK;
    if (a->tmp && fsync(a->fd) != 0 && errno != EINVAL && errno != EROFS)
        st = io_error(diag, a->path, errno, "write failed");
    if (close(a->fd) != 0 && st == GEOM_OK && errno != EINTR)
        st = io_error(diag, a->path, errno, "write failed");
    a->fd = -1;
    if (a->tmp) {
        if (st == GEOM_OK && rename(a->tmp, a->dest) != 0)
            st = io_error(diag, a->path, errno, "cannot rename the temporary file onto it");
        if (st != GEOM_OK)
            unlink(a->tmp);
    }
    release(a);
    return st;
}

void geom_meshio__atomic_abort(mio_atomic *a)
{
    if (!a->path)
        return;
    if (a->fd >= 0)
        close(a->fd);
    if (a->tmp)
        unlink(a->tmp);
    release(a);
}
