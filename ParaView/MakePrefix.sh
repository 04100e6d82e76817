#!/usr/bin/env bash
# Makes the prefix the ParaView plugin builds and runs against (Documentation/ParaView.md):
#   ParaView/MakePrefix.sh PREFIX PYTHON3_PARAVIEW_DEB
# Debian 12's python3-paraview (pvpython, ParaView's Python modules, the wrapping hierarchy of
# ParaView's VTK) conflicts with python3-vtk9, which the standalone build needs (both hold
# /usr/lib/python3/dist-packages/vtkmodules), and ParaView's CMake config refuses to load without
# those files. So the package is unpacked into PREFIX/usr instead of installed, and PREFIX/usr is
# completed with links to the installed paraview and paraview-dev files (CMake config, libraries,
# headers, tools): ParaView's config, found at PREFIX/usr/lib/<arch>/cmake/paraview-5.11, computes
# its paths from there and finds every file it names. Nothing outside PREFIX is written.
set -euo pipefail
prefix=$1
deb=$2
arch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)
lib=/usr/lib/$arch
rm -rf "$prefix"
mkdir -p "$prefix"
dpkg-deb -x "$deb" "$prefix"
mkdir -p "$prefix/usr/bin" "$prefix/usr/include" "$prefix$lib/cmake"
# A tree of links, not one link: the config files must sit under PREFIX to compute PREFIX.
cp -as "$lib/cmake/paraview-5.11" "$prefix$lib/cmake/"
ln -s /usr/include/paraview-5.11 "$prefix/usr/include/paraview-5.11"
# The libraries and tools of paraview and paraview-dev (files directly in usr/bin and the
# library folder; their subfolders are linked whole).
for f in $(dpkg -L paraview paraview-dev | grep -E "^(/usr/bin|$lib|$lib/paraview-5.11)/[^/]+\$"); do
  [ -e "$prefix$f" ] || [ -L "$prefix$f" ] || ln -s "$f" "$prefix$f"
done
echo "ParaView prefix ready: $prefix (ParaView_DIR=$prefix$lib/cmake/paraview-5.11)"
