#!/usr/bin/env bash
# The result as a ParaView user meets it: solve builtin:cornell on two ranks, move the result and
# its XDMF sidecar together to another folder, open the sidecar in ParaView headless (pvbatch
# under xvfb-run: Debian's ParaView is built for X11) and check the picture (check_result.py).
# Usage: paraview_test.sh RADIOSITY MPIEXEC [PICTURE.png to keep]. Exit 77 (skipped) where
# ParaView is not installed; .ci/setup installs it.
set -euo pipefail
radiosity=$1 mpiexec=$2 keep=${3:-}
here=$(cd "$(dirname "$0")" && pwd)
for tool in pvbatch xvfb-run; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIPPED: $tool is not installed (Debian: paraview python3-paraview xvfb xauth)"
    exit 77
  fi
done
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir "$dir/run" "$dir/moved"
"$mpiexec" -n 2 "$radiosity" solve builtin:cornell --rays 256 -q -o "$dir/run/cornell.h5"
mv "$dir/run/cornell.h5" "$dir/run/cornell.xmf" "$dir/moved/"
patches=$("$radiosity" info "$dir/moved/cornell.h5" | awk '$1 == "/patches/area" { gsub(/[][]/, "", $3); print $3 }')
# ParaView's X error on closing its window after the script ended does not count: the verdict is
# the script's own PASS line.
(cd "$dir" && xvfb-run -a pvbatch "$here/check_result.py" moved/cornell.xmf picture.png "$patches" \
  2>&1 | grep -v "^X Error\|^  " || true) | tee "$dir/log"
grep -q "^PASS:" "$dir/log"
if [[ -n "$keep" ]]; then cp "$dir/picture.png" "$keep"; fi
