# Shared by the scripts in this folder: install what is missing, and build.  Sourced, not run.

# Debian/Ubuntu packages firmament needs to build and test (nothing else is downloaded).
FIRMAMENT_PACKAGES="build-essential cmake pkg-config libopenexr-dev libcjson-dev libcmocka-dev libopencolorio-dev libpng-dev"

install_missing_packages() {
    local missing=""
    for p in $FIRMAMENT_PACKAGES "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
    done
    [ -z "$missing" ] && return 0
    echo "installing:$missing"
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends $missing
}

# build DIR [cmake options...]: configure (once) and build everything in DIR.
build() {
    local dir=$1
    shift
    cmake -S "$ROOT" -B "$ROOT/$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
    cmake --build "$ROOT/$dir" -j "$(nproc)"
}
