/*
 * Subdivision masks of Catmull-Clark (Catmull & Clark 1978), Loop (Loop
 * 1987) and bilinear subdivision with semi-sharp creases (DeRose, Kass and
 * Truong 1998), and their limit masks, with the weights, rules and
 * transitions of OpenSubdiv's Sdc::Scheme so refined values agree with it.
 */
#include "masks.h"

#include <math.h>

geom_status sd_scratch_init(const geom_allocator *a, sd_scratch *s, uint32_t max_valence)
{
    s->cap = max_valence + 1;
    s->w = sd_calloc(a, 4 * (size_t)s->cap, sizeof(double));
    s->s = sd_calloc(a, 2 * (size_t)s->cap, sizeof(float));
    if (!s->w || !s->s) {
        sd_scratch_free(a, s);
        return GEOM_ERR_NOMEM;
    }
    return GEOM_OK;
}

void sd_scratch_free(const geom_allocator *a, sd_scratch *s)
{
    sd_free(a, s->w, 4 * (size_t)s->cap, sizeof(double));
    sd_free(a, s->s, 2 * (size_t)s->cap, sizeof(float));
    s->w = NULL;
    s->s = NULL;
}

/* ------------------------------------------------------------ edge masks */

static void smooth_edge(const sd_opts *o, const sd_level *p, uint32_t e, double vw[2], sd_mask *m)
{
    int nf = (int)(p->ef_off[e + 1] - p->ef_off[e]);
    m->nf = nf;
    m->ne = 0;
    if (o->scheme == GEOM_SUBDIV_LOOP) {
        m->fcenters = 0;
        double fw = 0.125;
        vw[0] = vw[1] = 0.375;
        if (nf == 2) {
            m->f[0] = m->f[1] = fw;
        } else {
            fw *= 2.0 / (double)nf;
            for (int i = 0; i < nf; i++)
                m->f[i] = fw;
        }
        return;
    }
    m->fcenters = 1;
    int tri0 = 0, tri1 = 0, use_tri = o->smooth_tri;
    if (use_tri) {
        if (nf == 2) {
            uint32_t f0 = p->ef[p->ef_off[e]], f1 = p->ef[p->ef_off[e] + 1];
            tri0 = p->fv_off[f0 + 1] - p->fv_off[f0] == 3;
            tri1 = p->fv_off[f1 + 1] - p->fv_off[f1] == 3;
            use_tri = tri0 || tri1;
        } else {
            use_tri = 0;
        }
    }
    if (!use_tri) {
        vw[0] = vw[1] = 0.25;
        if (nf == 2) {
            m->f[0] = m->f[1] = 0.25;
        } else {
            double fw = 0.5 / (double)nf;
            for (int i = 0; i < nf; i++)
                m->f[i] = fw;
        }
    } else {
        const double tri_w = 0.470;
        double f0w = tri0 ? tri_w : 0.25, f1w = tri1 ? tri_w : 0.25;
        double fw = 0.5 * (f0w + f1w);
        double v = 0.5 * (1.0 - 2.0 * fw);
        vw[0] = vw[1] = v;
        m->f[0] = m->f[1] = fw;
    }
}

void sd_edge_mask(const sd_opts *o, const sd_level *p, uint32_t e, int cRule, double vw[2],
                  sd_mask *m)
{
    m->v = 0.0;
    m->ne = 0;
    if (o->scheme == GEOM_SUBDIV_BILINEAR || cRule == SD_RULE_CREASE) {
        if (o->scheme == GEOM_SUBDIV_BILINEAR || p->esharp[e] > 0.0f) {
            vw[0] = vw[1] = 0.5;
            m->nf = 0;
            m->fcenters = 0;
            return;
        }
    }
    if (p->esharp[e] <= 0.0f) {
        smooth_edge(o, p, e, vw, m);
        return;
    }
    /* Crease on the parent, smooth (or dart) child: blend. */
    smooth_edge(o, p, e, vw, m);
    double pw = (double)p->esharp[e];
    double cw = 1.0 - pw;
    vw[0] = pw * 0.5 + cw * vw[0];
    vw[1] = pw * 0.5 + cw * vw[1];
    for (int i = 0; i < m->nf; i++)
        m->f[i] *= cw;
}

