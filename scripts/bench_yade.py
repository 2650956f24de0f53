# Yade counterpart of `demfem bench dem` (docs/bench.md).
#
# Usage (Debian package `yade`, not a project dependency):
#   yade -j T -n -x scripts/bench_yade.py --dim 3 --n N --steps S [--json]
#   yade -j T -n -x scripts/bench_yade.py --material FILE --n N --steps S [--json]
#
# With --material (a material.json of `demfem calibrate`, as `demfem bench dem
# --material`): radii from the file's size-distribution pieces (uniform or
# clipped Gaussian diameters, times the diameter multiplier, pieces by
# volume fraction), lattice spacing 2 x the mean radius, young = E*,
# poisson = 1/kappa* (Yade's ks/kn), friction, density; the bond strengths
# vary as in the material: Yade takes a contact's cohesion from its two
# bodies' materials, so 64 materials with normalCohesion drawn from the
# tensile-strength distribution (and shearCohesion the cohesion mean) are
# assigned to the bodies at random. The dimension is the file's.
#
# Same scene as apps/bench_command.cc: N spheres of radii uniform in
# [0.8, 1.2] r0 (r0 = 1 mm, density 2650) on a jittered lattice of spacing
# 2 r0 (3D: face-centred cubic; 2D: a hexagonal MONOLAYER of spheres with
# out-of-plane motion blocked, since Yade has no disks), every pair with a gap
# below ~0.1 r0 bonded at the start (CohFrictMat, setCohesionNow, huge
# normal/shear cohesion, moment transfer: Law2_ScGeom6D_CohFrictPhys_
# CohesionMoment), bottom layer fixed, top layer moving down at an axial
# strain rate of 0.1 /s, NewtonIntegrator(damping=0.7). Only O.run(S) is timed.
# Prints particle steps per second and the number of contacts (interactions).
import json
import math
import random
import sys
import time

from yade import O, utils
from yade.wrapper import (Bo1_Sphere_Aabb, CohFrictMat, ForceResetter,
                          Ig2_Sphere_Sphere_ScGeom6D, InsertionSortCollider,
                          InteractionLoop,
                          Ip2_CohFrictMat_CohFrictMat_CohFrictPhys,
                          Law2_ScGeom6D_CohFrictPhys_CohesionMoment,
                          NewtonIntegrator)


def parse(argv):
    opts = {"dim": 3, "n": 10000, "steps": 200, "json": False, "material": None}
    a = 0
    while a < len(argv):
        k = argv[a]
        if k == "--json":
            opts["json"] = True
        elif k == "--material" and a + 1 < len(argv):
            opts["material"] = argv[a + 1]
            a += 1
        elif k in ("--dim", "--n", "--steps") and a + 1 < len(argv):
            try:
                opts[k[2:]] = int(argv[a + 1])
            except ValueError:
                sys.exit("bench_yade: invalid value for %s: %s" % (k, argv[a + 1]))
            a += 1
        elif k != "dem":
            sys.exit("bench_yade: unknown option %s (allowed: --dim 2|3 --material FILE "
                     "--n N --steps S --json)" % k)
        a += 1
    if opts["material"]:
        try:
            with open(opts["material"]) as f:
                opts["mat"] = json.load(f)
            opts["dim"] = int(opts["mat"]["dim"])
            opts["mat"]["microparameters"]["size_distribution"]
        except (OSError, ValueError, KeyError) as e:
            sys.exit("bench_yade: --material %s: not a readable material file (%s)"
                     % (opts["material"], e))
    if opts["dim"] not in (2, 3):
        sys.exit("bench_yade: --dim must be 2 or 3")
    if opts["n"] < 8 or opts["steps"] < 1:
        sys.exit("bench_yade: --n must be >= 8 and --steps >= 1")
    return opts


def lattice(dim, n, a):
    """Same sites and order as apps/bench_command.cc (layer by layer)."""
    x = []
    if dim == 2:
        nx = max(2, int(round(math.sqrt(n))))
        row = 0
        while len(x) < n:
            for i in range(nx):
                if len(x) >= n:
                    break
                x.append(((i + 0.5 * (row % 2)) * a, row * a * math.sqrt(3.0) / 2, 0.0))
            row += 1
    else:
        c = a * math.sqrt(2.0)
        nxy = max(1, int(round((n / 4.0) ** (1.0 / 3.0))))
        plane = (((0, 0), (0.5, 0.5)), ((0.5, 0), (0, 0.5)))
        layer = 0
        while len(x) < n:
            half, kz = layer % 2, layer // 2
            for j in range(nxy):
                for i in range(nxy):
                    for s in range(2):
                        if len(x) < n:
                            x.append(((i + plane[half][s][0]) * c, (j + plane[half][s][1]) * c,
                                      (kz + 0.5 * half) * c))
            layer += 1
    return x


