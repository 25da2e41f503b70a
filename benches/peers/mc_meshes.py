"""Writes the isosurface meshes other marching-cubes programs make from one volume, for
`geocert mc verify` to check against the trilinear interpolant (called by `geocert prove`).

usage: mc_meshes.py VOLUME.raw NX NY NZ ISO OUTDIR
VOLUME.raw: little-endian float32 samples, x fastest. Every mesh is written as ASCII PLY in
grid units, coordinates (x, y, z). Prints one JSON object: for each program either
{"path", "version", "seconds", "triangles"} or {"error"}.
"""
import json
import os
import sys
import time

import numpy as np


def write_ply(path, verts, faces):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"element vertex {len(verts)}\nproperty double x\nproperty double y\nproperty double z\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in verts:
            f.write(f"{float(v[0])!r} {float(v[1])!r} {float(v[2])!r}\n")
        for t in faces:
            f.write(f"3 {int(t[0])} {int(t[1])} {int(t[2])}\n")


def skimage_mesh(vol_zyx, iso, method):
    import skimage
    from skimage import measure

    start = time.perf_counter()
    verts, faces, _, _ = measure.marching_cubes(vol_zyx, level=iso, method=method)
    return verts[:, ::-1], faces, time.perf_counter() - start, skimage.__version__


def vtk_mesh(data, dims, iso, flying):
    import vtk
    from vtk.util import numpy_support

    image = vtk.vtkImageData()
    image.SetDimensions(*dims)
    arr = numpy_support.numpy_to_vtk(data, deep=True, array_type=vtk.VTK_FLOAT)
    image.GetPointData().SetScalars(arr)
    f = vtk.vtkFlyingEdges3D() if flying else vtk.vtkMarchingCubes()
    f.SetInputData(image)
    f.SetValue(0, iso)
    if flying:
        f.ComputeNormalsOff()
        f.ComputeGradientsOff()
    else:
        f.ComputeNormalsOff()
        f.ComputeGradientsOff()
    start = time.perf_counter()
    f.Update()
    seconds = time.perf_counter() - start
    out = f.GetOutput()
    verts = numpy_support.vtk_to_numpy(out.GetPoints().GetData()) if out.GetNumberOfPoints() else np.zeros((0, 3))
    polys = numpy_support.vtk_to_numpy(out.GetPolys().GetData()) if out.GetNumberOfPolys() else np.zeros(0, dtype=int)
    faces = polys.reshape(-1, 4)[:, 1:]
    return verts, faces, seconds, vtk.vtkVersion.GetVTKVersion()


def pymcubes_mesh(vol_zyx, iso):
    import mcubes

    start = time.perf_counter()
    verts, faces = mcubes.marching_cubes(vol_zyx, iso)
    version = getattr(mcubes, "__version__", "installed")
    return verts[:, ::-1], faces, time.perf_counter() - start, version


def main():
    path, nx, ny, nz, iso, outdir = sys.argv[1:7]
    nx, ny, nz, iso = int(nx), int(ny), int(nz), float(iso)
    data = np.fromfile(path, dtype="<f4")
    if data.size != nx * ny * nz:
        raise SystemExit(f"{path}: {data.size} samples, expected {nx * ny * nz}")
    vol = data.reshape(nz, ny, nx)
    os.makedirs(outdir, exist_ok=True)
    programs = {
        "skimage_lewiner": lambda: skimage_mesh(vol, iso, "lewiner"),
        "skimage_lorensen": lambda: skimage_mesh(vol, iso, "lorensen"),
        "vtk_flying_edges": lambda: vtk_mesh(data, (nx, ny, nz), iso, True),
        "vtk_marching_cubes": lambda: vtk_mesh(data, (nx, ny, nz), iso, False),
        "pymcubes": lambda: pymcubes_mesh(vol, iso),
    }
    result = {}
    for name, run in programs.items():
        try:
            verts, faces, seconds, version = run()
            out = os.path.join(outdir, name + ".ply")
            write_ply(out, verts, faces)
            result[name] = {"path": out, "version": str(version), "seconds": seconds, "triangles": int(len(faces))}
        except Exception as e:  # a missing module or a failing program: reported, not fatal
            result[name] = {"error": f"{type(e).__name__}: {e}"}
    print(json.dumps(result))


if __name__ == "__main__":
    main()
