#!/usr/bin/env bash
# The ParaView state of a 2D tunnel run (scripts/tunnel_2d_view.py;
# docs/tunnel.md, "ParaView"): the default example, at coarser grains to be
# quick, rendered headless by pvbatch. Checks that the state loads the run's
# outputs and draws what it promises: the image at its size, the continuum
# in Viridis colours around the region, the grains in greys, and that a
# directory without a run is refused naming the missing file.
# Usage: paraview_view.sh DEMFEM_EXE SOURCE_DIR
set -euo pipefail
exe="$1"
src="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

OMP_NUM_THREADS=1 "$exe" tunnel "$src/apps/examples/tunnel_2d.prm" \
  --set "Problem/output directory=$work/run" --set "DEM region/grain diameter=0.2" \
  > "$work/run.log" 2>&1 || { tail -20 "$work/run.log"; fail "the tunnel run failed"; }

"$src/scripts/pvbatch_headless.sh" "$src/scripts/tunnel_2d_view.py" "$work/run" \
  "$work/view.png" > "$work/view.log" 2>&1 || { tail -20 "$work/view.log"; fail "pvbatch failed"; }
grep -q "wrote $work/view.png" "$work/view.log" || fail "no 'wrote' line: $(tail -3 "$work/view.log")"

# Pixel census with VTK's PNG reader (python3-vtk9).
/usr/bin/python3 - "$work/view.png" <<'PY'
import sys
import vtk
from vtk.util.numpy_support import vtk_to_numpy
r = vtk.vtkPNGReader()
r.SetFileName(sys.argv[1])
r.Update()
img = r.GetOutput()
nx, ny, _ = img.GetDimensions()
assert (nx, ny) == (1000, 1100), f"image {nx} x {ny}, expected 1000 x 1100"
px = vtk_to_numpy(img.GetPointData().GetScalars())[:, :3].astype(int)
n = len(px)
rr, gg, bb = px[:, 0], px[:, 1], px[:, 2]
grey = (abs(rr - gg) < 6) & (abs(gg - bb) < 6) & (rr < 245)        # grains
viridis = (gg > rr + 20) & (bb > 40) & (gg > 60)                     # continuum (teal/green)
print(f"grey {grey.sum() / n:.3f}, viridis {viridis.sum() / n:.3f}")
# The view spans 4.5 tunnel radii each way; the region (3.5 a) covers
# about half of it, the continuum most of the rest (measured 0.31 and 0.53).
assert grey.sum() > 0.10 * n, "too few grain pixels"
assert viridis.sum() > 0.10 * n, "too few continuum pixels"
PY

# A directory that holds no run is refused, naming what is missing.
mkdir -p "$work/empty"
if "$src/scripts/pvbatch_headless.sh" "$src/scripts/tunnel_2d_view.py" "$work/empty" \
     > "$work/empty.log" 2>&1; then
  fail "an empty directory was accepted"
fi
grep -q "no $work/empty/summary.json" "$work/empty.log" || fail "no message naming summary.json: $(tail -3 "$work/empty.log")"
echo "paraview view: ok"