/* ---------------------------------------------------------- vertex masks */

static void corner_mask(sd_mask *m)
{
    m->v = 1.0;
    m->ne = 0;
    m->nf = 0;
    m->fcenters = 0;
}

static void crease_mask(int valence, const int ends[2], sd_mask *m)
{
    m->v = 0.75;
    m->ne = valence;
    m->nf = 0;
    m->fcenters = 0;
    for (int i = 0; i < valence; i++)
        m->e[i] = 0.0;
    m->e[ends[0]] = 0.125;
    m->e[ends[1]] = 0.125;
}

static void smooth_mask(const sd_opts *o, int nfaces, sd_mask *m)
{
    int n = nfaces;
    double ew, vw;
    sd_smooth_weights(o->scheme == GEOM_SUBDIV_LOOP, (uint32_t)n, &ew, &vw);
    if (o->scheme == GEOM_SUBDIV_LOOP) {
        m->v = vw;
        m->ne = n;
        m->nf = 0;
        m->fcenters = 0;
        for (int i = 0; i < n; i++)
            m->e[i] = ew;
        return;
    }
    m->v = vw;
    m->ne = n;
    m->nf = n;
    m->fcenters = 1;
    for (int i = 0; i < n; i++) {
        m->e[i] = ew;
        m->f[i] = ew;
    }
}

static void combine(const sd_mask *src, double thisw, double dstw, sd_mask *dst)
{
    dst->v = dstw * dst->v + thisw * src->v;
    if (src->ne) {
        if (dst->ne == 0) {
            dst->ne = src->ne;
            for (int i = 0; i < src->ne; i++)
                dst->e[i] = thisw * src->e[i];
        } else {
            for (int i = 0; i < src->ne; i++)
                dst->e[i] = dstw * dst->e[i] + thisw * src->e[i];
        }
    }
    if (src->nf) {
        if (dst->nf == 0) {
            dst->nf = src->nf;
            dst->fcenters = src->fcenters;
            for (int i = 0; i < src->nf; i++)
                dst->f[i] = thisw * src->f[i];
        } else {
            for (int i = 0; i < src->nf; i++)
                dst->f[i] = dstw * dst->f[i] + thisw * src->f[i];
        }
    }
}

void sd_vertex_mask(const sd_opts *o, const sd_level *p, const sd_level *c, uint32_t pv,
                    uint32_t cv, sd_mask *m, sd_scratch *s)
{
    if (o->scheme == GEOM_SUBDIV_BILINEAR) {
        corner_mask(m);
        return;
    }
    int pRule = p->vtag[pv] & SD_V_RULE, cRule = c->vtag[cv] & SD_V_RULE;
    int nfaces = (int)(p->vf_off[pv + 1] - p->vf_off[pv]);
    int valence = (int)(p->ve_off[pv + 1] - p->ve_off[pv]);
    if (pRule == SD_RULE_SMOOTH || pRule == SD_RULE_DART) {
        smooth_mask(o, nfaces, m);
        return;
    }
    float *pes = s->s, *ces = s->s + s->cap;
    float pvs = 0.0f;
    int need = pRule == SD_RULE_CREASE || pRule != cRule;
    if (need) {
        pvs = p->vsharp[pv];
        for (int i = 0; i < valence; i++)
            pes[i] = p->esharp[p->ve[p->ve_off[pv] + (uint32_t)i]];
    }
    if (pRule == SD_RULE_CREASE) {
        int ends[2];
        sd_crease_pair(pes, valence, ends);
        crease_mask(valence, ends, m);
    } else {
        corner_mask(m);
    }
    if (cRule == pRule)
        return;
    sd_subdivide_edges_around(o->chaikin, valence, pes, ces);
    float cvs = c->vsharp[cv];
    sd_mask cm;
    cm.e = s->w + 2 * (size_t)s->cap;
    cm.f = s->w + 3 * (size_t)s->cap;
    if (cRule == SD_RULE_SMOOTH || cRule == SD_RULE_DART) {
        smooth_mask(o, nfaces, &cm);
    } else if (cRule == SD_RULE_CREASE) {
        int ends[2];
        sd_crease_pair(ces, valence, ends);
        crease_mask(valence, ends, &cm);
    } else {
        corner_mask(&cm);
    }
    double pw = (double)sd_fractional_weight(o->chaikin, pvs, cvs, valence, pes, ces);
    double cw = 1.0 - pw;
    combine(&cm, cw, pw, m);
}

