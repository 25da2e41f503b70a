"""Times pymartini (RTIN: 2-D longest-edge bisection) on a raw little-endian float32 height
grid of SIZE x SIZE samples (x fastest, SIZE = 2^k + 1): Martini(SIZE).create_tile(grid), then
tile.get_mesh(max_error) (called by `geocert prove`).

usage: martini_tile.py HEIGHT.raw SIZE MAX_ERROR RUNS [MESH.raw]
prints one JSON object: {"version", "median_s", "mesh_median_s", "triangles", "vertices"}.
With MESH.raw, also writes the last mesh as little-endian uint32: the vertex count, the
triangle count, the vertices (x, y in pymartini's order: x indexes the transposed grid's
rows, i.e. the height grid's y) and the triangles' vertex indices.
"""
import json
import statistics
import sys
import time

import numpy as np
from pymartini import Martini


def main():
    path, size, max_error, runs = sys.argv[1:5]
    out = sys.argv[5] if len(sys.argv) > 5 else None
    size, max_error, runs = int(size), float(max_error), int(runs)
    data = np.fromfile(path, dtype="<f4")
    if data.size != size * size:
        raise SystemExit(f"{path}: {data.size} samples, expected {size * size}")
    # pymartini indexes terrain[y * size + x] after transposing the (row, column) array.
    terrain = data.reshape(size, size).T.copy()
    totals, meshes = [], []
    vertices = triangles = None
    for _ in range(runs):
        start = time.perf_counter()
        tile = Martini(size).create_tile(terrain)
        mid = time.perf_counter()
        vertices, triangles = tile.get_mesh(max_error)
        end = time.perf_counter()
        totals.append(end - start)
        meshes.append(end - mid)
    if out is not None:
        v = np.asarray(vertices, dtype="<u4").ravel()
        t = np.asarray(triangles, dtype="<u4").ravel()
        header = np.array([v.size // 2, t.size // 3], dtype="<u4")
        np.concatenate([header, v, t]).astype("<u4").tofile(out)
    print(json.dumps({
        "version": "pymartini",
        "median_s": statistics.median(totals),
        "mesh_median_s": statistics.median(meshes),
        # get_mesh returns (n, 2) vertices and (m, 3) triangles (not flat arrays).
        "triangles": np.asarray(triangles).reshape(-1, 3).shape[0],
        "vertices": np.asarray(vertices).reshape(-1, 2).shape[0],
    }))


if __name__ == "__main__":
    main()
