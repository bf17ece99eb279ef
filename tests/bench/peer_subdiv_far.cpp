// Whole-process peer of `geom-subdivide --scheme loop|catmull-clark
// --levels N IN.obj -o OUT.obj`: read an OBJ (v and f lines; v/vt/vn
// corners use their vertex index), refine uniformly with OpenSubdiv Far
// (TopologyRefinerFactory<TopologyDescriptor>, RefineUniform, then
// PrimvarRefinerReal<double>::Interpolate, boundary EDGE_ONLY as
// geom-subdivide's default) and write the last level as OBJ with the
// shortest round-trip doubles of std::to_chars, as geom-subdivide writes
// exact doubles. Parsing uses std::from_chars (exact). Run by
// tests/bench/whole_process.sh against geom-subdivide; not a test.
//
// Usage: peer_subdiv_far loop|catmull-clark LEVELS IN.obj OUT.obj
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

using namespace OpenSubdiv;

namespace {

struct P3 {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(const P3 &s, double w)
    {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

const char *skip_ws(const char *s, const char *e)
{
    while (s < e && (*s == ' ' || *s == '\t'))
        s++;
    return s;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc != 5) {
        std::fprintf(stderr, "usage: %s loop|catmull-clark LEVELS IN.obj OUT.obj\n", argv[0]);
        return 2;
    }
    bool loop = std::strcmp(argv[1], "loop") == 0;
    int levels = std::atoi(argv[2]);
    FILE *f = std::fopen(argv[3], "rb");
    if (!f)
        return 1;
    std::fseek(f, 0, SEEK_END);
    long n = std::ftell(f);
    std::fseek(f, 0, SEEK_SET);
    std::string buf((size_t)n, '\0');
    if (std::fread(&buf[0], 1, (size_t)n, f) != (size_t)n)
        return 1;
    std::fclose(f);
    std::vector<P3> pos;
    std::vector<int> sizes, idx;
    const char *s = buf.data(), *e = s + buf.size();
    while (s < e) {
        const char *eol = (const char *)std::memchr(s, '\n', (size_t)(e - s));
        if (!eol)
            eol = e;
        if (s[0] == 'v' && s + 1 < eol && (s[1] == ' ' || s[1] == '\t')) {
            P3 p;
            const char *q = s + 1;
            for (int k = 0; k < 3; k++) {
                q = skip_ws(q, eol);
                auto r = std::from_chars(q, eol, p.p[k]);
                q = r.ptr;
            }
            pos.push_back(p);
        } else if (s[0] == 'f' && s + 1 < eol && (s[1] == ' ' || s[1] == '\t')) {
            const char *q = s + 1;
            int cnt = 0;
            for (;;) {
                q = skip_ws(q, eol);
                if (q >= eol || *q == '\r')
                    break;
                long v = 0;
                auto r = std::from_chars(q, eol, v);
                q = r.ptr;
                while (q < eol && *q != ' ' && *q != '\t')
                    q++;
                idx.push_back(v < 0 ? (int)pos.size() + (int)v : (int)v - 1);
                cnt++;
            }
            sizes.push_back(cnt);
        }
        s = eol + 1;
    }
    Far::TopologyDescriptor d;
    d.numVertices = (int)pos.size();
    d.numFaces = (int)sizes.size();
    d.numVertsPerFace = sizes.data();
    d.vertIndicesPerFace = idx.data();
    Sdc::Options opt;
    opt.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> F;
    std::unique_ptr<Far::TopologyRefiner> r(
        F::Create(d, F::Options(loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, opt)));
    if (!r)
        return 1;
    r->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
    std::vector<std::vector<P3>> lv(levels + 1);
    lv[0] = pos;
    Far::PrimvarRefinerReal<double> pr(*r);
    for (int l = 1; l <= levels; l++) {
        lv[l].resize(r->GetLevel(l).GetNumVertices());
        pr.Interpolate(l, lv[l - 1], lv[l]);
    }
    const Far::TopologyLevel &L = r->GetLevel(levels);
    FILE *o = std::fopen(argv[4], "wb");
    if (!o)
        return 1;
    std::vector<char> out;
    out.reserve(1 << 20);
    char tmp[64];
    auto flush = [&]() {
        std::fwrite(out.data(), 1, out.size(), o);
        out.clear();
    };
    for (const P3 &p : lv[levels]) {
        out.push_back('v');
        for (int k = 0; k < 3; k++) {
            out.push_back(' ');
            auto t = std::to_chars(tmp, tmp + sizeof tmp, p.p[k]);
            out.insert(out.end(), tmp, t.ptr);
        }
        out.push_back('\n');
        if (out.size() > (1 << 20))
            flush();
    }
    for (int fi = 0; fi < L.GetNumFaces(); fi++) {
        Far::ConstIndexArray fv = L.GetFaceVertices(fi);
        out.push_back('f');
        for (int k = 0; k < fv.size(); k++) {
            out.push_back(' ');
            auto t = std::to_chars(tmp, tmp + sizeof tmp, fv[k] + 1);
            out.insert(out.end(), tmp, t.ptr);
        }
        out.push_back('\n');
        if (out.size() > (1 << 20))
            flush();
    }
    flush();
    std::fclose(o);
    return 0;
}
