#!/usr/bin/env bash
# Submits affordance trials to Slurm: a job array of N tasks (affordance_array.sbatch, each
# task one shard of the seeds with K simulators on its node) and the merge as a job that runs
# once every task succeeded (affordance_merge.sbatch). Prints both job ids, where the output
# goes, and how to re-run a failed task. See README.md beside this script.
#
#   submit_affordances.sh --out-dir DIR --trials T [--shards N (4)] [--instances K (1)] [--seed S]
#                         [--affordance A] [--generator G] [--bin DIR] [--domain-base B]
#                         [--domain-blocks M] [--lock-dir DIR] [-- more affordance_trials options]
#
# sbatch's own settings (partition, time limit, account) come from its input environment
# variables: SBATCH_PARTITION, SBATCH_TIMELIMIT, SBATCH_ACCOUNT, ...
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
die() {
  echo "submit_affordances: $*" >&2
  exit 2
}

out_dir="" trials="" shards=4 instances=1 seed=1 affordance=lift generator=material bin_dir=""
passed=()  # options handed to the array's tasks as they are
extra=()
while (($#)); do
  case "$1" in
    --out-dir | --trials | --shards | --instances | --seed | --affordance | --generator | --bin | \
      --domain-base | --domain-blocks | --lock-dir)
      (($# >= 2)) || die "$1 needs a value"
      case "$1" in
        --out-dir) out_dir="$2" ;;
        --trials) trials="$2" ;;
        --shards) shards="$2" ;;
        --instances) instances="$2" ;;
        --seed) seed="$2" ;;
        --affordance) affordance="$2" ;;
        --generator) generator="$2" ;;
        --bin) bin_dir="$2" ;;
        *) passed+=("$1" "$2") ;;
      esac
      shift 2
      ;;
    --help | -h)
      sed -n '2,13s/^# \{0,1\}//p' "$0"
      exit 0
      ;;
    --)
      shift
      extra=("--" "$@")
      break
      ;;
    *) die "unknown argument '$1' (see --help)" ;;
  esac
done
[[ -n "$out_dir" ]] || die "say where the rows go: --out-dir DIR"
[[ -n "$trials" ]] || die "say how many trials: --trials T"
for pair in "--trials:$trials" "--shards:$shards" "--instances:$instances" "--seed:$seed"; do
  [[ "${pair#*:}" =~ ^[0-9]+$ ]] || die "${pair%%:*} takes a whole number: '${pair#*:}'"
done
((trials >= 1 && shards >= 1 && instances >= 1)) || die "--trials, --shards, --instances must be at least 1"
((shards <= trials)) || die "--shards $shards is more than --trials $trials"
[[ "$affordance" =~ ^(lift|push|climb|stack|traverse)$ ]] || die "unknown --affordance '$affordance' (lift, push, climb, stack, traverse)"
[[ "$generator" =~ ^(material|figure11|balanced)$ ]] || die "unknown --generator '$generator' (material, figure11, balanced)"

# affordance_trials: --bin, else the installation this script belongs to (share/macsim/slurm
# beside bin/), else the source tree's build (deploy/slurm beside build/), else PATH.
if [[ -z "$bin_dir" ]]; then
  if [[ "$(basename "$(dirname "$here")")" == macsim && -x "$here/../../../bin/affordance_trials" ]]; then
    bin_dir="$here/../../../bin"
  elif [[ -x "${MACSIM_BUILD:-$here/../../build}/bin/affordance_trials" ]]; then
    bin_dir="${MACSIM_BUILD:-$here/../../build}/bin"
  elif command -v affordance_trials > /dev/null; then
    bin_dir="$(dirname "$(command -v affordance_trials)")"
  else
    die "no affordance_trials found: give --bin DIR"
  fi
fi
[[ -x "$bin_dir/affordance_trials" ]] || die "no $bin_dir/affordance_trials"
bin_dir="$(cd "$bin_dir" && pwd)"
mkdir -p "$out_dir"
out_dir="$(cd "$out_dir" && pwd)"

common=(--out-dir "$out_dir" --trials "$trials" --shards "$shards" --seed "$seed"
  --affordance "$affordance" --generator "$generator" --bin "$bin_dir")
task_sbatch=(-c "$instances" --job-name "affordance-$affordance" --output "$out_dir/slurm-%A_%a.out")
task_args=("${common[@]}" --instances "$instances" "${passed[@]}" "${extra[@]}")
merge_sbatch=(--job-name "affordance-$affordance-merge" --output "$out_dir/slurm-merge-%j.out")

array_job="$(sbatch --parsable --array="0-$((shards - 1))" "${task_sbatch[@]}" \
  "$here/affordance_array.sbatch" "${task_args[@]}")"
array_job="${array_job%%;*}"
merge_job="$(sbatch --parsable --dependency="afterok:$array_job" "${merge_sbatch[@]}" \
  "$here/affordance_merge.sbatch" "${common[@]}")"
merge_job="${merge_job%%;*}"

echo "submit_affordances: array job $array_job: $shards task(s), $trials $affordance trials" \
  "(seeds $seed..$((seed + trials - 1))), $instances simulator(s) per task;" \
  "output in $out_dir/slurm-${array_job}_<task>.out"
echo "submit_affordances: merge job $merge_job (once every task succeeded): $out_dir/$affordance.csv," \
  "report in $out_dir/slurm-merge-$merge_job.out"
echo "submit_affordances: a task I that failed fills its missing rows when run again:"
printf '  sbatch --array=I'
printf ' %q' "${task_sbatch[@]}" "$here/affordance_array.sbatch" "${task_args[@]}"
printf '\n  then merge: sbatch'
printf ' %q' "${merge_sbatch[@]}" "$here/affordance_merge.sbatch" "${common[@]}"
printf '\n'
