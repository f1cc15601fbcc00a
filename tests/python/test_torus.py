"""torus_remesh from Python is the torus-remesh tool: the same grid, exact,
and the same figures; its .glb holds the grid's triangles and passes the
Khronos validator."""
import json

import numpy as np
import pytest

import ism
from conftest import run_tool
from test_gim import read_plain_glb

U, V = 16, 12
SECTIONS = ("inputs", "features_released", "curvature_weight", "partition", "features",
            "meta_mesh", "metric", "map", "grid", "distance")


@pytest.fixture(scope="module")
def runs(meshes, tmp_path_factory):
    out = tmp_path_factory.mktemp("torus")
    torus = meshes["torus"]
    status, _, err = run_tool("torus-remesh", torus, "-o", out / "cli.obj", "--size", f"{U}x{V}",
                              "--report", out / "cli.json", "-q")
    assert status == 0, err
    r = ism.torus_remesh(torus, size=(U, V), output=out / "py.glb", quiet=True)
    return out, r


def test_torus_remesh_is_the_tools(runs):
    out, r = runs
    assert r.grid.shape == (V, U, 3)
    assert np.array_equal(r.vertices, r.grid.reshape(-1, 3))
    assert r.quads.shape == (U * V, 4) and r.triangles.shape == (2 * U * V, 3)
    points, _ = ism.read_mesh(out / "cli.obj")  # the quads, read back as float32
    assert np.array_equal(points, r.vertices.astype(np.float32))
    cli = json.loads((out / "cli.json").read_text())
    for section in SECTIONS:
        assert r.report[section] == cli[section], section
    assert cli["remesh"]["face_kind"] == "quads"
    # Every vertex has valence 4 in the quads.
    assert np.array_equal(np.bincount(r.quads.ravel(), minlength=U * V), np.full(U * V, 4))


def test_the_glb_holds_the_grid_triangles(runs):
    out, r = runs
    assert r.report["remesh"] == {"vertices": U * V, "faces": 2 * U * V, "face_kind": "triangles"}
    positions, triangles = read_plain_glb(out / "py.glb")
    assert np.array_equal(positions[triangles], r.vertices[r.triangles].astype(np.float32))


def test_size_forms(meshes):
    with pytest.raises(ValueError, match="--size must be N or UxV"):
        ism.torus_remesh(meshes["torus"], size="2x2")
    with pytest.raises(ValueError, match=r"size must be N, \(U, V\) or 'UxV'"):
        ism.torus_remesh(meshes["torus"], size=(3, 4, 5))


def test_every_glb_passes_the_khronos_validator(runs, validate_gltf):
    out, _ = runs
    validate_gltf([out / "py.glb"])


def test_the_symmetric_core_is_the_tools_too(meshes, tmp_path):
    torus = meshes["torus"]
    status, _, err = run_tool("torus-remesh", torus, "-o", tmp_path / "cli.obj", "--size",
                              f"{U}x{V}", "--core", "symmetric", "--report",
                              tmp_path / "cli.json", "-q")
    assert status == 0, err
    r = ism.torus_remesh(torus, size=(U, V), core="symmetric", quiet=True)
    points, _ = ism.read_mesh(tmp_path / "cli.obj")
    assert np.array_equal(points, r.vertices.astype(np.float32))
    cli = json.loads((tmp_path / "cli.json").read_text())
    assert cli["map_core"] == "symmetric" and r.report["map"] == cli["map"]
    assert r.report["map"]["core"] == "symmetric" and r.report["meta_mesh"]["valid"]
    assert r.report["map"]["global_steps"] == 1
    with pytest.raises(ValueError, match="core must be"):
        ism.torus_remesh(torus, size=(U, V), core="spherical", quiet=True)


def test_grid_points_keep_every_vertex_at_its_grid_point(runs, meshes):
    _, r = runs
    grid = r.report["grid"]
    # Re-sampling folded triangles' points never adds a fold.
    assert grid["flipped_triangles"] <= grid["flipped_triangles_at_grid_points"]
    at_grid = ism.torus_remesh(meshes["torus"], size=(U, V), grid_points=True, quiet=True)
    g = at_grid.report["grid"]
    assert g["resampled_vertices"] == 0
    assert g["flipped_triangles"] == g["flipped_triangles_at_grid_points"]
