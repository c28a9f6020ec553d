#!/usr/bin/env bash
# render.sh — render a reel film on a Slurm cluster, as three dependent stages:
#
#   1. simulate  one job (--cpus CPUs):   reel simulate SCENE --cache DIR/cache --resume -q
#   2. render    a job array of K tasks,  reel render SCENE --cache DIR/cache --chunk I/K
#                --render-cpus each, after 1:       -o DIR/chunks/chunk_IIII.mp4 -q
#   3. join      one job, after all of 2: reel join DIR/chunks/chunk_0000.mp4 ... -o OUT
#
# Usage:
#   scripts/slurm/render.sh SCENE.json --chunks K [-o OUT.mp4] [--cache DIR]
#       [--reel PATH] [--partition P] [--cpus N] [--render-cpus N] [--wait]
#
#   --chunks K     number of render jobs (the film is cut into K runs of frames)
#   -o OUT         the film (default: render_out/<scene name>.mp4)
#   --cache DIR    the farm folder: the simulation cache (DIR/cache), chunks,
#                  logs and job scripts
#                  (default: render_out/farm/<scene name>); it, SCENE, OUT and
#                  the reel binary must be on a file system every node sees
#   --reel PATH    reel binary (default: $REEL, else `reel` on PATH, else
#                  <repo>/build/release/reel)
#   --partition P  submit to this partition (default: the cluster's default)
#   --cpus N       CPUs of the simulation job (default 2)
#   --render-cpus N  CPUs of each render job (default 2: reel draws, encodes
#                  and reads the cache on three threads, and Mesa rasterises
#                  on as many as it is given); the join takes 1
#   --wait         wait for the film; exit 1 and show the failing stage's log
#                  if a stage fails (interrupting the wait leaves jobs queued)
#
# Relative paths are taken from the current directory and made absolute, since
# the jobs run elsewhere. Each job runs with its working directory in DIR and
# OMP_NUM_THREADS and LP_NUM_THREADS set to the CPUs Slurm gave it.
#
# How a stage's outcome is known: sacct needs an accounting database, which a
# small cluster may lack, and "scontrol show job" forgets a job MinJobAge
# seconds (300 by default) after it ends. So every job writes its own outcome
# next to its log: DIR/status/<stage>-<job id>[_<task>].ok when reel exits 0,
# .failed (holding the exit status) when it does not or when Slurm stops it
# with SIGTERM (time limit, scancel). A job that never ran (its dependency
# failed) or was killed outright leaves neither; then scontrol's JobState, if it
# still knows the job, says why. The dependent jobs are submitted with
# --kill-on-invalid-dep=yes, so a failed stage cancels the ones after it
# instead of leaving them pending forever.
set -euo pipefail

prog=render.sh
repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)

die() { printf '%s: error: %s\n' "$prog" "$*" >&2; exit 2; }
usage() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; }

# ---- arguments -------------------------------------------------------------
scene="" chunks="" out="" cache="" reel="" partition="" cpus=2 render_cpus=2 wait=0
while (($#)); do
  arg=$1
  # Accept both "--opt VALUE" and "--opt=VALUE".
  if [[ $arg == --*=* ]]; then
    set -- "${arg%%=*}" "${arg#*=}" "${@:2}"
    arg=$1
  fi
  case $arg in
    -h | --help) usage; exit 0 ;;
    --wait) wait=1; shift; continue ;;
    --chunks | -o | --output | --cache | --reel | --partition | --cpus | --render-cpus)
      (($# >= 2)) || die "$arg needs a value (try --help)"
      case $arg in
        --chunks) chunks=$2 ;;
        -o | --output) out=$2 ;;
        --cache) cache=$2 ;;
        --reel) reel=$2 ;;
        --partition) partition=$2 ;;
        --cpus) cpus=$2 ;;
        --render-cpus) render_cpus=$2 ;;
      esac
      shift 2 ;;
    -*) die "unknown option '$arg' (try --help)" ;;
    *)
      [[ -z $scene ]] || die "one scene only (got '$scene' and '$arg')"
      scene=$1; shift ;;
  esac
done

