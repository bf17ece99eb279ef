/* Reading whole files: mapped when they are regular files, read otherwise
 * (pipes, terminals, standard input). POSIX. */
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* madvise */

#include "core/internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

void geom__sys_reason(int err, char *buf, size_t size)
{
    buf[0] = '\0';
#if defined(__GLIBC__) && defined(_GNU_SOURCE)
    const char *s = strerror_r(err, buf, size);
    if (s != buf)
        snprintf(buf, size, "%s", s);
#else
    if (strerror_r(err, buf, size) != 0)
        snprintf(buf, size, "error %d", err);
#endif
}

static geom_status io_fail(geom_diag *d, const char *name, int err, const char *what)
{
    char reason[128];
    geom__sys_reason(err, reason, sizeof reason);
    return geom__diag_set(d, GEOM_ERR_IO, name, 0, 0, "%s: %s", what, reason);
}

static const unsigned char empty_file[1];

/* read() until the end into a growing buffer */
static geom_status read_all(int fd, const char *name, const geom_allocator *a, geom_file *f,
                            size_t hint, geom_diag *diag)
{
    size_t cap = hint > 65536 ? hint + 1 : 65536, n = 0;
    unsigned char *buf = geom__alloc(a, cap);
    if (!buf)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, name, 0, 0, "out of memory reading the file");
    for (;;) {
        if (n == cap) {
            geom_status st = geom__grow(a, (void **)&buf, &cap, n + 1, 1);
            if (st != GEOM_OK) {
                geom__free(a, buf, cap);
                return geom__diag_set(diag, st, name, 0, 0, "out of memory reading the file");
            }
        }
        ssize_t got = read(fd, buf + n, cap - n);
        if (got < 0 && errno == EINTR)
            continue;
        if (got < 0) {
            int err = errno;
            geom__free(a, buf, cap);
            return io_fail(diag, name, err, "read error");
        }
        if (got == 0)
            break;
        n += (size_t)got;
    }
    f->data = buf;
    f->size = n;
    f->impl_base = buf;
    f->impl_size = cap;
    f->impl_mapped = 0;
    f->impl_alloc = a;
    return GEOM_OK;
}

geom_status geom_file_map_fd(int fd, const char *name, const geom_allocator *alloc,
                             geom_file *out, geom_diag *diag)
{
    if (!out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, name, 0, 0, "NULL output");
    memset(out, 0, sizeof *out);
    out->data = empty_file;
    if (fd < 0)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, name, 0, 0, "invalid file descriptor");
    struct stat st;
    if (fstat(fd, &st) != 0)
        return io_fail(diag, name, errno, "cannot read");
    if (S_ISDIR(st.st_mode))
        return geom__diag_set(diag, GEOM_ERR_IO, name, 0, 0, "cannot read: is a directory");
    if (S_ISREG(st.st_mode)) {
        off_t pos = lseek(fd, 0, SEEK_CUR);
        if (pos == 0 && st.st_size == 0)
            return GEOM_OK;
        if (pos == 0 && (uintmax_t)st.st_size <= SIZE_MAX) {
            size_t size = (size_t)st.st_size;
            void *p = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
            if (p != MAP_FAILED) {
                posix_madvise(p, size, POSIX_MADV_SEQUENTIAL);
                out->data = p;
                out->size = size;
                out->impl_base = p;
                out->impl_size = size;
                out->impl_mapped = 1;
                return GEOM_OK;
            }
        }
        /* a file that cannot be mapped (or is read from an offset) is read */
        return read_all(fd, name, alloc, out, (size_t)st.st_size, diag);
    }
    return read_all(fd, name, alloc, out, 0, diag);
}

geom_status geom_file_map(const char *path, const geom_allocator *alloc, geom_file *out,
                          geom_diag *diag)
{
    if (out) {
        memset(out, 0, sizeof *out);
        out->data = empty_file;
    }
    if (!path || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0, "NULL path or output");
    int fd;
    do
        fd = open(path, O_RDONLY | O_CLOEXEC);
    while (fd < 0 && errno == EINTR);
    if (fd < 0)
        return io_fail(diag, path, errno, "cannot open");
    geom_status s = geom_file_map_fd(fd, path, alloc, out, diag);
    close(fd); /* a mapping outlives its descriptor */
    return s;
}

void geom__file_drop_pages(geom_file *f)
{
    /* a private read-only file mapping: dropped pages read back from the file */
    if (f && f->impl_mapped && f->impl_size) {
#ifdef MADV_DONTNEED
        /* not posix_madvise: glibc ignores POSIX_MADV_DONTNEED */
        madvise(f->impl_base, f->impl_size, MADV_DONTNEED);
#endif
    }
}

void geom_file_unmap(geom_file *f)
{
    if (!f)
        return;
    if (f->impl_mapped)
        munmap(f->impl_base, f->impl_size);
    else if (f->impl_base)
        geom__free(f->impl_alloc, f->impl_base, f->impl_size);
    memset(f, 0, sizeof *f);
    f->data = empty_file;
}
