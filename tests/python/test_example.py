"""The README's Python one-liner and examples/remesh.py run as documented."""
import os
import re
import subprocess
import sys

from conftest import SOURCE_DIR


def test_the_readme_one_liner_remeshes_blob():
    readme = (SOURCE_DIR / "README.md").read_text()
    match = re.search(r'^PYTHONPATH=build/python /usr/bin/python3 -c "(import ism;[^"]*)"$', readme,
                      re.M)
    assert match, "no Python one-liner in the README"
    done = subprocess.run([sys.executable, "-c", match.group(1)], cwd=SOURCE_DIR,
                          capture_output=True, text=True, check=False, env=os.environ)
    assert done.returncode == 0, done.stderr
    shape, efficiency, psnr = done.stdout.split(")")[0] + ")", *done.stdout.split(")")[1].split()
    assert shape == "(65, 65, 3)"
    assert 0.5 < float(efficiency) <= 1 and float(psnr) > 50


def test_the_example_script(meshes, tmp_path):
    done = subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "remesh.py"),
                           str(meshes["blob"]), "--size", "17", "--out", str(tmp_path)],
                          capture_output=True, text=True, check=False, env=os.environ)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "17x17 geometry image" in done.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blob.exr", "blob.glb", "blob.json"]
