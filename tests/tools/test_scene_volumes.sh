#!/bin/bash
# Volumes in scene files (tools/scene_json.c): a scene's {"type": "volume"}
# is read as geom-iso --volume reads it. Python (numpy, gzip, bz2, zlib,
# struct) writes one int16 distance field (1000 * the distance to a centre,
# anisotropic spacing, an origin) as NRRD (raw, gzip, bzip2, ascii,
# detached, whole file .gz), MetaImage (.mha, compressed .mha, .mhd + .raw),
# INRIMAGE (.inr, .inr.gz), NIfTI-1 (.nii, .nii.gz, .nii.bz2, a negative
# sform axis) and headerless samples ("dims", "sample", "skip", "spacing",
# "origin", "big_endian"); geom-raycast shoots rays at the iso 2000 sphere
# (radius 2) of each: every hit on the trilinear interpolant's iso 2000
# (computed here), within 0.075 of t = distance - 2 (the interpolant's own
# error at this spacing), with the normal facing the ray; and
# every file whose header stores the same spacing and origin exactly gives
# output byte-identical to the raw NRRD's. A NRRD with an unknown spacing
# warns naming the file; bad volume files (truncated gzip, corrupt bzip2,
# malformed header, wrong size, missing file) exit 1 with a message naming
# the scene, the object, the key and the volume file; misused raw keys too.
# A CT-like volume (5000 - that field: dense inside, NIfTI int16) at iso 3000,
# the same sphere: without "inside" it is detected as above (as geom-iso
# does), so the normals face outward (d.n < 0 from outside) and --all gives
# enter then leave; "inside": "above" gives the same bytes, "below" the
# inward normals; a bad "inside" names the object and the key. With
# geom-scene and geom-iso given, the CT scene's export and geom-iso's
# isosurface of the same file both have a positive signed volume (outward
# normals), equal within 2 %.
# Usage: test_scene_volumes.sh /path/to/geom-raycast [geom-scene geom-iso]
#        (env PYTHON3)
set -u
TOOL=$1
SCENE_TOOL=${2:-}
ISO_TOOL=${3:-}
PY=${PYTHON3:-/usr/bin/python3}
T=$(mktemp -d "${TMPDIR:-/tmp}/geom-scenevol-test.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/testlib.sh"

"$PY" - "$T" "$(dirname "$0")" <<'PYEOF' || { echo "FAIL: cannot make the test volumes" >&2; exit 1; }
import sys, gzip, bz2, struct, zlib, numpy as np
T = sys.argv[1]
sys.path.insert(0, sys.argv[2])
import volume_files
n = (24, 20, 16); sp = (0.5, 0.6, 0.75); org = (-3.0, 10.0, 100.0)
c = (org[0] + 11.5 * sp[0], org[1] + 9.5 * sp[1], org[2] + 7.5 * sp[2])
k, j, i = np.meshgrid(np.arange(n[2]), np.arange(n[1]), np.arange(n[0]), indexing='ij')
x = org[0] + i * sp[0]; y = org[1] + j * sp[1]; z = org[2] + k * sp[2]
d = np.round(1000 * np.sqrt((x - c[0])**2 + (y - c[1])**2 + (z - c[2])**2))  # [z, y, x]
le, be = d.astype('<i2').tobytes(), d.astype('>i2').tobytes()
same, other = [], []      # (file, extra JSON keys): exact header placement / float32 placement
def w(name, data):
    open(T + '/' + name, 'wb').write(data)
def nrrd(enc, extra=''):
    return ('NRRD0004\ntype: short\ndimension: 3\nsizes: %d %d %d\nencoding: %s\nendian: big\n'
            'space dimension: 3\nspace directions: (%g,0,0) (0,%g,0) (0,0,%g)\n'
            'space origin: (%g,%g,%g)\n%s\n' % (n + (enc,) + sp + org + (extra,))).encode()
w('raw.nrrd', nrrd('raw') + be)
w('gz.nrrd', nrrd('gzip') + gzip.compress(be)); same.append('gz.nrrd')
w('bz.nrrd', nrrd('bzip2') + bz2.compress(be)); same.append('bz.nrrd')
w('txt.nrrd', nrrd('ascii') + '\n'.join('%d' % v for v in d.ravel()).encode()); same.append('txt.nrrd')
w('det.nhdr', nrrd('raw', 'data file: det.raw\n')); w('det.raw', be); same.append('det.nhdr')
w('whole.nrrd.gz', gzip.compress(nrrd('raw') + be)); same.append('whole.nrrd.gz')
def mhead(f, comp=False):
    return ('ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n'
            'CompressedData = %s\nTransformMatrix = 1 0 0 0 1 0 0 0 1\nOffset = %g %g %g\n'
            'ElementSpacing = %g %g %g\nDimSize = %d %d %d\nElementType = MET_SHORT\nElementDataFile = %s\n'
            % (('True' if comp else 'False',) + org + sp + n + (f,))).encode()
w('v.mha', mhead('LOCAL') + le); same.append('v.mha')
w('z.mha', mhead('LOCAL', True) + zlib.compress(le)); same.append('z.mha')
w('v.mhd', mhead('v.raw')); w('v.raw', le); same.append('v.mhd')
def inr(big):
    h = ('#INRIMAGE-4#{\nXDIM=%d\nYDIM=%d\nZDIM=%d\nVDIM=1\nTYPE=signed fixed\nPIXSIZE=16 bits\n'
         'SCALE=2**0\nCPU=%s\nVX=%g\nVY=%g\nVZ=%g\nXO=%g\nYO=%g\nZO=%g\n'
         % (n + ('sun' if big else 'decm',) + sp + org))
    return (h + '\n' * (256 - 4 - len(h)) + '##}\n').encode() + (be if big else le)
w('v.inr', inr(True)); same.append('v.inr')
w('v.inr.gz', gzip.compress(inr(False))); same.append('v.inr.gz')
def nifti(flip):
    return volume_files.nifti(d.astype('i2'), sp, org, flip)
w('v.nii', nifti(False)); other.append('v.nii')
w('flip.nii', nifti(True)); other.append('flip.nii')
w('v.nii.gz', gzip.compress(nifti(False))); other.append('v.nii.gz')
w('v.nii.bz2', bz2.compress(nifti(False))); other.append('v.nii.bz2')
raw = ', "dims": [%d, %d, %d], "sample": "%%s", "spacing": [%r, %r, %r], "origin": [%r, %r, %r]' % (n + sp + org)
w('le.bin', b'H' * 13 + le); same.append('le.bin' + (raw % 'i16') + ', "skip": 13')
w('be.bin', be); same.append('be.bin' + (raw % 'int16') + ', "big_endian": true')
def scene(f, extra=''):
    return '{"objects": [{"type": "volume", "file": "%s", "iso": 2000%s}]}\n' % (f, extra)
for name, lst in (('same', same), ('other', other)):
    with open(T + '/' + name, 'w') as o:
        for s in lst:
            f, _, extra = s.partition(',')
            open(T + '/s_' + f + '.json', 'w').write(scene(f, (', ' + extra) if extra else ''))
            o.write(f + '\n')
open(T + '/s_raw.nrrd.json', 'w').write(scene('raw.nrrd'))
# rays from 10 away from the centre, along the axes and diagonals, both ways
with open(T + '/rays.txt', 'w') as o:
    for dv in ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1), (1, 1, 1), (-1, 2, -0.5)):
        u = np.array(dv, float); u /= np.linalg.norm(u)
        p = np.array(c) - 10 * u
        o.write('%.17g %.17g %.17g %.17g %.17g %.17g\n' % (tuple(p) + tuple(u)))