/* ----------------------------------------------------------- limit masks */

static void cc_smooth_limit(int n, sd_mask *pos)
{
    if (n == 2) {
        corner_mask(pos);
        return;
    }
    pos->ne = n;
    pos->nf = n;
    pos->fcenters = 0;
    if (n == 4) {
        pos->v = 4.0 / 9.0;
        for (int i = 0; i < 4; i++) {
            pos->e[i] = 1.0 / 9.0;
            pos->f[i] = 1.0 / 36.0;
        }
        return;
    }
    double N = (double)n;
    double fw = 1.0 / (N * (N + 5.0));
    double ew = 4.0 * fw;
    pos->v = 1.0 - N * (ew + fw);
    for (int i = 0; i < n; i++) {
        pos->e[i] = ew;
        pos->f[i] = fw;
    }
}

static void cc_corner_tangents(int valence, sd_mask *t1, sd_mask *t2, double scale)
{
    t1->ne = t2->ne = valence;
    t1->nf = t2->nf = 0;
    t1->fcenters = t2->fcenters = 0;
    t1->v = -scale;
    t2->v = -scale;
    for (int i = 0; i < valence; i++)
        t1->e[i] = t2->e[i] = 0.0;
    t1->e[0] = scale;
    t2->e[1] = scale;
}

static void cc_smooth_tangents(int n, sd_mask *t1, sd_mask *t2)
{
    if (n == 2) {
        cc_corner_tangents(2, t1, t2, 1.0);
        return;
    }
    t1->ne = t2->ne = n;
    t1->nf = t2->nf = n;
    t1->fcenters = t2->fcenters = 0;
    t1->v = t2->v = 0.0;
    if (n == 4) {
        static const double e1[4] = {4, 0, -4, 0}, f1[4] = {1, -1, -1, 1};
        static const double e2[4] = {0, 4, 0, -4}, f2[4] = {1, 1, -1, -1};
        for (int i = 0; i < 4; i++) {
            t1->e[i] = e1[i];
            t1->f[i] = f1[i];
            t2->e[i] = e2[i];
            t2->f[i] = f2[i];
        }
        return;
    }
    double theta = 2.0 * GEOM_PI / (double)n;
    double ct = cos(theta), cht = cos(theta * 0.5);
    double lambda = (5.0 / 16.0) + (1.0 / 16.0) * (ct + cht * sqrt(2.0 * (9.0 + ct)));
    double escale = 4.0, fscale = 1.0 / (4.0 * lambda - 1.0);
    for (int i = 0; i < n; i++) {
        double ci = cos(i * theta), ci1 = cos((i + 1) * theta);
        t1->e[i] = escale * ci;
        t1->f[i] = fscale * (ci + ci1);
    }
    t2->e[0] = t1->e[n - 1];
    t2->f[0] = t1->f[n - 1];
    for (int i = 1; i < n; i++) {
        t2->e[i] = t1->e[i - 1];
        t2->f[i] = t1->f[i - 1];
    }
}

