"""Fixtures of the Python module's tests: the built tools, small generated
meshes, the shared models (skipped with a message when absent) and the
Khronos glTF validator (skipped with a message when node or it is absent)."""
import json
import os
import pathlib
import shutil
import subprocess

import pytest

BINARY_DIR = pathlib.Path(os.environ.get("ISM_BINARY_DIR", "build"))
SOURCE_DIR = pathlib.Path(os.environ.get("ISM_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
SHARED_DIR = pathlib.Path(os.environ.get("ISM_SHARED_DIR", SOURCE_DIR.parent / "shared"))
VALIDATOR = SOURCE_DIR / "scripts" / "gltf-validator" / "validate.mjs"


def run_tool(tool, *args):
    """Runs build/bin/TOOL ARGS; returns (status, stdout, stderr)."""
    done = subprocess.run([str(BINARY_DIR / "bin" / tool), *map(str, args)],
                          capture_output=True, text=True, check=False)
    return done.returncode, done.stdout, done.stderr


@pytest.fixture(scope="session")
def meshes(tmp_path_factory):
    """Small generated closed surfaces: blob (genus 0), torus (genus 1)."""
    folder = tmp_path_factory.mktemp("meshes")
    out = {}
    for shape, faces in (("blob", 500), ("torus", 500)):
        path = folder / f"{shape}.obj"
        status, _, err = run_tool("ism-genmesh", shape, "--faces", faces, "-o", path)
        assert status == 0, err
        out[shape] = path
    return out


@pytest.fixture(scope="session")
def shared_models():
    folder = SHARED_DIR / "models"
    if not folder.is_dir():
        pytest.skip(f"shared models not found at {folder} (clone ../shared beside the repository)")
    return folder


def validator_missing():
    if shutil.which("node") is None:
        return "node not found (install Node.js, then scripts/install-node-tools.sh)"
    package = VALIDATOR.parent / "node_modules" / "gltf-validator"
    if not package.is_dir():
        return f"gltf-validator not installed at {package} (run scripts/install-node-tools.sh)"
    return None


@pytest.fixture(scope="session")
def validate_gltf():
    """validate_gltf(paths) -> per-file reports; fails the test on any error."""
    why = validator_missing()
    if why:
        pytest.skip(f"glTF validator unavailable, .glb not validated: {why}")

    def validate(paths):
        done = subprocess.run(["node", str(VALIDATOR), *map(str, paths)], capture_output=True,
                              text=True, check=False)
        reports = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
        assert len(reports) == len(paths), done.stdout + done.stderr
        for report in reports:
            assert report["errors"] == 0, report
        assert done.returncode == 0, done.stdout + done.stderr
        return reports

    return validate
