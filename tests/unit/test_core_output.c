/*
 * geom_output_*: cp's destination rules through the public API. A new file
 * and a replaced file (mode kept, no temporary left), abort leaves the
 * destination as it was, a device is written through (no temporary), a
 * directory and a dangling symbolic link are refused, a symbolic link to a
 * file stays a link.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
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
    snprintf(dir, sizeof dir, "/tmp/geom_output_test_XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static void slurp(const char *path, char *buf, size_t size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = '\0';
    fclose(f);
}

static int temporaries(void)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        n += strstr(e->d_name, ".geomtmp") != NULL;
    closedir(d);
    return n;
}

static void write_all(const char *path, const char *text, geom_status want_commit)
{
    geom_output o;
    geom_diag d;
    assert_int_equal(geom_output_open(path, NULL, &o, &d), GEOM_OK);
    assert_int_equal(geom_output_write(&o, text, strlen(text), &d), GEOM_OK);
    assert_int_equal(geom_output_commit(&o, &d), want_commit);
    assert_int_equal(o.fd, -1);
}

static void test_new_and_replaced(void **state)
{
    (void)state;
    char p[300], buf[64];
    snprintf(p, sizeof p, "%s/a.txt", dir);
    write_all(p, "first", GEOM_OK);
    slurp(p, buf, sizeof buf);
    assert_string_equal(buf, "first");
    assert_int_equal(chmod(p, 0640), 0);
    write_all(p, "second", GEOM_OK);
    slurp(p, buf, sizeof buf);
    assert_string_equal(buf, "second");
    struct stat st;
    assert_int_equal(stat(p, &st), 0);
    assert_int_equal(st.st_mode & 07777, 0640);
    assert_int_equal(temporaries(), 0);

    /* abort: the destination is untouched, the temporary is gone */
    geom_output o;
    assert_int_equal(geom_output_open(p, NULL, &o, NULL), GEOM_OK);
    assert_non_null(o.temporary);
    assert_int_equal(temporaries(), 1);
    assert_int_equal(geom_output_write(&o, "third", 5, NULL), GEOM_OK);
    geom_output_abort(&o);
    geom_output_abort(&o); /* twice is a no-op */
    geom_output_abort(NULL);
    slurp(p, buf, sizeof buf);
    assert_string_equal(buf, "second");
    assert_int_equal(temporaries(), 0);

    /* a symbolic link stays a link; its target is replaced */
    char l[300];
    snprintf(l, sizeof l, "%s/link.txt", dir);
    assert_int_equal(symlink("a.txt", l), 0);
    write_all(l, "through", GEOM_OK);
    struct stat lst;
    assert_int_equal(lstat(l, &lst), 0);
    assert_true(S_ISLNK(lst.st_mode));
    slurp(p, buf, sizeof buf);
    assert_string_equal(buf, "through");
}

static void test_device_and_refusals(void **state)
{
    (void)state;
    geom_output o;
    geom_diag d;
    assert_int_equal(geom_output_open("/dev/null", NULL, &o, &d), GEOM_OK);
    assert_null(o.temporary);
    assert_int_equal(geom_output_write(&o, "x", 1, &d), GEOM_OK);
    assert_int_equal(geom_output_commit(&o, &d), GEOM_OK);

    assert_int_equal(geom_output_open(dir, NULL, &o, &d), GEOM_ERR_IO);
    assert_int_equal(d.status, GEOM_ERR_IO);
    assert_non_null(strstr(d.message, "directory"));
    assert_int_equal(o.fd, -1);

    char l[300];
    snprintf(l, sizeof l, "%s/dangling", dir);
    assert_int_equal(symlink("nowhere", l), 0);
    assert_int_equal(geom_output_open(l, NULL, &o, &d), GEOM_ERR_IO);
    assert_non_null(strstr(d.message, "dangling"));

    assert_int_equal(geom_output_open(NULL, NULL, &o, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_output_open("", NULL, &o, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_output_commit(&o, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(d.status, GEOM_ERR_INVALID_ARG);
    assert_int_equal(temporaries(), 0);

    /* /dev/full: the write (or the close) fails with the system's reason */
    if (geom_output_open("/dev/full", NULL, &o, &d) == GEOM_OK) {
        geom_status st = geom_output_write(&o, "x", 1, &d);
        if (st == GEOM_OK)
            st = geom_output_commit(&o, &d);
        else
            geom_output_abort(&o);
        assert_int_equal(st, GEOM_ERR_IO);
        assert_non_null(strstr(d.message, "No space"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_new_and_replaced),
        cmocka_unit_test(test_device_and_refusals),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
