#!/usr/bin/env bash
# Installs everything mixload builds and runs with, from Debian's packages only.
# Idempotent: a second call checks and returns in about a second.
#
# OpenFOAM: Debian ships v1912 binaries and shared libraries but no headers. We fetch Debian's own
# source package of the *same* version (so headers match the installed ABI) and build a flat include
# tree per source folder, as OpenFOAM's lnInclude does. The tree lives outside the build directory,
# under $MIXLOAD_OPENFOAM_HEADERS (default /opt/mixload/openfoam-headers).
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git
  libgtest-dev
  libeigen3-dev libsundials-dev libnlopt-cxx-dev libnlopt-dev
  libhdf5-dev hdf5-tools libgsl-dev libsqlite3-dev sqlite3
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev
  gnuplot-nox
  openfoam libopenfoam openmpi-bin libopenmpi-dev
  dpkg-dev xz-utils
)
HEADERS=${MIXLOAD_OPENFOAM_HEADERS:-/opt/mixload/openfoam-headers}

need_install=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need_install+=("$p")
done

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"

if [ ${#need_install[@]} -gt 0 ]; then
  echo "deps: installing ${need_install[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need_install[@]}" >/dev/null
fi

of_version=$(dpkg-query -W -f='${Version}' openfoam)
# The layout number changes whenever this script adds to the tree, so old trees are rebuilt.
tree_id="$of_version layout 2"
stamp="$HEADERS/.version"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$tree_id" ]; then
  exit 0
fi

echo "deps: building OpenFOAM $of_version include tree in $HEADERS"
src_list=/etc/apt/sources.list.d/mixload-deb-src.sources
if ! grep -rqs "deb-src" /etc/apt/sources.list /etc/apt/sources.list.d/; then
  # Same mirrors as the binary list, with Types: deb-src.
  sed 's/^Types: deb$/Types: deb-src/' /etc/apt/sources.list.d/debian.sources | $SUDO tee "$src_list" >/dev/null
  $SUDO apt-get update -qq
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
( cd "$work" && apt-get source --download-only -qq "openfoam=$of_version" >/dev/null )
orig=$(ls "$work"/openfoam_*.orig.tar.* | head -n 1)
mkdir -p "$work/src"
tar -xf "$orig" -C "$work/src" --strip-components=1 --wildcards '*/src/*' \
  '*/applications/solvers/multiphase/interFoam/*' '*/applications/solvers/multiphase/VoF/*' \
  '*/etc/*' 2>/dev/null || tar -xf "$orig" -C "$work/src" --strip-components=1

tmp_headers="$HEADERS.tmp.$$"
rm -rf "$tmp_headers"
mkdir -p "$tmp_headers"
# One flat folder per OpenFOAM library: every header (and template .C that headers include) found
# below that library's source folder, as wmake's lnInclude does.
for lib in OpenFOAM OSspecific/POSIX finiteVolume meshTools sampling dynamicFvMesh dynamicMesh \
           transportModels/incompressible transportModels/twoPhaseMixture transportModels/interfaceProperties \
           transportModels/immiscibleIncompressibleTwoPhaseMixture \
           TurbulenceModels/turbulenceModels TurbulenceModels/incompressible fileFormats surfMesh; do
  [ -d "$work/src/src/$lib" ] || continue
  dest="$tmp_headers/$lib"
  mkdir -p "$dest"
  find "$work/src/src/$lib" -type f \( -name '*.H' -o -name '*.C' -o -name '*.hxx' \) -print0 |
    while IFS= read -r -d '' f; do cp -n "$f" "$dest/" ; done
done
# interFoam itself, unmodified, for mixload to compile against the installed libraries: Debian's
# own /usr/bin/interFoam diverges on every mesh whose faces are not aligned with the axes (README,
# "Why mixload builds its own interFoam"). transportModels/ is kept as a tree too, because the
# solver includes some of its headers by relative path.
mkdir -p "$tmp_headers/solvers" "$tmp_headers/tree"
cp -r "$work/src/applications/solvers/multiphase/interFoam" "$tmp_headers/solvers/interFoam"
cp -r "$work/src/applications/solvers/multiphase/VoF" "$tmp_headers/solvers/VoF"
cp -r "$work/src/src/transportModels" "$tmp_headers/tree/transportModels"
echo "$tree_id" > "$tmp_headers/.version"
$SUDO mkdir -p "$(dirname "$HEADERS")"
rm -rf "$HEADERS"
mv "$tmp_headers" "$HEADERS"
echo "deps: OpenFOAM headers ready"
