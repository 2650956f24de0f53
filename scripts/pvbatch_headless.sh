#!/usr/bin/env bash
# Runs pvbatch with its arguments on a private X server (Debian's ParaView
# renders through X): Xvfb on a display chosen from this process id, waited
# for until its socket exists, stopped on exit; -noreset, because VTK
# connects twice and a server that resets when the first client leaves
# refuses the second. Used by the ParaView view
# test (tests/paraview_view.sh) and for headless screenshots:
#   scripts/pvbatch_headless.sh scripts/tunnel_2d_view.py out/tunnel_2d [FILE.png]
set -euo pipefail
for tool in Xvfb pvbatch; do
  command -v "$tool" > /dev/null || { echo "pvbatch_headless.sh: $tool not found (Debian packages xvfb, paraview and python3-paraview; the last conflicts with libvtk9-dev: docs/tunnel.md, \"ParaView\")" >&2; exit 2; }
done
display=""
for n in $(seq $((100 + $$ % 800)) $((100 + $$ % 800 + 50))); do
  [ -e "/tmp/.X$n-lock" ] || [ -e "/tmp/.X11-unix/X$n" ] || { display=$n; break; }
done
[ -n "$display" ] || { echo "pvbatch_headless.sh: no free X display" >&2; exit 2; }
Xvfb ":$display" -screen 0 1280x1200x24 -nolisten tcp -noreset > /dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb 2> /dev/null || true' EXIT
for _ in $(seq 100); do
  [ -S "/tmp/.X11-unix/X$display" ] && break
  kill -0 $xvfb 2> /dev/null || { echo "pvbatch_headless.sh: Xvfb :$display did not start" >&2; exit 2; }
  sleep 0.1
done
DISPLAY=":$display" pvbatch "$@"
