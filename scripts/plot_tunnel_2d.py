#!/usr/bin/python3
"""Draws the last frame of a 2D `demfem tunnel` run as an SVG, a rock
engineer's view of a window of the run around the tunnel:

- the continuum's cells coloured by a stress measure in MPa, computed from
  its stress_xx, stress_yy, stress_xy: the major in-plane principal
  (compressive) stress sigma_1, compression positive (default), or the deviator
  sigma_1 - sigma_3 (--stress deviator); the scale runs between the 1st and
  99th percentiles of the cells in the window whose centre is outside the
  region, rounded out to 5 MPa (the layer under the grains is not drawn);
- the grains (disks of their radius) shaded by displacement magnitude in mm,
  by default the displacement caused by the excavation (last frame minus the
  frame at the end of the in-situ phase, grains matched by id; the total
  displacement with --total-displacement or when that frame is not found);
  the scale is clipped at a percentile (--percentile, default 98) of the
  grains outside the opening, so that a grain that fell into it does not
  wash out the scale;
- cracks as segments (red: tensile, blue: shear), the tunnel outline and the
  region boundary (dashed);
- two colour bars and a caption with the in-situ stresses and crack counts
  (summary.json).

usage: scripts/plot_tunnel_2d.py OUTPUT_DIR [FILE.svg] [options]
FILE.svg defaults to OUTPUT_DIR/tunnel_2d.svg; --help lists the options.
Reads particles_*.vtp, cracks_*.vtp, continuum_*.vtu, particles.pvd,
summary.json and manifest.json (tunnel radius). Needs Debian's python3-vtk9
(installed by ./demfem); run it with /usr/bin/python3."""
import argparse
import glob
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import vtk

VIRIDIS = ["#440154", "#472d7b", "#3b528b", "#2c728e", "#21918c",
           "#28ae80", "#5ec962", "#addc30", "#fde725"]
GREYS = ["#f2f2f2", "#3c3c3c"]
TENSILE, SHEAR = "#d62728", "#1f4fd6"
FONT = 'font-family="DejaVu Sans, Arial, sans-serif"'


def colour(ramp, t):
    """Colour at t in [0, 1] of a ramp of hex anchors, linearly interpolated."""
    t = min(1.0, max(0.0, t)) * (len(ramp) - 1)
    i = min(int(t), len(ramp) - 2)
    f = t - i
    a = [int(ramp[i][k:k + 2], 16) for k in (1, 3, 5)]
    b = [int(ramp[i + 1][k:k + 2], 16) for k in (1, 3, 5)]
    return "#%02x%02x%02x" % tuple(round(x + f * (y - x)) for x, y in zip(a, b))


def percentile(values, q):
    """q-th percentile, linearly interpolated; 0 for no values."""
    values = sorted(values)
    if len(values) < 2:
        return values[0] if values else 0.0
    pos = q / 100.0 * (len(values) - 1)
    i = min(int(pos), len(values) - 2)
    return values[i] + (pos - i) * (values[i + 1] - values[i])


def nice_step(span, n=5):
    raw = span / n
    mag = 10 ** math.floor(math.log10(raw))
    for m in (1, 2, 2.5, 5, 10):
        if m * mag >= raw:
            return m * mag
    return 10 * mag


def read(path):
    reader = (vtk.vtkXMLUnstructuredGridReader() if path.endswith(".vtu")
              else vtk.vtkXMLPolyDataReader())
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def frames(out_dir, name):
    """[(time, path)] of a series, from NAME.pvd, else the files' numbers."""
    pvd = os.path.join(out_dir, name + ".pvd")
    if os.path.exists(pvd):
        return [(float(d.get("timestep")), os.path.join(out_dir, d.get("file")))
                for d in ET.parse(pvd).getroot().iter("DataSet")]
    files = sorted(glob.glob(os.path.join(out_dir, name + "_*.vt?")),
                   key=lambda f: int(f.rsplit("_", 1)[1].split(".")[0]))
    return [(None, f) for f in files]


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def parse_args():
    p = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0].replace("\n", " "),
        usage="scripts/plot_tunnel_2d.py OUTPUT_DIR [FILE.svg] [options]")
    p.add_argument("out_dir", metavar="OUTPUT_DIR",
                   help="output directory of a 2D `demfem tunnel` run")
    p.add_argument("target", metavar="FILE.svg", nargs="?",
                   help="SVG to write (default OUTPUT_DIR/tunnel_2d.svg)")
    p.add_argument("--stress", choices=("sigma1", "deviator"), default="sigma1",
                   help="continuum colour: major principal compressive stress "
                        "sigma_1 (default) or the deviator sigma_1 - sigma_3, MPa")
    p.add_argument("--half-width", type=float, metavar="M",
                   help="view window |x|, |y| <= M metres (default: 4.5 tunnel "
                        "radii, at least the region radius plus one tunnel radius)")
    p.add_argument("--percentile", type=float, default=98.0, metavar="P",
                   help="grain displacement scale clipped at this percentile "
                        "of the grains outside the opening (default 98)")
    p.add_argument("--total-displacement", action="store_true",
                   help="shade grains by their total displacement instead of "
                        "the excavation's")
    p.add_argument("--tunnel-radius", type=float, metavar="A",
                   help="tunnel radius in m (default: manifest.json's Tunnel/radius)")
    return p.parse_args()


