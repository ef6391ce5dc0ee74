#!/usr/bin/env bash
# firmament batch slurm on a real one-node Slurm cluster (cluster.sh: munge, slurmctld, slurmd on
# 127.0.0.1): a 48-job manifest as an array of 12 tasks with at most 2 running, every map and sidecar
# checked; then a second array with one running task cancelled (scancel), resubmitted with
# --skip-existing: only the missing jobs run, no partial file is left; every map the same bits as a
# local `batch run`.  Skipped (77) without slurm-wlm and munge, or when not root (slurmd is).
# Usage: test_slurm.sh path/to/firmament
set -u
FM=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
for c in munged slurmctld slurmd sbatch squeue scancel sinfo; do
    command -v $c >/dev/null || { echo "skipped: $c is not installed (Debian: slurm-wlm, munge)"; exit 77; }
done
[ "$(id -u)" -eq 0 ] || { echo "skipped: slurmd must run as root"; exit 77; }
. "$here/cluster.sh"
. "$here/../cli/harness.sh"
trap 'cluster_stop; rm -rf "$work"' EXIT
cluster_start "$work/cluster" 2 || exit 1
cd "$work"
now() { date +%s.%N; }

# submit SCRIPT_ARGS...: submits, prints the array's id
submit() {
    "$FM" batch slurm "$@" --submit >submit.out || { fail "batch slurm $*: $(cat submit.out)"; return 1; }
    sed -n 's/^submitted job array \([0-9]*\);.*/\1/p' submit.out
}
# same_bits DIR1 DIR2: every map of DIR1 is in DIR2 with the same bytes
same_bits() {
    local n=0 same=0 f
    for f in "$1"/*.exr; do
        n=$((n + 1))
        cmp -s "$f" "$2/$(basename "$f")" && same=$((same + 1))
    done
    [ "$n" -gt 0 ] && [ "$same" -eq "$n" ] && ok || fail "$1 vs $2: $same of $n maps identical"
}
# sidecars_match MANIFEST: every job's map exists and its sidecar records the job
sidecars_match() {
    python3 - "$1" <<'PY' && ok || fail "$1: maps or sidecars missing or not of their jobs"
import json, os, sys
for line in open(sys.argv[1]):
    job = json.loads(line)
    assert os.path.getsize(job["output"]) > 0, job["output"]
    assert json.load(open(job["sidecar"]))["job"] == job, job["sidecar"]
PY
}

# --- 1. 48 jobs, 12 tasks of 4, at most 2 at once ------------------------------------------------
times=07:00,08:00,09:00,10:00,11:00,12:00,13:00,14:00,15:00,16:00,17:00,18:00
"$FM" batch plan -o a.jsonl --out-dir a --preset clear-noon --preset golden-hour \
    --place paris,48.8566,2.3522,+01:00 --place cairo,30.04,31.24,+02:00 --date 2025-06-21 --times $times \
    --set width=16 --set quality=preview >/dev/null
[ "$(wc -l <a.jsonl)" -eq 48 ] && ok || fail "manifest: $(wc -l <a.jsonl) jobs, expected 48"
t0=$(now)
id=$(submit a.jsonl --jobs-per-task 4 --max-concurrent 2)
grep -q '^#SBATCH --array=0-11%2$' a.sbatch && ok || fail "a.sbatch: $(grep array a.sbatch)"
most=0
while [ -n "$(squeue -h -j "$id" -o %i 2>/dev/null)" ]; do
    r=$(squeue -h -j "$id" -t R -o %i | wc -l)
    [ "$r" -gt "$most" ] && most=$r
    sleep 0.2
done
t1=$(now)
[ "$most" -ge 1 ] && [ "$most" -le 2 ] && ok || fail "array: up to $most tasks ran at once, expected 1 or 2"
sidecars_match a.jsonl
logs=$(ls slurm-"$id"_*.out 2>/dev/null | wc -l)
[ "$logs" -eq 12 ] && ok || fail "$logs task logs, expected 12"
[ "$(cat slurm-"$id"_*.out | grep -c '^batch: 4 rendered, 0 skipped, 0 failed')" -eq 12 ] && ok ||
    fail "tasks: $(grep -h '^batch:' slurm-"$id"_*.out | sort | uniq -c)"
# the same manifest in one local process
mkdir b && sed 's#"a/#"b/#g' a.jsonl >b.jsonl
t2=$(now)
"$FM" batch run b.jsonl --index 0 --count 48 --threads 1 >b.out || fail "local batch run failed"
t3=$(now)
same_bits a b
python3 -c "import sys; s, l = float(sys.argv[2]) - float(sys.argv[1]), float(sys.argv[4]) - float(sys.argv[3])
print('48 jobs: Slurm array (12 tasks of 4, 2 at once) %.1f s = %.0f jobs/min; local batch run %.1f s = %.0f jobs/min'
      % (s, 48 * 60 / s, l, 48 * 60 / l))" "$t0" "$t1" "$t2" "$t3"

# --- 2. one running task cancelled, the array resubmitted with --skip-existing --------------------
"$FM" batch plan -o c.jsonl --out-dir c --place paris,48.8566,2.3522,+01:00 --date 2025-06-21 \
    --times 08:00,09:00,10:00,11:00,12:00,13:00,14:00,15:00,16:00,17:00,18:00,19:00 \
    --set width=32 --set quality=preview --set sample_scale=3 >/dev/null
id=$(submit c.jsonl --jobs-per-task 4 --max-concurrent 2)
# task 0 cancelled once its first job is done and its second started
first=c/paris_20250621_0800.json
for _ in $(seq 1 1500); do [ -e "$first" ] && break; sleep 0.2; done
[ -e "$first" ] && ok || fail "task 0 finished no job"
sleep 1
scancel "${id}_0"
cluster_wait "$id" 600 || fail "the second array did not finish"
missing=$(python3 -c 'import json, os, sys; print(sum(not os.path.exists(json.loads(l)["sidecar"]) for l in open(sys.argv[1])))' c.jsonl)
[ "$missing" -ge 1 ] && [ "$missing" -le 3 ] && ok || fail "after scancel: $missing jobs missing, expected 1 to 3"
[ -z "$(ls -A c | grep -v '^paris_.*\.\(exr\|json\)$')" ] && ok || fail "partial files left: $(ls -A c)"
for f in c/*.exr c/*.json; do [ -e "${f%.*}.exr" ] && [ -e "${f%.*}.json" ] || fail "$f without its pair"; done
stat -c '%n %i %Y' c/* >before.txt
id2=$(submit c.jsonl --jobs-per-task 4 --max-concurrent 2 --skip-existing -o c2.sbatch)
cluster_wait "$id2" 600 || fail "the resubmitted array did not finish"
sidecars_match c.jsonl
rendered=$(cat slurm-"$id2"_*.out | awk '/^batch: / { n += $2 } END { print n + 0 }')
[ "$rendered" = "$missing" ] && ok || fail "resubmitted: $rendered jobs rendered, $missing were missing"
while read -r name inode mtime; do
    [ "$(stat -c '%i %Y' "$name")" = "$inode $mtime" ] || fail "$name was rewritten by the resubmission"
done <before.txt
mkdir d && sed 's#"c/#"d/#g' c.jsonl >d.jsonl
"$FM" batch run d.jsonl --index 0 --count 12 --threads 1 >/dev/null || fail "local batch run of c failed"
same_bits c d

echo "test_slurm: $checks checks, $failures failures"
[ "$failures" -eq 0 ]
