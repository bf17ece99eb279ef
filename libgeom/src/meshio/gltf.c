/* glTF 2.0 binary (.glb) writer: one mesh, one triangle primitive (polygons
 * triangulated one at a time, see geom__meshio_export_build), with
 * POSITION, NORMAL, TEXCOORD_0, TANGENT and COLOR_0 attributes (one vertex per
 * distinct corner) and 16- or 32-bit indices. Layout per the glTF 2.0
 * specification: 12-byte header, a JSON chunk padded with spaces and a BIN
 * chunk padded with zeros, each 4-byte aligned; every bufferView starts on
 * a 4-byte boundary; POSITION has the accessor min/max the spec requires. */
#include "meshio/meshio_internal.h"

#include <float.h>
#include <stdio.h>

#define GLB_MAGIC 0x46546C67u
#define GLB_JSON 0x4E4F534Au
#define GLB_BIN 0x004E4942u

static void json_floats(mio_sink *j, const float *v, int n)
{
    int save = j->precision;
    j->precision = 0; /* the exact value of each float */
    mio_putc(j, '[');
    for (int i = 0; i < n; i++) {
        if (i)
            mio_putc(j, ',');
        geom__meshio_put_double(j, (double)v[i]);
    }
    mio_putc(j, ']');
    j->precision = save;
}

static void json_accessor(mio_sink *j, int first, size_t view, unsigned ctype, size_t count,
                          const char *type, const float *mn, const float *mx, int ncomp)
{
    if (!first)
        mio_putc(j, ',');
    geom__meshio_puts(j, "{\"bufferView\":");
    geom__meshio_put_u64(j, view);
    geom__meshio_puts(j, ",\"componentType\":");
    geom__meshio_put_u64(j, ctype);
    geom__meshio_puts(j, ",\"count\":");
    geom__meshio_put_u64(j, count);
    geom__meshio_puts(j, ",\"type\":\"");
    geom__meshio_puts(j, type);
    mio_putc(j, '"');
    if (mn) {
        geom__meshio_puts(j, ",\"min\":");
        json_floats(j, mn, ncomp);
        geom__meshio_puts(j, ",\"max\":");
        json_floats(j, mx, ncomp);
    }
    mio_putc(j, '}');
}

static void json_view(mio_sink *j, int first, size_t off, size_t len, unsigned target)
{
    if (!first)
        mio_putc(j, ',');
    geom__meshio_puts(j, "{\"buffer\":0,\"byteOffset\":");
    geom__meshio_put_u64(j, off);
    geom__meshio_puts(j, ",\"byteLength\":");
    geom__meshio_put_u64(j, len);
    geom__meshio_puts(j, ",\"target\":");
    geom__meshio_put_u64(j, target);
    mio_putc(j, '}');
}

