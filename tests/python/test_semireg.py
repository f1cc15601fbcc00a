"""semireg from Python is the semireg tool: the same remesh and base, exact,
and the same figures; bases given as arrays; .glb outputs validated."""
import json

import numpy as np
import pytest

import ism
from conftest import run_tool

LEVELS = 2
SECTIONS = ("inputs", "base", "features_released", "curvature_weight", "partition", "meta_mesh",
            "levels", "metric", "map", "remesh", "distance")


@pytest.fixture(scope="module")
def runs(meshes, tmp_path_factory):
    out = tmp_path_factory.mktemp("semireg")
    blob = meshes["blob"]
    status, _, err = run_tool("semireg", blob, "-o", out / "cli.obj", "--base-size", 12, "--levels",
                              LEVELS, "--write-base", out / "cli_base.obj", "--report",
                              out / "cli.json", "-q")
    assert status == 0, err
    r = ism.semireg(blob, base_size=12, levels=LEVELS, output=out / "py.glb", glb_draco=True,
                    write_base=out / "py_base.glb", quiet=True)
    return out, r


def test_semireg_is_the_tools(runs):
    out, r = runs
    # The OBJ holds 17 digits; the reader (OpenMesh) parses them as float32.
    V, F = ism.read_mesh(out / "cli.obj")
    assert np.array_equal(V, r.vertices.astype(np.float32)) and np.array_equal(F, r.faces)
    BV, BF = ism.read_mesh(out / "cli_base.obj")
    assert np.array_equal(BV, r.base_vertices.astype(np.float32))
    assert np.array_equal(BF, r.base_faces)
    cli = json.loads((out / "cli.json").read_text())
    for section in SECTIONS:
        assert r.report[section] == cli[section], section
    # Exact subdivision connectivity: F_base * 4^levels faces, base vertices first.
    assert len(r.base_vertices) == 12 and len(r.faces) == len(r.base_faces) * 4**LEVELS
    assert np.array_equal(r.vertices[:12], r.base_vertices)
    assert ism.check(r.vertices, r.faces)["genus"] == 0


def test_a_base_given_as_arrays(runs, meshes):
    _, r = runs
    again = ism.semireg(*ism.read_mesh(meshes["blob"]), base=(r.base_vertices, r.base_faces),
                        levels=1, grid_points=True, quiet=True)
    # grid_points (--grid-points): no vertex re-sampled off its grid point.
    assert again.report["remesh"]["resampled_vertices"] == 0
    assert len(again.faces) == len(r.base_faces) * 4
    assert again.report["base"]["source"] == "file" and again.report["base"]["file"] == "base"
    # The same connectivity, its vertices snapped to nearby surface vertices.
    assert again.report["base"]["vertices"] == 12
    assert again.report["base"]["faces"] == len(r.base_faces)
    assert again.report["base"]["largest_snap_distance_relative"] < 0.05
    with pytest.raises(TypeError, match=r"base must be a mesh file's path or a tuple \(V, F\)"):
        ism.semireg(meshes["blob"], base=(r.base_vertices,))
    with pytest.raises(ValueError, match=r"contenders must be in 0\.\.12"):
        ism.semireg(meshes["blob"], base_size=12, contenders=13)
    with pytest.raises(ValueError, match=r"drop_behind must be in \[-1, 1\]"):
        ism.semireg(meshes["blob"], base_size=12, drop_behind=2.0)


def test_every_glb_passes_the_khronos_validator(runs, validate_gltf):
    out, _ = runs
    reports = validate_gltf([out / "py.glb", out / "py_base.glb"])
    assert len(reports) == 2


def test_the_symmetric_core_is_the_tools_too(meshes, tmp_path):
    torus = meshes["torus"]
    status, _, err = run_tool("semireg", torus, "-o", tmp_path / "cli.obj", "--base-size", 16,
                              "--levels", LEVELS, "--core", "symmetric", "--report",
                              tmp_path / "cli.json", "-q")
    assert status == 0, err
    r = ism.semireg(torus, base_size=16, levels=LEVELS, core="symmetric", quiet=True)
    V, F = ism.read_mesh(tmp_path / "cli.obj")
    assert np.array_equal(V, r.vertices.astype(np.float32)) and np.array_equal(F, r.faces)
    cli = json.loads((tmp_path / "cli.json").read_text())
    assert cli["map_core"] == "symmetric" and r.report["map"] == cli["map"]
    assert r.report["map"]["core"] == "symmetric" and r.report["meta_mesh"]["valid"]
    assert ism.check(r.vertices, r.faces)["genus"] == 1
    with pytest.raises(ValueError, match="core must be"):
        ism.semireg(torus, base_size=16, core="spherical", quiet=True)
