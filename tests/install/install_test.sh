#!/usr/bin/env bash
# `cmake --install` gives a working tree: installs the build into a scratch prefix and checks it
# as a user of the installed copy meets it, away from the source tree: the program runs alone
# and under mpiexec, the batch templates are there and executable, run_until_done.sh finds the
# installed program on PATH, ParaView's picture script and the README and docs are there, the man
# page reads and the bash completion completes.
# Usage: install_test.sh CMAKE BUILD_DIR MPIEXEC (mpiexec's flags from MPIEXEC_NUMPROC_FLAG,
# MPIEXEC_PREFLAGS and MPIEXEC_POSTFLAGS in the environment, as tests/CMakeLists.txt sets them).
set -euo pipefail
cmake=$1 build=$2 mpiexec=$3
read -ra preflags <<<"${MPIEXEC_PREFLAGS:-}"
read -ra postflags <<<"${MPIEXEC_POSTFLAGS:-}"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
prefix=$dir/prefix
failures=0
fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}

"$cmake" --install "$build" --prefix "$prefix" >"$dir/install.log" ||
  { cat "$dir/install.log" >&2; echo "FAIL: cmake --install" >&2; exit 1; }
radiosity=$prefix/bin/radiosity
[[ -x $radiosity ]] || { echo "FAIL: no $radiosity" >&2; exit 1; }

# Runs from a folder without build/, with the installed bin/ first on PATH.
mkdir "$dir/work"
cd "$dir/work"
export PATH=$prefix/bin:$PATH

# Every library resolves without the build tree (RPATH, or the system's folders).
if ldd "$radiosity" | grep -q "not found"; then
  fail "libraries not found: $(ldd "$radiosity" | grep "not found" | tr -s ' \t' ' ')"
fi
version=$("$radiosity" --version 2>&1) || fail "radiosity --version: exit $?"
[[ $version == *radiosity* ]] || fail "radiosity --version printed: $version"

"$mpiexec" "${MPIEXEC_NUMPROC_FLAG:--n}" 1 "${preflags[@]}" "$radiosity" "${postflags[@]}" \
  solve builtin:cornell --rays 16 -q -o x.h5 >solve.log 2>&1 || fail "solve: $(cat solve.log)"
[[ -s x.h5 && -s x.xmf ]] || fail "solve wrote no x.h5 and x.xmf"
radiosity info x.h5 >info.log 2>&1 || fail "info x.h5: $(cat info.log)"

templates=$prefix/share/radiosity/templates
for template in run_until_done.sh slurm.sbatch pbs.sh; do
  [[ -x $templates/$template ]] || fail "$templates/$template missing or not executable"
done
# ParaView's picture of a result (tests/paraview runs it; here: that it is there and is Python).
picture_script=$prefix/share/radiosity/paraview_picture.py
if [[ ! -s $picture_script ]]; then
  fail "$picture_script missing"
elif ! grep -q "^# Usage (installed as share/radiosity/paraview_picture.py)" "$picture_script"; then
  fail "$picture_script has no usage in its header"
elif command -v python3 >/dev/null &&
  ! python3 -c 'import ast, sys; ast.parse(open(sys.argv[1]).read())' "$picture_script" \
    2>parse.log; then
  fail "$picture_script is not Python: $(cat parse.log)"
fi
# The plain-mpirun template, RADIOSITY unset and no build/radiosity here: the one on PATH.
printf 'scene = "builtin:box"\noutput = "box.h5"\nrays = 16\nquiet = true\n' >job.toml
if (unset RADIOSITY; NP=1 bash "$templates/run_until_done.sh" job.toml >template.log 2>&1); then
  [[ -s box.h5 ]] || fail "run_until_done.sh wrote no box.h5"
else
  fail "run_until_done.sh: $(cat template.log)"
fi

docs=$prefix/share/doc/radiosity
for doc in README.md LICENSE CITATION.cff CHANGELOG.md docs/design.md docs/result-format.md \
  docs/design/solve.md docs/notebook/measurements.md docs/cornell.png docs/your-own-scene.md \
  examples/README.md examples/room.obj examples/room.mtl; do
  [[ -s $docs/$doc ]] || fail "$docs/$doc missing"
done

# The installed docs speak of the installed program (the logs kept with the measurements are
# records of runs, as they were).
if grep -rl --include='*.md' "build/radiosity" "$docs" >/dev/null; then
  fail "installed docs name build/radiosity: $(grep -rl --include='*.md' "build/radiosity" "$docs" | tr '\n' ' ')"
fi

# The man page and the bash completion, made from the command line at build time.
manpage=$prefix/share/man/man1/radiosity.1
if [[ ! -s $manpage ]]; then
  fail "$manpage missing"
elif command -v man >/dev/null; then
  page=$(MANWIDTH=80 man -l "$manpage" 2>&1) || fail "man -l $manpage: $page"
  for word in "--target-error" "EXIT STATUS" "radiosity verify"; do
    [[ $page == *"$word"* ]] || fail "the man page does not mention $word"
  done
fi
completion=$prefix/share/bash-completion/completions/radiosity
if [[ ! -s $completion ]]; then
  fail "$completion missing"
else
  # What the completion offers after `radiosity solve --ta` and `radiosity solve --estimator `.
  offered=$(bash -c 'source "$1"
    COMP_WORDS=(radiosity solve --ta); COMP_CWORD=2; _radiosity; echo "${COMPREPLY[*]}"
    COMP_WORDS=(radiosity solve --estimator ""); COMP_CWORD=3; _radiosity; echo "${COMPREPLY[*]}"
    COMP_WORDS=(radiosity ve); COMP_CWORD=1; _radiosity; echo "${COMPREPLY[*]}"' _ "$completion")
  [[ $offered == *"--target-error"* ]] || fail "completion of 'solve --ta' offered: $offered"
  [[ $offered == *"hemisphere"* ]] || fail "completion of 'solve --estimator' offered: $offered"
  [[ $offered == *"verify"* ]] || fail "completion of 've' offered: $offered"
fi

if ((failures > 0)); then
  echo "installed tree ($prefix):" >&2
  (cd "$prefix" && find . | sort) >&2
  exit 1
fi
echo "PASS: the installed tree works: bin/radiosity, share/radiosity/templates and" \
  "paraview_picture.py, share/doc/radiosity, the man page, the bash completion"
