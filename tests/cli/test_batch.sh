#!/usr/bin/env bash
# firmament batch plan / run (docs/batch.md): manifests from a date range and from a product, jobs
# rendered as `render` renders them, reruns that skip only finished jobs, bad manifests refused.
# Usage: test_batch.sh path/to/firmament
set -u
FM=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
. "$here/harness.sh"

cd "$work"
tiny=(--set width=32 --set quality=preview)

# --- plan: every hour of two June days in Paris with the sun above the horizon ---------------------
# Paris on 2025-06-21/22: sunrise 05:46-05:47 and sunset 21:58 CEST (timeanddate.com, Paris), i.e.
# 04:46 and 20:58 at +01:00: the hours 05:00 ... 20:00 have the sun up, 16 a day.
# year/ does not exist: plan makes the manifest's folder and the maps' (year/maps), as mkdir -p
"$FM" batch plan -o year/m.jsonl --preset clear-noon --place paris,48.8566,2.3522,+01:00 \
    --date-start 2025-06-21 --date-end 2025-06-22 --time-start 00:00 --time-end 23:00 --step 60 \
    --sun-above 0 "${tiny[@]}" >/dev/null || fail "plan with --sun-above failed"
[ -d year/maps ] && ok || fail "plan: year/maps was not made"
n=$(wc -l <year/m.jsonl)
[ "$n" -eq 32 ] && ok || fail "plan: $n jobs for two days, expected 16 + 16"
python3 - year/m.jsonl <<'EOF' && ok || fail "plan: jobs' keys"
import json, sys
jobs = [json.loads(l) for l in open(sys.argv[1])]
hours = sorted({j["time"] for j in jobs})
assert hours[0] == "05:00:00" and hours[-1] == "20:00:00", hours
assert [j["seed"] for j in jobs] == list(range(32))
assert len({j["output"] for j in jobs}) == 32
for j in jobs:
    assert j["preset"] == "clear-noon" and j["width"] == 32 and j["latitude"] == 48.8566
    assert j["output"].startswith("maps/") and j["sidecar"] == j["output"][:-4] + ".json"
EOF

# --- plan: presets x places x times --------------------------------------------------------------
"$FM" batch plan -o prod.jsonl --out-dir prod --preset clear-noon --preset hazy-desert \
    --place paris,48.8566,2.3522,+01:00 --place cairo,30.04,31.24,+02:00 --date 2025-03-20 \
    --times 09:00,12:00,15:00 "${tiny[@]}" >/dev/null || fail "product plan failed"
[ "$(wc -l <prod.jsonl)" -eq 12 ] && ok || fail "product: $(wc -l <prod.jsonl) jobs, expected 2 x 2 x 3"
[ -d prod ] && ok || fail "product: the output folder was not made"

# --- run: the jobs are the maps `render` makes; the same bits on any thread count ------------------
"$FM" batch run prod.jsonl --index 0 --count 12 --threads 2 >run.out || fail "batch run failed"
grep -q '^batch: 12 rendered, 0 skipped, 0 failed' run.out && ok || fail "batch run: $(tail -1 run.out)"
python3 - prod.jsonl <<'EOF' && ok || fail "sidecars do not record their jobs"
import json, sys
for line in open(sys.argv[1]):
    job = json.loads(line)
    side = json.load(open(job["sidecar"]))
    assert side["job"] == job, (side.get("job"), job)
    assert side["parameters"]["seed"] == job["seed"]
    assert side["parameters"]["time"] == job["time"]
EOF
job=$(sed -n 11p prod.jsonl)   # hazy-desert in Cairo at 12:00, seed 10
mkdir direct
out=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["output"])' "$job")
args=$(python3 -c 'import json,sys; j = json.loads(sys.argv[1]); print(*(f"--{k} {j[k]}" for k in
       ("preset", "latitude", "longitude", "utc_offset", "date", "time", "seed")))' "$job" | tr _ -)
