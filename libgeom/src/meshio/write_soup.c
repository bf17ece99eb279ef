/*
 * Writing an indexed polygon soup (positions, optional per-vertex normals,
 * faces) as OBJ without building a geom_mesh: for results whose
 * connectivity their producer already guarantees (marching cubes), where a
 * half-edge mesh would only be built to be written. The bytes are those
 * geom__meshio_write_obj writes for the mesh geom_mesh_build makes of the
 * same soup (vertices in order, faces in order from their first vertex, a
 * VERTEX "normal" channel as vn with v//vn corners); test_iso_write
 * compares the two byte for byte on isosurfaces.
 */
#include "meshio/meshio_internal.h"

#include <stdio.h>

/* first: the file's (0-based) number of the soup's first vertex; face
 * indices are file numbers. */
static geom_status check_soup(const geom_meshio_soup *s, size_t first,
                              const geom_meshio_write_options *o, geom_diag *diag,
                              const char *path)
{
    if (!s)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0, "NULL soup");
    if ((s->n_vertices && !s->xyz) || (s->n_faces && !s->indices))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0, "NULL soup arrays");
    if (s->n_vertices >= (size_t)UINT32_MAX || first >= (size_t)UINT32_MAX - s->n_vertices)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, path, 0, 0, "too many vertices");
    if (o->format != GEOM_MESHIO_FORMAT_OBJ)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0,
                             "a soup is written as OBJ only (build a mesh for other formats)");
    /* every face before the first byte: a bad face found while writing
     * would leave a partial file on the caller's stream */
    const uint32_t *ix = s->indices;
    size_t nv = first + s->n_vertices, c = 0;
    for (size_t f = 0; f < s->n_faces; f++) {
        size_t n = s->face_sizes ? s->face_sizes[f] : 3;
        if (n < 3)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0,
                                 "face %zu has %zu vertices", f, n);
        for (size_t q = 0; q < n; q++)
            if ((size_t)ix[c + q] >= nv)
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, path, 0, 0,
                                     "face %zu: vertex index %u out of range (%zu vertices)", f,
                                     (unsigned)ix[c + q], nv);
        c += n;
    }
    return GEOM_OK;
}

typedef struct soup_part {
    const geom_meshio_soup *s;
    size_t first; /* file number of s's first vertex (0-based) */
    int header;
} soup_part;

static void write_soup_obj(const soup_part *sp, const geom_meshio_write_options *o, mio_sink *k)
{
    const geom_meshio_soup *s = sp->s;
    if (sp->header) {
        geom__meshio_puts(k, "# written by libgeom ");
        geom__meshio_puts(k, geom_version_string());
        mio_putc(k, '\n');
    }
    size_t nv = s->n_vertices;
    const double *nrm = (o->omit & GEOM_MESHIO_ATTR_NORMAL) ? NULL : s->normals;
    for (int pass = 0; pass < 2; pass++) {
        const double *d = pass ? nrm : s->xyz;
        if (!d)
            continue;
        for (size_t v = 0; v < nv && k->status == GEOM_OK; v++) {
            geom__meshio_puts(k, pass ? "vn" : "v");
            for (int i = 0; i < 3; i++) {
                mio_putc(k, ' ');
                geom__meshio_put_double(k, d[3 * v + (size_t)i]);
            }
            mio_putc(k, '\n');
        }
    }
    const uint32_t *ix = s->indices;
    size_t c = 0;
    for (size_t f = 0; f < s->n_faces && k->status == GEOM_OK; f++) {
        size_t n = s->face_sizes ? s->face_sizes[f] : 3; /* checked by check_soup */
        mio_putc(k, 'f');
        for (size_t q = 0; q < n; q++) {
            uint64_t v = (uint64_t)ix[c + q] + 1;
            mio_putc(k, ' ');
            geom__meshio_put_u64(k, v);
            if (nrm) {
                geom__meshio_puts(k, "//");
                geom__meshio_put_u64(k, v);
            }
        }
        mio_putc(k, '\n');
        c += n;
    }
}

static geom_status soup_body(const void *ctx, const geom_meshio_write_options *o, mio_sink *k)
{
    write_soup_obj(ctx, o, k);
    return GEOM_OK;
}

static void soup_options(const geom_meshio_write_options *opt, geom_meshio_write_options *o)
{
    if (opt)
        *o = *opt;
    else
        memset(o, 0, sizeof *o);
}

geom_status geom_meshio_write_soup_part(const geom_meshio_soup *s, size_t first_vertex,
                                        int header, const geom_meshio_write_options *opt,
                                        geom_meshio_write_fn fn, void *user, geom_diag *diag)
{
    geom_diag_clear(diag);
    if (!fn)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "NULL write function");
    geom_meshio_write_options o;
    soup_options(opt, &o);
    geom_status st = check_soup(s, first_vertex, &o, diag, NULL);
    if (st != GEOM_OK)
        return st;
    soup_part sp = {s, first_vertex, header};
    return geom__meshio_write_body_stream(soup_body, &sp, &o, fn, user, diag);
}

geom_status geom_meshio_write_soup_stream(const geom_meshio_soup *s,
                                          const geom_meshio_write_options *opt,
                                          geom_meshio_write_fn fn, void *user, geom_diag *diag)
{
    return geom_meshio_write_soup_part(s, 0, 1, opt, fn, user, diag);
}

geom_status geom_meshio_write_soup(const geom_meshio_soup *s, const char *path,
                                   const geom_meshio_write_options *opt, geom_diag *diag)
{
    geom_diag_clear(diag);
    if (!path)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "NULL path");
    geom_meshio_write_options o;
    soup_options(opt, &o);
    if (!o.format)
        o.format = geom_meshio_format_from_name(path);
    geom_status st = check_soup(s, 0, &o, diag, path);
    if (st != GEOM_OK)
        return st;
    soup_part sp = {s, 0, 1};
    return geom__meshio_write_body_path(soup_body, &sp, &o, path, diag);
}
