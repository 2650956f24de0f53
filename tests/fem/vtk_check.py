#!/usr/bin/env python3
"""Read back the VTK series of `demfem fem` (2 ranks, 2 stages): parse the
.pvd XML, load every referenced .pvtu with VTK's own reader, and check the
arrays, their finiteness and the connectivity range (no VTK reader checks
connectivity; a truncated file can load silently as empty).
usage: vtk_check.py DEMFEM_EXE MPIRUN SOURCE_DIR WORK_DIR"""
import math, os, shutil, subprocess, sys
import xml.etree.ElementTree as ET
import vtk

exe, mpirun, src, work = sys.argv[1:5]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
expected = ["displacement", "stress_xx", "stress_yy", "stress_zz", "stress_xy", "stress_xz",
            "stress_yz", "principal_stress_1", "principal_stress_2", "principal_stress_3"]
failed = []
for dim in (2, 3):
    out = os.path.join(work, f"vtk_{dim}d")
    shutil.rmtree(out, ignore_errors=True)
    prm = os.path.join(src, f"apps/examples/kirsch_{dim}d.prm")
    cmd = ["timeout", "120", mpirun, "--oversubscribe", "-np", "2", exe, "fem", prm,
           "--set", f"Problem/output directory={out}", "--set", "Tunnel/excavation stages=2",
           "--set", "Continuum/element degree=1"]
    r = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        print(r.stdout)
        sys.exit(f"{dim}D run failed ({r.returncode})")
    pvd = os.path.join(out, "solution.pvd")
    sets = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    times = [float(d.get("timestep")) for d in sets]
    if times != [0.0, 0.5, 1.0]:
        failed.append(f"{dim}D: pvd times {times}")
    for d in sets:
        path = os.path.join(out, d.get("file"))  # relative to the .pvd
        reader = vtk.vtkXMLPUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        grid = reader.GetOutput()
        n_pts, n_cells = grid.GetNumberOfPoints(), grid.GetNumberOfCells()
        if n_pts == 0 or n_cells == 0:
            failed.append(f"{path}: empty")
            continue
        conn = grid.GetCells().GetConnectivityArray()
        ids = [conn.GetValue(i) for i in range(conn.GetNumberOfValues())]
        if min(ids) < 0 or max(ids) >= n_pts:
            failed.append(f"{path}: connectivity out of range")
        pd = grid.GetPointData()
        for name in expected:
            arr = pd.GetArray(name)
            if arr is None:
                failed.append(f"{path}: array {name} missing")
                continue
            vals = [arr.GetValue(i) for i in range(arr.GetNumberOfValues())]
            if not all(math.isfinite(v) for v in vals):
                failed.append(f"{path}: array {name} not finite")
        # Stage 0 is the pre-excavation state: zero induced displacement and
        # the in-situ stress sxx = -30 MPa everywhere.
        if float(d.get("timestep")) == 0.0:
            u = pd.GetArray("displacement")
            sxx = pd.GetArray("stress_xx")
            if max(abs(u.GetValue(i)) for i in range(u.GetNumberOfValues())) != 0.0:
                failed.append(f"{path}: stage 0 displacement not zero")
            if max(abs(sxx.GetValue(i) + 30e6) for i in range(sxx.GetNumberOfTuples())) > 1e-6:
                failed.append(f"{path}: stage 0 stress_xx is not the in-situ value")
        print(f"{path}: {n_pts} points, {n_cells} cells, ok")
print("\n".join(failed) if failed else "all VTK files read back")
sys.exit(1 if failed else 0)
