// OpenSubdiv part of the validation shim: see geom_validate_osd.h.
#include "geom_validate_osd.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

struct V3 {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(const V3 &s, double w)
    {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

struct V2 {
    double p[2];
    void Clear() { p[0] = p[1] = 0.0; }
    void AddWithWeight(const V2 &s, double w)
    {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
    }
};

void set_err(char *err, size_t len, const std::string &m)
{
    if (err && len) {
        std::snprintf(err, len, "%s", m.c_str());
    }
}

} // namespace

struct gv_osd {
    std::unique_ptr<Far::TopologyRefiner> refiner;
    std::vector<std::vector<V3>> pos;
    std::vector<V3> limit, tan1, tan2;
    std::vector<std::vector<V2>> fvar;
    std::vector<V2> fvar_limit;
    bool has_fvar = false;
    int vtx = 1, fvlin = 5, crease = 0, tri = 0;
};

extern "C" gv_osd *gv_osd_create(const gv_osd_shape *s, int levels, char *err, size_t errlen)
{
    try {
        if (!s || !s->positions || !s->face_sizes || !s->indices || levels < 0 || levels > 10) {
            set_err(err, errlen, "invalid arguments");
            return nullptr;
        }
        std::unique_ptr<gv_osd> h(new gv_osd);
        // Options as the regression harness's GetSdcOptions.
        Sdc::Options opt;
        opt.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
        opt.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
        opt.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);
        bool propagate = false;
        std::vector<int> creaseVerts, cornerVerts, holes;
        std::vector<float> creaseW, cornerW;
        for (size_t i = 0; i < s->ntags; i++) {
            const gv_osd_tag &t = s->tags[i];
            std::string name = t.name ? t.name : "";
            if (name == "interpolateboundary" && t.nint >= 1) {
                switch (t.ints[0]) {
                case 0: opt.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_NONE); break;
                case 1: opt.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER); break;
                case 2: opt.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY); break;
                default: break;
                }
            } else if (name == "facevaryinginterpolateboundary" && t.nint >= 1) {
                switch (t.ints[0]) {
                case 0: opt.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_NONE); break;
                case 1: opt.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_CORNERS_ONLY); break;
                case 2: opt.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1); break;
                case 3: opt.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2); break;
                case 4: opt.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_BOUNDARIES); break;
                case 5: opt.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL); break;
                default: break;
                }
            } else if (name == "facevaryingpropagatecorners" && t.nint >= 1) {
                propagate = t.ints[0] != 0;
            } else if (name == "creasemethod" && t.nstring >= 1) {
                std::string m = t.strings[0];
                if (m == "normal")
                    opt.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
                else if (m == "chaikin")
                    opt.SetCreasingMethod(Sdc::Options::CREASE_CHAIKIN);
            } else if (name == "smoothtriangles" && t.nstring >= 1) {
                std::string m = t.strings[0];
                if (m == "catmark")
                    opt.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);
                else if (m == "smooth")
                    opt.SetTriangleSubdivision(Sdc::Options::TRI_SUB_SMOOTH);
            } else if (name == "crease") {
                for (size_t j = 0; j + 1 < t.nint; j += 2) {
                    if (t.nfloat == 0)
                        break;
                    double w = t.floats[t.nfloat > 1 ? j / 2 : 0];
                    creaseVerts.push_back((int)t.ints[j]);
                    creaseVerts.push_back((int)t.ints[j + 1]);
                    creaseW.push_back(std::max(0.0f, (float)w));
                }
            } else if (name == "corner") {
                for (size_t j = 0; j < t.nint; j++) {
                    if (t.nfloat == 0)
                        break;
                    double w = t.floats[t.nfloat > 1 ? j : 0];
                    cornerVerts.push_back((int)t.ints[j]);
                    cornerW.push_back(std::max(0.0f, (float)w));
                }
            } else if (name == "hole") {
                for (size_t j = 0; j < t.nint; j++)
                    if (t.ints[j] >= 0 && (size_t)t.ints[j] < s->nfaces)
                        holes.push_back((int)t.ints[j]);
            }
        }
        if (propagate && opt.GetFVarLinearInterpolation() == Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1)
            opt.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2);
        h->vtx = (int)opt.GetVtxBoundaryInterpolation();
        h->fvlin = (int)opt.GetFVarLinearInterpolation();
        h->crease = (int)opt.GetCreasingMethod();
        h->tri = (int)opt.GetTriangleSubdivision();

        std::vector<int> sizes(s->face_sizes, s->face_sizes + s->nfaces);
        size_t nfv = 0;
        for (size_t f = 0; f < s->nfaces; f++)
            nfv += s->face_sizes[f];
        std::vector<int> idx(s->indices, s->indices + nfv);
        std::vector<int> fvidx;
        Far::TopologyDescriptor d;
        d.numVertices = (int)s->nverts;
        d.numFaces = (int)s->nfaces;
        d.numVertsPerFace = sizes.data();
        d.vertIndicesPerFace = idx.data();
        d.numCreases = (int)creaseW.size();
        d.creaseVertexIndexPairs = creaseVerts.data();
        d.creaseWeights = creaseW.data();
        d.numCorners = (int)cornerW.size();
        d.cornerVertexIndices = cornerVerts.data();
        d.cornerWeights = cornerW.data();
        d.numHoles = (int)holes.size();
        d.holeIndices = holes.data();
        Far::TopologyDescriptor::FVarChannel ch;
        if (s->n_fvar_values > 0 && s->fvar_values && s->fvar_indices) {
            fvidx.assign(s->fvar_indices, s->fvar_indices + nfv);
            ch.numValues = (int)s->n_fvar_values;
            ch.valueIndices = fvidx.data();
            d.numFVarChannels = 1;
            d.fvarChannels = &ch;
            h->has_fvar = true;
        }
        Sdc::SchemeType type = s->scheme == GV_OSD_LOOP       ? Sdc::SCHEME_LOOP
                               : s->scheme == GV_OSD_BILINEAR ? Sdc::SCHEME_BILINEAR
                                                              : Sdc::SCHEME_CATMARK;
        typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
        h->refiner.reset(Factory::Create(d, Factory::Options(type, opt)));
        if (!h->refiner) {
            set_err(err, errlen, "Far::TopologyRefinerFactory refused the shape");
            return nullptr;
        }
        Far::TopologyRefiner::UniformOptions uo(levels);
        uo.orderVerticesFromFacesFirst = true;
        uo.fullTopologyInLastLevel = true;
        h->refiner->RefineUniform(uo);
        Far::PrimvarRefinerReal<double> pr(*h->refiner);
        h->pos.resize(levels + 1);
        h->pos[0].resize(s->nverts);
        for (size_t v = 0; v < s->nverts; v++)
            for (int k = 0; k < 3; k++)
                h->pos[0][v].p[k] = s->positions[3 * v + k];
        for (int l = 1; l <= levels; l++) {
            h->pos[l].resize(h->refiner->GetLevel(l).GetNumVertices());
            pr.Interpolate(l, h->pos[l - 1], h->pos[l]);
        }
        size_t nl = h->pos[levels].size();
        h->limit.resize(nl);
        // Far 3.5's Limit with tangents sizes its weight buffer by the
        // maximum valence, which a vertex on an edge with more than two
        // faces exceeds (it has twice as many faces as the edge): tangents
        // only when every base edge has at most two faces.
        bool manifold_edges = true;
        const Far::TopologyLevel &base = h->refiner->GetLevel(0);
        for (int e = 0; e < base.GetNumEdges(); e++)
            if (base.GetEdgeFaces(e).size() > 2)
                manifold_edges = false;
        if (manifold_edges) {
            h->tan1.resize(nl);
            h->tan2.resize(nl);
            pr.Limit(h->pos[levels], h->limit, h->tan1, h->tan2);
        } else {
            pr.Limit(h->pos[levels], h->limit);
        }
        if (h->has_fvar) {
            h->fvar.resize(levels + 1);
            h->fvar[0].resize(s->n_fvar_values);
            for (size_t i = 0; i < s->n_fvar_values; i++)
                for (int k = 0; k < 2; k++)
                    h->fvar[0][i].p[k] = s->fvar_values[2 * i + k];
            for (int l = 1; l <= levels; l++) {
                h->fvar[l].resize(h->refiner->GetLevel(l).GetNumFVarValues(0));
                pr.InterpolateFaceVarying(l, h->fvar[l - 1], h->fvar[l], 0);
            }
            h->fvar_limit.resize(h->fvar[levels].size());
            pr.LimitFaceVarying(h->fvar[levels], h->fvar_limit, 0);
        }
        return h.release();
    } catch (const std::exception &e) {
        set_err(err, errlen, e.what());
    } catch (...) {
        set_err(err, errlen, "unknown exception");
    }
    return nullptr;
}

