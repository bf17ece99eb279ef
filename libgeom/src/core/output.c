/* Output files written as cp would write them (POSIX), for the mesh writers
 * and the tools alike (geom_output_*, core.h). A regular destination (or the regular
 * file a symbolic link points to) is replaced through a temporary file in
 * its directory, renamed over it when complete, keeping its mode (and owner
 * where permitted); anything else that can be opened for writing (a device
 * such as /dev/null, a FIFO) is written through, never replaced. The
 * temporary file is ".NAME.XXXXXXXX.geomtmp" (NAME cut so that the whole
 * fits NAME_MAX), so a stale one left by a killed process is recognisable. */
#define _XOPEN_SOURCE 700 /* realpath, with POSIX.1-2008 */

#include "core/internal.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
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
    return geom__diag_set(d, GEOM_ERR_IO, path, 0, 0, "%s: %s", what, reason);
}

static char *dup_string(const geom_allocator *al, const char *s, size_t *size)
{
    *size = strlen(s) + 1;
    char *p = geom__alloc(al, *size);
    if (p)
        memcpy(p, s, *size);
    return p;
}

static void release(geom_output *a)
{
    geom__free(a->impl_alloc, a->impl_path, a->impl_path_size);
    geom__free(a->impl_alloc, a->impl_dest, a->impl_dest_size);
    geom__free(a->impl_alloc, a->temporary, a->impl_tmp_size);
    a->impl_path = a->impl_dest = a->temporary = NULL;
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

/* Create the temporary file next to a->impl_dest. */
static geom_status open_temporary(geom_output *a, const struct stat *old, geom_diag *diag)
{
    static const char suffix[] = ".geomtmp";
    const char *dest = a->impl_dest;
    const char *slash = strrchr(dest, '/');
    size_t dirlen = slash ? (size_t)(slash - dest) + 1 : 0;
    const char *base = dest + dirlen;
    size_t blen = strlen(base);
    /* "." NAME "." 8 random suffix */
    size_t room = NAME_MAX - (1 + 1 + 8 + (sizeof suffix - 1));
    size_t keep = cut_name(base, blen, room);
    a->impl_tmp_size = dirlen + 1 + keep + 1 + 8 + sizeof suffix;
    a->temporary = geom__alloc(a->impl_alloc, a->impl_tmp_size);
    if (!a->temporary)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, a->impl_path, 0, 0, "out of memory");

    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    uint64_t seed = geom__hash_mix((uint64_t)ts.tv_nsec, (uint64_t)ts.tv_sec);
    seed = geom__hash_mix(seed, (uint64_t)getpid());
    seed = geom__hash_mix(seed, (uint64_t)(uintptr_t)&ts);
    static const char alphabet[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    int err = 0;
    for (int attempt = 0; attempt < 100; attempt++) {
        uint64_t r = geom__hash_mix(seed, (uint64_t)attempt);
        char rnd[9];
        for (int i = 0; i < 8; i++) {
            rnd[i] = alphabet[r % 36];
            r /= 36;
        }
        rnd[8] = '\0';
        snprintf(a->temporary, a->impl_tmp_size, "%.*s.%.*s.%s%s", (int)dirlen, dest, (int)keep, base, rnd,
                 suffix);
        int fd = open(a->temporary, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
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
                    unlink(a->temporary);
                    a->fd = -1;
                    return io_error(diag, a->impl_path, err, "cannot set the mode of the temporary file");
                }
            }
            return GEOM_OK;
        }
        err = errno;
        if (err != EEXIST)
            break;
    }
    return io_error(diag, a->impl_path, err, "cannot create output file");
}

geom_status geom_output_open(const char *path, const geom_allocator *al, geom_output *a,
                            geom_diag *diag)
{
    if (!a)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "NULL output");
    memset(a, 0, sizeof *a);
    a->fd = -1;
    a->impl_alloc = al;
    if (!path)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "NULL path");
    size_t plen = strlen(path);
    if (plen == 0)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "empty output path");
    if (path[plen - 1] == '/')
        return geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "output path names a directory");
    a->impl_path = dup_string(al, path, &a->impl_path_size);
    if (!a->impl_path)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, path, 0, 0, "out of memory");

    struct stat lst, st;
    geom_status s = GEOM_OK;
    if (lstat(path, &lst) != 0) {
        if (errno != ENOENT) {
            s = io_error(diag, path, errno, "cannot open for writing");
            goto fail;
        }
        a->impl_dest = dup_string(al, path, &a->impl_dest_size); /* a new file */
        if (!a->impl_dest)
            goto nomem;
        s = open_temporary(a, NULL, diag);
        if (s != GEOM_OK)
            goto fail;
        return GEOM_OK;
    }
    if (stat(path, &st) != 0) { /* a symbolic link that leads nowhere */
        s = errno == ENOENT ? geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0,
                                            "not writing through a dangling symbolic link")
                            : io_error(diag, path, errno, "cannot open for writing");
        goto fail;
    }
    if (S_ISDIR(st.st_mode)) {
        s = geom__diag_set(diag, GEOM_ERR_IO, path, 0, 0, "is a directory");
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
        a->impl_dest = dup_string(al, real, &a->impl_dest_size);
        free(real);
    } else {
        a->impl_dest = dup_string(al, path, &a->impl_dest_size);
    }
    if (!a->impl_dest)
        goto nomem;
    s = open_temporary(a, &st, diag);
    if (s != GEOM_OK)
        goto fail;
    return GEOM_OK;
nomem:
    s = geom__diag_set(diag, GEOM_ERR_NOMEM, path, 0, 0, "out of memory");
fail:
    release(a);
    return s;
}

geom_status geom_output_write(geom_output *a, const void *data, size_t n, geom_diag *diag)
{
    if (!a || a->fd < 0 || (n && !data))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "output is not open");
    const char *p = data;
    while (n > 0) {
        ssize_t w = write(a->fd, p, n);
        if (w < 0) {
            if (errno == EINTR)
                continue;
            return io_error(diag, a->impl_path, errno, "write failed");
        }
        if (w == 0)
            return geom__diag_set(diag, GEOM_ERR_IO, a->impl_path, 0, 0, "write failed: no progress");
        p += w;
        n -= (size_t)w;
    }
    return GEOM_OK;
}

geom_status geom_output_commit(geom_output *a, geom_diag *diag)
{
    if (!a || a->fd < 0)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "output is not open");
    geom_status st = GEOM_OK;
    if (a->temporary && fsync(a->fd) != 0 && errno != EINVAL && errno != EROFS)
        st = io_error(diag, a->impl_path, errno, "write failed");
    if (close(a->fd) != 0 && st == GEOM_OK && errno != EINTR)
        st = io_error(diag, a->impl_path, errno, "write failed");
    a->fd = -1;
    if (a->temporary) {
        if (st == GEOM_OK && rename(a->temporary, a->impl_dest) != 0)
            st = io_error(diag, a->impl_path, errno, "cannot rename the temporary file onto it");
        if (st != GEOM_OK)
            unlink(a->temporary);
    }
    release(a);
    return st;
}

void geom_output_abort(geom_output *a)
{
    if (!a || !a->impl_path)
        return;
    if (a->fd >= 0)
        close(a->fd);
    if (a->temporary)
        unlink(a->temporary);
    release(a);
}
