"""Meshes in and out of the module: read_mesh, check (= ism-info --json),
dtype and shape checks, and errors carrying the tools' one-line messages."""
import json

import numpy as np
import pytest

import ism
from conftest import SOURCE_DIR, run_tool

BLOB = SOURCE_DIR / "models" / "blob.obj"


def test_read_mesh_gives_float64_positions_and_int64_faces():
    V, F = ism.read_mesh(BLOB)
    assert V.dtype == np.float64 and V.shape == (2562, 3)
    assert F.dtype == np.int64 and F.shape == (5120, 3)
    assert F.min() == 0 and F.max() == len(V) - 1
    # Closed and consistently oriented: every directed edge once, its twin once.
    edges = {(int(a), int(b)) for f in F for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    assert len(edges) == 3 * len(F)
    assert all((b, a) in edges for a, b in edges)
    # Outward: positive signed volume.
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    assert np.einsum("ij,ij->i", a, np.cross(b, c)).sum() > 0


def test_check_is_ism_info_json():
    status, out, err = run_tool("ism-info", BLOB, "--json")
    assert status == 0, err
    assert ism.check(str(BLOB)) == json.loads(out)
    info = ism.check(*ism.read_mesh(BLOB))
    assert info["genus"] == 0 and info["valid_surface"] and info["closed"]
    assert info["file"] == "(V, F)"


@pytest.mark.parametrize("face_dtype", [np.int32, np.int64, np.uint32])
@pytest.mark.parametrize("position_dtype", [np.float64, np.float32])
def test_dtypes_are_accepted(face_dtype, position_dtype):
    V, F = ism.read_mesh(BLOB)
    info = ism.check(V.astype(position_dtype), F.astype(face_dtype))
    assert (info["vertices"], info["faces"], info["genus"]) == (2562, 5120, 0)


def test_non_contiguous_arrays_are_accepted_as_is():
    V, F = ism.read_mesh(BLOB)
    Vf, Ff = np.asfortranarray(V), np.asfortranarray(F)
    assert not Vf.flags.c_contiguous
    wide = np.zeros((len(V), 6))
    wide[:, ::2] = V  # a strided view
    reference = ism.check(V, F)
    assert ism.check(Vf, Ff) == reference
    assert ism.check(wide[:, ::2], F) == reference
    assert ism.check(V.tolist(), F.tolist()) == reference  # lists convert too


def test_bad_arrays_are_refused_clearly():
    V, F = ism.read_mesh(BLOB)
    with pytest.raises(TypeError, match=r"V must be a float array \(float64 or float32\), got int64"):
        ism.check(V.astype(np.int64), F)
    with pytest.raises(TypeError, match="F must be an integer array .* got float64"):
        ism.check(V, F.astype(np.float64))
    with pytest.raises(ValueError, match=r"V must have shape \(n, 3\), got \(2562, 2\)"):
        ism.check(V[:, :2], F)
    with pytest.raises(ValueError, match=r"F must have shape \(m, 3\), got \(5120, 4\)"):
        ism.check(V, np.c_[F, F[:, 0]])
    bad = F.copy()
    bad[7, 2] = len(V)
    with pytest.raises(ValueError, match=r"F\[7, 2\] = 2562 is out of range for 2562 vertices"):
        ism.check(V, bad)
    with pytest.raises(TypeError, match="give a mesh file's path"):
        ism.gim_remesh(V)


def test_bad_mesh_raises_value_error_with_the_tools_message(tmp_path):
    V, F = ism.read_mesh(BLOB)
    open_mesh = tmp_path / "open.obj"
    with open(open_mesh, "w") as f:
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F[1:])
    status, _, err = run_tool("torus-remesh", open_mesh, "-o", tmp_path / "x.obj")
    assert status == 1
    message = err.strip()
    assert message.startswith(f"{open_mesh}: 1 boundary loop, torus-remesh needs a closed surface")
    with pytest.raises(ValueError) as raised:
        ism.torus_remesh(open_mesh)
    assert str(raised.value) == message
    with pytest.raises(ValueError, match=r"^\(V, F\): 1 boundary loop, torus-remesh needs a closed"):
        ism.torus_remesh(V, F[1:])
    with pytest.raises(ValueError, match="genus 0, torus-remesh needs genus 1"):
        ism.torus_remesh(V, F)
    assert not (tmp_path / "x.obj").exists()


def test_options_and_files_fail_like_the_tools(tmp_path):
    status, _, err = run_tool("gim-remesh", BLOB, "-o", tmp_path / "x.exr", "--size", "64")
    assert status == 1
    with pytest.raises(ValueError) as raised:
        ism.gim_remesh(BLOB, size=64)
    assert str(raised.value) == err.strip()
    with pytest.raises(ValueError, match="--metric must be right-isosceles or equilateral"):
        ism.gim_remesh(BLOB, metric="square")
    with pytest.raises(ValueError, match=r"--inverse-weight must be in \[0.001, 1.0\], got 2.0"):
        ism.gim_remesh(BLOB, inverse_weight=2.0)
    with pytest.raises(ValueError, match="give exactly one of --base BASE"):
        ism.semireg(BLOB)
    with pytest.raises(OSError, match="no such file"):
        ism.read_mesh(tmp_path / "missing.obj")
    with pytest.raises(OSError, match="no such file"):
        ism.gim_remesh(tmp_path / "missing.obj")
    with pytest.raises(OSError, match="output folder .* does not exist"):
        ism.gim_remesh(BLOB, output=tmp_path / "no" / "x.exr")
    with pytest.raises(OSError, match="refusing to overwrite an input file"):
        ism.gim_remesh(BLOB, mesh=BLOB)
    garbage = tmp_path / "garbage.obj"
    garbage.write_text("this is not a mesh\n")
    with pytest.raises(ValueError, match="garbage.obj"):
        ism.read_mesh(garbage)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["garbage.obj"]  # nothing partial