# unknown spacing (NRRD nan): 1 with a warning
w('nan.nrrd', ('NRRD0004\ntype: short\ndimension: 3\nsizes: %d %d %d\nencoding: raw\nendian: little\n'
               'spacings: nan 1 1\n\n' % n).encode() + le)
open(T + '/s_nan.json', 'w').write(scene('nan.nrrd'))
# bad volumes
gzd = nrrd('gzip') + gzip.compress(be); w('cut_gz.nrrd', gzd[:len(gzd) - 60])
bzd = bytearray(nrrd('bzip2') + bz2.compress(be)); bzd[len(bzd) // 2] ^= 0x55; w('corrupt_bz.nrrd', bytes(bzd))
w('badhead.nrrd', b'NRRD0004\ntype: quaternion\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n' + b'\0' * 64)
w('short.mha', mhead('LOCAL') + le[:100])
w('cut.nii.gz', gzip.compress(nifti(False))[:500])
w('notvol.txt', b'hello, not a volume\n')
for f in ('cut_gz.nrrd', 'corrupt_bz.nrrd', 'badhead.nrrd', 'short.mha', 'cut.nii.gz', 'notvol.txt', 'missing.nrrd'):
    open(T + '/bad_' + f + '.json', 'w').write(scene(f))
open(T + '/centre', 'w').write('%.17g %.17g %.17g\n' % c)
np.save(T + '/d.npy', d)
# CT-like: dense inside, the same sphere at iso 3000
w('ct.nii', volume_files.nifti((5000 - d).astype('i2'), sp, org))
for name, extra in (('ct', ''), ('ct_above', ', "inside": "above"'), ('ct_below', ', "inside": "below"'),
                    ('ct_bad', ', "inside": "up"'), ('ct_num', ', "inside": 1')):
    open(T + '/s_' + name + '.json', 'w').write(
        '{"camera": {"eye": [%r, %r, %r], "center": [%r, %r, %r], "up": [0, 0, 1]},\n'
        ' "objects": [{"type": "volume", "name": "scan", "file": "ct.nii", "iso": 3000%s}]}\n'
        % ((c[0], c[1] - 10, c[2]) + c + (extra,)))
PYEOF

check_hits() { # geom-raycast output: 8 hits on the interpolant's iso 2000, near t = 8
    "$PY" - "$1" "$T/rays.txt" "$T/d.npy" <<'PYEOF'
import sys, numpy as np
rays = [[float(v) for v in l.split()] for l in open(sys.argv[2])]
lines = open(sys.argv[1]).read().split('\n')[:-1]
d = np.load(sys.argv[3])  # [z, y, x]
n = (24, 20, 16); sp = (0.5, 0.6, 0.75); org = (-3.0, 10.0, 100.0)
def trilinear(p):
    g = [(p[a] - org[a]) / sp[a] for a in range(3)]
    i = [min(int(np.floor(g[a])), n[a] - 2) for a in range(3)]
    f = [g[a] - i[a] for a in range(3)]
    v = 0.0
    for dz in (0, 1):
        for dy in (0, 1):
            for dx in (0, 1):
                w = (f[0] if dx else 1 - f[0]) * (f[1] if dy else 1 - f[1]) * (f[2] if dz else 1 - f[2])
                v += w * d[i[2] + dz, i[1] + dy, i[0] + dx]
    return v
assert len(lines) == len(rays), lines
for l, r in zip(lines, rays):
    h = [float(v) for v in l.split()]
    # the interpolant's sphere lies within sqrt(r^2 + |sp/2|^2) - r = 0.074 of the true one
    assert abs(h[0] - 8) <= 0.075, ('t', h[0], l)
    p = [r[k] + h[0] * r[3 + k] for k in range(3)]
    assert max(abs(p[k] - h[1 + k]) for k in range(3)) <= 1e-9, ('point', p, l)
    assert abs(trilinear(p) - 2000) <= 0.01, ('f at the hit', trilinear(p), l)
    dot = sum(h[4 + k] * r[3 + k] for k in range(3))
    assert dot < -0.99, ('normal', dot, l)
PYEOF
}

run_hits() { # SCENE OUT WHAT: geom-raycast SCENE, then check_hits on OUT
    "$TOOL" "$1" --rays "$T/rays.txt" >"$2" 2>"$T/err"
    local rc=$?
    checks=$((checks + 1))
    if [ $rc -ne 0 ]; then
        fail "$3: exit $rc: $(cat "$T/err")"
    else
        check_hits "$2" || fail "$3: hits or normals"
    fi
}
run_hits "$T/s_raw.nrrd.json" "$T/ref.out" "raw NRRD scene"
while read -r f; do
    checks=$((checks + 1))
    "$TOOL" "$T/s_$f.json" --rays "$T/rays.txt" >"$T/o.out" 2>"$T/err"
    rc=$?
    if [ $rc -ne 0 ]; then
        fail "$f in a scene: exit $rc: $(cat "$T/err")"
        continue
    fi
    check_hits "$T/o.out" || fail "$f in a scene: hits"
    if grep -qx "$f" "$T/same"; then
        checks=$((checks + 1))
        cmp -s "$T/o.out" "$T/ref.out" || fail "$f in a scene: output differs from the raw NRRD's"
    fi
done < <(cat "$T/same" "$T/other")

# unknown spacing: read as 1, warning naming the file
run "$T/s_nan.json" --rays "$T/rays.txt"
expect_rc 0 "nan spacing"
expect_err "geom-raycast: warning: $T/nan.nrrd: " "nan spacing"
expect_err "spacing unknown (nan), 1 used" "nan spacing"

# bad volume files: exit 1, message naming scene, object, key and file
for f in cut_gz.nrrd corrupt_bz.nrrd badhead.nrrd short.mha cut.nii.gz notvol.txt missing.nrrd; do
    run "$T/bad_$f.json" --rays "$T/rays.txt"
    expect_rc 1 "bad $f"
    checks=$((checks + 1))
    [[ $err == "geom-raycast: "*"bad_$f.json"*"objects[0]"*'"file": '*"$T/$f"* ]] ||
        fail "bad $f: message does not name the scene, object, key and file: $err"
    checks=$((checks + 1))
    [ "$(wc -l <"$T/stderr")" -le 2 ] || fail "bad $f: more than a message: $err"
done

# raw keys misused
bad_keys() { # JSON extra keys, expected message part
    printf '{"objects": [{"type": "volume", "file": "le.bin", "iso": 2000%s}]}\n' "$1" >"$T/k.json"
    run "$T/k.json" --rays "$T/rays.txt"
    expect_rc 1 "keys '$1'"
    expect_err "objects[0]" "keys '$1'"
    expect_err "$2" "keys '$1'"
}
bad_keys ', "dims": [24, 20, 16]' 'a raw volume needs both "dims" and "sample"'
bad_keys ', "sample": "i16"' 'a raw volume needs both "dims" and "sample"'
bad_keys ', "skip": 13' '"skip" applies to raw volumes'
bad_keys ', "dims": [24, 20, 16], "sample": "complex"' '"sample": unknown sample type "complex"'
bad_keys ', "dims": [24, 20.5, 16], "sample": "i16"' '"dims": element 1 is not an integer >= 1'
bad_keys ', "dims": [24, 20, 16], "sample": "i16", "skip": -1' '"skip": expected a byte count >= 0'
bad_keys ', "dims": [24, 20, 16], "sample": "i16", "spacing": [1, 0, 1]' '"spacing": expected numbers > 0'
bad_keys ', "dims": [24, 20, 16], "sample": "i16", "big_endian": 1' '"big_endian": expected true or false'
bad_keys ', "dims": [24, 20, 16], "sample": "i16"' 'le.bin: byte 15373: data has 15373 bytes but 24x20x16 i16 samples need 15360'

# CT-like volume: inside detected (above), outward normals, enter then leave
run_hits "$T/s_ct.json" "$T/ct.out" "CT scene (inside detected)"
"$TOOL" "$T/s_ct_above.json" --rays "$T/rays.txt" >"$T/ct_above.out" 2>"$T/err"
checks=$((checks + 1))
cmp -s "$T/ct.out" "$T/ct_above.out" || fail "CT scene: \"inside\": \"above\" differs from the detected side"
"$TOOL" "$T/s_ct_below.json" --rays "$T/rays.txt" >"$T/ct_below.out" 2>"$T/err"
pycheck "CT scene with \"inside\": \"below\": inward normals" "$T/ct_below.out" "$T/rays.txt" <<'PYEOF'
import sys
rays = [[float(v) for v in l.split()] for l in open(sys.argv[2])]
lines = open(sys.argv[1]).read().split('\n')[:-1]
assert len(lines) == len(rays), lines
for l, r in zip(lines, rays):
    h = [float(v) for v in l.split()]
    dot = sum(h[4 + k] * r[3 + k] for k in range(3))
    assert dot > 0.99, ('normal', dot, l)
print('ok')
PYEOF
for f in ct ct_below d; do
    scene=$T/s_$f.json
    [ "$f" = d ] && scene=$T/s_raw.nrrd.json
    "$TOOL" "$scene" --rays "$T/rays.txt" --all >"$T/all_$f.out" 2>"$T/err"
    pycheck "--all on $f: two hits, enter then leave (leave then enter when inside is wrong)" \
        "$T/all_$f.out" "$f" <<'PYEOF'
import sys
want = ['leave', 'enter'] if sys.argv[2] == 'ct_below' else ['enter', 'leave']
lines = open(sys.argv[1]).read().split('\n')[:-1]
assert len(lines) == 8, lines
for l in lines:
    w = l.split()
    assert len(w) == 4 and [w[1], w[3]] == want, l
    assert 7.9 < float(w[0]) < 8.1 and 11.9 < float(w[2]) < 12.1, l
print('ok')
PYEOF
done
for f in ct_bad ct_num; do
    run "$T/s_$f.json" --rays "$T/rays.txt"
    expect_rc 1 "$f"
    expect_err 'objects[0] ("scan"): "inside": expected' "$f"
done

# the CT scene exported by geom-scene and geom-iso's surface of the file:
# both outward (positive signed volume), the same volume within 2 %
if [ -n "$SCENE_TOOL" ] && [ -n "$ISO_TOOL" ]; then
    "$SCENE_TOOL" "$T/s_ct.json" --export "$T/ct_scene.obj" --tol 0.01 >"$T/so" 2>"$T/err" ||
        fail "geom-scene on the CT scene: $(cat "$T/err")"
    "$ISO_TOOL" --volume "$T/ct.nii" --iso 3000 -o "$T/ct_iso.obj" >"$T/so" 2>"$T/err" ||
        fail "geom-iso on the CT volume: $(cat "$T/err")"
    pycheck "CT: geom-scene export and geom-iso agree (outward, same volume)" \
        "$T/ct_scene.obj" "$T/ct_iso.obj" <<'PYEOF'
import sys
def signed_volume(path):
    v, vol = [], 0.0
    for l in open(path):
        w = l.split()
        if not w:
            continue
        if w[0] == 'v':
            v.append([float(x) for x in w[1:4]])
        elif w[0] == 'f':
            idx = [int(x.split('/')[0]) for x in w[1:]]
            idx = [i - 1 if i > 0 else len(v) + i for i in idx]
            a = v[idx[0]]
            for b, c in zip(idx[1:-1], idx[2:]):
                b, c = v[b], v[c]
                vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                        + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6
    return vol
vs, vi = signed_volume(sys.argv[1]), signed_volume(sys.argv[2])
sphere = 4 / 3 * 3.141592653589793 * 8
assert vs > 0 and vi > 0, (vs, vi)
assert abs(vs - vi) <= 0.02 * vi, (vs, vi)
assert abs(vi - sphere) <= 0.08 * sphere, (vi, sphere)  # the interpolant lies inside the sphere
print('ok')
PYEOF
fi

testlib_summary
