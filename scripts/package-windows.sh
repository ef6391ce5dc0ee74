#!/usr/bin/env bash
# scripts/package-windows.sh BIN_DIR: cross-compiles firmament.exe for Windows x64 with Debian's
# mingw-w64 and writes it into BIN_DIR (scripts/package windows-x64 calls it).  One self-contained
# executable: the libraries, built from Debian's source packages by scripts/windows-deps.sh, and the
# C/C++ runtimes are linked in statically, so no DLL travels with it.  Without OpenColorIO: the
# colour spaces of presets/ocio/config.ocio are compiled in (docs/decisions/2026-12-06-windows-build.md).
# Build folder: $FIRMAMENT_WINDOWS_BUILD (default build-windows/); the libraries are built once
# there, the executable incrementally.  The copyright files of the libraries go to BIN_DIR/../licenses.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
. "$ROOT/scripts/common.sh"
[ $# -eq 1 ] || { echo "usage: scripts/package-windows.sh BIN_DIR" >&2; exit 2; }
bin=$1
build=${FIRMAMENT_WINDOWS_BUILD:-$ROOT/build-windows}
FIRMAMENT_PACKAGES="cmake pkg-config mingw-w64 dpkg-dev" install_missing_packages

mkdir -p "$build"
"$ROOT/scripts/windows-deps.sh" "$build" >&2
prefix=$build/deps/prefix
# pkg-config finds only the cross-built libraries (cJSON, libpng), never the build machine's.
PKG_CONFIG_LIBDIR=$prefix/lib/pkgconfig PKG_CONFIG_SYSROOT_DIR=/ \
    cmake -S "$ROOT" -B "$build/firmament" -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/mingw-w64-x86_64.cmake" \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release -DFIRMAMENT_WERROR=ON -DFIRMAMENT_TESTS=OFF \
    -DFIRMAMENT_X86_64_V3=OFF -DFIRMAMENT_OCIO=OFF -DFIRMAMENT_PORTABLE=ON >/dev/null
cmake --build "$build/firmament" -j "$(nproc)" --target firmament >/dev/null
mkdir -p "$bin"
x86_64-w64-mingw32-strip -o "$bin/firmament.exe" "$build/firmament/firmament.exe"
licenses=$(dirname "$bin")/licenses
mkdir -p "$licenses"
for src in "$build"/deps/src/*/debian/copyright; do
    name=$(basename "$(dirname "$(dirname "$src")")")
    cp "$src" "$licenses/${name%%-[0-9]*}.copyright"
done