static void cc_crease_tangents(int ne, int nf, const int ends[2], sd_mask *t1, sd_mask *t2)
{
    t1->ne = t2->ne = ne;
    t1->nf = t2->nf = nf;
    t1->fcenters = t2->fcenters = 0;
    t1->v = 0.0;
    for (int i = 0; i < ne; i++)
        t1->e[i] = 0.0;
    for (int i = 0; i < nf; i++)
        t1->f[i] = 0.0;
    t1->e[ends[0]] = 0.5;
    t1->e[ends[1]] = -0.5;
    for (int i = 0; i < ends[0]; i++) {
        t2->e[i] = 0.0;
        t2->f[i] = 0.0;
    }
    int interior = ends[1] - ends[0] - 1;
    if (interior == 1) {
        t2->v = -4.0 / 6.0;
        t2->e[ends[0]] = -1.0 / 6.0;
        t2->e[ends[0] + 1] = 4.0 / 6.0;
        t2->e[ends[1]] = -1.0 / 6.0;
        t2->f[ends[0]] = 1.0 / 6.0;
        t2->f[ends[0] + 1] = 1.0 / 6.0;
    } else if (interior > 1) {
        double k = (double)(interior + 1);
        double theta = GEOM_PI / k;
        double ct = cos(theta), st = sin(theta);
        double denom = 1.0 / (k * (3.0 + ct));
        double R = (ct + 1.0) / st;
        double vwt = 4.0 * R * (ct - 1.0);
        double cwt = -R * (1.0 + 2.0 * ct);
        t2->v = vwt * denom;
        t2->e[ends[0]] = cwt * denom;
        t2->e[ends[1]] = cwt * denom;
        t2->f[ends[0]] = st * denom;
        double si = 0.0, si1 = st;
        for (int i = 1; i < k; i++) {
            si = si1;
            si1 = sin((i + 1) * theta);
            t2->e[ends[0] + i] = (4.0 * si) * denom;
            t2->f[ends[0] + i] = (si + si1) * denom;
        }
    } else {
        t2->v = -6.0;
        t2->e[ends[0]] = 3.0;
        t2->e[ends[1]] = 3.0;
        t2->f[ends[0]] = 0.0;
    }
    for (int i = ends[1]; i < nf; i++)
        t2->f[i] = 0.0;
    for (int i = ends[1] + 1; i < ne; i++)
        t2->e[i] = 0.0;
}

static void loop_smooth_limit(int n, sd_mask *pos)
{
    pos->ne = n;
    pos->nf = 0;
    pos->fcenters = 0;
    if (n == 6) {
        pos->v = 0.5;
        for (int i = 0; i < 6; i++)
            pos->e[i] = 1.0 / 12.0;
        return;
    }
    double dn = (double)n, inv = 1.0 / dn;
    double c = cos(GEOM_PI * 2.0 * inv);
    double beta = 0.25 * c + 0.375;
    double gamma = (0.625 - beta * beta) * inv;
    double ew = 1.0 / (dn + 3.0 / (8.0 * gamma));
    pos->v = 1.0 - ew * dn;
    for (int i = 0; i < n; i++)
        pos->e[i] = ew;
}

static void loop_smooth_tangents(int n, sd_mask *t1, sd_mask *t2)
{
    t1->ne = t2->ne = n;
    t1->nf = t2->nf = 0;
    t1->fcenters = t2->fcenters = 0;
    t1->v = t2->v = 0.0;
    if (n == 6) {
        const double r = 0.5 * 1.73205080756887729352;
        static const double e1[6] = {1.0, 0.5, -0.5, -1.0, -0.5, 0.5};
        const double e2[6] = {0.0, r, r, 0.0, -r, -r};
        for (int i = 0; i < 6; i++) {
            t1->e[i] = e1[i];
            t2->e[i] = e2[i];
        }
        return;
    }
    double alpha = 2.0 * GEOM_PI / n;
    for (int i = 0; i < n; i++) {
        double ai = alpha * i;
        t1->e[i] = cos(ai);
        t2->e[i] = sin(ai);
    }
}

