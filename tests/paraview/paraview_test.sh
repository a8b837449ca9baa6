#!/usr/bin/env bash
# The result as a ParaView user meets it: solve builtin:cornell on two ranks, move the result and
# its XDMF sidecar together to another folder; there, make its picture with paraview_picture.py
# (the script installed as share/radiosity/paraview_picture.py), naming the result by its bare
# file name, as `radiosity render` makes one; then open the sidecar in ParaView and check what
# it shows and the picture (check_result.py). ParaView runs headless: pvbatch on a virtual X
# server, Xvfb (Debian's ParaView is built for X11).
# Usage: paraview_test.sh RADIOSITY MPIEXEC PARAVIEW_PICTURE.py [PICTURE.png to keep]. Exit 77
# (skipped) where ParaView is not installed; .ci/setup installs it.
set -euo pipefail
radiosity=$1 mpiexec=$2 keep=${4:-}
here=$(cd "$(dirname "$0")" && pwd)
script=$(cd "$(dirname "$3")" && pwd)/$(basename "$3")  # (run from the result's folder)
for tool in pvbatch Xvfb; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIPPED: $tool is not installed (Debian: paraview python3-paraview xvfb)"
    exit 77
  fi
done
dir=$(mktemp -d)
xserver=""
trap '[[ -n $xserver ]] && kill "$xserver" 2>/dev/null; rm -rf "$dir"' EXIT

# Xvfb picks a free display itself and writes its number once it accepts connections
# (-displayfd). -noreset: pvbatch opens a window to probe OpenGL, closes it and opens another; an
# X server resets when its last client leaves and refuses connections meanwhile, which made
# pvbatch abort with "bad X server connection" about one run in fifteen (xvfb-run does not pass
# -noreset). Local clients need no authority file.
start_x_server() {
  Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset 3>"$dir/display" 2>"$dir/xvfb.log" &
  xserver=$!
  for ((tenth = 0; tenth < 300; ++tenth)); do
    if [[ -s $dir/display ]] && grep -q '^[0-9]' "$dir/display"; then
      export DISPLAY=":$(head -n 1 "$dir/display")"
      return 0
    fi
    kill -0 "$xserver" 2>/dev/null || break
    sleep 0.1
  done
  echo "FAILED: Xvfb did not start; its log:" >&2
  cat "$dir/xvfb.log" >&2
  exit 1
}
mkdir "$dir/run" "$dir/moved"
# mpiexec as ctest describes it (tests/CMakeLists.txt): NUMPROC_FLAG N PREFLAGS PROGRAM POSTFLAGS.
read -ra preflags <<<"${MPIEXEC_PREFLAGS:-}"
read -ra postflags <<<"${MPIEXEC_POSTFLAGS:-}"
"$mpiexec" "${MPIEXEC_NUMPROC_FLAG:--n}" 2 "${preflags[@]}" "$radiosity" "${postflags[@]}" \
  solve builtin:cornell --rays 256 -q -o "$dir/run/cornell.h5"
mv "$dir/run/cornell.h5" "$dir/run/cornell.xmf" "$dir/moved/"
patches=$("$radiosity" info "$dir/moved/cornell.h5" | awk '$1 == "/patches/area" { gsub(/[][]/, "", $3); print $3 }')
"$radiosity" render "$dir/moved/cornell.h5" -o "$dir/rendered.png" 2>"$dir/render.log" ||
  { cat "$dir/render.log" >&2; echo "FAILED: radiosity render" >&2; exit 1; }
# ParaView's X error on closing its window after the script ended does not count: the verdicts are
# the scripts' own lines.
start_x_server
# By the bare file name, from the result's folder (ParaView itself, given "cornell.xmf", looks for
# "cornell.xmfcornell.h5" and aborts; the script hands it an absolute path).
(cd "$dir/moved" && pvbatch "$script" cornell.xmf ../picture.png 2>&1 | grep -v "^X Error\|^  " ||
  true) | tee "$dir/log"
if ! grep -q "^wrote ../picture.png" "$dir/log" || [[ ! -s $dir/picture.png ]]; then
  echo "FAILED: paraview_picture.py made no picture (display $DISPLAY); the X server's log:" >&2
  cat "$dir/xvfb.log" >&2
  exit 1
fi
# The sidecar as "./cornell.xmf" (the form ParaView opens from the folder itself).
(cd "$dir/moved" && pvbatch "$here/check_result.py" ./cornell.xmf ../picture.png ../rendered.png \
  "$patches" 2>&1 | grep -v "^X Error\|^  " || true) | tee "$dir/log"
if ! grep -q "^PASS:" "$dir/log"; then
  echo "FAILED: no PASS from ParaView's script (display $DISPLAY); the X server's log:" >&2
  cat "$dir/xvfb.log" >&2
  exit 1
fi
if [[ -n "$keep" ]]; then cp "$dir/picture.png" "$keep"; fi
