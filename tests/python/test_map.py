"""map_surfaces from Python is the ism-map tool: the same overlay pair and
correspondences, exact, and the same figures; a bijection checked on the
arrays; bad arguments refused with one message."""
import json

import numpy as np
import pytest

import ism
from conftest import run_tool


@pytest.fixture(scope="module")
def pair(meshes, tmp_path_factory):
    out = tmp_path_factory.mktemp("map")
    sphere = out / "sphere.obj"
    status, _, err = run_tool("ism-genmesh", "sphere", "--faces", 400, "-o", sphere)
    assert status == 0, err
    blob = meshes["blob"]
    status, _, err = run_tool("ism-map", sphere, blob, "-o", out / "cli", "--report",
                              out / "cli.json", "-q")
    assert status == 0, err
    r = ism.map_surfaces(sphere, ism.read_mesh(blob), quiet=True)
    return out, sphere, blob, r


def test_map_surfaces_is_the_tools(pair):
    out, sphere, blob, r = pair
    # The OBJs hold 17 digits; read_mesh rounds to float32 as every reader.
    V, F = ism.read_mesh(out / "cli_on_A.obj")
    assert np.array_equal(F, r.faces)
    assert np.array_equal(V, r.on_a.astype(np.float32))
    V, F = ism.read_mesh(out / "cli_on_B.obj")
    assert np.array_equal(V, r.on_b.astype(np.float32))
    cli = json.loads((out / "cli.json").read_text())
    for key in ("faces", "symmetric_efficiency", "symmetric_dirichlet", "efficiency_a_to_b",
                "efficiency_b_to_a", "overlay"):
        assert r.report["map"][key] == cli["map"][key], key
    assert r.report["partition"] == cli["partition"]
    # The same schedule (small inputs: the thorough one).
    for key in ("schedule", "level_sweeps", "relaxation_gain"):
        assert r.report["map"][key] == cli["map"][key], key
    assert r.report["map"]["schedule"] == "thorough"
    # The same coarse race (default 2,3), the same copy kept.
    race = r.report["map"]["coarse_race"]
    assert race["kept"] == cli["map"]["coarse_race"]["kept"]
    assert race["efficiencies"] == cli["map"]["coarse_race"]["efficiencies"]
    assert len(race["efficiencies"]) == 2
    # The correspondences are the files' rows: i, the corners of the face, weights.
    _, BF = ism.read_mesh(blob)
    rows = np.loadtxt(out / "cli_A_to_B.txt").reshape(-1, 3, 3)
    face, bary = r.a_to_b
    assert len(face) == len(rows) == len(ism.read_mesh(sphere)[0])
    assert np.array_equal(rows[:, :, 1].astype(np.int64), BF[face])
    assert np.array_equal(rows[:, :, 2], bary)


def test_the_overlay_pair_is_a_bijection(pair):
    _, sphere, blob, r = pair
    assert r.report["map"]["symmetric_efficiency"] > 0.9
    for positions, surface in ((r.on_a, sphere), (r.on_b, blob)):
        V, F = ism.read_mesh(surface)
        def areas(P, T):
            return 0.5 * np.linalg.norm(np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]),
                                        axis=1)
        # Same area as the surface (every part covered once), no degenerate triangle
        # pointing inward: the signed volume matches too.
        assert abs(areas(positions, r.faces).sum() - areas(V, F).sum()) < 1e-6 * areas(V, F).sum()
        def volume(P, T):
            return np.einsum("ij,ij->i", P[T[:, 0]], np.cross(P[T[:, 1]], P[T[:, 2]])).sum() / 6
        assert abs(volume(positions, r.faces) - volume(V, F)) < 1e-6 * abs(volume(V, F))
    check = ism.check(r.on_a, r.faces)
    assert check["closed"] and check["genus"] == 0


def test_bad_arguments(pair, meshes):
    _, sphere, _, _ = pair
    with pytest.raises(TypeError, match=r"b must be a mesh file's path or a tuple \(V, F\)"):
        ism.map_surfaces(sphere, 3)
    with pytest.raises(TypeError, match="features must be a pairs file's path"):
        ism.map_surfaces(sphere, sphere, features=[1, 2])
    with pytest.raises(ValueError, match="genus"):
        ism.map_surfaces(sphere, meshes["torus"], quiet=True)
    with pytest.raises(ValueError, match="schedule must be one of auto, thorough, fast"):
        ism.map_surfaces(sphere, sphere, schedule="quick")
