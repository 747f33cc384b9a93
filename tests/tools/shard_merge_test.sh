#!/usr/bin/env bash
# Sharded studies and batch evaluations (issue 25 item 5, chapters/commands.md "Past one
# machine"): shards run by GNU parallel as separate local processes, `legkit merge` of them gives
# byte for byte the single-machine study's and eval's table and files; bad --shard values, shards
# of different runs, a missing, doubled or truncated shard and a bad log among good ones are
# refused with a clear error and the documented exit code, and nothing is merged.
# tools/slurm/submit.sh is run too, on a stand-in sbatch that runs each job at once (Slurm itself
# cannot run here): the array's tasks as Slurm starts them, then the dependent merge.
#   shard_merge_test.sh LEGKIT SOURCE_DIR   (exit 77: GNU parallel is not installed: skipped)
set -uo pipefail
legkit=${1:?usage: shard_merge_test.sh path/to/legkit source/dir}
source_dir=${2:?usage: shard_merge_test.sh path/to/legkit source/dir}
legkit=$(realpath "$legkit") && source_dir=$(realpath "$source_dir") || exit 1
[[ -x $legkit ]] || { echo "$legkit: not a program"; exit 1; }
if ! command -v parallel > /dev/null; then
  echo "GNU parallel is not installed (tools/setup-debian.sh installs it): skipped"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0

fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}
# expect STATUS TEXT COMMAND...: the command exits STATUS and its standard error contains TEXT.
expect() {
  local status=$1 text=$2
  shift 2
  "$@" > out.txt 2> err.txt
  local got=$?
  if [[ $got != "$status" ]]; then
    fail "$* exited $got, expected $status: $(tail -n 3 err.txt)"
  elif ! grep -qF -- "$text" err.txt; then
    fail "$*: the error does not say '$text': $(tail -n 3 err.txt)"
  fi
}
same() {
  cmp -s "$1" "$2" || fail "$1 and $2 differ"
}

# Each Monte Carlo study on one machine, then as shards run in parallel, merged in any order.
check_study() {  # NAME N ARGS...: the study NAME as N shards against its single-machine run
  local name=$1 n=$2
  shift 2
  local run=("$legkit" study "$name" --no-plots "$@")
  # on every core, the shards one thread each: the result depends on neither
  "${run[@]}" --out "$name" > "$name.txt" 2> /dev/null || fail "study $name failed"
  parallel "${run[@]}" --threads 1 --shard "{}/$n" --out "$name-$n-{}" ::: $(seq "$n") \
    > /dev/null 2>&1 || fail "parallel: a shard of study $name failed"
  mapfile -t shards < <(seq "$n" -1 1 | sed "s/^/$name-$n-/")
  "$legkit" merge "$name-merged" "${shards[@]}" --no-plots > "$name-merged.txt" ||
    fail "legkit merge of study $name failed"
  same "$name.txt" "$name-merged.txt"
  same "$name/$name.csv" "$name-merged/$name.csv"
}
check_study convergence 2 --runs 2 --duration 5.1
check_study sweep 2 --runs 3 --duration 1

# The physics studies (MuJoCo: the shortest runs that split), sharded over their scenarios (slip:
# and, as the last item, its contact-source comparison: 1 + 2 items) and fault cases. Their tables name their
# output folder: the single-machine run's folder is moved aside and the merge writes one of the
# same name, so that the two standard outputs compare byte for byte.
check_physics() {  # NAME N FILES ARGS...: the study NAME as N shards, FILES compared
  local name=$1 n=$2 files=$3
  shift 3
  local run=("$legkit" study "$name" --no-plots "$@")
  "${run[@]}" --out "$name" > "$name.txt" 2> /dev/null || fail "study $name failed"
  mv "$name" "$name-whole"
  parallel "${run[@]}" --shard "{}/$n" --out "$name-$n-{}" ::: $(seq "$n") > /dev/null 2>&1 ||
    fail "parallel: a shard of study $name failed"
  mapfile -t shards < <(seq "$n" -1 1 | sed "s/^/$name-$n-/")
  "$legkit" merge "$name" "${shards[@]}" --no-plots > "$name-merged.txt" ||
    fail "legkit merge of study $name failed"
  same "$name.txt" "$name-merged.txt"
  for f in $files; do same "$name-whole/$f" "$name/$f"; done
}
check_physics contact 2 "contact.csv contact-trace.csv" --duration 1 \
  --scenarios physics-stand,physics-trot
