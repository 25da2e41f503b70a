"""Times vtkDecimatePro (Schroeder-style vertex removal, the nearest peer of the paper's
node decimation) on a PLY mesh, side by side with geocert's `decimate` fast path (called
by `geocert prove`).

usage: vtk_decimate.py IN.ply TARGET_REDUCTION OUT.ply RUNS
prints one JSON object: {"version", "median_s", "times_s", "triangles", "vertices"};
writes the last run's output to OUT.ply (binary, for geocert's quality measures).
"""
import json
import statistics
import sys
import time

import vtk


def main():
    path, reduction, out_path, runs = sys.argv[1:5]
    reduction, runs = float(reduction), int(runs)
    vtk.vtkSMPTools.SetBackend("Sequential")
    reader = vtk.vtkPLYReader()
    reader.SetFileName(path)
    reader.Update()
    mesh = reader.GetOutput()
    times = []
    result = None
    for _ in range(runs):
        f = vtk.vtkDecimatePro()
        f.SetInputData(mesh)
        f.SetTargetReduction(reduction)
        f.PreserveTopologyOn()
        f.SplittingOff()
        f.BoundaryVertexDeletionOn()
        f.SetMaximumError(vtk.VTK_DOUBLE_MAX)
        t = time.perf_counter()
        f.Update()
        times.append(time.perf_counter() - t)
        result = f.GetOutput()
    clean = vtk.vtkCleanPolyData()
    clean.SetInputData(result)
    clean.PointMergingOff()
    clean.Update()
    writer = vtk.vtkPLYWriter()
    writer.SetFileName(out_path)
    writer.SetFileTypeToBinary()
    writer.SetInputData(clean.GetOutput())
    writer.Write()
    print(json.dumps({
        "version": vtk.vtkVersion.GetVTKVersion(),
        "median_s": statistics.median(times),
        "times_s": times,
        "triangles": result.GetNumberOfPolys(),
        "vertices": clean.GetOutput().GetNumberOfPoints(),
    }))


if __name__ == "__main__":
    main()
