#!/usr/bin/env bash
# Runs `demfem bench dem` and the same scene in Yade (scripts/bench_yade.py)
# on this machine in one invocation and prints the speed ratio demfem / Yade
# in particle steps per second per core (docs/bench.md; target >= 3).
#
# Usage: scripts/bench_compare.sh [--dim 2|3 | --material FILE] [--n N] [--steps S] [--threads T]
#   DEMFEM_EXE   demfem executable (default: build/apps/demfem)
#   YADE         yade executable   (default: yade; Debian package `yade`)
# --dim 2 compares demfem disks with a Yade monolayer of spheres (planar
# motion); --dim 3 (default) compares spheres with spheres. --material FILE
# runs both codes on a calibrated material (its dimension, sizes, stiffness
# and strength distributions; scripts/bench_yade.py says how Yade gets them).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exe="${DEMFEM_EXE:-$here/build/apps/demfem}"
yade="${YADE:-yade}"
dim=3 n=10000 steps=200 threads=1 material=
while [ $# -gt 0 ]; do
  case "$1" in
    --dim) dim="$2"; shift 2 ;;
    --material) material="$2"; shift 2 ;;
    --n) n="$2"; shift 2 ;;
    --steps) steps="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench_compare: unknown option '$1' (allowed: --dim --material --n --steps --threads)" >&2; exit 2 ;;
  esac
done
[ -x "$exe" ] || { echo "bench_compare: $exe not found (run ./demfem build)" >&2; exit 1; }
command -v "$yade" >/dev/null || { echo "bench_compare: '$yade' not found (apt-get install yade)" >&2; exit 1; }

if [ -n "$material" ]; then
  scene=(--material "$material")
else
  scene=(--dim "$dim")
fi
d_json="$("$exe" bench dem "${scene[@]}" --n "$n" --steps "$steps" --threads "$threads" --json)"
y_json="$("$yade" -j "$threads" -n -x "$here/scripts/bench_yade.py" "${scene[@]}" --n "$n" \
           --steps "$steps" --json 2>/dev/null | grep '^{')"

python3 - "$d_json" "$y_json" <<'EOF'
import json, sys
d, y = json.loads(sys.argv[1]), json.loads(sys.argv[2])
def per_core(r):
    return r["particle_steps_per_s"] / r["threads"]
print("%-8s %4s %9s %9s %7s %6s %9s %14s %14s" % ("code", "dim", "particles", "contacts",
      "threads", "steps", "wall_s", "psteps/s", "psteps/s/core"))
for name, r in (("demfem", d), ("yade", y)):
    print("%-8s %4d %9d %9d %7d %6d %9.3f %14.4g %14.4g" % (name, r["dim"], r["n_particles"],
          r["n_contacts"], r["threads"], r["steps"], r["wall_s"], r["particle_steps_per_s"],
          per_core(r)))
ratio = per_core(d) / per_core(y)
# Same ratio from CPU time (all threads): robust when other jobs share the
# machine, and it charges each code for the cores it actually kept busy.
cpu_ratio = (d["n_particles"] * d["steps"] / d["cpu_s"]) / (y["n_particles"] * y["steps"] / y["cpu_s"])
print("ratio demfem/yade (particle steps per second per core): %.3g (target >= 3)" % ratio)
print("ratio demfem/yade (particle steps per CPU second):       %.3g" % cpu_ratio)
print(json.dumps({"demfem": d, "yade": y, "ratio_per_core": ratio, "ratio_per_cpu_s": cpu_ratio}))
EOF
