/*
 * Output size of an isosurface before extracting it: the field sampled on a
 * coarse grid (a sampled grid: every cell), its crossing cells counted and
 * scaled to the requested resolution; with caps, the cap triangles of the
 * box's boundary cells counted by extract.c's rule (do_cap) and scaled.
 */
#include "iso/iso_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

/* Marching cubes makes about two triangles per cell the surface crosses. */
#define TRIS_PER_CELL 2.0

/* A node value as the extraction sees it (extract.c's shifted(), after the
 * negation of inside-above): <= 0 inside, NaN outside, infinities finite. */
static double node_g(double v, double iso, int above)
{
    double d = above ? iso - v : v - iso;
    if (!(d >= -DBL_MAX && d <= DBL_MAX))
        d = d < 0 ? -DBL_MAX : DBL_MAX;
    return d;
}

static int cell_crossed(const double g[8])
{
    int below = 0, above = 0;
    for (int q = 0; q < 8; q++) {
        below |= !(g[q] > 0);
        above |= g[q] > 0;
    }
    return below && above;
}

/* The triangles extract.c's do_cap makes on face f of a boundary cell with
 * node values g (*nin: the face's inside corners): the inside part of the
 * face as one polygon (inside corners plus crossing points, fanned) or, for
 * separated diagonal corners (the face decider), one triangle each. */
static int cap_tris(int f, const double g[8], int *nin)
{
    int in[4], changes, n = geom__iso_face_inside(f, g, in, &changes);
    *nin = n;
    if (n == 0)
        return 0;
    if (changes == 4) {
        int jn[2];
        if (!geom__iso_face_join(f, g, jn))
            return 2;
    }
    return n + changes - 2;
}

/* Bit f set for each box face that cell (i, j, k) of an n[0] x n[1] x n[2]
 * cell grid lies on. */
static unsigned boundary_faces(size_t i, size_t j, size_t k, const size_t n[3])
{
    return (unsigned)(i == 0) | (unsigned)(i + 1 == n[0]) << 1 | (unsigned)(j == 0) << 2 |
           (unsigned)(j + 1 == n[1]) << 3 | (unsigned)(k == 0) << 4 | (unsigned)(k + 1 == n[2]) << 5;
}

static geom_status check_options(const geom_iso_options *opt)
{
    if (opt && (!isfinite(opt->iso) ||
                (opt->inside != GEOM_ISO_INSIDE_BELOW && opt->inside != GEOM_ISO_INSIDE_ABOVE)))
        return GEOM_ERR_INVALID_ARG;
    return GEOM_OK;
}