def main():
    args = parse_args()
    out_dir = args.out_dir
    target = args.target or os.path.join(out_dir, "tunnel_2d.svg")
    if not os.path.isdir(out_dir):
        sys.exit(f"no directory {out_dir}")
    summary = load_json(os.path.join(out_dir, "summary.json"))
    params = load_json(os.path.join(out_dir, "manifest.json")).get("parameters", {})

    a = args.tunnel_radius or float(params.get("Tunnel", {}).get("radius", "nan"))
    if not a > 0:
        sys.exit("no tunnel radius in manifest.json: pass --tunnel-radius")
    region = summary.get("dem_region_radius") or float(
        params.get("DEM region", {}).get("radius", "nan"))
    half = args.half_width or max(4.5 * a, (region if region > 0 else 0) + a)

    pframes = frames(out_dir, "particles")
    cframes = frames(out_dir, "cracks")
    qframes = frames(out_dir, "continuum")
    if not pframes:
        sys.exit(f"no particles_*.vtp in {out_dir}")
    particles = read(pframes[-1][1])
    pd = particles.GetPointData()
    radius, disp, ids = pd.GetArray("radius"), pd.GetArray("displacement"), pd.GetArray("id")
    n = particles.GetNumberOfPoints()
    pos = [particles.GetPoint(i) for i in range(n)]
    u = [disp.GetTuple3(i) for i in range(n)]

    # Excavation displacement: minus the frame that ends the in-situ phase.
    reference = None
    t_insitu = next((ph.get("time_end_s") for ph in summary.get("phases", [])
                     if ph.get("name") == "in-situ"), None)
    if not args.total_displacement and t_insitu is not None and ids is not None:
        for t, path in pframes[:-1]:
            if t is not None and abs(t - t_insitu) <= 1e-9 * abs(t_insitu):
                ref = read(path)
                rd, rid = ref.GetPointData().GetArray("displacement"), \
                    ref.GetPointData().GetArray("id")
                reference = {int(rid.GetValue(i)): rd.GetTuple3(i)
                             for i in range(ref.GetNumberOfPoints())}
                break
    if reference is not None:
        u = [tuple(c - r for c, r in zip(ui, reference.get(int(ids.GetValue(i)), (0, 0, 0))))
             for i, ui in enumerate(u)]
    umag = [math.hypot(ui[0], ui[1]) for ui in u]
    in_opening = [math.hypot(p[0], p[1]) < a for p in pos]
    outside = [m for m, o in zip(umag, in_opening) if not o]
    umax = percentile(outside, args.percentile) or max(umag + [1e-12])

    # Continuum stress per cell (deal.II writes cell-wise values at the corners).
    cells, measure = [], []
    if qframes:
        cont = read(qframes[-1][1])
        cpd = cont.GetPointData()
        arrays = [cpd.GetArray(k) for k in ("stress_xx", "stress_yy", "stress_xy")]
        if any(arr is None for arr in arrays):
            sys.exit("continuum_*.vtu has no stress_xx, stress_yy, stress_xy")
        for c in range(cont.GetNumberOfCells()):
            pid = cont.GetCell(c).GetPointIds()
            k = [pid.GetId(j) for j in range(pid.GetNumberOfIds())]
            pts = [cont.GetPoint(j) for j in k]
            if (min(p[0] for p in pts) > half or max(p[0] for p in pts) < -half or
                    min(p[1] for p in pts) > half or max(p[1] for p in pts) < -half):
                continue
            if region > 0 and math.hypot(sum(p[0] for p in pts) / len(pts),
                                         sum(p[1] for p in pts) / len(pts)) < region:
                continue  # the overlap layer under the grains: hidden
            xx, yy, xy = (sum(arr.GetValue(j) for j in k) / len(k) / 1e6 for arr in arrays)
            mean, r = 0.5 * (xx + yy), math.hypot(0.5 * (xx - yy), xy)
            cells.append(pts)
            measure.append(2 * r if args.stress == "deviator" else r - mean)
    if measure:
        s_lo = 5 * math.floor(percentile(measure, 1) / 5)
        s_hi = 5 * math.ceil(percentile(measure, 99) / 5)
        if s_hi <= s_lo:
            s_hi = s_lo + 5
    else:
        s_lo, s_hi = 0.0, 1.0

    # Layout (px): the map window, then the two colour bars, then the caption.
    width, margin, top = 800.0, 20.0, 10.0
    mapsize = width - 2 * margin
    scale = mapsize / (2 * half)
    bar_y = top + mapsize + 38
    height = bar_y + 78

    def sx(x):
        return margin + (x + half) * scale

    def sy(y):
        return top + (half - y) * scale

    def f(v):
        return f"{v:.2f}".rstrip("0").rstrip(".")

    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" '
           f'height="{height:.0f}" viewBox="0 0 {width:.0f} {height:.0f}">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<clipPath id="view"><rect x="{f(margin)}" y="{f(top)}" '
           f'width="{f(mapsize)}" height="{f(mapsize)}"/></clipPath>',
           '<g clip-path="url(#view)">']
    # Continuum cells (stroke of their own colour hides hairline seams).
    svg.append('<g stroke-width="0.6">')
    for pts, s in zip(cells, measure):
        col = colour(VIRIDIS, (s - s_lo) / (s_hi - s_lo))
        pts_s = " ".join(f"{f(sx(p[0]))},{f(sy(p[1]))}" for p in pts)
        svg.append(f'<polygon points="{pts_s}" fill="{col}" stroke="{col}"/>')
    svg.append('</g>')
    # Grains, over a white disk that hides the continuum's overlap layer.
    if region > 0:
        svg.append(f'<circle cx="{f(sx(0))}" cy="{f(sy(0))}" r="{f(region * scale)}" '
                   'fill="white"/>')
    svg.append('<g stroke="none">')
    for p, r, m in zip(pos, (radius.GetValue(i) for i in range(n)), umag):
        svg.append(f'<circle cx="{f(sx(p[0]))}" cy="{f(sy(p[1]))}" r="{f(r * scale)}" '
                   f'fill="{colour(GREYS, m / umax)}"/>')
    svg.append('</g>')
    # Tunnel outline and region boundary.
    svg.append(f'<circle cx="{f(sx(0))}" cy="{f(sy(0))}" r="{f(a * scale)}" fill="none" '
               'stroke="black" stroke-width="1.5"/>')
    if region > 0:
        svg.append(f'<circle cx="{f(sx(0))}" cy="{f(sy(0))}" r="{f(region * scale)}" '
                   'fill="none" stroke="black" stroke-width="1.2" stroke-dasharray="8 5"/>')
    # Cracks, on a white halo.
    n_cracks = {0: 0, 1: 0}
    if cframes:
        cracks = read(cframes[-1][1])
        mode = cracks.GetCellData().GetArray("mode")
        segs = []
        for c in range(cracks.GetNumberOfCells()):
            pid = cracks.GetCell(c).GetPointIds()
            p0 = cracks.GetPoint(pid.GetId(0))
            p1 = cracks.GetPoint(pid.GetId(pid.GetNumberOfIds() - 1))
            kind = 0 if mode is None or mode.GetValue(c) == 0 else 1
            n_cracks[kind] += 1
            segs.append((f'x1="{f(sx(p0[0]))}" y1="{f(sy(p0[1]))}" '
                         f'x2="{f(sx(p1[0]))}" y2="{f(sy(p1[1]))}"', kind))
        svg.append('<g stroke="white" stroke-width="5.4" stroke-linecap="round">')
        svg += [f'<line {s}/>' for s, _ in segs]
        svg.append('</g><g stroke-width="3" stroke-linecap="round">')
        svg += [f'<line {s} stroke="{TENSILE if k == 0 else SHEAR}"/>' for s, k in segs]
        svg.append('</g>')
    svg.append('</g>')
    svg.append(f'<rect x="{f(margin)}" y="{f(top)}" width="{f(mapsize)}" '
               f'height="{f(mapsize)}" fill="none" stroke="#666" stroke-width="1"/>')
    # Scale bar: the tunnel radius rounded to whole metres.
    bar_m = max(1, round(a))
    x0, y0 = margin + 14, top + mapsize - 16
    svg.append(f'<rect x="{f(x0 - 6)}" y="{f(y0 - 20)}" width="{f(bar_m * scale + 12)}" '
               'height="28" fill="white"/>')
    svg.append(f'<path d="M{f(x0)},{f(y0 - 5)}v5h{f(bar_m * scale)}v-5" fill="none" '
               'stroke="black" stroke-width="1.5"/>')
    svg.append(f'<text x="{f(x0 + bar_m * scale / 2)}" y="{f(y0 - 8)}" {FONT} font-size="13" '
               f'text-anchor="middle">{bar_m} m</text>')

    def colour_bar(x, w, lo, hi, ramp, title, over, under=False):
        out = [f'<text x="{f(x)}" y="{f(bar_y - 8)}" {FONT} font-size="14">{title}</text>']
        steps = 64
        for j in range(steps):
            out.append(f'<rect x="{f(x + j * w / steps)}" y="{f(bar_y)}" '
                       f'width="{f(w / steps + 0.5)}" height="14" '
                       f'fill="{colour(ramp, (j + 0.5) / steps)}"/>')
        if over:  # values above the scale: a triangle in the top colour
            out.append(f'<path d="M{f(x + w)},{f(bar_y)}l10,7l-10,7z" '
                       f'fill="{colour(ramp, 1)}" stroke="#666" stroke-width="0.6"/>')
        if under:  # values below the scale
            out.append(f'<path d="M{f(x)},{f(bar_y)}l-10,7l10,7z" '
                       f'fill="{colour(ramp, 0)}" stroke="#666" stroke-width="0.6"/>')
        out.append(f'<rect x="{f(x)}" y="{f(bar_y)}" width="{f(w)}" height="14" '
                   'fill="none" stroke="#666" stroke-width="0.6"/>')
        step = nice_step(hi - lo)
        v = math.ceil(lo / step - 1e-9) * step
        while v <= hi + 1e-9 * step:
            xv = x + (v - lo) / (hi - lo) * w
            out.append(f'<line x1="{f(xv)}" y1="{f(bar_y + 14)}" x2="{f(xv)}" '
                       f'y2="{f(bar_y + 18)}" stroke="#333"/>')
            out.append(f'<text x="{f(xv)}" y="{f(bar_y + 31)}" {FONT} font-size="12" '
                       f'text-anchor="middle">{v:g}</text>')
            v += step
        return out

    stress_title = ("continuum deviator σ1 − σ3 (MPa)" if args.stress == "deviator"
                    else "continuum σ1, major principal stress (MPa)")
    svg += colour_bar(margin + 10, 340, s_lo, s_hi, VIRIDIS, stress_title,
                      bool(measure) and max(measure) > s_hi,
                      bool(measure) and min(measure) < s_lo)
    disp_title = ("grain displacement by the excavation (mm)" if reference is not None
                  else "grain displacement (mm)")
    svg += colour_bar(width / 2 + 20, 340, 0, umax * 1e3, GREYS, disp_title,
                      max(umag) > umax)

    # Caption: in-situ stresses (compression positive, as sigma_1) and cracks.
    st = summary.get("in_situ_stress", [])
    insitu = ""
    if len(st) >= 2:
        comps = [("σxx", st[0]), ("σyy", st[1])] + ([("σxy", st[2])] if len(st) > 2 and st[2] else [])
        insitu = "in situ (compression +) " + ", ".join(
            f"{k} = {-v / 1e6:g} MPa".replace("-", "−") for k, v in comps) + "; "
    total = n_cracks[0] + n_cracks[1]
    before = summary.get("cracks_before_excavation")
    after = f" ({total - before} from the excavation)" if before is not None else ""
    opening = sum(in_opening)
    fell = f"; {opening} grains in the opening, not in the scale" if opening else ""
    svg.append(f'<text x="{f(margin)}" y="{f(bar_y + 64)}" {FONT} font-size="14">'
               f'{insitu}{total} cracks{after}: '
               f'<tspan fill="{TENSILE}">{n_cracks[0]} tensile</tspan>, '
               f'<tspan fill="{SHEAR}">{n_cracks[1]} shear</tspan>{fell}</text>')
    svg.append("</svg>")
    with open(target, "w") as out:
        out.write("\n".join(svg) + "\n")
    print(target)


if __name__ == "__main__":
    main()
