#!/usr/bin/env bash
# geom-render: an orthographic Lambertian sphere lit from the eye is kd*n_z
# at every interior pixel of the PFM (within 1e-3, ray; raster within 1e-3
# plus the shading turn its tessellation error allows); PNG
# output is a valid 8-bit sRGB PNG; AOVs; the report says what was built
# (an object behind the camera is not built, analytic shapes are never
# tessellated for ray, no refraction rays without glass); bad input fails
# with a message naming the file and the key; progress only on a terminal.
. "$(dirname "$0")/strict.sh" "$@"

cat > "$tmp/lambert.json" <<'JSON'
{"camera": {"eye": [0, 0, 5], "center": [0, 0, 0], "projection": "orthographic",
            "ortho_height": 2.2, "width": 81, "height": 81},
 "lights": [{"type": "directional", "direction": [0, 0, -1], "color": 1}],
 "materials": {"m": {"kd": [0.7, 0.5, 0.3], "ka": 0, "ks": 0}},
 "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"},
             {"type": "mesh", "file": "nowhere.obj", "name": "unused"}]}
JSON
# the mesh file does not exist: the parser must say so
if "$tool" "$tmp/lambert.json" -o "$tmp/x.pfm" 2> "$tmp/err"; then fail "missing mesh accepted"; fi
grep -q "nowhere.obj" "$tmp/err" || fail "missing mesh not named: $(cat "$tmp/err")"
sed -i 's/,\n *{"type": "mesh".*//' "$tmp/lambert.json"
$py - "$tmp/lambert.json" <<'PY'
import json, sys
p = sys.argv[1]
s = json.load(open(p))
s["objects"] = s["objects"][:1]
s["objects"].append({"type": "sphere", "center": [40, 0, 0], "radius": 1, "material": "m", "name": "aside"})
json.dump(s, open(p, "w"))
PY
for method in ray raster; do
  "$tool" "$tmp/lambert.json" -o "$tmp/l_$method.pfm" --method $method --pixel-error 0.02 --json > "$tmp/r_$method.json"
  $py - "$tmp/l_$method.pfm" "$tmp/r_$method.json" $method <<'PY'
import json, struct, sys, math
path, rep, method = sys.argv[1:4]
data = open(path, "rb").read()
parts = data.split(b"\n", 3)
assert parts[0] == b"PF", parts[0]
w, h = map(int, parts[1].split())
scale = float(parts[2])
assert scale < 0
px = struct.unpack("<%df" % (w * h * 3), parts[3][: w * h * 12])
r = json.load(open(rep))
objs = r["objects"]
# Raster shades a tessellation: at a pixel whose sphere normal has z
# component nz the flat triangle lies up to err/nz below the sphere along
# the view ray (err: the tessellation's reported distance to the mesh), and
# the interpolated unit normal (vertex normals p/R) points at that flat
# point, so it turns by up to err * sqrt(1 - nz^2) / nz / R radians and
# kd * n_z changes by at most kd times that. 1e-3 covers the rest (float
# PFM, 1/256-pixel vertex snapping); ray tracing hits the analytic sphere.
err = objs[0]["tessellation"]["error"]["max"] if method == "raster" else 0.0
worst = 0.0
n = 0
for j in range(h):            # PFM rows are bottom to top
    y = -1.1 + 2.2 * (j + 0.5) / h
    for i in range(w):
        x = -1.1 + 2.2 * (i + 0.5) / w
        r2 = x * x + y * y
        if r2 > 0.9:
            continue
        nz = math.sqrt(1 - r2)
        k = 3 * (j * w + i)
        turn = err * math.sqrt(r2) / nz
        worst = max(worst, abs(px[k] - 0.7 * nz) - 0.7 * turn, abs(px[k + 2] - 0.3 * nz) - 0.3 * turn)
        n += 1
assert n > 3000, n
tol = 1e-3
if worst > tol:
    sys.exit("%s: Lambert sphere off by %g beyond the tessellation's share" % (method, worst))
assert objs[0]["visible"] and objs[0]["built"], objs[0]
assert not objs[1]["visible"] and not objs[1]["built"], objs[1]
if method == "ray":
    assert not objs[0]["tessellated"] and not objs[0]["acceleration"]
    assert r["rays"]["refraction"] == 0 and r["rays"]["reflection"] == 0
    assert r["rays"]["primary"] == 81 * 81
else:
    assert objs[0]["tessellated"] and objs[0]["tessellation"]["error"]["max"] <= objs[0]["tolerance"]
    assert not objs[0]["uvs"] and not objs[0]["tangents"]
