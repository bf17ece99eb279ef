/*
 * geom_file_map / geom_file_map_fd: the bytes of a regular file (mapped),
 * an empty file, a pipe (read), a descriptor positioned past the start
 * (read from there), and the errors (missing file, directory), compared
 * with the bytes written.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "geom/core.h"

static char dir[256];

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/geom_file_test_XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char p[300];
    snprintf(p, sizeof p, "%s/big", dir);
    unlink(p);
    snprintf(p, sizeof p, "%s/empty", dir);
    unlink(p);
    rmdir(dir);
    return 0;
}

static unsigned char *pattern(size_t n)
{
    unsigned char *b = malloc(n);
    for (size_t i = 0; i < n; i++)
        b[i] = (unsigned char)(i * 2654435761u >> 13);
    return b;
}

static void test_regular_and_empty(void **state)
{
    (void)state;
    char p[300];
    const size_t n = 3 * 65536 + 123;
    unsigned char *b = pattern(n);
    snprintf(p, sizeof p, "%s/big", dir);
    FILE *fp = fopen(p, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(b, 1, n, fp), n);
    fclose(fp);

    geom_file f;
    assert_int_equal(geom_file_map(p, NULL, &f, NULL), GEOM_OK);
    assert_int_equal(f.size, n);
    assert_true(f.impl_mapped);
    assert_memory_equal(f.data, b, n);
    geom_file_unmap(&f);
    assert_int_equal(f.size, 0);
    geom_file_unmap(&f); /* twice: no-op */
    geom_file_unmap(NULL);

    /* a descriptor past the start: read from there */
    int fd = open(p, O_RDONLY);
    assert_true(fd >= 0);
    assert_int_equal(lseek(fd, 1000, SEEK_SET), 1000);
    assert_int_equal(geom_file_map_fd(fd, "x", NULL, &f, NULL), GEOM_OK);
    close(fd);
    assert_int_equal(f.size, n - 1000);
    assert_false(f.impl_mapped);
    assert_memory_equal(f.data, b + 1000, n - 1000);
    geom_file_unmap(&f);

    snprintf(p, sizeof p, "%s/empty", dir);
    fp = fopen(p, "wb");
    fclose(fp);
    assert_int_equal(geom_file_map(p, NULL, &f, NULL), GEOM_OK);
    assert_int_equal(f.size, 0);
    assert_non_null(f.data);
    geom_file_unmap(&f);
    free(b);
}

static void test_pipe(void **state)
{
    (void)state;
    const size_t n = 200000; /* more than a pipe buffer: written by a child */
    unsigned char *b = pattern(n);
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(fds[0]);
        size_t off = 0;
        while (off < n) {
            ssize_t w = write(fds[1], b + off, n - off);
            if (w <= 0)
                _exit(1);
            off += (size_t)w;
        }
        _exit(0);
    }
    close(fds[1]);
    geom_file f;
    assert_int_equal(geom_file_map_fd(fds[0], "<pipe>", NULL, &f, NULL), GEOM_OK);
    close(fds[0]);
    assert_int_equal(f.size, n);
    assert_false(f.impl_mapped);
    assert_memory_equal(f.data, b, n);
    geom_file_unmap(&f);
    free(b);
}

static void test_errors(void **state)
{
    (void)state;
    geom_file f;
    geom_diag d;
    char p[300];
    snprintf(p, sizeof p, "%s/missing", dir);
    assert_int_equal(geom_file_map(p, NULL, &f, &d), GEOM_ERR_IO);
    assert_string_equal(d.source, p);
    assert_non_null(strstr(d.message, "cannot open"));
    assert_int_equal(f.size, 0);
    geom_file_unmap(&f);
    assert_int_equal(geom_file_map(dir, NULL, &f, &d), GEOM_ERR_IO);
    assert_non_null(strstr(d.message, "directory"));
    assert_int_equal(geom_file_map(NULL, NULL, &f, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_file_map_fd(-1, "x", NULL, &f, NULL), GEOM_ERR_INVALID_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_regular_and_empty),
        cmocka_unit_test(test_pipe),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