# shellcheck disable=SC2086
"$FM" render $args --width 32 --quality preview -o "direct/$(basename "$out")" --threads 1 || fail "direct render failed"
cmp -s "direct/$(basename "$out")" "$out" && ok || fail "job 10 differs from the same render by 'firmament render'"
mkdir -p t1 && sed 's#"prod/#"t1/#g' prod.jsonl >t1.jsonl
"$FM" batch run t1.jsonl --index 0 --count 12 --threads 1 >/dev/null || fail "batch run --threads 1 failed"
same=0
for f in prod/*.exr; do cmp -s "$f" "t1/$(basename "$f")" && same=$((same + 1)); done
[ "$same" -eq 12 ] && ok || fail "threads 2 vs 1: $same of 12 maps identical"

# --- rerun with --skip-existing: only what is missing or changed ----------------------------------
touch -d '2000-01-01' prod/*
rm prod/hazy-desert_cairo_20250320_1200.exr                        # job 10: its map lost
sed -i '4s/"seed":3,/"seed":99,/' prod.jsonl                      # job 3: another job now
"$FM" batch run prod.jsonl --index 0 --count 12 --skip-existing >rerun.out || fail "rerun failed"
grep -q '^batch: 2 rendered, 10 skipped, 0 failed' rerun.out && ok || fail "rerun: $(tail -1 rerun.out)"
grep -q '^job 3: rendered' rerun.out && grep -q '^job 10: rendered' rerun.out && ok || fail "rerun: $(cat rerun.out)"
[ "$(find prod -type f -newermt 2001-01-01 | wc -l)" -eq 4 ] && ok ||
    fail "rerun touched other files: $(find prod -newermt 2001-01-01)"
# a count past the end is cut at the end (an array's last task)
"$FM" batch run prod.jsonl --index 10 --count 5 --skip-existing >tail.out && ok || fail "last task failed"
grep -q '^batch: 0 rendered, 2 skipped' tail.out && ok || fail "last task: $(tail -1 tail.out)"

# --- an interrupted run leaves finished jobs and no partial file ---------------------------------
"$FM" batch plan -o int.jsonl --out-dir int --place paris,48.8566,2.3522,+01:00 --date 2025-06-21 --times 12:00,13:00,14:00,15:00 \
    --set width=512 --set quality=final >/dev/null
"$FM" batch run int.jsonl --index 0 --count 4 --threads 1 >int.out 2>int.err &
pid=$!
for _ in $(seq 1 600); do [ -e int/paris_20250621_1200.json ] && break; sleep 0.1; done
sleep 0.5
kill -TERM $pid
wait $pid
rc=$?
[ $rc -eq 143 ] && ok || fail "interrupted batch run: exit $rc, expected 143"
[ -e int/paris_20250621_1200.exr ] && ok || fail "interrupted: the finished job's map is gone"
[ -z "$(ls -A int | grep -v '^paris_20250621_1200\.')" ] && ok || fail "interrupted: files left: $(ls -A int)"

# --- bad input: one line, exit 2, nothing written ------------------------------------------------
printf '%s\n' "$(sed -n 1p prod.jsonl)" '{"output": "x.exr", "turbidity": "lots"}' >bad.jsonl
expect_usage_error "a bad value in a manifest" batch run "$work/bad.jsonl" --index 0
grep -q 'line 2' "$work/stderr" && grep -q -- '--turbidity' "$work/stderr" && ok || fail "bad value: $(cat "$work/stderr")"
printf '{"output": "x.exr", "colour": 3}\n' >bad.jsonl
expect_usage_error "an unknown key" batch run "$work/bad.jsonl" --index 0
grep -q "line 1: key 'colour'" "$work/stderr" && ok || fail "unknown key: $(cat "$work/stderr")"
printf '{"output": "x.exr"}\nnot json\n' >bad.jsonl
expect_usage_error "a line that is not JSON" batch run "$work/bad.jsonl" --index 0
grep -q 'line 2: not a JSON object' "$work/stderr" && ok || fail "not JSON: $(cat "$work/stderr")"
expect_usage_error "an index past the end" batch run "$work/prod.jsonl" --index 12
expect_usage_error "no manifest" batch run "$work/none.jsonl" --index 0
expect_usage_error "a bad place" batch plan -o m.jsonl --place paris,48.8,500,+01:00
expect_usage_error "--sun-above without a place" batch plan -o m.jsonl --sun-above 0 --date 2025-01-01 --times 12:00
expect_usage_error "a bad --set value" batch plan -o m.jsonl --set turbidity=-1
expect_usage_error "a bad --set value, into new folders (none made)" batch plan -o new/m.jsonl --set turbidity=-1
touch "$work/a-file"
expect_usage_error "a manifest's folder that is a file" batch plan -o "$work/a-file/m.jsonl"
grep -qF -- "-o: cannot create the folder '$work/a-file'" "$work/stderr" && ok || fail "folder error: $(cat "$work/stderr")"

echo "test_batch: $checks checks, $failures failures"
[ "$failures" -eq 0 ]
