"""geom.scene textures, textured materials, displacement and the rasterizer
over caller-made draws, against closed forms: bilinear reproduction of
linear texel data, MIP levels and the box-filtered mean, wrap modes;
coverage, depth, object ids and Lambert colours of flat triangles under an
orthographic camera computed with edge functions in numpy; a constant
texture equal to the same colour folded into kd and ka (ray and raster);
displacement of a plane by a linear height map."""
import numpy as np
import pytest

import geom

pytestmark = pytest.mark.skipif(not geom.has_module("scene"), reason="scene module not built")

scene = geom.scene if geom.has_module("scene") else None


def linear_image(w, h, coef):
    """(h, w, c) texels whose value is a + b u + c v at the texel centres,
    coef (c, 3) rows (a, b, c) per channel."""
    x, y = np.meshgrid(np.arange(w), np.arange(h))
    u = (x + 0.5) / w
    v = 1 - (y + 0.5) / h
    return np.stack([a + b * u + c * v for a, b, c in coef], axis=-1)


# ----------------------------------------------------------------- textures

def test_texture_is_bilinear_and_exact_on_linear_data():
    rng = np.random.default_rng(3)
    w, h = 16, 8
    coef = rng.uniform(-2, 2, (4, 3))
    t = scene.Texture(linear_image(w, h, coef))
    assert t.channels == 4 and t.size == (16, 8) and t.levels == 5
    for _ in range(200):
        u = rng.uniform(0.5 / w, 1 - 0.5 / w)
        v = rng.uniform(0.5 / h, 1 - 0.5 / h)
        want = coef[:, 0] + coef[:, 1] * u + coef[:, 2] * v
        np.testing.assert_allclose(t.sample(u, v), want, rtol=0, atol=1e-12)
        du, dv = t.gradient(u, v)
        assert abs(du - coef[0, 1]) < 1e-9 and abs(dv - coef[0, 2]) < 1e-9


def test_texel_centres_and_orientation():
    img = np.arange(12.0).reshape(3, 4)         # row 0 is the TOP row
    t = scene.Texture(img)
    for y in range(3):
        for x in range(4):
            s = t.sample((x + 0.5) / 4, 1 - (y + 0.5) / 3)
            assert s.shape == (1,) and abs(s[0] - img[y, x]) < 1e-12
    assert t.sample(np.nan, 0.3)[0] == img[0, 0]      # non-finite: texel (0, 0) of level 0
    assert t.sample(0.3, np.inf)[0] == img[0, 0]


@pytest.mark.parametrize("w,h,levels", [(1, 1, 1), (2, 1, 2), (5, 3, 3), (8, 4, 4), (7, 9, 4)])
def test_mip_level_count(w, h, levels):
    t = scene.Texture(np.ones((h, w, 3)))
    assert t.levels == levels and t.size == (w, h) and t.channels == 3


def test_large_footprint_gives_the_mean_of_a_power_of_two_image():
    rng = np.random.default_rng(5)
    img = rng.uniform(0, 1, (4, 8, 2))
    t = scene.Texture(img)
    for u, v in ((0.1, 0.2), (0.77, 0.5)):
        np.testing.assert_allclose(t.sample(u, v, footprint=1e3), img.mean(axis=(0, 1)),
                                   rtol=0, atol=1e-14)
    # footprint of one texel at level 0 (lod 0): still bilinear on level 0
    np.testing.assert_allclose(t.sample(0.3125, 0.375, footprint=1 / 8),
                               t.sample(0.3125, 0.375), atol=1e-14)


def test_wrap_modes():
    rng = np.random.default_rng(7)
    img = rng.uniform(0, 1, (4, 8))
    rep = scene.Texture(img, wrap="repeat")
    cl = scene.Texture(img, wrap="clamp")
    for u, v in ((0.3125, 0.375), (0.015625, 0.96875), (0.5, 0.5)):
        np.testing.assert_allclose(rep.sample(u + 1, v), rep.sample(u, v), atol=1e-14)
        np.testing.assert_allclose(rep.sample(u - 2, v + 3), rep.sample(u, v), atol=1e-14)
    # clamp: beyond the left edge the first column, beyond the top the first row
    assert cl.sample(-5.0, 1 - 0.5 / 4)[0] == img[0, 0]
    assert cl.sample(7.0, 1 - 2.5 / 4)[0] == img[2, 7]
    assert cl.sample((3 + 0.5) / 8, 9.0)[0] == img[0, 3]
    # repeat blends the last and the first column at u = 0
    assert abs(rep.sample(0.0, 1 - 0.5 / 4)[0] - 0.5 * (img[0, 0] + img[0, 7])) < 1e-15


