#!/usr/bin/env bash
# The README's "A first run" does what it says: every command of its sh blocks is run as
# written, in an empty folder beside a copy of examples/, with build/radiosity and mpirun
# replaced by this build and the mpiexec ctest describes. `paraview` (a GUI) is left out.
# Usage: readme_commands_test.sh SOURCE_DIR RADIOSITY MPIEXEC (mpiexec's flags from
# MPIEXEC_NUMPROC_FLAG, MPIEXEC_PREFLAGS and MPIEXEC_POSTFLAGS in the environment).
set -euo pipefail
root=$1 radiosity=$2 mpiexec=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cp -r "$root/examples" "$dir/examples"

# The sh blocks between "## A first run" and the next section.
awk '/^## A first run/ { inside = 1; next } /^## / { inside = 0 }
     inside && /^```sh/ { block = 1; next } inside && /^```/ { block = 0; next }
     inside && block' "$root/README.md" >"$dir/commands.txt"
[[ -s $dir/commands.txt ]] || { echo "FAIL: no sh block under '## A first run'"; exit 1; }

launcher="$mpiexec ${MPIEXEC_NUMPROC_FLAG:--n} 2 ${MPIEXEC_PREFLAGS:-}"
count=0
while IFS= read -r line; do
  command=${line%%#*}
  [[ -z ${command// /} || $command == paraview* || $command == export\ OMPI* ]] && continue
  # (through placeholders: the build's own path may hold "build/radiosity")
  command=${command//mpirun -n 2 build\/radiosity/@LAUNCH@ @RADIOSITY@ ${MPIEXEC_POSTFLAGS:-}}
  command=${command//build\/radiosity/@RADIOSITY@}
  command=${command//@LAUNCH@/$launcher}
  command=${command//@RADIOSITY@/$radiosity}
  echo "+ $command"
  if ! (cd "$dir" && bash -c "$command" </dev/null >"$dir/log" 2>&1); then
    echo "FAIL: the README's command failed: $line"
    cat "$dir/log"
    exit 1
  fi
  count=$((count + 1))
done <"$dir/commands.txt"

for made in cornell.h5 cornell.png cornell.obj scene.h5 furnace.h5 office.h5 office.vf \
  office-groups.csv; do
  [[ -s $dir/$made ]] || { echo "FAIL: the README's commands made no $made"; exit 1; }
done
echo "PASS: the README's $count commands of 'A first run' ran"
