#!/usr/bin/env bash
# Submits a sharded legkit run to Slurm: a job array of N shards (shard-array.sbatch), then
# `legkit merge OUT/merged OUT/shard-1 .. OUT/shard-N` as a job that starts only once every shard
# has succeeded (--dependency=afterok; with --no-plots in the command, the merge draws none either).
# Prints the two job ids.
#   tools/slurm/submit.sh N OUT LEGKIT COMMAND...
#   tools/slurm/submit.sh 8 /scratch/consistency build/legkit study consistency --runs 96 --no-plots
#   tools/slurm/submit.sh 4 /scratch/eval build/legkit eval /data/logs --config robot.yaml
# Extra sbatch options (partition, account) go in SBATCH_PARTITION, SBATCH_ACCOUNT, ... (sbatch's
# own input environment variables).
set -euo pipefail
n=${1:?usage: submit.sh N OUT LEGKIT COMMAND...}
out=${2:?usage: submit.sh N OUT LEGKIT COMMAND...}
legkit=${3:?usage: submit.sh N OUT LEGKIT COMMAND...}
shift 2
here=$(dirname "$0")
mkdir -p "$out"
array=$(sbatch --parsable --array="1-${n}" --output="${out}/shard-%a.out" \
  "${here}/shard-array.sbatch" "$out" "$@")
array=${array%%;*}  # "jobid;cluster" on a federation
merge=("$legkit" merge "${out}/merged")
for ((i = 1; i <= n; ++i)); do merge+=("${out}/shard-${i}"); done
for a in "$@"; do
  if [[ $a == --no-plots ]]; then merge+=(--no-plots); fi  # nor a study's figure
done
job=$(sbatch --parsable --dependency="afterok:${array}" --job-name=legkit-merge \
  --output="${out}/merge.out" --wrap="$(printf '%q ' "${merge[@]}")")
echo "shards: job array ${array} (1-${n}); merge: job ${job%%;*} into ${out}/merged"