def test_texture_bad_input():
    with pytest.raises(geom.GeomError) as e:
        scene.Texture(np.array([[0.0, np.nan]]))
    assert e.value.code == "ERR_INVALID_ARG"
    with pytest.raises(geom.GeomError):
        scene.Texture(np.array([[0.0, np.inf]]))
    with pytest.raises(ValueError):
        scene.Texture(np.zeros((2, 2, 5)))
    with pytest.raises(ValueError):
        scene.Texture(np.zeros((0, 4)))
    with pytest.raises(ValueError):
        scene.Texture(np.zeros(4))
    with pytest.raises(ValueError):
        scene.Texture(np.zeros((2, 2)), wrap="mirror")
    with pytest.raises(ValueError):
        scene.material_needs({"bump": np.zeros((2, 2))})   # a texture must be a Texture


def test_material_needs():
    t = scene.Texture(np.ones((2, 2)))
    assert "uv" not in scene.material_needs({})
    assert "uv" in scene.material_needs({"texture": t})
    assert {"uv", "tangent"} <= scene.material_needs({"normal_map": t})
    assert {"uv", "tangent"} <= scene.material_needs({"bump": t, "bump_scale": 2})
    assert "uv" in scene.material_needs({"displace": t})
    assert "reflection" in scene.material_needs({"reflect": 0.5})
    assert "refraction" in scene.material_needs({"transmit": 0.5, "ior": 1.5})
    assert not {"reflection", "refraction"} & scene.material_needs({"kd": 0.3})


def test_camera_resolved_defaults():
    c = scene.camera_resolved(scene.camera((0, 0, 5), (0, 0, 0), width=0, height=0, fovy=0))
    assert (c.width, c.height, c.fovy_degrees, c.samples) == (320, 240, 45.0, 1)


# ------------------------------------------------- textured scene rendering

def _sphere_scene():
    rs = geom.RayScene()
    rs.add_sphere([0, 0, 0], 1)
    rs.add_box([-3, -3, -2], [3, 3, -1.5])
    rs.build()
    return rs


@pytest.mark.parametrize("method", ["ray", "raster"])
def test_constant_texture_equals_the_colour_in_kd_and_ka(method):
    rs = _sphere_scene()
    sh = scene.Shapes(rs)
    cam = scene.camera([0.5, 1, 8], [0, 0, 0], width=48, height=36, fovy=35)
    c = np.array([0.5, 0.25, 1.0])
    tex = scene.Texture(np.broadcast_to(c, (3, 5, 3)))
    lights = ({"kind": "directional", "direction": (-0.3, -0.2, -1)},
              {"kind": "ambient", "color": 0.7})
    textured = [{"kd": (0.6, 0.7, 0.8), "texture": tex}, {"kd": 0.4}]
    folded = [{"kd": np.array([0.6, 0.7, 0.8]) * c, "ka": 0.1 * c}, {"kd": 0.4}]
    a, ra = scene.render(sh, cam, lights=lights, materials=textured, object_material=[0, 1],
                         method=method)
    b, rb = scene.render(sh, cam, lights=lights, materials=folded, object_material=[0, 1],
                         method=method)
    assert a.shape == (36, 48, 3) and a.max() > 0.2
    if method == "ray":
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
        t, _ = scene.trace(rs, cam, lights=lights, materials=textured, object_material=[0, 1])
        np.testing.assert_allclose(t, b, rtol=0, atol=1e-12)
    else:
        # the textured sphere is tessellated with UVs, the folded one without:
        # the same triangles, so the same pixels up to rounding
        assert ra["objects"][0]["uvs"] and not rb["objects"][0]["uvs"]
        assert np.mean(np.abs(a - b) < 1e-9) > 0.99
        assert np.abs(a - b).max() < 0.05