geom_status geom__meshio_write_glb(const geom_mesh *m, const geom_meshio_write_options *opt,
                                   mio_sink *k)
{
    const geom_allocator *al = opt->alloc;
    if (geom__meshio_check_finite(m, k) != GEOM_OK)
        return k->status;
    uint32_t chan[MIO_NATTR];
    geom__meshio_attr_channels(m, opt->omit, 1, chan);
    mio_export e;
    geom_status st = geom__meshio_export_build(&e, m, chan, al, 1); /* triangles */
    if (st != GEOM_OK) {
        return geom__meshio_sink_fail(k, st, "%s while preparing the output",
                                      geom_status_str(st));
    }
    if (e.nv > UINT32_MAX - 1 || e.nidx > UINT32_MAX) {
        geom__meshio_export_free(&e);
        return geom__meshio_sink_fail(k, GEOM_ERR_LIMIT, "too many vertices for glTF");
    }
    int ncol = chan[MIO_ATTR_COLOR] != GEOM_INVALID_INDEX &&
                       geom_mesh_channel_ncomp(m, chan[MIO_ATTR_COLOR]) >= 4
                   ? 4
                   : 3;
    int flip = !opt->gltf_keep_v;

    /* BIN chunk: one bufferView per attribute, then the indices */
    mio_sink bin, json;
    memset(&bin, 0, sizeof bin);
    memset(&json, 0, sizeof json);
    bin.alloc = json.alloc = al;
    bin.diag = json.diag = k->diag;
    json.precision = k->precision;
    const double *pos = geom_mesh_cpositions(m);
    size_t view_off[MIO_NATTR + 2], view_len[MIO_NATTR + 2];
    int has[MIO_NATTR];
    float mn[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, mx[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    view_off[0] = 0;
    for (size_t i = 0; i < e.nv && bin.status == GEOM_OK; i++) {
        const double *p0 = pos + 3 * (size_t)e.vert[i];
        double zup[3] = {p0[0], p0[2], -p0[1]};
        const double *p = opt->gltf_z_up ? zup : p0;
        for (int j = 0; j < 3; j++) {
            if (!isfinite(p[j]) || fabs(p[j]) > FLT_MAX) {
                geom__meshio_sink_fail(&bin, GEOM_ERR_INVALID_ARG,
                                       "vertex %lu: coordinate %g cannot be stored as a float",
                                       (unsigned long)e.vert[i], p[j]);
                break;
            }
            float f = (float)p[j];
            mn[j] = f < mn[j] ? f : mn[j];
            mx[j] = f > mx[j] ? f : mx[j];
            geom__meshio_put_f32(&bin, f, 0);
        }
    }
    view_len[0] = bin.total;
    for (int a = 0; a < MIO_NATTR; a++) {
        has[a] = chan[a] != GEOM_INVALID_INDEX && e.nv > 0;
        view_off[a + 1] = bin.total;
        if (!has[a])
            continue;
        for (size_t i = 0; i < e.nv && bin.status == GEOM_OK; i++) {
            double v[4] = {0, 0, 0, 1};
            geom__meshio_export_value(&e, m, a, i, v, 4);
            int n = a == MIO_ATTR_UV ? 2 : a == MIO_ATTR_NORMAL ? 3 : a == MIO_ATTR_TANGENT ? 4 : ncol;
            if (a == MIO_ATTR_TANGENT && geom_mesh_channel_ncomp(m, chan[a]) < 4)
                v[3] = 1.0;
            if (flip && a == MIO_ATTR_UV)
                v[1] = 1.0 - v[1];
            if (opt->gltf_z_up && (a == MIO_ATTR_NORMAL || a == MIO_ATTR_TANGENT)) {
                double y = v[1];
                v[1] = v[2];
                v[2] = -y;
            }
            if (flip && a == MIO_ATTR_TANGENT)
                v[3] = -v[3];
            for (int j = 0; j < n; j++) {
                double x = isfinite(v[j]) && fabs(v[j]) <= FLT_MAX ? v[j] : 0.0;
                geom__meshio_put_f32(&bin, (float)x, 0);
            }
        }
        view_len[a + 1] = bin.total - view_off[a + 1];
    }
    size_t ntri_idx = e.nidx; /* every face is a triangle now */
    int short_idx = e.nv <= 65535;
    view_off[MIO_NATTR + 1] = bin.total;
    for (size_t i = 0; i < ntri_idx && bin.status == GEOM_OK; i++) {
        if (short_idx)
            geom__meshio_put_u16(&bin, (uint16_t)e.fidx[i], 0);
        else
            geom__meshio_put_u32(&bin, e.fidx[i], 0);
    }
    view_len[MIO_NATTR + 1] = bin.total - view_off[MIO_NATTR + 1];
    while (bin.total % 4 && bin.status == GEOM_OK)
        mio_putc(&bin, 0);

    /* JSON chunk */
    geom__meshio_puts(&json, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"libgeom ");
    geom__meshio_puts(&json, geom_version_string());
    geom__meshio_puts(&json, "\"},\"scene\":0,");
    if (e.nv == 0) {
        geom__meshio_puts(&json, "\"scenes\":[{}]}");
    } else {
        static const char *const names[MIO_NATTR] = {"NORMAL", "TEXCOORD_0", "COLOR_0",
                                                     "TANGENT"};
        geom__meshio_puts(&json, "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
                                 "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0");
        size_t acc = 1;
        for (int a = 0; a < MIO_NATTR; a++) {
            if (!has[a])
                continue;
            geom__meshio_puts(&json, ",\"");
            geom__meshio_puts(&json, names[a]);
            geom__meshio_puts(&json, "\":");
            geom__meshio_put_u64(&json, acc++);
        }
        mio_putc(&json, '}');
        if (ntri_idx) {
            geom__meshio_puts(&json, ",\"indices\":");
            geom__meshio_put_u64(&json, acc);
            geom__meshio_puts(&json, ",\"mode\":4");
        } else {
            geom__meshio_puts(&json, ",\"mode\":0");
        }
        geom__meshio_puts(&json, "}]}],\"accessors\":[");
        size_t view = 0;
        json_accessor(&json, 1, view++, 5126, e.nv, "VEC3", mn, mx, 3);
        static const char *const types[MIO_NATTR] = {"VEC3", "VEC2", NULL, "VEC4"};
        for (int a = 0; a < MIO_NATTR; a++) {
            if (!has[a])
                continue;
            const char *ty = types[a] ? types[a] : ncol == 4 ? "VEC4" : "VEC3";
            json_accessor(&json, 0, view++, 5126, e.nv, ty, NULL, NULL, 0);
        }
        if (ntri_idx)
            json_accessor(&json, 0, view, short_idx ? 5123 : 5125, ntri_idx, "SCALAR", NULL,
                          NULL, 0);
        geom__meshio_puts(&json, "],\"bufferViews\":[");
        json_view(&json, 1, view_off[0], view_len[0], 34962);
        for (int a = 0; a < MIO_NATTR; a++)
            if (has[a])
                json_view(&json, 0, view_off[a + 1], view_len[a + 1], 34962);
        if (ntri_idx)
            json_view(&json, 0, view_off[MIO_NATTR + 1], view_len[MIO_NATTR + 1], 34963);
        geom__meshio_puts(&json, "],\"buffers\":[{\"byteLength\":");
        geom__meshio_put_u64(&json, bin.total);
        geom__meshio_puts(&json, "}]}");
    }
    while (json.total % 4 && json.status == GEOM_OK)
        mio_putc(&json, ' ');

    st = bin.status != GEOM_OK ? bin.status : json.status;
    if (st == GEOM_OK) {
        uint64_t total = 12 + 8 + json.total + (bin.total ? 8 + bin.total : 0);
        if (total > UINT32_MAX) {
            st = geom__meshio_sink_fail(k, GEOM_ERR_LIMIT, "GLB larger than 4 GiB");
        } else {
            geom__meshio_put_u32(k, GLB_MAGIC, 0);
            geom__meshio_put_u32(k, 2, 0);
            geom__meshio_put_u32(k, (uint32_t)total, 0);
            geom__meshio_put_u32(k, (uint32_t)json.total, 0);
            geom__meshio_put_u32(k, GLB_JSON, 0);
            geom__meshio_put(k, json.buf, json.n);
            if (bin.total) {
                geom__meshio_put_u32(k, (uint32_t)bin.total, 0);
                geom__meshio_put_u32(k, GLB_BIN, 0);
                geom__meshio_put(k, bin.buf, bin.n);
            }
            st = k->status;
        }
    } else if (k->status == GEOM_OK) {
        k->status = st;
    }
    geom__free(al, bin.buf, bin.cap);
    geom__free(al, json.buf, json.cap);
    geom__meshio_export_free(&e);
    return st;
}
