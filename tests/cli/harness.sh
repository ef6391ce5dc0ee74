# Shared by the CLI test scripts (sourced, not run): a scratch directory, the pass/fail counters and
# the check that bad input is refused with exit 2, one "firmament:" line and nothing written.
# Needs FM, the executable's absolute path.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
checks=0

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { checks=$((checks + 1)); }

# no file of any kind left in $work/out (a clean directory per case)
expect_empty_dir() {
    local left
    left=$(ls -A "$work/out")
    if [ -n "$left" ]; then fail "$1: files left behind: $left"; else ok; fi
}

# expect_usage_error "description" args...: exit 2, exactly one stderr line starting "firmament:"
expect_usage_error() {
    local what=$1
    shift
    rm -rf "$work/out" && mkdir -p "$work/out"
    (cd "$work/out" && "$FM" "$@" >"$work/stdout" 2>"$work/stderr")
    local rc=$?
    local lines
    lines=$(wc -l <"$work/stderr")
    if [ $rc -ne 2 ]; then fail "$what: exit $rc, expected 2"; else ok; fi
    if [ "$lines" -ne 1 ] || ! grep -q '^firmament: ' "$work/stderr"; then
        fail "$what: expected one 'firmament:' line on stderr, got: $(cat "$work/stderr")"
    else ok; fi
    expect_empty_dir "$what"
}