def test_texture_must_outlive_nothing_after_the_call():
    """The materials array borrows the textures only during the call."""
    rs = _sphere_scene()
    sh = scene.Shapes(rs)
    cam = scene.camera([0, 0, 8], [0, 0, 0], width=16, height=12)
    img1, _ = scene.render(sh, cam, materials=[{"texture": scene.Texture(np.full((2, 2), 0.5))}])
    import gc
    gc.collect()
    img2, _ = scene.render(sh, cam, materials=[{"kd": 0.4, "ka": 0.05}])
    np.testing.assert_allclose(img1, img2, atol=1e-12)


# ------------------------------------------------------------- displacement

def plane_grid(n, lo, hi):
    s = np.linspace(lo, hi, n)
    x, y = np.meshgrid(s, s)
    pts = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            faces.append([a, a + 1, a + n + 1, a + n])
    return pts, np.array(faces)


def test_displace_plane_by_a_linear_height_map():
    a, b, c, scale = 0.2, 0.5, -0.25, 0.4
    tex = scene.Texture(linear_image(8, 8, [(a, b, c)]), wrap="clamp")
    pts, faces = plane_grid(9, 0.25, 0.75)       # inside the texel centres' square
    m = geom.Mesh.from_soup(pts, faces)
    m.set_channel("uv", pts[:, :2])
    scene.displace(m, tex, scale)
    p = m.positions
    np.testing.assert_allclose(p[:, :2], pts[:, :2], atol=1e-15)   # moved along +z only
    np.testing.assert_allclose(p[:, 2], scale * (a + b * pts[:, 0] + c * pts[:, 1]),
                               rtol=0, atol=1e-12)
    want = np.array([-scale * b, -scale * c, 1.0])
    want /= np.linalg.norm(want)
    if m.has_channel("normal"):
        np.testing.assert_allclose(m.channel("normal"), np.broadcast_to(want, p.shape), atol=1e-12)
    np.testing.assert_allclose(m.vertex_normals(), np.broadcast_to(want, p.shape), atol=1e-12)


def test_displace_needs_uvs():
    pts, faces = plane_grid(3, 0, 1)
    m = geom.Mesh.from_soup(pts, faces)
    with pytest.raises(geom.GeomError) as e:
        scene.displace(m, scene.Texture(np.ones((2, 2))), 1.0)
    assert e.value.code == "ERR_INVALID_ARG"
    with pytest.raises(ValueError):
        scene.displace(m, np.ones((2, 2)))


# ---------------------------------------------------------------- raster

W, H, OH = 40, 30, 3.0       # orthographic: 0.1 world units per pixel


def ortho_camera(samples=1):
    return scene.camera([0, 0, 5], [0, 0, 0], width=W, height=H, orthographic=True,
                        ortho_height=OH, samples=samples)


def pixel_centres():
    j, i = np.mgrid[0:H, 0:W]
    s = OH / H
    return (i + 0.5 - W / 2) * s, (H / 2 - (j + 0.5)) * s


SNAP = OH / H / 256          # the rasterizer snaps vertices to 1/256 pixel


def inside_triangle(tri, x, y):
    """Edge functions at the pixel centres; also the smallest distance of a
    centre to an edge's line (coverage is compared only where it exceeds
    the vertex snapping)."""
    e = []
    for k in range(3):
        (x0, y0), (x1, y1) = tri[k, :2], tri[(k + 1) % 3, :2]
        e.append(((x1 - x0) * (y - y0) - (y1 - y0) * (x - x0)) / np.hypot(x1 - x0, y1 - y0))
    e = np.array(e)
    inside = np.all(e > 0, axis=0) | np.all(e < 0, axis=0)
    return inside, np.abs(e).min()


# vertices chosen so that every pixel centre is at least 0.005 (13 snapping
# steps) from the edges' lines, here and shifted by (0.3, -0.1)
TRI = np.array([[-1.216, -0.905, 0.0], [1.107, -0.91, 0.0], [0.056, 1.213, 0.0]])


