"""Times VTK's isosurface filters on a raw little-endian float32 volume (x fastest), one
thread, side by side with geocert's `mc` fast path (called by `geocert prove`).

usage: vtk_isosurface.py VOLUME.raw NX NY NZ ISO RUNS [THREADS]
prints one JSON object: {"version", "flying_edges": {"median_s", "triangles"},
"marching_cubes": {"median_s", "triangles"}}. With THREADS > 1, flying edges alone on VTK's
threaded SMP backend (STDThread) with that many threads, and "backend", "threads".
"""
import json
import statistics
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support


def main():
    path, nx, ny, nz, iso, runs = sys.argv[1:7]
    nx, ny, nz, runs, iso = int(nx), int(ny), int(nz), int(runs), float(iso)
    threads = int(sys.argv[7]) if len(sys.argv) > 7 else 1
    if threads > 1:
        vtk.vtkSMPTools.SetBackend("STDThread")
        vtk.vtkSMPTools.Initialize(threads)
    else:
        vtk.vtkSMPTools.SetBackend("Sequential")
        vtk.vtkSMPTools.Initialize(1)
    data = np.fromfile(path, dtype="<f4")
    if data.size != nx * ny * nz:
        raise SystemExit(f"{path}: {data.size} samples, expected {nx * ny * nz}")
    image = vtk.vtkImageData()
    image.SetDimensions(nx, ny, nz)
    arr = numpy_support.numpy_to_vtk(data, deep=True, array_type=vtk.VTK_FLOAT)
    arr.SetName("f")
    image.GetPointData().SetScalars(arr)
    out = {"version": vtk.vtkVersion.GetVTKVersion()}
    filters = [("flying_edges", vtk.vtkFlyingEdges3D), ("marching_cubes", vtk.vtkMarchingCubes)]
    if threads > 1:
        filters = filters[:1]
        out["backend"] = vtk.vtkSMPTools.GetBackend()
        out["threads"] = vtk.vtkSMPTools.GetEstimatedNumberOfThreads()
    for name, cls in filters:
        times = []
        tris = 0
        for _ in range(runs):
            f = cls()
            f.SetInputData(image)
            f.SetValue(0, iso)
            if hasattr(f, "ComputeNormalsOff"):
                f.ComputeNormalsOff()
            if hasattr(f, "ComputeGradientsOff"):
                f.ComputeGradientsOff()
            if hasattr(f, "ComputeScalarsOff"):
                f.ComputeScalarsOff()
            t = time.perf_counter()
            f.Update()
            times.append(time.perf_counter() - t)
            tris = f.GetOutput().GetNumberOfPolys()
        out[name] = {"median_s": statistics.median(times), "triangles": tris}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
