"""geom.Output / write_file (geom_output_*): atomic replacement keeping the
mode, abandon on an exception, write-through to a device, refusals; the
progress callbacks of tessellate and marching_cubes (fractions rising to 1,
an exception raised after the call); the render options' layout."""

import os
import stat

import numpy as np
import pytest

import geom
from geom._ffi import ffi


def test_write_file_replaces_atomically_and_keeps_mode(tmp_path):
    p = tmp_path / "out.txt"
    p.write_bytes(b"old")
    os.chmod(p, 0o640)
    with geom.Output(str(p)) as f:
        assert f.temporary and f.temporary.endswith(".geomtmp")
        assert os.path.exists(f.temporary)
        f.write(b"new ")
        f.write(np.arange(3, dtype=np.uint8))
        assert p.read_bytes() == b"old"          # not replaced before the commit
    assert p.read_bytes() == b"new \x00\x01\x02"
    assert stat.S_IMODE(os.stat(p).st_mode) == 0o640
    geom.write_file(str(tmp_path / "new.bin"), b"x" * 10)
    assert (tmp_path / "new.bin").read_bytes() == b"x" * 10
    assert sorted(os.listdir(tmp_path)) == ["new.bin", "out.txt"]


def test_output_abandoned_on_exception(tmp_path):
    p = tmp_path / "keep.txt"
    p.write_bytes(b"precious")
    with pytest.raises(RuntimeError):
        with geom.Output(str(p)) as f:
            f.write(b"half")
            raise RuntimeError("interrupted")
    assert p.read_bytes() == b"precious"
    assert os.listdir(tmp_path) == ["keep.txt"]  # no temporary left


def test_output_devices_and_refusals(tmp_path):
    with geom.Output("/dev/null") as f:      # written through, never replaced
        assert f.temporary is None
        f.write(b"abc")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    with pytest.raises(geom.GeomError) as info:
        geom.Output(str(tmp_path))             # a directory
    assert info.value.code == "ERR_IO" and str(tmp_path) in str(info.value)
    with pytest.raises(ValueError):
        geom.Output(str(tmp_path / "a\0b"))
    if os.path.exists("/dev/full"):
        with pytest.raises(geom.GeomError) as info:
            with geom.Output("/dev/full") as f:
                f.write(b"x" * 100000)
        assert info.value.code == "ERR_IO"
    f = geom.Output(str(tmp_path / "x"))
    f.commit()
    with pytest.raises(geom.GeomError):
        f.write(b"closed")
    f.abort()                                  # a no-op once closed


def test_progress_callbacks():
    seen = []
    mesh, _ = geom.marching_cubes("x*x + y*y + z*z - 1", bounds=(-1.5,) * 3 + (1.5,) * 3,
                                  resolution=(24, 24, 24), progress=seen.append)
    assert seen and seen[-1] == 1.0 and all(0 < f <= 1 for f in seen)
    assert all(a <= b for a, b in zip(seen, seen[1:]))
    mesh.close()

    def boom(fraction):
        raise KeyError("stop")

    with pytest.raises(KeyError):
        geom.marching_cubes("x*x + y*y + z*z - 1", bounds=(-1.5,) * 3 + (1.5,) * 3,
                            resolution=(8, 8, 8), progress=boom)
    s = geom.surface.NurbsSurface(3, 3, [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1],
                                  np.random.default_rng(4).uniform(0, 1, (4, 4, 3)))
    seen = []
    mesh, _ = geom.tessellate(s, tolerance=1e-3, progress=seen.append)
    assert seen and max(seen) == 1.0 and all(0 < f <= 1 for f in seen)
    mesh.close()
    with pytest.raises(KeyError):
        geom.tessellate(s, tolerance=1e-3, progress=boom)


def test_render_options_layout():
    """The struct fields are declared as in scene.h (test_abi compares the
    text); the progress field takes a callback."""
    for name in ("geom_render_options", "geom_trace_options"):
        o = ffi.new(name + " *")
        p = geom.Progress(lambda f: None)
        p.install(o)
        assert o.progress != ffi.NULL and o.progress_user == ffi.NULL
        assert ffi.offsetof(name, "progress_user") == ffi.offsetof(name, "progress") + 8
    assert ffi.sizeof("geom_render_options") == ffi.offsetof("geom_render_options",
                                                             "progress_user") + 8