def test_raster_coverage_depth_and_object_ids():
    m = geom.Mesh.from_soup(TRI, [[0, 1, 2]])
    shift = np.array([0.3, -0.1, 0.5])
    T = geom.core.translate(shift)
    draw = {"mesh": m, "transform": T, "object_id": 7}
    x, y = pixel_centres()
    inside, margin = inside_triangle(TRI + shift, x, y)
    assert margin > 2 * SNAP and 50 < inside.sum() < W * H
    obj, rep = scene.raster([draw], ortho_camera(), aov="object")
    assert obj.shape == (H, W, 1)
    np.testing.assert_array_equal(obj[:, :, 0], np.where(inside, 7, -1))
    assert rep["triangles_in"] == 1 and rep["fragments"] == inside.sum()
    depth, _ = scene.raster([draw], ortho_camera(), aov="depth")
    assert np.all(np.abs(depth[:, :, 0][inside] - 4.5) < 1e-12)    # view distance 5 - 0.5
    assert np.all(np.isinf(depth[:, :, 0][~inside]))
    nrm, _ = scene.raster([draw], ortho_camera(), aov="normal",
                          materials=[{"shading": "flat"}])
    np.testing.assert_allclose(np.abs(nrm[inside]), np.broadcast_to([0, 0, 1], (inside.sum(), 3)),
                               atol=1e-12)
    assert np.all(nrm[~inside] == 0)


def test_raster_nearer_draw_wins_and_draws_default_ids():
    far = geom.Mesh.from_soup(TRI, [[0, 1, 2]])
    small = np.array([[-0.934, -0.696, 0.0], [0.971, -0.709, 0.0], [0.015, 0.723, 0.0]])
    near = geom.Mesh.from_soup(small, [[0, 1, 2]])
    x, y = pixel_centres()
    in_far, m1 = inside_triangle(TRI, x, y)
    in_near, m2 = inside_triangle(small, x, y)
    assert min(m1, m2) > 2 * SNAP
    obj, _ = scene.raster([far, {"mesh": near, "transform": geom.core.translate([0, 0, 1])}],
                          ortho_camera(), aov="object")
    want = np.where(in_near, 1, np.where(in_far, 0, -1))
    np.testing.assert_array_equal(obj[:, :, 0], want)


def test_raster_lambert_and_textured_colour():
    kd = np.array([0.2, 0.4, 0.6])
    lights = ({"kind": "directional", "direction": (0, 0, -1)}, {"kind": "ambient", "color": 0.5})
    m = geom.Mesh.from_soup(TRI, [[0, 1, 2]])
    x, y = pixel_centres()
    inside, _ = inside_triangle(TRI, x, y)
    img, _ = scene.raster([m], ortho_camera(), lights=lights,
                          materials=[{"kd": kd, "shading": "flat"}], background=(0.1, 0.2, 0.3))
    # ambient ka * 0.5 plus Lambert kd * (n . l) with n . l = 1 (two-sided)
    np.testing.assert_allclose(img[inside], np.broadcast_to(0.05 + kd, (inside.sum(), 3)),
                               atol=1e-12)
    np.testing.assert_allclose(img[~inside], np.broadcast_to([0.1, 0.2, 0.3],
                                                             ((~inside).sum(), 3)), atol=0)
    c = np.array([0.5, 0.25, 1.0])
    m.set_channel("uv", TRI[:, :2] * 0.3 + 0.5)
    tex = scene.Texture(np.broadcast_to(c, (4, 4, 3)))
    img2, _ = scene.raster([m], ortho_camera(), lights=lights,
                           materials=[{"kd": kd, "shading": "flat", "texture": tex}])
    np.testing.assert_allclose(img2[inside], np.broadcast_to((0.05 + kd) * c, (inside.sum(), 3)),
                               atol=1e-12)


def test_raster_textured_ramp_follows_the_uvs():
    """A linear texture mapped by uv = affine(x, y): each covered pixel's
    colour (flat light, kd 1, no ambient) is the ramp at its centre's uv."""
    coef = [(0.1, 0.6, 0.2)]
    tex = scene.Texture(linear_image(64, 64, coef))
    m = geom.Mesh.from_soup(TRI, [[0, 1, 2]])
    uv = TRI[:, :2] * 0.3 + 0.5                    # inside the texel centres' square
    m.set_channel("uv", uv)
    x, y = pixel_centres()
    inside, _ = inside_triangle(TRI, x, y)
    img, _ = scene.raster([m], ortho_camera(), lights=({"kind": "directional",
                                                         "direction": (0, 0, -1)},),
                          materials=[{"kd": 1.0, "ka": 0.0, "texture": tex,
                                      "shading": "flat"}])
    u, v = x * 0.3 + 0.5, y * 0.3 + 0.5
    want = 0.1 + 0.6 * u + 0.2 * v
    # the pixel footprint (0.03 UV units, about 2 texels) selects a MIP level
    # between 0 and 1: a box-filtered linear ramp stays the same ramp except
    # near the image border, which these uvs stay away from. The vertices are
    # snapped to 1/256 pixel (at most SNAP/2 per coordinate), which moves the
    # interpolated uv by at most 0.3 * SNAP/2 * sqrt(2) and the ramp by
    # (0.6 + 0.2) times that
    bound = 0.8 * 0.3 * SNAP / 2 * np.sqrt(2) + 1e-12
    err = np.abs(img[:, :, 0][inside] - want[inside])
    assert err.max() <= bound, (err.max(), bound)