geom_status geom_iso_estimate_triangles(const geom_iso_field *f, const double bounds[6],
                                        const size_t res[3], const geom_iso_options *opt,
                                        double *triangles)
{
    if (!triangles)
        return GEOM_ERR_INVALID_ARG;
    *triangles = 0.0;
    if (!f || !f->value || !bounds || !res || check_options(opt) != GEOM_OK)
        return GEOM_ERR_INVALID_ARG;
    const double iso = opt ? opt->iso : 0.0;
    const int above = opt && opt->inside == GEOM_ISO_INSIDE_ABOVE, caps = opt && opt->caps;
    size_t c[3];
    double fine[3], scale = 1.0;
    for (int a = 0; a < 3; a++) {
        if (res[a] == 0 || !(bounds[a] < bounds[a + 3]))
            return GEOM_ERR_INVALID_ARG;
        c[a] = res[a] < 40 ? res[a] : 40;
        fine[a] = (double)res[a] / (double)c[a];
        scale *= fine[a];
    }
    /* a surface piece crossing one coarse cell crosses about
     * (fine cells per coarse cell)^(2/3) fine cells */
    scale = pow(scale, 2.0 / 3.0);
    /* fine face cells per coarse face cell, for faces normal to x, y, z */
    const double area[3] = {fine[1] * fine[2], fine[0] * fine[2], fine[0] * fine[1]};
    size_t nx = c[0] + 1, ny = c[1] + 1, nz = c[2] + 1;
    double *val = malloc(nx * ny * 2 * sizeof *val);
    if (!val)
        return GEOM_ERR_NOMEM;
    size_t crossing = 0;
    double cap = 0.0;
    for (size_t k = 0; k < nz; k++) {
        double *cur = val + (k & 1) * nx * ny, *prev = val + ((k + 1) & 1) * nx * ny;
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                double p[3] = {bounds[0] + (bounds[3] - bounds[0]) * (double)i / (double)c[0],
                               bounds[1] + (bounds[4] - bounds[1]) * (double)j / (double)c[1],
                               bounds[2] + (bounds[5] - bounds[2]) * (double)k / (double)c[2]};
                cur[i + nx * j] = node_g(f->value(f->user, p), iso, above);
            }
        if (k == 0)
            continue;
        for (size_t j = 0; j + 1 < ny; j++)
            for (size_t i = 0; i + 1 < nx; i++) {
                double g[8];
                for (int q = 0; q < 8; q++) {
                    const double *layer = (q & 4) ? cur : prev;
                    g[q] = layer[i + (q & 1) + nx * (j + ((q >> 1) & 1))];
                }
                crossing += cell_crossed(g);
                unsigned faces = caps ? boundary_faces(i, j, k - 1, c) : 0;
                for (int fc = 0; faces; fc++, faces >>= 1) {
                    if (!(faces & 1))
                        continue;
                    /* One coarse face cell stands for A = area fine ones:
                     * inside where its corners are (A nin / 4 cells, two
                     * triangles each) plus the cut cells along the
                     * boundary curve (about sqrt(A) of them for each cut
                     * coarse cell, with the extra triangles the cut makes
                     * at A = 1): exact when A = 1. */
                    int nin, t = cap_tris(fc, g, &nin);
                    double A = area[fc >> 1];
                    if (nin == 4)
                        cap += 2.0 * A;
                    else if (nin > 0)
                        cap += A * nin / 2.0 + sqrt(A) * (t - nin / 2.0);
                }
            }
    }
    free(val);
    *triangles = TRIS_PER_CELL * (double)crossing * scale + cap;
    return GEOM_OK;
}

geom_status geom_iso_grid_estimate_triangles(const geom_iso_grid *g, const geom_iso_options *opt,
                                             double *triangles)
{
    if (!triangles)
        return GEOM_ERR_INVALID_ARG;
    *triangles = 0.0;
    geom_status st = geom_iso_grid_check(g);
    if (st != GEOM_OK)
        return st;
    if (check_options(opt) != GEOM_OK)
        return GEOM_ERR_INVALID_ARG;
    const double iso = opt ? opt->iso : 0.0;
    const int above = opt && opt->inside == GEOM_ISO_INSIDE_ABOVE, caps = opt && opt->caps;
    size_t nx = g->dims[0], ny = g->dims[1], nz = g->dims[2];
    const size_t cells[3] = {nx - 1, ny - 1, nz - 1};
    const float *f32 = g->type == GEOM_ISO_SCALAR_F32 ? g->data : NULL;
    const double *f64 = g->type == GEOM_ISO_SCALAR_F64 ? g->data : NULL;
    size_t crossing = 0, cap = 0;
    for (size_t k = 0; k + 1 < nz; k++)
        for (size_t j = 0; j + 1 < ny; j++)
            for (size_t i = 0; i + 1 < nx; i++) {
                double v[8];
                for (int q = 0; q < 8; q++) {
                    size_t idx = (i + (q & 1)) + nx * ((j + ((q >> 1) & 1)) + ny * (k + (q >> 2)));
                    v[q] = node_g(f32 ? (double)f32[idx] : f64[idx], iso, above);
                }
                crossing += cell_crossed(v);
                unsigned faces = caps ? boundary_faces(i, j, k, cells) : 0;
                for (int fc = 0; faces; fc++, faces >>= 1) {
                    int nin;
                    if (faces & 1)
                        cap += (size_t)cap_tris(fc, v, &nin);
                }
            }
    *triangles = TRIS_PER_CELL * (double)crossing + (double)cap;
    return GEOM_OK;
}
