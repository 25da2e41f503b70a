"""Cross-checks geocert's `deviation` with VTK: the distance from every vertex of ORIGINAL's
surface (vertices no triangle uses are skipped, as geocert skips them) to the surface
SIMPLIFIED by vtkDistancePolyDataFilter (unsigned, first distance only), as the maximum and
the root mean square in % of the bounding-box diagonal of ORIGINAL's surface.

usage: vtk_distance.py ORIGINAL.ply SIMPLIFIED.ply
prints one JSON object: {"version", "max_percent", "rms_percent", "points"}
"""
import json
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def read(path):
    reader = vtk.vtkPLYReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def main():
    original, simplified = (read(p) for p in sys.argv[1:3])
    vtk.vtkSMPTools.SetBackend("Sequential")
    f = vtk.vtkDistancePolyDataFilter()
    f.SetInputData(0, original)
    f.SetInputData(1, simplified)
    f.SignedDistanceOff()
    f.ComputeSecondDistanceOff()
    f.Update()
    d = np.abs(vtk_to_numpy(f.GetOutput().GetPointData().GetArray("Distance")))
    pts = vtk_to_numpy(original.GetPoints().GetData()).astype(np.float64)
    used = np.zeros(len(pts), dtype=bool)
    used[vtk_to_numpy(original.GetPolys().GetConnectivityArray())] = True
    d, pts = d[used], pts[used]
    diag = float(np.linalg.norm(pts.max(0) - pts.min(0)))
    print(json.dumps({
        "version": vtk.vtkVersion.GetVTKVersion(),
        "max_percent": 100.0 * float(d.max()) / diag,
        "rms_percent": 100.0 * float(np.sqrt((d ** 2).mean())) / diag,
        "points": int(len(d)),
    }))


if __name__ == "__main__":
    main()
