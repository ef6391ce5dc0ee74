#!/usr/bin/env bash
# Issue 48 item 4's overcast and fog checks (tests/physics/test_overcast.c) with SCALE times the
# paths CI gives them (default 25: about 12 min of CPU): the same comparisons against
# adding-doubling and the measured overcast sky, each standard error SCALE^-1/2 of the test's.
#   bench/overcast.sh [SCALE] [CHECK]     (CHECK: one of the test's functions, e.g. fog_with_the_observer_inside)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
TEST=${TEST_OVERCAST:-$HERE/../build/tests/test_overcast}
FM_OVERCAST_PATHS=${1:-25} exec "$TEST" ${2:+"$2"}