print(method, "max error", worst)
PY
done

# PNG: signature, 8-bit RGB, sRGB chunk, size
"$tool" "$data/scenes/spheres.json" -o "$tmp/s.png" > "$tmp/report.txt"
grep -q "behind the camera (sphere): not visible" "$tmp/report.txt" || fail "report: $(cat "$tmp/report.txt")"
$py - "$tmp/s.png" <<'PY'
import sys, struct
d = open(sys.argv[1], "rb").read()
assert d[:8] == b"\x89PNG\r\n\x1a\n"
w, h, depth, ctype = struct.unpack(">IIBB", d[16:26])
assert (w, h, depth, ctype) == (320, 240, 8, 2), (w, h, depth, ctype)
assert b"sRGB" in d
PY
for aov in depth normal object; do
  "$tool" "$data/scenes/spheres.json" -o "$tmp/a_$aov.pfm" --aov $aov > /dev/null
  "$tool" "$data/scenes/spheres.json" -o "$tmp/a_$aov.png" --aov $aov --method raster > /dev/null
done
head -c 2 "$tmp/a_depth.pfm" | grep -q "Pf" || fail "depth AOV is not a 1-channel PFM"
head -c 2 "$tmp/a_normal.pfm" | grep -q "PF" || fail "normal AOV is not a 3-channel PFM"

# progress: nothing on stderr when it is not a terminal; on a terminal
# (script(1) gives one) percent and ETA (GEOM_PROGRESS_AFTER=0: from the
# start, whatever the machine's speed), and nothing with --quiet
"$tool" "$data/scenes/spheres.json" -o "$tmp/p.png" > /dev/null 2> "$tmp/err"
[ ! -s "$tmp/err" ] || fail "progress printed to a non-terminal: $(cat "$tmp/err")"
if command -v script > /dev/null; then
  big="$tmp/big.json"
  $py - "$data/scenes/spheres.json" "$big" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["camera"]["width"], s["camera"]["height"], s["camera"]["samples"] = 400, 300, 9
json.dump(s, open(sys.argv[2], "w"))
PY
  GEOM_PROGRESS_AFTER=0 script -qec "'$tool' '$big' -o '$tmp/p.png' > /dev/null" /dev/null > "$tmp/tty" 2>&1 || fail "render under a terminal failed"
  grep -q "rendering.*%.*ETA" "$tmp/tty" || fail "no progress on a terminal: $(head -c 300 "$tmp/tty")"
  GEOM_PROGRESS_AFTER=0 script -qec "'$tool' '$big' -o '$tmp/p.png' --quiet > /dev/null" /dev/null > "$tmp/tty" 2>&1 || fail "quiet render failed"
  ! grep -q "%" "$tmp/tty" || fail "--quiet still shows progress"
fi

# bad input
echo '{"camera": {"eye": [0,0,1], "center": [0,0,1]}, "objects": []}' > "$tmp/bad1.json"
if "$tool" "$tmp/bad1.json" -o "$tmp/x.png" 2> "$tmp/err"; then fail "degenerate camera accepted"; fi
grep -q "camera" "$tmp/err" || fail "camera error not named: $(cat "$tmp/err")"
echo '{"camera": {"eye": [0,0,5]}, "materials": {"g": {"ior": "x"}}, "objects": []}' > "$tmp/bad2.json"
if "$tool" "$tmp/bad2.json" -o "$tmp/x.png" 2> "$tmp/err"; then fail "bad ior accepted"; fi
grep -q "materials.g.ior" "$tmp/err" || fail "ior error not named: $(cat "$tmp/err")"
echo '{"camera": {"eye": [0,0,5]}, "objects": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "nope"}]}' > "$tmp/bad3.json"
if "$tool" "$tmp/bad3.json" -o "$tmp/x.png" 2> "$tmp/err"; then fail "unknown material accepted"; fi
grep -q "nope" "$tmp/err" || fail "material error not named: $(cat "$tmp/err")"
printf '{"camera": {"eye": [0,0,5]},\n "objects": [}' > "$tmp/bad4.json"
if "$tool" "$tmp/bad4.json" -o "$tmp/x.png" 2> "$tmp/err"; then fail "syntax error accepted"; fi
grep -q "bad4.json:2" "$tmp/err" || fail "syntax error line: $(cat "$tmp/err")"
if "$tool" "$data/scenes/spheres.json" -o "$tmp/x.jpg" 2> /dev/null; then fail ".jpg accepted"; fi
[ ! -e "$tmp/x.png" ] || fail "a failed run left an output"
echo ok
