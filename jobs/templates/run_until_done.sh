#!/usr/bin/env bash
# Plain mpirun, no scheduler: run a solve, and after a stop (exit 75: SIGTERM, SIGINT or SIGUSR1
# arrived, a checkpoint was written) or a crash, start it again from its checkpoint.
#   NP=4 bash jobs/templates/run_until_done.sh job.toml
# job.toml holds the solve's options (`radiosity solve --config`), e.g.
#   scene = "builtin:rooms?patches=100000"
#   output = "rooms.h5"
#   rays = 1024
# Ctrl-C (or SIGTERM to this script) stops it: the solve writes its checkpoint and the script
# exits 75 without starting again; a second Ctrl-C ends the solve at once. mpirun runs in a
# process group of its own, so a Ctrl-C reaches only this script, which asks the solve to stop
# with SIGUSR1 (mpirun passes SIGUSR1 on to every rank; a SIGINT or SIGTERM to mpirun itself
# would kill the ranks about a second later, before the checkpoint is written).
set -uo pipefail
job=${1:?usage: run_until_done.sh JOB_FILE}
np=${NP:-2}
# Without RADIOSITY: build/radiosity from a source tree, else the installed one on PATH.
radiosity=${RADIOSITY:-build/radiosity}
[[ -n ${RADIOSITY:-} || -x $radiosity ]] || radiosity=$(command -v radiosity || echo "$radiosity")
checkpoint=${CHECKPOINT:-${job%.*}.checkpoint.h5}
every=${CHECKPOINT_EVERY:-600}
attempts=${ATTEMPTS:-10}

# mpirun ends its ranks on SIGTERM, but on a loaded node that can take seconds: wait for it (it
# exits after its ranks), and after 10 s kill its whole session so that no rank outlives us.
end_now() {
  kill -TERM "$1" 2>/dev/null
  for ((tenth = 0; tenth < 100; ++tenth)); do
    [[ $(ps -o stat= -p "$1" 2>/dev/null) == Z* || -z $(ps -o stat= -p "$1" 2>/dev/null) ]] && return
    sleep 0.1
  done
  pkill -KILL -s "$1" 2>/dev/null
}

stopping=0 pid=""
interrupt() {
  if ((stopping)); then
    echo "second interrupt: ending the solve now, without a checkpoint" >&2
    [[ -n $pid ]] && end_now "$pid"
    exit 130
  fi
  stopping=1
  echo "interrupt: the solve writes its checkpoint and stops (Ctrl-C again to end it at once)" >&2
  [[ -n $pid ]] && kill -USR1 "$pid" 2>/dev/null
}
trap interrupt INT TERM

for ((attempt = 1; attempt <= attempts; ++attempt)); do
  restart=()
  [[ -f $checkpoint ]] && restart=(--restart "$checkpoint")
  setsid mpirun -n "$np" "$radiosity" solve --config "$job" --checkpoint "$checkpoint" \
    --checkpoint-every "$every" "${restart[@]}" &
  pid=$!
  # wait returns early when a trapped signal arrives: wait again until mpirun has ended.
  while true; do
    wait "$pid"
    code=$?
    kill -0 "$pid" 2>/dev/null || break
  done
  pid=""
  if ((stopping)); then
    [[ $code == 75 ]] && echo "stopped; the state is in $checkpoint: run again to go on" >&2
    exit "$code"
  fi
  case $code in
    0) exit 0 ;;
    75) echo "stopped by a signal; the state is in $checkpoint" >&2; exit 75 ;;
    2 | 3 | 4) exit "$code" ;;  # usage, bad input, numerical failure: running again won't help
    *) echo "attempt $attempt ended with exit $code; restarting from $checkpoint" >&2 ;;
  esac
done
exit 1
