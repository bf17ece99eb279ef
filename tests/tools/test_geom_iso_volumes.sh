#!/bin/bash
# Tests of geom-iso --volume on every volume format and sample type: Python
# (numpy, gzip, struct) writes the distance to a centre, sampled on an
# anisotropic grid with an origin, as raw (every sample type, both byte
# orders, with --skip), NRRD (raw, gzip, bzip2, ascii, detached), MetaImage
# (.mha, .mhd + .raw, compressed), INRIMAGE (.inr, .inr.gz) and NIfTI-1 (.nii,
# .nii.gz, .nii.bz2, negative sform axis); every vertex of the isosurface must lie at
# the sphere's radius around the world centre (so spacing and origin come
# from the header) and every file must give a closed surface. Then CGAL's
# liver.inr.gz (libcgal-demo) when present: vertices inside the header's box.
# Usage: test_geom_iso_volumes.sh /path/to/geom-iso   (env PYTHON3: Debian's python3)
set -u
TOOL=$1
PY=${PYTHON3:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-isovol-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
failures=0
checks=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

"$PY" - "$T" "$(dirname "$0")" <<'PYEOF' || { echo "FAIL: cannot make the test volumes" >&2; exit 1; }
import sys, gzip, struct, zlib, numpy as np
T = sys.argv[1]
sys.path.insert(0, sys.argv[2])
import volume_files
n = (24, 20, 16); sp = (0.5, 0.6, 0.75); org = (-3.0, 10.0, 100.0)
c = (org[0] + 11.5 * sp[0], org[1] + 9.5 * sp[1], org[2] + 7.5 * sp[2])
k, j, i = np.meshgrid(np.arange(n[2]), np.arange(n[1]), np.arange(n[0]), indexing='ij')
x = org[0] + i * sp[0]; y = org[1] + j * sp[1]; z = org[2] + k * sp[2]
d = np.sqrt((x - c[0])**2 + (y - c[1])**2 + (z - c[2])**2)   # [z, y, x]: x fastest
vals = {'u8': np.round(d * 20), 'i8': np.round(d * 20) - 100, 'u16': np.round(d * 1000),
        'i16': np.round(d * 1000) - 3000, 'u32': np.round(d * 1e6), 'i32': np.round(d * 1e6) - 4e6,
        'f32': d, 'f64': d}
iso = {'u8': 40, 'i8': -60, 'u16': 2000, 'i16': -1000, 'u32': 2e6, 'i32': -2e6, 'f32': 2, 'f64': 2}
dt = {'u8': 'u1', 'i8': 'i1', 'u16': 'u2', 'i16': 'i2', 'u32': 'u4', 'i32': 'i4', 'f32': 'f4', 'f64': 'f8'}
cases = []
def arr(t, big=False):
    return vals[t].astype(('>' if big else '<') + dt[t]).tobytes()
def case(name, t, extra=''):
    cases.append('%s %s %s' % (name, iso[t], extra))
# raw, every type and order, 13 header bytes
for t in dt:
    for big in (0, 1):
        fn = '%s/raw_%s_%d.bin' % (T, t, big)
        open(fn, 'wb').write(b'H' * 13 + arr(t, big))
        case(fn, t, '--dims=%d,%d,%d --type=%s --skip=13 --spacing=%g,%g,%g --origin=%g,%g,%g%s'
             % (n + (t,) + sp + org + (' --big-endian' if big else '',)))
ntype = {'u8': 'uchar', 'i8': 'int8', 'u16': 'ushort', 'i16': 'short', 'u32': 'uint',
         'i32': 'int', 'f32': 'float', 'f64': 'double'}
def nrrd_head(t, enc, extra=''):
    return ('NRRD0004\ntype: %s\ndimension: 3\nsizes: %d %d %d\nencoding: %s\nendian: big\n'
            'space dimension: 3\nspace directions: (%g,0,0) (0,%g,0) (0,0,%g)\n'
            'space origin: (%g,%g,%g)\n%s\n' % ((ntype[t],) + n + (enc,) + sp + org + (extra,)))
for t in dt:
    open('%s/v_%s.nrrd' % (T, t), 'wb').write(nrrd_head(t, 'raw').encode() + arr(t, True))
    case('%s/v_%s.nrrd' % (T, t), t)
open(T + '/gz.nrrd', 'wb').write(nrrd_head('i16', 'gzip').encode() + gzip.compress(arr('i16', True)))
case(T + '/gz.nrrd', 'i16')
open(T + '/txt.nrrd', 'wb').write(nrrd_head('f64', 'ascii').encode() +
                                  '\n'.join('%.17g' % v for v in vals['f64'].ravel()).encode())
case(T + '/txt.nrrd', 'f64')
open(T + '/det.nhdr', 'w').write(nrrd_head('u16', 'raw', 'data file: det.raw\n'))
open(T + '/det.raw', 'wb').write(arr('u16', True))
case(T + '/det.nhdr', 'u16')
# MetaImage
met = {'u8': 'MET_UCHAR', 'i8': 'MET_CHAR', 'u16': 'MET_USHORT', 'i16': 'MET_SHORT',
       'u32': 'MET_UINT', 'i32': 'MET_INT', 'f32': 'MET_FLOAT', 'f64': 'MET_DOUBLE'}
def mhead(t, f, comp=False):
    return ('ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n'
            'CompressedData = %s\nTransformMatrix = 1 0 0 0 1 0 0 0 1\nOffset = %g %g %g\n'
            'ElementSpacing = %g %g %g\nDimSize = %d %d %d\nElementType = %s\nElementDataFile = %s\n'
            % (('True' if comp else 'False',) + org + sp + n + (met[t], f))).encode()
open(T + '/v.mha', 'wb').write(mhead('u32', 'LOCAL') + arr('u32'))
case(T + '/v.mha', 'u32')
open(T + '/z.mha', 'wb').write(mhead('f32', 'LOCAL', True) + zlib.compress(arr('f32')))
case(T + '/z.mha', 'f32')
open(T + '/v.mhd', 'wb').write(mhead('i8', 'v.raw'))
open(T + '/v.raw', 'wb').write(arr('i8'))
case(T + '/v.mhd', 'i8')
# INRIMAGE (no origin field in the format as CGAL writes it: use XO/YO/ZO)
def inr(t, big):
    kind = 'float' if t[0] == 'f' else ('unsigned fixed' if t[0] == 'u' else 'signed fixed')
    h = ('#INRIMAGE-4#{\nXDIM=%d\nYDIM=%d\nZDIM=%d\nVDIM=1\nTYPE=%s\nPIXSIZE=%d bits\nSCALE=2**0\n'
         'CPU=%s\nVX=%g\nVY=%g\nVZ=%g\nXO=%g\nYO=%g\nZO=%g\n' %
         (n + (kind, int(t[1:]), 'sun' if big else 'decm') + sp + org))
    h = h + '\n' * (256 - 4 - len(h)) + '##}\n'
    return h.encode() + arr(t, big)
open(T + '/v.inr', 'wb').write(inr('u16', True))
case(T + '/v.inr', 'u16')
open(T + '/v.inr.gz', 'wb').write(gzip.compress(inr('f64', False)))
case(T + '/v.inr.gz', 'f64')
# NIfTI-1: sform with a negative x axis (file x runs from +x to -x)
def nifti(t, flip):
    return volume_files.nifti(vals[t].astype('<' + dt[t]), sp, org, flip)
open(T + '/v.nii', 'wb').write(nifti('i16', True))
case(T + '/v.nii', 'i16')
open(T + '/v.nii.gz', 'wb').write(gzip.compress(nifti('f32', False)))
case(T + '/v.nii.gz', 'f32')
# bzip2: the NRRD encoding and a whole .nii.bz2 (Python's bz2: the same
# samples as v_i16.nrrd and v.nii.gz, which must read identically); a
# truncated stream
import bz2
open(T + '/bz.nrrd', 'wb').write(nrrd_head('i16', 'bzip2').encode() + bz2.compress(arr('i16', True)))
case(T + '/bz.nrrd', 'i16')
open(T + '/v.nii.bz2', 'wb').write(bz2.compress(nifti('f32', False)))
case(T + '/v.nii.bz2', 'f32')
bzd = nrrd_head('i16', 'bzip2').encode() + bz2.compress(arr('i16', True))
open(T + '/cut_bz.nrrd', 'wb').write(bzd[:len(bzd) - 40])
bad = bytearray(bzd); bad[len(bzd) // 2] ^= 0x55
open(T + '/corrupt_bz.nrrd', 'wb').write(bytes(bad))
# spacing: NRRD nan (unknown: 1 with a warning), NIfTI pixdim 0 (1 with a
# warning), MetaImage and INRIMAGE zero spacing (errors)
open(T + '/nan.nrrd', 'wb').write(('NRRD0004\ntype: float\ndimension: 3\nsizes: %d %d %d\n'
    'encoding: raw\nendian: little\nspacings: nan 1 nan\n\n' % n).encode() + arr('f32'))
h = bytearray(nifti('f32', False)); struct.pack_into('<hh', h, 252, 0, 0)
struct.pack_into('<f', h, 80, 0.0)
open(T + '/pix0.nii', 'wb').write(bytes(h))
open(T + '/zero.mha', 'wb').write(mhead('u8', 'LOCAL').replace(b'ElementSpacing = 0.5', b'ElementSpacing = 0') + arr('u8'))
open(T + '/zero.inr', 'wb').write(inr('u8', False).replace(b'VY=0.6\n', b'VY=0\n\n\n'))
open(T + '/cases', 'w').write('\n'.join(cases) + '\n')
open(T + '/centre', 'w').write('%.17g %.17g %.17g\n' % c)
PYEOF

check_sphere() { # OBJ: every vertex at radius 2 (0.05 tolerance) around the centre, closed
    "$PY" - "$1" "$T/centre" <<'PYEOF'
import sys
c = [float(v) for v in open(sys.argv[2]).read().split()]
vs, edges = [], {}
for ln in open(sys.argv[1]):
    t = ln.split()
    if t and t[0] == 'v':
        vs.append([float(x) for x in t[1:4]])
    elif t and t[0] == 'f':
        f = [int(x.split('/')[0]) for x in t[1:]]
        for a, b in zip(f, f[1:] + f[:1]):
            edges[(a, b)] = edges.get((a, b), 0) + 1
if len(vs) < 100:
    sys.exit('only %d vertices' % len(vs))
bad = [v for v in vs if abs(sum((v[i] - c[i])**2 for i in range(3))**0.5 - 2) > 0.05]
if bad:
    sys.exit('%d of %d vertices off the radius-2 sphere, e.g. %s' % (len(bad), len(vs), bad[0]))
if any(n != 1 or edges.get((b, a)) != 1 for (a, b), n in edges.items()):
    sys.exit('not closed and oriented')
PYEOF
}

while read -r file iso extra; do
    checks=$((checks + 1))
    # shellcheck disable=SC2086
    if ! "$TOOL" --volume "$file" --iso "$iso" $extra -o "$T/out.obj" >"$T/stdout" 2>"$T/stderr"; then
        fail "$(basename "$file") $extra: exit $? ($(cat "$T/stderr"))"
        continue
    fi
    msg=$(check_sphere "$T/out.obj" 2>&1) || fail "$(basename "$file") $extra: $msg"
done <"$T/cases"

# errors: truncated data, a gzip file cut short, raw without --type, --skip too large
checks=$((checks + 4))
head -c 300 "$T/v_f32.nrrd" >"$T/short.nrrd"
"$TOOL" --volume "$T/short.nrrd" -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "short.nrrd" "$T/err" || fail "short NRRD: exit $rc, $(cat "$T/err")"
head -c 500 "$T/v.nii.gz" >"$T/cut.nii.gz"
"$TOOL" --volume "$T/cut.nii.gz" -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "cut.nii.gz" "$T/err" || fail "cut gzip: exit $rc, $(cat "$T/err")"
"$TOOL" --volume "$T/raw_u8_0.bin" --dims 24,20,16 -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 2 ] || fail "raw without --type: exit $rc"
"$TOOL" --volume "$T/raw_u8_0.bin" --dims 24,20,16 --type u8 --skip 14 -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "need" "$T/err" || fail "--skip 14: exit $rc, $(cat "$T/err")"

# bzip2 reads exactly as raw and gzip: the same OBJ, byte for byte
checks=$((checks + 2))
"$TOOL" --volume "$T/v_i16.nrrd" --iso -1000 -o "$T/a.obj" >/dev/null 2>&1
"$TOOL" --volume "$T/bz.nrrd" --iso -1000 -o "$T/b.obj" >/dev/null 2>&1
cmp -s "$T/a.obj" "$T/b.obj" || fail "bzip2 NRRD differs from raw NRRD"
"$TOOL" --volume "$T/v.nii.gz" --iso 2 -o "$T/a.obj" >/dev/null 2>&1
"$TOOL" --volume "$T/v.nii.bz2" --iso 2 -o "$T/b.obj" >/dev/null 2>&1
cmp -s "$T/a.obj" "$T/b.obj" || fail ".nii.bz2 differs from .nii.gz"
# truncated and corrupt bzip2 streams: exit 1, the file and "bzip2" named
for f in cut_bz corrupt_bz; do
    checks=$((checks + 1))
    "$TOOL" --volume "$T/$f.nrrd" --iso 0 -o "$T/o.obj" 2>"$T/err"; rc=$?
    [ $rc -eq 1 ] && grep -q "$f.nrrd.*bzip2" "$T/err" || fail "$f: exit $rc, $(cat "$T/err")"
done
# unknown spacing: read as 1 with a warning naming the file, the field and
# the value, and --json carries it; invalid MetaImage/INRIMAGE spacing: errors
checks=$((checks + 4))
"$TOOL" --volume "$T/nan.nrrd" --iso 2 --json -o "$T/o.obj" >"$T/j" 2>"$T/err" || fail "nan.nrrd: $(cat "$T/err")"
grep -q "warning: .*nan.nrrd: line 7: 'spacings: nan 1 nan': axis 0, 2 spacing unknown (nan), 1 used" "$T/err" ||
    fail "nan.nrrd: no warning: $(cat "$T/err")"
"$PY" -c 'import json,sys; w=json.load(open(sys.argv[1])).get("warnings",[]); sys.exit(0 if any("spacings: nan 1 nan" in x for x in w) else 1)' "$T/j" ||
    fail "nan.nrrd: --json lacks the warning: $(cat "$T/j")"
"$TOOL" --volume "$T/pix0.nii" --iso 2 -o "$T/o.obj" >/dev/null 2>"$T/err" || fail "pix0.nii: $(cat "$T/err")"
grep -q "warning: .*pix0.nii: pixdim\[1\] = 0 (byte 80): not a positive voxel width, 1 used" "$T/err" ||
    fail "pix0.nii: no warning: $(cat "$T/err")"
"$TOOL" --volume "$T/zero.mha" --iso 40 -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "zero.mha:8:1: ElementSpacing: spacing 0 is not a positive finite number" "$T/err" ||
    fail "zero.mha: exit $rc, $(cat "$T/err")"
checks=$((checks + 1))
"$TOOL" --volume "$T/zero.inr" --iso 40 -o "$T/o.obj" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "zero.inr:.*VY: spacing 0" "$T/err" || fail "zero.inr: exit $rc, $(cat "$T/err")"

LIVER=/usr/share/doc/libcgal-dev/data.tar.gz
if [ -f "$LIVER" ] && tar xzf "$LIVER" -C "$T" data/images/liver.inr.gz 2>/dev/null; then
    checks=$((checks + 1))
    if "$TOOL" --volume "$T/data/images/liver.inr.gz" --iso 100 --json -o "$T/liver.obj" >"$T/j" 2>"$T/err"; then
        "$PY" - "$T/liver.obj" "$T/j" <<'PYEOF' || fail "liver: bad result"
import sys, json
j = json.load(open(sys.argv[2]))
hi = [437 * 0.617188, 352 * 0.617188, 164 * 1.33333]
n = 0
for ln in open(sys.argv[1]):
    if ln.startswith('v '):
        p = [float(x) for x in ln.split()[1:4]]
        n += 1
        if any(p[i] < -1e-9 or p[i] > hi[i] + 1e-9 for i in range(3)):
            sys.exit('vertex %s outside the header box' % p)
if n != j['vertices'] or j['triangles'] < 100000:
    sys.exit('%d vertices, json %s' % (n, j))
PYEOF
    else
        fail "liver.inr.gz: $(cat "$T/err")"
    fi
fi

if [ "$failures" -ne 0 ]; then
    echo "$failures of $checks checks failed" >&2
    exit 1
fi
echo "all $checks checks passed"
