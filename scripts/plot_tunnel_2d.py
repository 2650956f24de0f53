#!/usr/bin/python3
"""Draws the last frame of a 2D `demfem tunnel` run as an SVG: grains
(shaded by displacement magnitude) and cracks (red: tensile, blue: shear).

usage: scripts/plot_tunnel_2d.py OUTPUT_DIR [FILE.svg]
Needs Debian's python3-vtk9 (installed by ./demfem)."""
import glob
import sys

import vtk


def read(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out_dir = sys.argv[1]
    target = sys.argv[2] if len(sys.argv) > 2 else out_dir + "/tunnel_2d.svg"
    particles = read(sorted(glob.glob(out_dir + "/particles_*.vtp"))[-1])
    cracks = read(sorted(glob.glob(out_dir + "/cracks_*.vtp"))[-1])

    radius = particles.GetPointData().GetArray("radius")
    disp = particles.GetPointData().GetArray("displacement")
    xs = [particles.GetPoint(i) for i in range(particles.GetNumberOfPoints())]
    extent = max(max(abs(p[0]), abs(p[1])) for p in xs) * 1.05
    umax = max(sum(c * c for c in disp.GetTuple3(i)) ** 0.5
               for i in range(disp.GetNumberOfTuples())) or 1.0
    size = 800.0
    scale = size / (2 * extent)

    def sx(x):
        return (x + extent) * scale

    def sy(y):
        return (extent - y) * scale

    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{size:.0f}" '
           f'height="{size + 40:.0f}" viewBox="0 0 {size:.0f} {size + 40:.0f}">',
           '<rect width="100%" height="100%" fill="white"/>']
    for i, p in enumerate(xs):
        u = sum(c * c for c in disp.GetTuple3(i)) ** 0.5 / umax
        shade = int(235 - 150 * u)
        svg.append(f'<circle cx="{sx(p[0]):.1f}" cy="{sy(p[1]):.1f}" '
                   f'r="{radius.GetValue(i) * scale:.2f}" '
                   f'fill="rgb({shade},{shade},{min(255, shade + 20)})" stroke="none"/>')
    mode = cracks.GetCellData().GetArray("mode")
    for c in range(cracks.GetNumberOfCells()):
        ids = cracks.GetCell(c).GetPointIds()
        a = cracks.GetPoint(ids.GetId(0))
        b = cracks.GetPoint(ids.GetId(ids.GetNumberOfIds() - 1))
        colour = "#d62728" if mode.GetValue(c) == 0 else "#1f4fd6"
        svg.append(f'<line x1="{sx(a[0]):.1f}" y1="{sy(a[1]):.1f}" x2="{sx(b[0]):.1f}" '
                   f'y2="{sy(b[1]):.1f}" stroke="{colour}" stroke-width="3"/>')
    svg.append(f'<text x="10" y="{size + 28:.0f}" font-family="sans-serif" font-size="16">'
               f'{particles.GetNumberOfPoints()} grains (darker: larger displacement, '
               f'max {umax * 1e3:.2f} mm); {cracks.GetNumberOfCells()} cracks: '
               f'red tensile, blue shear</text>')
    svg.append("</svg>")
    with open(target, "w") as f:
        f.write("\n".join(svg) + "\n")
    print(target)


if __name__ == "__main__":
    main()
