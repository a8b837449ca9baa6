#!/usr/bin/env bash
# Plain mpirun, no scheduler: run a solve, and after a stop (exit 75: SIGTERM, SIGINT or SIGUSR1
# arrived, a checkpoint was written) or a crash, start it again from its checkpoint.
#   NP=4 bash jobs/templates/run_until_done.sh job.toml
# job.toml holds the solve's options (`radiosity solve --config`), e.g.
#   scene = "builtin:rooms?patches=100000"
#   output = "rooms.h5"
#   rays = 1024
# Stop it for good with Ctrl-C twice (the first stops the solve with a checkpoint).
set -uo pipefail
job=${1:?usage: run_until_done.sh JOB_FILE}
np=${NP:-2}
radiosity=${RADIOSITY:-build/radiosity}
checkpoint=${CHECKPOINT:-${job%.*}.checkpoint.h5}
every=${CHECKPOINT_EVERY:-600}
attempts=${ATTEMPTS:-10}

for ((attempt = 1; attempt <= attempts; ++attempt)); do
  restart=()
  [[ -f $checkpoint ]] && restart=(--restart "$checkpoint")
  mpirun -n "$np" "$radiosity" solve --config "$job" --checkpoint "$checkpoint" \
    --checkpoint-every "$every" "${restart[@]}"
  code=$?
  case $code in
    0) exit 0 ;;
    75) echo "stopped by a signal; the state is in $checkpoint" >&2; exit 75 ;;
    2 | 3 | 4) exit "$code" ;;  # usage, bad input, numerical failure: running again won't help
    *) echo "attempt $attempt ended with exit $code; restarting from $checkpoint" >&2 ;;
  esac
done
exit 1