[[ -n $scene ]] || die "no scene file given (usage: $prog SCENE.json --chunks K [options]; try --help)"
[[ -f $scene ]] || die "scene file '$scene' not found"
[[ -n $chunks ]] || die "--chunks K is required (K render jobs)"
# positive N: is N a whole number of at least 1 (leading zeros allowed)?
positive() { [[ $1 =~ ^[0-9]+$ ]] && ((10#$1 >= 1)); }
positive "$chunks" || die "--chunks must be a positive integer, got '$chunks'"
chunks=$((10#$chunks))
positive "$cpus" || die "--cpus must be a positive integer, got '$cpus'"
cpus=$((10#$cpus))
positive "$render_cpus" || die "--render-cpus must be a positive integer, got '$render_cpus'"
render_cpus=$((10#$render_cpus))

if ! command -v sbatch >/dev/null 2>&1 || ! command -v squeue >/dev/null 2>&1; then
  die "sbatch/squeue not found on PATH: no Slurm here. Run scripts/slurm/setup-single-node.sh (as root) to start a single-node cluster on this machine, or run this on a cluster's login node."
fi

# The reel binary: --reel, then $REEL, then PATH, then this checkout's build.
if [[ -z $reel ]]; then
  if [[ -n ${REEL:-} ]]; then reel=$REEL
  elif command -v reel >/dev/null 2>&1; then reel=$(command -v reel)
  else reel=$repo_root/build/release/reel
  fi
fi
[[ -f $reel && -x $reel ]] || die "reel binary '$reel' not found or not executable (build it, or pass --reel PATH / set REEL)"

name=$(basename "$scene")
name=${name%.json}
[[ -n $out ]] || out=render_out/$name.mp4
[[ -n $cache ]] || cache=render_out/farm/$name

# Absolute paths: the jobs start in DIR on some other node.
scene=$(realpath "$scene")
reel=$(realpath "$reel")
out=$(realpath -m "$out")
cache=$(realpath -m "$cache")

mkdir -p "$cache/chunks" "$cache/logs" "$cache/status" "$cache/jobs" "$(dirname "$out")"

# ---- job scripts -----------------------------------------------------------
# Each stage gets a small batch script in DIR/jobs (Slurm copies it at
# submission, so a later run may overwrite it). Paths are baked in with
# printf %q, so spaces and quotes in them survive.
q() { printf '%q' "$1"; }

# write_job FILE STAGE STATUS_NAME COMMAND...: STATUS_NAME and each COMMAND
# line are shell text for the job script, expanded when the job runs.
write_job() {
  local file=$1 stage=$2 status_name=$3
  shift 3
  {
    printf '#!/bin/bash\n'
    printf '# %s stage of the reel film %s (written by scripts/slurm/render.sh)\n' "$stage" "$(q "$name")"
    printf 'set -uo pipefail\n'
    printf 'stage=%s\n' "$stage"
    printf 'status=%s/%s\n' "$(q "$cache/status")" "$status_name"
    # Slurm sends SIGTERM on scancel or at the time limit; bash runs the trap
    # once reel (which gets the signal too) has exited.
    cat <<'EOF_HEAD'
trap '{ set +x; } 2>/dev/null; echo "stopped by SIGTERM (scancel or time limit)" | tee "$status.failed"; exit 143' TERM
export OMP_NUM_THREADS=${SLURM_CPUS_PER_TASK:-1}
export LP_NUM_THREADS=$OMP_NUM_THREADS  # Mesa's llvmpipe rasterises on as many threads
echo "reel $stage on $(hostname) at $(date -Is): job $SLURM_JOB_ID${SLURM_ARRAY_TASK_ID:+ (array ${SLURM_ARRAY_JOB_ID}_$SLURM_ARRAY_TASK_ID)}, $OMP_NUM_THREADS CPU(s)"
EOF_HEAD
    printf '%s\n' "$@"
    cat <<'EOF_TAIL'
{ rc=$?; set +x; } 2>/dev/null
if ((rc == 0)); then touch "$status.ok"; else echo "exit status $rc" >"$status.failed"; fi
echo "finished at $(date -Is): exit status $rc"
exit $rc
EOF_TAIL
  } >"$file"
  chmod +x "$file"
}

chunk_files=()
for ((i = 0; i < chunks; i++)); do
  chunk_files+=("$cache/chunks/$(printf 'chunk_%04d.mp4' "$i")")
done

# shellcheck disable=SC2016  # job ids are known only when the job runs
write_job "$cache/jobs/simulate.sh" simulate 'sim-${SLURM_JOB_ID}' \
  "set -x" \
  "$(q "$reel") simulate $(q "$scene") --cache $(q "$cache/cache") --resume -q"
# shellcheck disable=SC2016
write_job "$cache/jobs/render.sh" render 'render-${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}' \
  "chunk=\$(printf %04d \"\$SLURM_ARRAY_TASK_ID\")" \
  "set -x" \
  "$(q "$reel") render $(q "$scene") --cache $(q "$cache/cache") --chunk \"\$SLURM_ARRAY_TASK_ID/$chunks\" -o $(q "$cache/chunks")/chunk_\"\$chunk\".mp4 -q"
join_cmd="$(q "$reel") join"
for f in "${chunk_files[@]}"; do join_cmd+=" $(q "$f")"; done
join_cmd+=" -o $(q "$out")"
# shellcheck disable=SC2016
write_job "$cache/jobs/join.sh" join 'join-${SLURM_JOB_ID}' "set -x" "$join_cmd"

# ---- submission ------------------------------------------------------------
common=(--parsable --ntasks=1 --chdir="$cache")
[[ -z $partition ]] || common+=(--partition="$partition")

submitted=()
# If a later sbatch fails, cancel what was already queued rather than leave
# half a chain behind.
cancel_submitted() {
  ((${#submitted[@]})) || return 0
  scancel "${submitted[@]}" 2>/dev/null || true
  printf '%s: cancelled the jobs already submitted: %s\n' "$prog" "${submitted[*]}" >&2
}

# submit ARGS...: prints the job id (sbatch --parsable may append ";cluster").
submit() {
  local id
  if ! id=$(sbatch "${common[@]}" "$@"); then
    cancel_submitted
    die "sbatch failed (see its message above)"
  fi
  id=${id%%;*}
  [[ $id =~ ^[0-9]+$ ]] || { cancel_submitted; die "sbatch printed '$id', not a job id"; }
  printf '%s' "$id"
}

sim_id=$(submit --job-name="reel-sim-$name" --cpus-per-task="$cpus" \
  --output="$cache/logs/%x-%j.out" "$cache/jobs/simulate.sh")
submitted+=("$sim_id")
render_id=$(submit --job-name="reel-render-$name" --cpus-per-task="$render_cpus" --array="0-$((chunks - 1))" \
  --dependency="afterok:$sim_id" --kill-on-invalid-dep=yes \
  --output="$cache/logs/%x-%A_%a.out" "$cache/jobs/render.sh")
submitted+=("$render_id")
join_id=$(submit --job-name="reel-join-$name" --cpus-per-task=1 \
  --dependency="afterok:$render_id" --kill-on-invalid-dep=yes \
  --output="$cache/logs/%x-%j.out" "$cache/jobs/join.sh")

echo "simulate: job $sim_id"
echo "render:   job array ${render_id}_[0-$((chunks - 1))] ($chunks chunks)"
echo "join:     job $join_id"
echo "film:     $out"
echo "logs:     $cache/logs"

((wait)) || exit 0

# ---- --wait ----------------------------------------------------------------
# Poll every 2 s until none of the three jobs is pending, running or completing.
echo "waiting for the jobs to finish..."
fails=0
while :; do
  if left=$(squeue -h -o %A -j "$sim_id,$render_id,$join_id" 2>&1); then
    fails=0
    [[ -n $left ]] || break
  elif [[ $left == *"Invalid job id"* ]]; then
    break  # every job has ended and been forgotten
  else
    # Controller busy or restarting: keep trying for about two minutes.
    ((++fails < 60)) || die "squeue keeps failing: $left"
  fi
  sleep 2
done

# job_state ID: "JobState Reason" from scontrol, or "unknown" once forgotten.
job_state() {
  local info
  info=$(scontrol show job "$1" 2>/dev/null | tr ' ' '\n') || { echo "unknown"; return; }
  printf '%s %s\n' "$(sed -n 's/^JobState=//p' <<<"$info" | head -n1)" \
    "$(sed -n 's/^Reason=//p' <<<"$info" | head -n1)"
}

# outcome STATUS_NAME JOB_ID: "ok", "failed: <why>" or "did not finish: <state>".
# A status file written on another node may take a moment to show up over a
# shared file system, so a job Slurm calls COMPLETED or FAILED gets 10 s.
outcome() {
  local base=$cache/status/$1 state
  for _ in $(seq 10); do
    if [[ -e $base.ok ]]; then echo ok; return; fi
    if [[ -e $base.failed ]]; then echo "failed: $(head -n1 "$base.failed")"; return; fi
    state=$(job_state "$2")
    [[ $state == COMPLETED* || $state == FAILED* ]] || break
    sleep 1
  done
  echo "did not finish: ${state:-unknown}"
}

failed_log=""
sim=$(outcome "sim-$sim_id" "$sim_id")
echo "simulate (job $sim_id): $sim"
[[ $sim == ok ]] || failed_log=$cache/logs/reel-sim-$name-$sim_id.out

n_ok=0 bad=()
for ((i = 0; i < chunks; i++)); do
  r=$(outcome "render-${render_id}_$i" "${render_id}_$i")
  if [[ $r == ok ]]; then
    n_ok=$((n_ok + 1))
  else
    bad+=("chunk $i: $r")
    [[ -n $failed_log ]] || failed_log=$cache/logs/reel-render-$name-${render_id}_$i.out
  fi
done
echo "render (job array $render_id): $n_ok of $chunks chunks ok"
((${#bad[@]} == 0)) || printf '  %s\n' "${bad[@]:0:5}"
((${#bad[@]} <= 5)) || echo "  ... and $((${#bad[@]} - 5)) more"

join=$(outcome "join-$join_id" "$join_id")
echo "join (job $join_id): $join"
[[ $join == ok || -n $failed_log ]] || failed_log=$cache/logs/reel-join-$name-$join_id.out

if [[ $join == ok && -s $out ]]; then
  echo "film: $out"
  exit 0
fi
if [[ -n $failed_log && -e $failed_log ]]; then
  echo "--- last lines of $failed_log:"
  tail -n 20 "$failed_log"
elif [[ -n $failed_log ]]; then
  echo "(no log: $failed_log was never written; the job did not start)"
fi
[[ $join != ok ]] || echo "join reported success, but $out is missing or empty"
echo "$prog: the film was not made" >&2
exit 1