def material_radii(m, n, rng):
    """n radii of the material's size distribution (pieces by volume)."""
    pieces = list(m["size_distribution"].values())
    mult = m.get("diameter_multiplier", 1.0)
    radii = []
    for p in pieces:
        k = max(1, int(round(n * p["volume_fraction"])))
        for _ in range(k):
            if p["kind"] == "gaussian":
                d = min(max(rng.gauss(p["mean_m"], p["sd_m"]), p["D_lo_m"]), p["D_hi_m"])
            else:
                d = rng.uniform(p["D_lo_m"], p["D_hi_m"])
            radii.append(0.5 * d * mult)
    rng.shuffle(radii)
    while len(radii) < n:
        radii.append(radii[rng.randrange(len(radii))])
    return radii[:n]


def scene_materials(m, rng):
    """Yade materials of a calibrated flat-jointed material (see the header)."""
    mats = []
    for _ in range(64):
        ten = max(0.0, rng.gauss(m["fj_ten_mean_Pa"], m["fj_ten_sd_Pa"]))
        mats.append(O.materials.append(CohFrictMat(
            young=m["emod_Pa"], poisson=1.0 / m["krat"], density=m["density_kg_m3"],
            frictionAngle=math.atan(m["fric"]), isCohesive=True, normalCohesion=ten,
            shearCohesion=m["fj_coh_mean_Pa"], momentRotationLaw=True)))
    return mats


def main():
    o = parse(sys.argv[1:])
    dim, n, steps = o["dim"], o["n"], o["steps"]
    r0, rate = 1e-3, 0.1
    t0 = time.perf_counter()
    rng = random.Random(12345)
    # ks/kn = poisson in Yade's CohFrictPhys: kappa* = 2 -> 0.5 (as demfem).
    micro = o["mat"]["microparameters"] if o["material"] else None
    if micro:
        mats = scene_materials(micro, rng)
        radii = material_radii(micro, n, rng)
        r0 = sum(radii) / n
    else:
        mats = [O.materials.append(CohFrictMat(young=50e9, poisson=0.5, density=2650,
                                               frictionAngle=math.atan(0.5), isCohesive=True,
                                               normalCohesion=1e20, shearCohesion=1e20,
                                               momentRotationLaw=True))]
        radii = [rng.uniform(0.8, 1.2) * r0 for _ in range(n)]
    bodies = []
    for k, site in enumerate(lattice(dim, n, 2 * r0)):
        p = [site[d] + (rng.uniform(-1e-3, 1e-3) * r0 if d < dim else 0.0) for d in range(3)]
        bodies.append(utils.sphere(p, radii[k], material=mats[rng.randrange(len(mats))]))
    ids = O.bodies.append(bodies)
    up = dim - 1  # y in 2D, z in 3D
    lo = min(O.bodies[i].state.pos[up] for i in ids)
    hi = max(O.bodies[i].state.pos[up] for i in ids)
    height = hi - lo
    for i in ids:
        b = O.bodies[i]
        if b.state.pos[up] < lo + r0:
            b.state.blockedDOFs = "xyzXYZ"
        elif b.state.pos[up] > hi - r0:
            b.state.blockedDOFs = "xyzXYZ"
            v = [0.0, 0.0, 0.0]
            v[up] = -rate * height
            b.state.vel = v
        elif dim == 2:
            b.state.blockedDOFs = "zXY"  # planar motion of the monolayer
    # Bond every pair with gap < ~0.1 r0 (detection factor 1.05 on R1 + R2 ~ 2 r0)
    # during the first step, then detect only touching pairs (standard Yade idiom).
    factor = 1.05
    bo1 = Bo1_Sphere_Aabb(aabbEnlargeFactor=factor)
    ig2 = Ig2_Sphere_Sphere_ScGeom6D(interactionDetectionFactor=factor)
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([bo1]),
        InteractionLoop([ig2],
                        [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True,
                                                                  setCohesionOnNewContacts=False)],
                        [Law2_ScGeom6D_CohFrictPhys_CohesionMoment(always_use_moment_law=True)]),
        NewtonIntegrator(damping=0.7),
    ]
    O.dt = 0.8 * utils.PWaveTimeStep()
    O.step()
    bo1.aabbEnlargeFactor = -1
    ig2.interactionDetectionFactor = 1.0
    O.step()
    setup = time.perf_counter() - t0
    contacts = O.interactions.countReal()
    c1, t1 = time.process_time(), time.perf_counter()
    O.run(steps, True)
    wall = time.perf_counter() - t1
    cpu = time.process_time() - c1  # all threads of the process
    threads = O.numThreads
    res = {
        "code": "yade", "dim": dim, "n_particles": len(ids), "n_contacts": contacts,
        "threads": threads, "steps": steps, "setup_s": setup, "wall_s": wall, "cpu_s": cpu,
        "timestep": O.dt, "particle_steps_per_s": len(ids) * steps / wall,
        "contact_updates_per_s": contacts * steps / wall,
        "particle_steps_per_s_per_thread": len(ids) * steps / wall / threads,
        "scene": "3D spheres" if dim == 3 else "monolayer of spheres (planar motion)",
        "material": o["material"] or "single-group scene",
    }
    if o["json"]:
        print(json.dumps(res))
    else:
        for k, v in res.items():
            print("%-32s %s" % (k, v))


main()
