#!/usr/bin/env bash
# PBS (Pro or Torque): PBS sends SIGTERM at the walltime and SIGKILL after the queue's kill
# delay, usually seconds: too short to rely on, so this job also checkpoints every 15 minutes
# and loses at most that. A SIGTERM that comes in time still stops the solve at a safe point
# with a fresh checkpoint (exit 75); the job then asks to be run again (qrerun), and the next
# run resumes with --restart.
#   qsub -v JOB=job.toml jobs/templates/pbs.sh
#PBS -N radiosity
#PBS -l select=4:ncpus=16:mpiprocs=16
#PBS -l walltime=04:00:00
#PBS -r y
#PBS -j oe
set -uo pipefail
cd "${PBS_O_WORKDIR:-.}" || exit 1
job=${JOB:?submit with qsub -v JOB=job.toml}
# Without RADIOSITY: build/radiosity from a source tree, else the installed one on PATH.
radiosity=${RADIOSITY:-build/radiosity}
[[ -n ${RADIOSITY:-} || -x $radiosity ]] || radiosity=$(command -v radiosity || echo "$radiosity")
checkpoint=${CHECKPOINT:-${job%.*}.checkpoint.h5}

restart=()
[[ -f $checkpoint ]] && restart=(--restart "$checkpoint")
mpirun "$radiosity" solve --config "$job" --checkpoint "$checkpoint" --checkpoint-every 900 \
  "${restart[@]}" &
solver=$!
trap 'kill -TERM "$solver"' TERM USR1
code=0
while kill -0 "$solver" 2>/dev/null; do
  wait "$solver"
  code=$?
done
if ((code == 75)); then
  qrerun "$PBS_JOBID" || true
fi
exit "$code"
