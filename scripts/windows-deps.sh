#!/usr/bin/env bash
# Cross-builds the libraries firmament.exe links (static, for Windows x64, with Debian's mingw-w64)
# from Debian's own source packages (`apt-get source`): zlib, Imath, OpenEXR, cJSON, libpng.
# Usage: scripts/windows-deps.sh BUILD_DIR -> BUILD_DIR/deps/prefix.  Each library is built once:
# a stamp file per library makes a rerun skip it (delete BUILD_DIR/deps to start over).
# OpenColorIO is not among them (docs/decisions/2026-12-06-windows-build.md says why).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DEPS=$(mkdir -p "$1/deps" && cd "$1/deps" && pwd)
SRC=$DEPS/src
PREFIX=$DEPS/prefix
TOOLCHAIN=$ROOT/cmake/mingw-w64-x86_64.cmake
HOST=x86_64-w64-mingw32
jobs=$(nproc)
SUITE=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")
mkdir -p "$SRC" "$PREFIX" "$DEPS/stamp"

# The deb-src entry for the mirror apt already uses (deb822 .sources or one-line .list files).
ensure_deb_src() {
    apt-cache showsrc zlib 2>/dev/null | grep -q '^Package:' && return 0
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    if [ -f /etc/apt/sources.list.d/debian.sources ]; then
        sed 's/^Types: deb$/Types: deb-src/' /etc/apt/sources.list.d/debian.sources |
            $sudo tee /etc/apt/sources.list.d/firmament-deb-src.sources >/dev/null
    else
        grep -hs '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list | sed 's/^deb /deb-src /' |
            $sudo tee /etc/apt/sources.list.d/firmament-deb-src.list >/dev/null
    fi
    $sudo apt-get update -qq
}

# fetch PACKAGE: Debian's source package, unpacked with Debian's patches, once; prints its folder.
fetch() {
    local dir
    dir=$(find "$SRC" -maxdepth 1 -type d -name "$1-[0-9]*" | head -n 1)
    if [ -z "$dir" ]; then
        # from the release's own suite: the security suite's newer versions may list sources its
        # mirror does not hold
        (cd "$SRC" && apt-get source -qq "$1/$SUITE" >/dev/null 2>&1) ||
            { echo "apt-get source $1/$SUITE failed" >&2; exit 1; }
        dir=$(find "$SRC" -maxdepth 1 -type d -name "$1-[0-9]*" | head -n 1)
    fi
    echo "$dir"
}

# cmake_dep NAME PACKAGE [cmake options...]: configure, build and install one static library.
cmake_dep() {
    local name=$1 pkg=$2
    shift 2
    [ -f "$DEPS/stamp/$name" ] && return 0
    local src start=$SECONDS
    src=$(fetch "$pkg")
    rm -rf "$DEPS/build/$name"
    cmake -S "$src" -B "$DEPS/build/$name" -DCMAKE_TOOLCHAIN_FILE="$TOOLCHAIN" -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_INSTALL_PREFIX="$PREFIX" -DCMAKE_PREFIX_PATH="$PREFIX" -DBUILD_SHARED_LIBS=OFF \
        -DBUILD_TESTING=OFF -DFETCHCONTENT_FULLY_DISCONNECTED=ON "$@" >"$DEPS/build-$name.log" 2>&1
    cmake --build "$DEPS/build/$name" -j "$jobs" >>"$DEPS/build-$name.log" 2>&1
    cmake --install "$DEPS/build/$name" >>"$DEPS/build-$name.log" 2>&1
    touch "$DEPS/stamp/$name"
    echo "$name: $((SECONDS - start)) s"
}

# zlib compiled file by file into the plain static libz.a that OpenEXR and libpng look for (Debian's
# source drops upstream's win32/ makefiles; zlib's CMake names its static library zlibstatic).
zlib_dep() {
    [ -f "$DEPS/stamp/zlib" ] && return 0
    local src start=$SECONDS f
    src=$(fetch zlib)
    rm -rf "$DEPS/build/zlib" && mkdir -p "$DEPS/build/zlib" "$PREFIX/include" "$PREFIX/lib"
    for f in adler32 compress crc32 deflate gzclose gzlib gzread gzwrite infback inffast inflate inftrees trees \
             uncompr zutil; do
        $HOST-gcc-posix -O2 -c "$src/$f.c" -o "$DEPS/build/zlib/$f.o"
    done
    $HOST-ar rcs "$PREFIX/lib/libz.a" "$DEPS/build/zlib"/*.o
    cp "$src/zlib.h" "$src/zconf.h" "$PREFIX/include/"
    mkdir -p "$PREFIX/lib/pkgconfig" # for libpng's pkg-config file, which requires zlib
    printf 'prefix=%s\nName: zlib\nDescription: zlib\nVersion: 1.2.13\nLibs: -L${prefix}/lib -lz\nCflags: -I${prefix}/include\n' \
        "$PREFIX" >"$PREFIX/lib/pkgconfig/zlib.pc"
    touch "$DEPS/stamp/zlib"
    echo "zlib: $((SECONDS - start)) s"
}

ensure_deb_src
zlib_dep
cmake_dep imath imath -DPYTHON=OFF
cmake_dep openexr openexr -DOPENEXR_BUILD_TOOLS=OFF -DOPENEXR_INSTALL_EXAMPLES=OFF -DOPENEXR_INSTALL_TOOLS=OFF \
    -DZLIB_ROOT="$PREFIX" -DZLIB_LIBRARY="$PREFIX/lib/libz.a" -DZLIB_INCLUDE_DIR="$PREFIX/include"
cmake_dep cjson cjson -DENABLE_CJSON_TEST=OFF -DENABLE_CJSON_UTILS=OFF -DENABLE_CUSTOM_COMPILER_FLAGS=OFF \
    -DBUILD_SHARED_AND_STATIC_LIBS=OFF
cmake_dep libpng libpng1.6 -DPNG_SHARED=OFF -DPNG_STATIC=ON -DPNG_TESTS=OFF -DPNG_EXECUTABLES=OFF \
    -DZLIB_LIBRARY="$PREFIX/lib/libz.a" -DZLIB_INCLUDE_DIR="$PREFIX/include"
echo "dependencies in $PREFIX"
