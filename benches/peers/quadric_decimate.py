"""Runs the quadric simplifiers people use today on a PLY/OBJ mesh at a target triangle
count, side by side with geocert's `decimate` (called by `geocert prove`):
fast-simplification (pip; Garland-Heckbert edge collapse after Sp4cerat's
Fast-Quadric-Mesh-Simplification), vtkQuadricDecimation and vtkDecimatePro (pip vtk, one
thread).

usage: quadric_decimate.py IN.{ply,obj} TRIANGLES OUT_PREFIX RUNS
prints one JSON object per peer and line: {"peer", "version", "median_s", "times_s",
"triangles", "vertices", "out"} or {"peer", "unavailable": reason}; writes each peer's last
output to OUT_PREFIX-PEER.ply (binary) for geocert's deviation measures.
"""
import json
import statistics
import sys
import time

import numpy as np


def read_mesh(path):
    import vtk
    reader = vtk.vtkPLYReader() if path.endswith(".ply") else vtk.vtkOBJReader()
    reader.SetFileName(path)
    reader.Update()
    poly = reader.GetOutput()
    from vtk.util.numpy_support import vtk_to_numpy
    points = vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    cells = vtk_to_numpy(poly.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return poly, points, cells


def write_ply(path, points, faces):
    points = np.asarray(points, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int32)
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
                 "property double x\nproperty double y\nproperty double z\n"
                 "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(points), len(faces))).encode())
        f.write(points.astype("<f8").tobytes())
        rec = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
        rec["n"] = 3
        rec["i"] = faces
        f.write(rec.tobytes())


def report(peer, version, times, points, faces, out):
    write_ply(out, points, faces)
    print(json.dumps({
        "peer": peer, "version": version, "median_s": statistics.median(times),
        "times_s": times, "triangles": int(len(faces)), "vertices": int(len(points)),
        "out": out,
    }), flush=True)


def vtk_faces(poly):
    from vtk.util.numpy_support import vtk_to_numpy
    pts = vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    cells = vtk_to_numpy(poly.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return pts, cells


def main():
    path, triangles, prefix, runs = sys.argv[1:5]
    triangles, runs = int(triangles), int(runs)
    import vtk
    vtk.vtkSMPTools.SetBackend("Sequential")
    poly, points, cells = read_mesh(path)
    reduction = 1.0 - triangles / len(cells)
    try:
        import fast_simplification
        from importlib.metadata import version
        times, out = [], None
        for _ in range(runs):
            t = time.perf_counter()
            out = fast_simplification.simplify(points, cells, target_count=triangles)
            times.append(time.perf_counter() - t)
        report("fast-simplification", version("fast-simplification"), times, out[0], out[1],
               prefix + "-fast-simplification.ply")
    except ImportError as e:
        print(json.dumps({"peer": "fast-simplification", "unavailable": str(e)}))
    for name, make in [("vtkQuadricDecimation", vtk.vtkQuadricDecimation),
                       ("vtkDecimatePro", vtk.vtkDecimatePro)]:
        times, result = [], None
        for _ in range(runs):
            f = make()
            f.SetInputData(poly)
            f.SetTargetReduction(reduction)
            if name == "vtkDecimatePro":
                f.PreserveTopologyOn()
                f.SplittingOff()
                f.BoundaryVertexDeletionOn()
                f.SetMaximumError(vtk.VTK_DOUBLE_MAX)
            else:
                f.VolumePreservationOff()
            t = time.perf_counter()
            f.Update()
            times.append(time.perf_counter() - t)
            result = f.GetOutput()
        pts, faces = vtk_faces(result)
        report(name, vtk.vtkVersion.GetVTKVersion(), times, pts, faces, prefix + "-" + name + ".ply")


if __name__ == "__main__":
    main()