def test_raster_bad_input():
    m = geom.Mesh.from_soup(TRI, [[0, 1, 2]])
    with pytest.raises(geom.GeomError) as e:
        scene.raster([{"mesh": m, "material": 3}], ortho_camera())
    assert e.value.code == "ERR_INVALID_ARG"
    bad = geom.Mesh.from_soup(TRI, [[0, 1, 2]])
    p = bad.positions
    p[0, 0] = np.nan
    bad.positions = p
    with pytest.raises(geom.GeomError) as e:
        scene.raster([bad], ortho_camera())
    assert e.value.code == "ERR_INVALID_ARG"
    with pytest.raises(geom.GeomError) as e:
        scene.raster([m], scene.camera([0, 0, 0], [0, 0, 0]))
    assert e.value.code == "ERR_DEGENERATE"
    with pytest.raises(ValueError):
        scene.raster([TRI], ortho_camera())
    with pytest.raises(ValueError):
        scene.raster([{"mesh": m, "colour": 1}], ortho_camera())
    with pytest.raises(ValueError):
        scene.raster([m], ortho_camera(), aov="albedo")
    # no draws: the background
    img, rep = scene.raster([], ortho_camera(), background=0.25)
    assert np.all(img == 0.25) and rep["triangles_in"] == 0


def test_raster_supersampling_and_shadow_maps():
    m = geom.Mesh.from_soup(TRI, [[0, 1, 2]])
    x, y = pixel_centres()
    inside, _ = inside_triangle(TRI, x, y)
    one, r1 = scene.raster([m], ortho_camera(1), materials=[{"kd": 0.8, "shading": "flat"}])
    four, r4 = scene.raster([m], ortho_camera(4), materials=[{"kd": 0.8, "shading": "flat"}])
    assert r1["samples_per_pixel"] == 1 and r4["samples_per_pixel"] == 4
    # box filter of 2 x 2 samples: pixels far from the edges keep their colour
    # (0.8 inside, 0 outside), edge pixels get 0.8 times the covered quarter
    s = OH / H

    def far_from_edges(tri, d):
        e = []
        for k in range(3):
            (x0, y0), (x1, y1) = tri[k, :2], tri[(k + 1) % 3, :2]
            e.append(np.abs((x1 - x0) * (y - y0) - (y1 - y0) * (x - x0)) / np.hypot(x1 - x0, y1 - y0))
        return np.min(e, axis=0) > d
    away = far_from_edges(TRI, s)
    np.testing.assert_array_equal(four[:, :, 0][away], one[:, :, 0][away])
    edge = ~away
    quarters = four[:, :, 0] / 0.2
    np.testing.assert_allclose(quarters, np.round(quarters), atol=1e-9)
    assert np.any((four[:, :, 0][edge] > 0.1) & (four[:, :, 0][edge] < 0.7))

    # shadow maps: a small triangle at height 2 over a large ground triangle,
    # light travelling along (1, 0, -1): the shadow is the small triangle moved by +2 in x
    ground = np.array([[-3.0, -2.5, 0.0], [3.0, -2.5, 0.0], [0.0, 3.0, 0.0]])
    small = TRI * 0.6 + [-1.5, 0, 2]
    draws = [geom.Mesh.from_soup(ground, [[0, 1, 2]]), geom.Mesh.from_soup(small, [[0, 1, 2]])]
    lights = ({"kind": "directional", "direction": (1, 0, -1)}, {"kind": "ambient", "color": 1.0})
    mats = [{"kd": 1.0, "ka": 0.1, "shading": "flat"}]
    lit, rep = scene.raster(draws, ortho_camera(), lights=lights, materials=mats, shadows=True)
    assert rep["shadow_maps"] >= 1
    on_ground = inside_triangle(ground, x, y)[0] & ~inside_triangle(small, x, y)[0]
    shadow = inside_triangle(small + [2, 0, -2], x, y)[0]
    d = 1.5 * s                                          # 1.5 pixels from every edge
    sure_shadow = on_ground & shadow & far_from_edges(small + [2, 0, -2], d) & \
        far_from_edges(small, d)
    sure_lit = on_ground & ~shadow & far_from_edges(small + [2, 0, -2], d) & \
        far_from_edges(ground, d)
    assert sure_shadow.sum() > 20 and sure_lit.sum() > 100
    np.testing.assert_allclose(lit[sure_shadow], 0.1, atol=1e-12)          # ambient only
    np.testing.assert_allclose(lit[sure_lit], 0.1 + np.sqrt(0.5), atol=1e-12)
    plain, _ = scene.raster(draws, ortho_camera(), lights=lights, materials=mats)
    np.testing.assert_allclose(plain[sure_shadow], 0.1 + np.sqrt(0.5), atol=1e-12)


