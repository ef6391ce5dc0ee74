#!/usr/bin/env bash
# run.sh TARGET SEEDS REGRESSIONS CORPUS SECONDS: replays every regression input (each once crashed
# the target), then fuzzes for SECONDS from the seeds and the scratch corpus, with libFuzzer's
# random seed fixed (FM_FUZZ_SEED, 1) so that a CI run does the same work each time; longer runs
# with other seeds are for exploring by hand (tests/fuzz/README.md).  A crash fails the
# test and leaves its input (crash-*) in CORPUS/..; add it to REGRESSIONS once fixed.
set -eu
target=$(realpath "$1") seeds=$(realpath "$2") regressions=$(realpath -m "$3") corpus=$(realpath -m "$4") seconds=$5
mkdir -p "$corpus"
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
if [ -n "$(ls -A "$regressions" 2>/dev/null)" ]; then
    "$target" -runs=0 "$regressions"/* >"$corpus.regressions.log" 2>&1 ||
        { tail -n 40 "$corpus.regressions.log"; echo "FAIL: a regression input crashes $target"; exit 1; }
fi
cd "$(dirname "$corpus")"
"$target" -seed="${FM_FUZZ_SEED:-1}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
    "$corpus" "$seeds" >"$corpus.log" 2>&1 || { tail -n 60 "$corpus.log"; echo "FAIL: $target crashed"; exit 1; }
grep -E 'stat::number_of_executed_units|stat::new_units_added' "$corpus.log" || true
echo "corpus: $(ls "$corpus" | wc -l) inputs"