extern "C" void gv_osd_destroy(gv_osd *h)
{
    delete h;
}

static bool level_ok(const gv_osd *h, int level)
{
    return h && level >= 0 && level <= h->refiner->GetMaxLevel();
}

extern "C" size_t gv_osd_vertices(const gv_osd *h, int level)
{
    return level_ok(h, level) ? (size_t)h->refiner->GetLevel(level).GetNumVertices() : 0;
}

extern "C" size_t gv_osd_faces(const gv_osd *h, int level)
{
    return level_ok(h, level) ? (size_t)h->refiner->GetLevel(level).GetNumFaces() : 0;
}

extern "C" size_t gv_osd_face_vertices(const gv_osd *h, int level)
{
    return level_ok(h, level) ? (size_t)h->refiner->GetLevel(level).GetNumFaceVertices() : 0;
}

extern "C" int gv_osd_topology(const gv_osd *h, int level, uint32_t *sizes, uint32_t *indices)
{
    if (!level_ok(h, level))
        return GV_OSD_ERR;
    const Far::TopologyLevel &l = h->refiner->GetLevel(level);
    size_t k = 0;
    for (int f = 0; f < l.GetNumFaces(); f++) {
        Far::ConstIndexArray fv = l.GetFaceVertices(f);
        if (sizes)
            sizes[f] = (uint32_t)fv.size();
        for (int i = 0; i < fv.size(); i++, k++)
            if (indices)
                indices[k] = (uint32_t)fv[i];
    }
    return GV_OSD_OK;
}