check_physics slip 2 "slip.csv slip-sources.csv slip-terrain.csv slip-trace.csv" --duration 1 \
  --scenarios physics-ice,physics-trot --filters invariant-ekf
# study faults prints its table and writes no files; its shards write theirs into --out.
"$legkit" study faults > faults.txt || fail "study faults failed"
parallel "$legkit" study faults --shard "{}/2" --out "faults-2-{}" ::: 1 2 > /dev/null 2>&1 ||
  fail "parallel: a shard of study faults failed"
"$legkit" merge faults-merged faults-2-2 faults-2-1 > faults-merged.txt ||
  fail "legkit merge of study faults failed"
same faults.txt faults-merged.txt
# What cannot be split, or not that finely, is refused before anything is run or written.
expect 1 "nothing to split" "$legkit" study fusion --shard 2/2 --quick --out fusion-bad
expect 1 "only 2 scenarios" "$legkit" study contact --scenarios physics-stand,physics-trot \
  --shard 3/3 --out contact-bad
expect 1 "only 7 fault cases" "$legkit" study faults --shard 8/8 --out faults-bad
expect 1 "--out" "$legkit" study faults --out faults-bad
for bad in fusion-bad contact-bad faults-bad; do [[ -e $bad ]] && fail "a refused study wrote $bad"; done
# Their shards, when they cannot be merged: exit 2 naming the folder, nothing written.
cp -r contact-2-2 contact-cut
head -n 5 contact-2-2/rows.csv > contact-cut/rows.csv
expect 2 "contact-cut/rows.csv" "$legkit" merge pm contact-2-1 contact-cut
expect 2 "kind" "$legkit" merge pm slip-2-1 contact-2-2
expect 2 "shard 2/2 missing" "$legkit" merge pm slip-2-1
cp -r faults-2-2 faults-other
sed -i 's/"case": "FR force sensor/"case": "XX force sensor/' faults-other/shard.json
expect 2 "faults-other/shard.json" "$legkit" merge pm faults-2-1 faults-other
[[ -e pm ]] && fail "a refused merge of physics shards wrote its output folder"

# study consistency as 2 and 3 shards (blocks of 2+2 and 1+1+2 runs); its shards are the ones the
# refusals below are tried on.
study=("$legkit" study consistency --runs 4 --duration 2 --no-plots --threads 1)
"${study[@]}" --out whole > whole.txt 2> /dev/null || fail "the single-machine study failed"
for n in 2 3; do
  parallel "${study[@]}" --shard "{}/$n" --out "s$n-{}" ::: $(seq "$n") > /dev/null 2>&1 ||
    fail "parallel: a shard of $n failed"
  mapfile -t shards < <(seq "$n" -1 1 | sed "s/^/s$n-/")  # given in any order
  "$legkit" merge "merged$n" "${shards[@]}" --no-plots > "merged$n.txt" ||
    fail "legkit merge of $n shards failed"
  same whole.txt "merged$n.txt"
  same whole/consistency.csv "merged$n/consistency.csv"
done

# The Slurm job array and its dependent merge (tools/slurm/), on a stand-in sbatch.
mkdir stub
cat > stub/sbatch << 'STUB'
#!/usr/bin/env bash
# Slurm's sbatch, as far as submit.sh uses it: runs the job array's tasks (or --wrap) at once.
array='' wrap=''
while (($#)); do
  case $1 in
    --array=*) array=${1#--array=} ;;
    --wrap=*) wrap=${1#--wrap=} ;;
    --*) ;;
    *) break ;;
  esac
  shift
