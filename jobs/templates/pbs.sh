#!/usr/bin/env bash
# PBS (Pro or Torque): a solve that outlives its walltime, chunk after chunk, and loses nothing.
#   qsub -v JOB=job.toml jobs/templates/pbs.sh
# 1. --stop-after: the solve writes its checkpoint and exits 75 on its own clock, MARGIN seconds
#    (default 600) before the job's walltime (qstat's Resource_List.walltime): no signal needed.
# 2. At the walltime PBS sends SIGTERM to the job's processes and SIGKILL after the kill delay
#    (often seconds). mpirun runs in a session of its own, so that PBS's SIGTERM reaches only
#    this script, which asks the solve to stop with SIGUSR1 (Open MPI forwards it to every rank;
#    a SIGTERM to mpirun kills the ranks a second or two later, before a large checkpoint is
#    written). Periodic checkpoints (--checkpoint-every) bound what a short kill delay loses.
# After exit 75 the job submits its successor (qsub -W depend=afterany: it starts once this job
# has ended; no operator rights needed, unlike qrerun), which resumes with --restart; at most
# MAX_RESUBMITS times, and not after a chunk that made no progress (the checkpoint's
# `radiosity info` the same before and after), so a job that cannot advance stops.
#PBS -N radiosity
#PBS -l select=4:ncpus=16:mpiprocs=16
#PBS -l walltime=04:00:00
#PBS -j oe
set -uo pipefail
cd "${PBS_O_WORKDIR:-.}" || exit 1
job=${JOB:?submit with qsub -v JOB=job.toml}
radiosity=${RADIOSITY:-build/radiosity}
[[ -n ${RADIOSITY:-} || -x $radiosity ]] || radiosity=$(command -v radiosity || echo "$radiosity")
checkpoint=${CHECKPOINT:-${job%.*}.checkpoint.h5}
margin=${MARGIN:-600}
max_resubmits=${MAX_RESUBMITS:-20}
resubmits=${RESUBMITS:-0}

# [D-][HH:]MM:SS in seconds (PBS's walltime); fails for anything else.
seconds_of() {
  [[ $1 =~ ^(([0-9]+)-)?(([0-9]+):)?([0-9]+):([0-9]+)$ ]] || return 1
  local r=("${BASH_REMATCH[@]}")
  echo $((10#${r[2]:-0} * 86400 + 10#${r[4]:-0} * 3600 + 10#${r[5]} * 60 + 10#${r[6]}))
}

options=(--checkpoint "$checkpoint" --checkpoint-every 900)
[[ -f $checkpoint ]] && options+=(--restart "$checkpoint")
walltime=$(qstat -f "$PBS_JOBID" 2>/dev/null | awk -F' = ' '/Resource_List.walltime/ { print $2 }')
if limit=$(seconds_of "$walltime") && ((limit > 2 * margin)); then
  options+=(--stop-after $((limit - margin)))
fi
before=$("$radiosity" info "$checkpoint" 2>/dev/null)

setsid mpirun "$radiosity" solve --config "$job" "${options[@]}" &
solver=$!
trap 'kill -USR1 "$solver" 2>/dev/null' TERM USR1
code=0
while kill -0 "$solver" 2>/dev/null; do  # wait again after a trapped signal interrupts wait
  wait "$solver"
  code=$?
done
if ((code == 75)); then
  if [[ $("$radiosity" info "$checkpoint" 2>/dev/null) == "$before" ]]; then
    echo "stopped without progress since the last chunk: not resubmitted; the state is in" \
      "$checkpoint" >&2
  elif ((resubmits >= max_resubmits)); then
    echo "stopped after $resubmits resubmissions (MAX_RESUBMITS): not resubmitted; the state" \
      "is in $checkpoint" >&2
  else
    echo "walltime near: checkpoint written to $checkpoint, submitting the next chunk" >&2
    # Every setting passed on: qsub -v gives the successor these variables and no others.
    settings="JOB=$job,RESUBMITS=$((resubmits + 1)),CHECKPOINT=$checkpoint,RADIOSITY=$radiosity"
    settings+=",MARGIN=$margin,MAX_RESUBMITS=$max_resubmits"
    qsub -W depend=afterany:"$PBS_JOBID" -v "$settings" "$0"
  fi
fi
exit "$code"
