"""Times OpenVDB's volumeToMesh with adaptivity on a raw little-endian float32 volume (x
fastest): FloatGrid.copyFromArray, then convertToPolygons(iso, adaptivity) (called by
`geocert prove`). Uses Debian's python3-openvdb (module `pyopenvdb`) with the system python3.

usage: openvdb_mesh.py VOLUME.raw NX NY NZ ISO ADAPTIVITY RUNS OUT.ply
prints one JSON object: {"version", "median_s", "triangles", "quads"}; writes the mesh of the
last run (quads split into two triangles) as an ASCII PLY in grid coordinates.
"""
import json
import statistics
import sys
import time

import numpy as np
import pyopenvdb as vdb


def main():
    path, nx, ny, nz, iso, adaptivity, runs, out = sys.argv[1:9]
    nx, ny, nz, runs = int(nx), int(ny), int(nz), int(runs)
    iso, adaptivity = float(iso), float(adaptivity)
    data = np.fromfile(path, dtype="<f4")
    if data.size != nx * ny * nz:
        raise SystemExit(f"{path}: {data.size} samples, expected {nx * ny * nz}")
    # x fastest on disk: index [z, y, x]; OpenVDB's copyFromArray takes [i, j, k] = [x, y, z].
    array = np.ascontiguousarray(data.reshape(nz, ny, nx).transpose(2, 1, 0))
    times = []
    points = tris = quads = None
    for _ in range(runs):
        start = time.perf_counter()
        grid = vdb.FloatGrid(background=float(array.min()))
        grid.copyFromArray(array)
        points, tris, quads = grid.convertToPolygons(isovalue=iso, adaptivity=adaptivity)
        times.append(time.perf_counter() - start)
    faces = [tuple(t) for t in tris] + [f for q in quads for f in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    with open(out, "w") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"element vertex {len(points)}\nproperty double x\nproperty double y\nproperty double z\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for p in points:
            f.write(f"{p[0]} {p[1]} {p[2]}\n")
        for t in faces:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")
    print(json.dumps({
        "version": ".".join(map(str, vdb.LIBRARY_VERSION)),
        "median_s": statistics.median(times),
        "triangles": len(tris),
        "quads": len(quads),
    }))


if __name__ == "__main__":
    main()
