#!/usr/bin/env python3
"""Read back the VTK series of a 3D `demfem tunnel` run (docs/architecture.md): parse each
.pvd, load every referenced file with VTK's own reader, and check that it is
3D (z coordinates spanning the slab), holds the expected arrays, is finite and
has its connectivity in range. Prints 'ok' or the failures (exit 1).
usage: vtk_check_3d.py OUTPUT_DIR SLAB_THICKNESS [AXIAL_EXTENSION]
(a tunnel section: the continuum spans -L .. t + L, the grains 0 .. t)"""
import math, os, sys
import xml.etree.ElementTree as ET
import vtk

out, t = sys.argv[1], float(sys.argv[2])
ext = float(sys.argv[3]) if len(sys.argv) > 3 else 0.0
expected = {
    "particles": (vtk.vtkXMLPolyDataReader, ["radius", "velocity", "displacement",
                                             "averaged_stress"]),
    "bonds": (vtk.vtkXMLPolyDataReader, []),
    "cracks": (vtk.vtkXMLPolyDataReader, []),
    "continuum": (vtk.vtkXMLUnstructuredGridReader,
                  ["displacement", "stress_xx", "stress_yy", "stress_zz", "stress_xy",
                   "stress_xz", "stress_yz"]),
}
failed = []
for series, (Reader, arrays) in expected.items():
    sets = ET.parse(os.path.join(out, series + ".pvd")).getroot().find("Collection")
    sets = sets.findall("DataSet")
    if not sets:
        failed.append(f"{series}.pvd: no data sets")
    for d in sets:
        path = os.path.join(out, d.get("file"))
        r = Reader()
        r.SetFileName(path)
        r.Update()
        g = r.GetOutput()
        n = g.GetNumberOfPoints()
        if series in ("particles", "continuum") and n == 0:
            failed.append(f"{path}: empty")
            continue
        zs = [g.GetPoint(i)[2] for i in range(n)]
        if series in ("particles", "continuum"):
            # Points are written as float32: 1e-6 relative.
            lo, hi = (-ext, t + ext) if series == "continuum" else (0.0, t)
            tol = 1e-6 * (hi - lo)
            if min(zs) < lo - tol or max(zs) > hi + tol or max(zs) - min(zs) < 0.3 * (hi - lo):
                failed.append(f"{path}: z range {min(zs) if zs else None}.."
                              f"{max(zs) if zs else None}, expected {lo}..{hi}")
        for a in arrays:
            arr = (g.GetPointData().GetArray(a) or g.GetCellData().GetArray(a))
            if arr is None:
                failed.append(f"{path}: no array {a}")
                continue
            vals = [arr.GetComponent(i, c) for i in range(arr.GetNumberOfTuples())
                    for c in range(arr.GetNumberOfComponents())]
            if not all(math.isfinite(v) for v in vals):
                failed.append(f"{path}: {a} not finite")
            if a == "averaged_stress" and arr.GetNumberOfComponents() != 9:
                failed.append(f"{path}: {a} has {arr.GetNumberOfComponents()} components")
            if a in ("velocity", "displacement") and arr.GetNumberOfComponents() != 3:
                failed.append(f"{path}: {a} has {arr.GetNumberOfComponents()} components")
        for c in range(g.GetNumberOfCells()):
            ids = g.GetCell(c).GetPointIds()
            if any(ids.GetId(k) < 0 or ids.GetId(k) >= n for k in range(ids.GetNumberOfIds())):
                failed.append(f"{path}: cell {c} connectivity out of range")
                break
print("\n".join(failed) if failed else "ok")
sys.exit(1 if failed else 0)
