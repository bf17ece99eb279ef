/*
 * What geom_meshio_write does to every kind of destination (issue 15,
 * "never destroy what is not ours"): devices made here with mknod (a null
 * and a full one, so a regression never replaces the machine's /dev/null)
 * are written through and stay devices, ENOSPC is GEOM_ERR_IO; a FIFO is
 * written through; a symbolic link to a regular file stays a link and its
 * target is replaced; a replaced file keeps its mode; a dangling link and a
 * directory are refused; a 255-byte name works; nothing named *.geomtmp is
 * left behind.
 */
#define _XOPEN_SOURCE 700

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "meshio_testutil.h"

#include <dirent.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

static geom_mesh *tetra(void)
{
    char path[1024];
    geom_mesh *m = NULL;
    assert_int_equal(geom_meshio_read(mt_path(path, sizeof path, 0, "tetra.off"), NULL, &m, NULL, NULL),
                     GEOM_OK);
    return m;
}

static int temporaries_left(const char *dir)
{
    int n = 0;
    DIR *dp = opendir(dir);
    assert_non_null(dp);
    struct dirent *de;
    while ((de = readdir(dp))) {
        size_t l = strlen(de->d_name);
        if (l > 8 && strcmp(de->d_name + l - 8, ".geomtmp") == 0)
            n++;
    }
    closedir(dp);
    return n;
}

static void test_destinations(void **state)
{
    (void)state;
    char dir[] = "/tmp/geom-atomic-test.XXXXXX";
    assert_non_null(mkdtemp(dir));
    geom_mesh *m = tetra();
    char p[600], q[600];
    geom_diag d;
    struct stat st;

    /* mode kept */
    snprintf(p, sizeof p, "%s/mode.obj", dir);
    FILE *fp = fopen(p, "w");
    fputs("old\n", fp);
    fclose(fp);
    assert_int_equal(chmod(p, 0640), 0);
    assert_int_equal(geom_meshio_write(m, p, NULL, &d), GEOM_OK);
    assert_int_equal(stat(p, &st), 0);
    assert_int_equal(st.st_mode & 07777, 0640);

    /* a symbolic link to a regular file stays a link */
    snprintf(q, sizeof q, "%s/link.obj", dir);
    assert_int_equal(symlink("mode.obj", q), 0);
    assert_int_equal(geom_meshio_write(m, q, NULL, &d), GEOM_OK);
    assert_int_equal(lstat(q, &st), 0);
    assert_true(S_ISLNK(st.st_mode));

    /* a dangling link and a directory are refused */
    snprintf(q, sizeof q, "%s/dangling.obj", dir);
    assert_int_equal(symlink("nowhere.obj", q), 0);
    assert_int_equal(geom_meshio_write(m, q, NULL, &d), GEOM_ERR_IO);
    assert_non_null(strstr(d.message, "dangling"));
    assert_int_equal(lstat(q, &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    snprintf(q, sizeof q, "%s/dir.obj", dir);
    assert_int_equal(mkdir(q, 0755), 0);
    assert_int_equal(geom_meshio_write(m, q, NULL, &d), GEOM_ERR_IO);
    assert_non_null(strstr(d.message, "directory"));

    /* devices are written through */
    geom_meshio_write_options wo = {.format = GEOM_MESHIO_FORMAT_OBJ};
    snprintf(p, sizeof p, "%s/null", dir);
    snprintf(q, sizeof q, "%s/full", dir);
    if (mknod(p, S_IFCHR | 0666, makedev(1, 3)) == 0 &&
        mknod(q, S_IFCHR | 0666, makedev(1, 7)) == 0) {
        assert_int_equal(geom_meshio_write(m, p, &wo, &d), GEOM_OK);
        assert_int_equal(stat(p, &st), 0);
        assert_true(S_ISCHR(st.st_mode));
        assert_int_equal(geom_meshio_write(m, q, &wo, &d), GEOM_ERR_IO);
        assert_non_null(strstr(d.message, "No space"));
        assert_int_equal(stat(q, &st), 0);
        assert_true(S_ISCHR(st.st_mode));
    }

    /* a FIFO is written through (a child reads it) */
    snprintf(p, sizeof p, "%s/fifo", dir);
    assert_int_equal(mkfifo(p, 0600), 0);
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        int fd = open(p, O_RDONLY);
        char buf[256];
        size_t total = 0;
        ssize_t got;
        while ((got = read(fd, buf, sizeof buf)) > 0)
            total += (size_t)got;
        _exit(total > 0 ? 0 : 1);
    }
    assert_int_equal(geom_meshio_write(m, p, &wo, &d), GEOM_OK);
    int status = 0;
    assert_int_equal(waitpid(child, &status, 0), child);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    assert_int_equal(stat(p, &st), 0);
    assert_true(S_ISFIFO(st.st_mode));

    /* a 255-byte name */
    char name[256];
    memset(name, 'n', 251);
    memcpy(name + 251, ".obj", 5);
    snprintf(p, sizeof p, "%s/%s", dir, name);
    assert_int_equal(geom_meshio_write(m, p, NULL, &d), GEOM_OK);
    assert_int_equal(stat(p, &st), 0);
    assert_int_equal(temporaries_left(dir), 0);

    geom_mesh_destroy(m);
    char cmd[700];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_destinations),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
