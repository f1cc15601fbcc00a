"""gim_remesh from Python is the gim-remesh tool: the same image bit for bit,
the same remesh and figures, from a path or from arrays; its .glb meshes
(plain and Draco-compressed) hold the remesh and pass the Khronos validator."""
import json
import struct

import numpy as np
import pytest

import ism
from conftest import run_tool

SIZE = 33
DETERMINISTIC_SECTIONS = ("inputs", "features_released", "curvature_weight", "partition", "meta_mesh",
                          "size", "metric", "map", "image", "distance")


@pytest.fixture(scope="module")
def runs(meshes, tmp_path_factory):
    """The tool and the module on the same surface, with the same options."""
    out = tmp_path_factory.mktemp("gim")
    blob = meshes["blob"]
    status, _, err = run_tool("gim-remesh", blob, "-o", out / "cli.exr", "--size", SIZE, "--mesh",
                              out / "cli.obj", "--report", out / "cli.json", "-q")
    assert status == 0, err
    from_path = ism.gim_remesh(blob, size=SIZE, output=out / "py.exr", mesh=out / "py.glb",
                               quiet=True)
    from_arrays = ism.gim_remesh(*ism.read_mesh(blob), size=SIZE, quiet=True)
    return out, from_path, from_arrays


def test_the_image_is_the_tools_bit_for_bit(runs):
    out, r, _ = runs
    assert r.image.shape == (SIZE, SIZE, 3) and r.image.dtype == np.float64
    cli = ism.read_geometry_image(out / "cli.exr")
    assert cli.dtype == np.float32 and cli.shape == (SIZE, SIZE, 3)
    # The EXR stores the samples as float32: the same bits.
    assert np.array_equal(r.image.astype(np.float32).view(np.uint32), cli.view(np.uint32))
    assert np.array_equal(ism.read_geometry_image(out / "py.exr").view(np.uint32),
                          cli.view(np.uint32))


def test_arrays_in_give_the_same_image_as_a_path(runs):
    _, r, r2 = runs
    assert np.array_equal(r.image.view(np.uint64), r2.image.view(np.uint64))
    assert np.array_equal(r.vertices, r2.vertices) and np.array_equal(r.faces, r2.faces)


def test_the_remesh_and_the_figures_are_the_tools(runs):
    out, r, _ = runs
    n = SIZE
    assert r.vertices.shape == ((n - 1) ** 2 + 2, 3) and r.faces.shape == (2 * (n - 1) ** 2, 3)
    # The OBJ holds 17 digits; the reader (OpenMesh) parses them as float32.
    V, F = ism.read_mesh(out / "cli.obj")
    assert np.array_equal(V, r.vertices.astype(np.float32)) and np.array_equal(F, r.faces)
    Vi, Fi = ism.geometry_image_mesh(r.image)
    assert np.array_equal(Vi, r.vertices) and np.array_equal(Fi, r.faces)
    cli = json.loads((out / "cli.json").read_text())
    for section in DETERMINISTIC_SECTIONS:
        assert r.report[section] == cli[section], section
    for variant, cli_variant in zip(r.report["map_variants"], cli["map_variants"]):
        # (Times, seconds*, differ from run to run; all else is the same.)
        for timed in (variant, cli_variant):
            for key in [k for k in timed if k.startswith("seconds")]:
                timed.pop(key)
        assert variant == cli_variant
    assert r.report["map"]["valid"] and r.report["meta_mesh"]["valid"]
    assert r.report["image"]["efficiency_square"] > 0.5
    assert r.report["distance"]["psnr_db"] > 40
    assert set(r.report["seconds"]) >= {"read", "check", "partition", "map", "sample", "total"}
    # Unit normals at every sample.
    assert np.allclose(np.linalg.norm(r.normals, axis=2), 1)


def glb_chunks(path):
    """The JSON and BIN chunks of a glTF binary file."""
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    chunks, offset = {}, 12
    while offset < len(data):
        size, kind = struct.unpack_from("<I4s", data, offset)
        chunks[kind] = data[offset + 8:offset + 8 + size]
        offset += 8 + size
    return json.loads(chunks[b"JSON"]), chunks.get(b"BIN\0")