static void loop_crease_tangents(int ne, const int ends[2], sd_mask *t1, sd_mask *t2)
{
    t1->ne = t2->ne = ne;
    t1->nf = t2->nf = 0;
    t1->fcenters = t2->fcenters = 0;
    t1->v = 0.0;
    for (int i = 0; i < ne; i++)
        t1->e[i] = 0.0;
    t1->e[ends[0]] = 1.5;
    t1->e[ends[1]] = -1.5;
    for (int i = 0; i < ends[0]; i++)
        t2->e[i] = 0.0;
    int interior = ends[1] - ends[0] - 1;
    if (interior == 2) {
        const double r3 = 1.73205080756887729352, r3h = r3 * 0.5;
        t2->v = -r3;
        t2->e[ends[0]] = -r3h;
        t2->e[ends[1]] = -r3h;
        t2->e[ends[0] + 1] = r3;
        t2->e[ends[0] + 2] = r3;
    } else if (interior > 2) {
        double theta = GEOM_PI / (interior + 1);
        t2->v = 0.0;
        double cwt = -3.0 * sin(theta);
        t2->e[ends[0]] = cwt;
        t2->e[ends[1]] = cwt;
        double ec = -3.0 * 2.0 * (cos(theta) - 1.0);
        for (int i = 1; i <= interior; i++)
            t2->e[ends[0] + i] = ec * sin(i * theta);
    } else if (interior == 1) {
        t2->v = -3.0;
        t2->e[ends[0]] = 0.0;
        t2->e[ends[1]] = 0.0;
        t2->e[ends[0] + 1] = 3.0;
    } else {
        t2->v = -6.0;
        t2->e[ends[0]] = 3.0;
        t2->e[ends[1]] = 3.0;
    }
    for (int i = ends[1] + 1; i < ne; i++)
        t2->e[i] = 0.0;
}

void sd_limit_masks(const sd_opts *o, const sd_level *l, uint32_t v, sd_mask *pos, sd_mask *t1,
                    sd_mask *t2, sd_scratch *s)
{
    int rule = l->vtag[v] & SD_V_RULE;
    int ne = (int)(l->ve_off[v + 1] - l->ve_off[v]);
    int nf = (int)(l->vf_off[v + 1] - l->vf_off[v]);
    int tangents = t1 && t2;
    if (o->scheme == GEOM_SUBDIV_BILINEAR) {
        corner_mask(pos);
        if (tangents) {
            t1->ne = t2->ne = 2;
            t1->nf = t2->nf = 0;
            t1->v = t2->v = -1.0;
            t1->e[0] = 1.0, t1->e[1] = 0.0;
            t2->e[0] = 0.0, t2->e[1] = 1.0;
        }
        return;
    }
    int loop = o->scheme == GEOM_SUBDIV_LOOP;
    if (rule == SD_RULE_SMOOTH || rule == SD_RULE_DART) {
        if (loop) {
            loop_smooth_limit(nf, pos);
            if (tangents)
                loop_smooth_tangents(nf, t1, t2);
        } else {
            cc_smooth_limit(nf, pos);
            if (tangents)
                cc_smooth_tangents(nf, t1, t2);
        }
    } else if (rule == SD_RULE_CREASE) {
        float *es = s->s;
        for (int i = 0; i < ne; i++)
            es[i] = l->esharp[l->ve[l->ve_off[v] + (uint32_t)i]];
        int ends[2];
        sd_crease_pair(es, ne, ends);
        pos->v = 2.0 / 3.0;
        pos->ne = ne;
        pos->nf = 0;
        pos->fcenters = 0;
        for (int i = 0; i < ne; i++)
            pos->e[i] = 0.0;
        pos->e[ends[0]] = 1.0 / 6.0;
        pos->e[ends[1]] = 1.0 / 6.0;
        if (tangents) {
            if (loop)
                loop_crease_tangents(ne, ends, t1, t2);
            else
                cc_crease_tangents(ne, nf, ends, t1, t2);
        }
    } else {
        corner_mask(pos);
        if (tangents)
            cc_corner_tangents(ne, t1, t2, loop ? 3.0 : 1.0);
    }
}