def test_export_makes_uvs_and_tangents_for_textured_materials():
    sh = scene.Shapes(_sphere_scene())
    t = scene.Texture(np.ones((2, 2)))
    plain, reps = scene.export(sh, tolerance=1e-2)
    assert not plain.has_channel("uv", "corner") and all(r["attributes"] & 1 == 0 for r in reps)
    tex, reps = scene.export(sh, tolerance=1e-2, materials=[{"texture": t}, {}],
                             object_material=[0, 1])
    assert tex.has_channel("uv", "corner") and not tex.has_channel("tangent", "corner")
    assert reps[0]["attributes"] & 1 and not reps[1]["attributes"] & 1
    nm, reps = scene.export(sh, tolerance=1e-2, materials=[{"normal_map": t}])
    assert nm.has_channel("uv", "corner") and nm.has_channel("tangent", "corner")
    assert reps[0]["attributes"] & 2


@pytest.mark.parametrize("wrap", ["repeat", "clamp"])
def test_texture_sample_many_bitwise_single_calls(wrap):
    """Texture.sample / gradient over arrays (geom_scene_texture_sample_many)
    give bitwise the single-point C functions, for points inside, on texel
    centres and edges, outside [0, 1], NaN/Inf, with per-point and shared
    footprints (level 0, between levels, beyond the last level)."""
    from geom._ffi import ffi, lib
    rng = np.random.default_rng(9)
    img = rng.uniform(-1, 1, (13, 10, 3))
    t = scene.Texture(img, wrap=wrap)
    n = 500
    u = rng.uniform(-1.5, 2.5, n)
    v = rng.uniform(-1.5, 2.5, n)
    u[:10], v[:10] = (np.arange(10) + 0.5) / 10, 1 - (np.arange(10) + 0.5) / 13
    u[10:14] = [0.0, 1.0, np.nan, np.inf]
    v[14:17] = [-np.inf, 0.0, 1.0]
    fp = rng.choice([0.0, -1.0, 0.01, 0.07, 0.3, 5.0], n)
    got = t.sample(u, v, fp)
    got_shared = t.sample(u, v, 0.07)
    gu, gv = t.gradient(u, v)
    assert got.shape == (n, 3) and gu.shape == (n,)
    out = ffi.new("double[4]")
    du, dv = ffi.new("double *"), ffi.new("double *")
    for i in range(n):
        lib.geom_scene_texture_sample(t._ptr, u[i], v[i], fp[i], out)
        assert np.array_equal(np.frombuffer(ffi.buffer(out, 24)).view(np.uint64),
                              got[i].view(np.uint64)), i
        lib.geom_scene_texture_sample(t._ptr, u[i], v[i], 0.07, out)
        assert np.array_equal(np.frombuffer(ffi.buffer(out, 24)), got_shared[i]), i
        lib.geom_scene_texture_gradient(t._ptr, u[i], v[i], du, dv)
        assert (du[0], dv[0]) == (gu[i], gv[i]), i
    # texel centres on level 0 give the texels (up to the rounding of the centres)
    c0 = fp[:10] <= 0
    assert c0.any()
    assert np.allclose(got[:10][c0], img[np.arange(10), np.arange(10)][c0], rtol=0, atol=1e-12)
    # scalars keep their old shapes; a bad footprint count is refused
    assert t.sample(0.3, 0.6).shape == (3,)
    assert isinstance(t.gradient(0.3, 0.6)[0], float)
    with pytest.raises(ValueError):
        t.sample(u, v, fp[:3])