done
if [[ -n $wrap ]]; then
  bash -c "$wrap" > slurm-merge.txt 2>&1 || exit 1
  echo 102
  exit 0
fi
script=$1
shift
for ((i = 1; i <= ${array#1-}; ++i)); do
  SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_COUNT=${array#1-} bash "$script" "$@" > /dev/null 2>&1 ||
    exit 1
done
echo 101
STUB
chmod +x stub/sbatch
PATH="$PWD/stub:$PATH" bash "$source_dir/tools/slurm/submit.sh" 3 slurm "${study[@]}" > /dev/null ||
  fail "tools/slurm/submit.sh failed"
same whole.txt slurm-merge.txt
same whole/consistency.csv slurm/merged/consistency.csv

# Bad --shard values: exit 1 naming the option.
for bad in 0/2 3/2 a/2 1/0 2 1/2/3 -1/2 "" 1/10001; do
  expect 1 "--shard" "${study[@]}" --shard "$bad" --out bad
done
expect 1 "only 4 runs" "${study[@]}" --shard 5/5 --out bad

# Shards that cannot be merged: exit 2, and nothing written.
expect 2 "shard 2/2 missing" "$legkit" merge m s2-1
expect 2 "given twice" "$legkit" merge m s2-1 s2-1 s2-2
expect 2 "shards of different splits" "$legkit" merge m s2-1 s3-2
expect 2 "kind" "$legkit" merge m s2-1 convergence-2-2
"${study[@]}" --seed 7 --shard 2/2 --out seed7 > /dev/null 2>&1
expect 2 "option 'seed'" "$legkit" merge m s2-1 seed7
"${study[@]}" --correct-yaw --shard 2/2 --out plain > /dev/null 2>&1
expect 2 "option 'correct_yaw'" "$legkit" merge m s2-1 plain
cp -r s2-2 version
sed -i 's/"legkit_version": "[^"]*"/"legkit_version": "0.0.0"/' version/shard.json
expect 2 "legkit_version" "$legkit" merge m s2-1 version
cp -r s2-2 cut
head -c 20000 s2-2/rows.csv > cut/rows.csv
expect 2 "cut/rows.csv" "$legkit" merge m s2-1 cut
expect 2 "no shard.json" "$legkit" merge m s2-1 whole
[[ -e m ]] && fail "a refused merge wrote its output folder"

# legkit eval over a folder of logs with one bad log among good ones.
mkdir logs
for seed in 1 2 3; do
  "$legkit" sim --scenario trot --duration 2 --seed "$seed" --out "logs/trot$seed.csv" > /dev/null ||
    fail "legkit sim failed"
done
cp logs/trot2.csv logs/broken.csv
sed -i '40s/^\([^,]*\),[^,]*,/\1,oops,/' logs/broken.csv
"$legkit" config --print > settings.yaml || fail "legkit config --print failed"
config=settings.yaml
expect 2 "logs/broken.csv:40" "$legkit" eval logs --config "$config" --out ewhole
cp out.txt ewhole.txt
grep -q "trot3.csv" ewhole.txt || fail "eval: the good logs after the bad one did not finish"
grep -q "broken.csv.*FAILED" ewhole.txt || fail "eval: the bad log's row does not say FAILED"
parallel "$legkit" eval logs --config "$config" --shard "{}/2" --out "e-{}" ::: 1 2 > /dev/null 2>&1
[[ $? == 1 ]] || fail "parallel eval: exactly the shard with the bad log should fail"
expect 2 "logs/broken.csv:40" "$legkit" merge emerged e-2 e-1
same ewhole.txt out.txt
same ewhole/eval.csv emerged/eval.csv
rm logs/broken.csv
expect 0 "" "$legkit" eval logs --config "$config" --out egood
expect 1 "only 3 logs" "$legkit" eval logs --config "$config" --shard 4/4 --out bad
expect 2 "shards of different runs" "$legkit" merge m e-1 s2-2

if ((failures)); then
  echo "$failures check(s) failed"
  exit 1
fi
echo "sharded study and eval merged bit for bit; every bad input refused"
