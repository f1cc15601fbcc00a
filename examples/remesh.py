#!/usr/bin/env python3
"""Remeshing from Python with the ism module, end to end.

    PYTHONPATH=build/python python3 examples/remesh.py [MESH] [--size N] [--out DIR]

Reads a closed genus-0 surface (default models/blob.obj), checks it, builds its
octahedral geometry image, and writes to DIR (default out/): the image
(.exr), the remesh as glTF (.glb, for any glTF viewer) and the report (.json).
Then it does with numpy what the arrays are for: the image rebuilt into the
remesh, and the distance of every remesh vertex to the input's vertices.
"""
import argparse
import json
import pathlib
import sys

import numpy as np

import ism


def main():
    root = pathlib.Path(__file__).resolve().parents[1]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", nargs="?", default=root / "models" / "blob.obj", type=pathlib.Path)
    parser.add_argument("--size", type=int, default=65, help="image size 2^k+1 (default 65)")
    parser.add_argument("--out", type=pathlib.Path, default=root / "out")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    stem = args.out / args.mesh.stem

    V, F = ism.read_mesh(args.mesh)
    info = ism.check(V, F)
    print(f"{args.mesh}: {info['vertices']} vertices, {info['faces']} faces, genus {info['genus']}")
    if not info["valid_surface"] or info["genus"] != 0:
        print("gim_remesh needs one genus-0 surface:", info["defects"] or "not genus 0")
        return 1
    if not info["closed"]:
        print(f"{len(info['loops'])} holes, capped for the map: the image gets an alpha channel")

    try:
        result = ism.gim_remesh(V, F, size=args.size, output=f"{stem}.exr", mesh=f"{stem}.glb",
                                report=f"{stem}.json", quiet=True)
    except ValueError as error:  # the tool's one-line message
        print(error)
        return 1
    report = result.report
    print(f"{args.size}x{args.size} geometry image: map efficiency "
          f"{report['map']['efficiency_domain_to_surface']:.3f}, image efficiency "
          f"{report['image']['efficiency_square']:.3f}, PSNR {report['distance']['psnr_db']:.1f} dB, "
          f"{report['seconds']['total']:.1f} s")

    # The image is the remesh: rebuilding it gives the same vertices and faces.
    Vr, Fr = ism.geometry_image_mesh(result.image)
    assert np.array_equal(Vr, result.vertices) and np.array_equal(Fr, result.faces)
    # Distance of each remesh vertex to the nearest input vertex (brute force, in blocks).
    nearest = np.concatenate([
        np.sqrt(((block[:, None, :] - V[None, :, :])**2).sum(axis=2)).min(axis=1)
        for block in np.array_split(result.vertices, max(1, len(result.vertices) // 512))
    ])
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    print(f"remesh: {len(result.vertices)} vertices, {len(result.faces)} faces; nearest input "
          f"vertex within {nearest.max() / diagonal:.4f} of the bounding-box diagonal")
    print(f"wrote {stem}.exr, {stem}.glb, {stem}.json")
    json.loads(pathlib.Path(f"{stem}.json").read_text())  # the same report, on disk
    return 0


if __name__ == "__main__":
    sys.exit(main())