extern "C" size_t gv_osd_edges(const gv_osd *h, int level)
{
    return level_ok(h, level) ? (size_t)h->refiner->GetLevel(level).GetNumEdges() : 0;
}

extern "C" int gv_osd_tags(const gv_osd *h, int level, uint32_t *edge_verts, float *edge_sharpness,
                           float *vertex_sharpness, uint8_t *vertex_rule, uint8_t *face_hole)
{
    if (!level_ok(h, level))
        return GV_OSD_ERR;
    const Far::TopologyLevel &l = h->refiner->GetLevel(level);
    for (int e = 0; e < l.GetNumEdges(); e++) {
        if (edge_verts) {
            Far::ConstIndexArray ev = l.GetEdgeVertices(e);
            edge_verts[2 * e] = (uint32_t)ev[0];
            edge_verts[2 * e + 1] = (uint32_t)ev[1];
        }
        if (edge_sharpness)
            edge_sharpness[e] = l.GetEdgeSharpness(e);
    }
    for (int v = 0; v < l.GetNumVertices(); v++) {
        if (vertex_sharpness)
            vertex_sharpness[v] = l.GetVertexSharpness(v);
        if (vertex_rule)
            vertex_rule[v] = (uint8_t)l.GetVertexRule(v);
    }
    for (int f = 0; f < l.GetNumFaces(); f++)
        if (face_hole)
            face_hole[f] = l.IsFaceHole(f) ? 1 : 0;
    return GV_OSD_OK;
}

extern "C" const double *gv_osd_positions(const gv_osd *h, int level)
{
    if (!level_ok(h, level) || h->pos[level].empty())
        return nullptr;
    return h->pos[level][0].p;
}

extern "C" const double *gv_osd_limit(const gv_osd *h)
{
    return h && !h->limit.empty() ? h->limit[0].p : nullptr;
}

extern "C" const double *gv_osd_limit_tan1(const gv_osd *h)
{
    return h && !h->tan1.empty() ? h->tan1[0].p : nullptr;
}

extern "C" const double *gv_osd_limit_tan2(const gv_osd *h)
{
    return h && !h->tan2.empty() ? h->tan2[0].p : nullptr;
}

extern "C" size_t gv_osd_fvar_values(const gv_osd *h, int level)
{
    if (!level_ok(h, level) || !h->has_fvar)
        return 0;
    return h->fvar[level].size();
}

extern "C" const double *gv_osd_fvar(const gv_osd *h, int level)
{
    if (!level_ok(h, level) || !h->has_fvar || h->fvar[level].empty())
        return nullptr;
    return h->fvar[level][0].p;
}

extern "C" int gv_osd_fvar_indices(const gv_osd *h, int level, uint32_t *indices)
{
    if (!level_ok(h, level) || !h->has_fvar || !indices)
        return GV_OSD_ERR;
    const Far::TopologyLevel &l = h->refiner->GetLevel(level);
    size_t k = 0;
    for (int f = 0; f < l.GetNumFaces(); f++) {
        Far::ConstIndexArray fv = l.GetFaceFVarValues(f, 0);
        for (int i = 0; i < fv.size(); i++)
            indices[k++] = (uint32_t)fv[i];
    }
    return GV_OSD_OK;
}

extern "C" const double *gv_osd_fvar_limit(const gv_osd *h)
{
    return h && h->has_fvar && !h->fvar_limit.empty() ? h->fvar_limit[0].p : nullptr;
}

extern "C" void gv_osd_options(const gv_osd *h, int *vtx, int *fvar, int *crease, int *tri)
{
    if (!h)
        return;
    if (vtx)
        *vtx = h->vtx;
    if (fvar)
        *fvar = h->fvlin;
    if (crease)
        *crease = h->crease;
    if (tri)
        *tri = h->tri;
}