def read_plain_glb(path):
    """Positions and triangles of a one-primitive, uncompressed .glb."""
    gltf, binary = glb_chunks(path)
    primitive = gltf["meshes"][0]["primitives"][0]
    assert primitive.get("mode", 4) == 4  # triangles

    def accessor(index, components):
        a = gltf["accessors"][index]
        view = gltf["bufferViews"][a["bufferView"]]
        dtype = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}[a["componentType"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        values = np.frombuffer(binary, dtype, a["count"] * components, start)
        return values.reshape(-1, components) if components > 1 else values, a

    positions, position_accessor = accessor(primitive["attributes"]["POSITION"], 3)
    indices, _ = accessor(primitive["indices"], 1)
    assert np.allclose(position_accessor["min"], positions.min(axis=0))
    assert np.allclose(position_accessor["max"], positions.max(axis=0))
    return positions, indices.reshape(-1, 3)


def test_the_glb_holds_the_remesh(runs):
    out, r, _ = runs
    positions, triangles = read_plain_glb(out / "py.glb")
    assert len(triangles) == len(r.faces)
    # Corner by corner, the float32 of each remesh position, faces in order.
    assert np.array_equal(positions[triangles], r.vertices[r.faces].astype(np.float32))


def test_write_mesh_glb_plain_and_draco(runs, tmp_path):
    _, r, _ = runs
    ism.write_mesh(tmp_path / "plain.glb", r.vertices, r.faces)
    ism.write_mesh(tmp_path / "draco.glb", r.vertices, r.faces, glb_draco=True, draco_bits=12)
    positions, triangles = read_plain_glb(tmp_path / "plain.glb")
    assert np.array_equal(positions[triangles], r.vertices[r.faces].astype(np.float32))
    gltf, _ = glb_chunks(tmp_path / "draco.glb")
    assert "KHR_draco_mesh_compression" in gltf["extensionsRequired"]
    assert (tmp_path / "draco.glb").stat().st_size * 2 < (tmp_path / "plain.glb").stat().st_size


def test_every_glb_passes_the_khronos_validator(runs, tmp_path, validate_gltf):
    out, r, _ = runs
    ism.write_mesh(tmp_path / "plain.glb", r.vertices, r.faces)
    ism.write_mesh(tmp_path / "draco.glb", r.vertices, r.faces, glb_draco=True)
    reports = validate_gltf([out / "py.glb", tmp_path / "plain.glb", tmp_path / "draco.glb"])
    assert [report["errors"] for report in reports] == [0, 0, 0]


def test_an_open_surface_keeps_its_alpha_through_the_file(meshes, tmp_path):
    """A blob with one hole: the image marks the cap with alpha 0, the file's
    channel A reads back as the same bits; a closed surface's file has no A."""
    vertices, faces = ism.read_mesh(meshes["blob"])
    # Remove vertex 0 and its faces: one boundary loop round its ring.
    kept = faces[~np.any(faces == 0, axis=1)]
    vertices = vertices[1:]
    kept = kept - 1
    exr = tmp_path / "open.exr"
    r = ism.gim_remesh(vertices, kept, size=SIZE, output=exr, quiet=True)
    assert r.alpha is not None and r.alpha.shape == (SIZE, SIZE)
    assert set(np.unique(r.alpha)) == {0.0, 1.0}
    assert 0 < np.count_nonzero(r.alpha == 0) < SIZE * SIZE // 4
    image, alpha = ism.read_geometry_image(exr, alpha=True)
    assert image.shape == (SIZE, SIZE, 3) and alpha.dtype == np.float32
    assert np.array_equal(alpha.view(np.uint32), r.alpha.astype(np.float32).view(np.uint32))
    assert np.array_equal(image, ism.read_geometry_image(exr))
    closed = tmp_path / "closed.exr"
    ism.gim_remesh(meshes["blob"], size=SIZE, output=closed, quiet=True)
    _, none = ism.read_geometry_image(closed, alpha=True)
    assert none is None


def test_the_symmetric_core_is_the_tools_too(meshes, tmp_path):
    blob = meshes["blob"]
    status, _, err = run_tool("gim-remesh", blob, "-o", tmp_path / "cli.exr", "--size", SIZE,
                              "--core", "symmetric", "--report", tmp_path / "cli.json", "-q")
    assert status == 0, err
    r = ism.gim_remesh(blob, size=SIZE, core="symmetric", quiet=True)
    cli = ism.read_geometry_image(tmp_path / "cli.exr")
    assert np.array_equal(r.image.astype(np.float32).view(np.uint32), cli.view(np.uint32))
    report = json.loads((tmp_path / "cli.json").read_text())
    assert report["map_core"] == "symmetric" and r.report["map"] == report["map"]
    with pytest.raises(ValueError, match="core must be"):
        ism.gim_remesh(blob, size=SIZE, core="spherical", quiet=True)


def test_grid_points_keep_every_pixel_at_its_grid_point(runs, meshes):
    _, r, _ = runs
    image = r.report["image"]
    # Re-sampling folded triangles' pixels never adds a fold.
    assert image["flipped_triangles"] <= image["flipped_triangles_at_grid_points"]
    at_grid = ism.gim_remesh(meshes["blob"], size=SIZE, grid_points=True, quiet=True)
    g = at_grid.report["image"]
    assert g["resampled_vertices"] == 0
    assert g["flipped_triangles"] == g["flipped_triangles_at_grid_points"]
    assert g["flipped_triangles_at_grid_points"] == image["flipped_triangles_at_grid_points"]
    # The same map, so the pixels that were not re-sampled are the same samples.
    moved = np.any(r.image != at_grid.image, axis=2)
    assert moved.sum() <= 4 * image["resampled_vertices"]  # mirrors: a side pixel 2, -z 4
