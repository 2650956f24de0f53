#!/usr/bin/env bash
# Fault-injection probes of run ownership and checkpoint integrity
# (docs/tunnel.md, "Output directory: lock, manifest, --overwrite" and
# "Checkpoints and restart"), replayed on the built executable:
#   1. two concurrent runs into one directory: the second is refused, naming
#      the holder; the first finishes;
#   2. a re-run into a used directory without --overwrite is refused, with
#      --overwrite it runs;
#   3. a checkpoint with corrupted bytes is refused naming the checksum
#      failure and the file;
#   4. a full disk gives one error naming the file;
#   5. outcome checks (docs/tunnel.md, "Run status and exit codes"): phases
#      cut by the step limit not_equilibrated (exit 3, or 0 with --accept;
#      a short ramp still installs sigma0: the installation is kinematic),
#      an absurd stiffness contrast in_situ_not_reached (exit 4).
# Usage: fault_injection.sh DEMFEM_EXE SOURCE_DIR
set -u
exe="$1"
src="$2"
work="$(mktemp -d "${TMPDIR:-/tmp}/demfem_fault_XXXXXX")"
trap 'rm -rf "$work"' EXIT
failed=0
check() { # check NAME CONDITION...
  local name="$1"; shift
  if "$@"; then echo "ok: $name"; else echo "FAILED: $name"; failed=$((failed + 1)); fi
}

# The small verification region of the material keys (no material file).
small=(--set "DEM region/material file=" --set "Continuum/young modulus=16.3e9"
       --set "Continuum/poisson ratio=0.11" --set "DEM region/fj ten=8e6"
       --set "DEM region/fj coh=40e6" --set "DEM region/lnm emod=20e9"
       --set "DEM region/radius=1.0" --set "Tunnel/radius=0.4"
       --set "DEM region/grain diameter=" --set "DEM region/grain diameter min=0.08"
       --set "DEM region/grain diameter max=0.12"
       --set "Continuum/outer radius=10" --set "Output/interval=0"
       --set "Coupling/step limit=300" --set "Coupling/ramp crossing times=3"
       --set "Output/checkpoint interval=200")
prm="$src/apps/examples/tunnel_2d.prm"
out="$work/run"

# 1. Two concurrent runs. The first never reaches equilibrium (ratio 1e-12),
# so it is still running when the second starts; SIGTERM then stops it with
# a checkpoint, and its lock is released.
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$out" \
  --set "Coupling/equilibrium ratio=1e-12" --set "Coupling/step limit=1000000" \
  > "$work/first.log" 2>&1 &
first=$!
for _ in $(seq 1 600); do [ -f "$out/demfem.lock" ] && break; sleep 0.05; done
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$out" \
  > "$work/second.log" 2>&1
second_rc=$?
kill -TERM "$first"
wait "$first"
first_rc=$?
check "concurrent: second run refused (exit $second_rc)" [ "$second_rc" -eq 1 ]
check "concurrent: message names the holder" \
  grep -q "in use by another demfem run: pid $first on host" "$work/second.log"
check "concurrent: first run stopped by SIGTERM (exit $first_rc)" [ "$first_rc" -eq 143 ]
check "concurrent: manifest status interrupted" \
  grep -q '"status": "interrupted"' "$out/manifest.json"
check "concurrent: lock released" [ ! -e "$out/demfem.lock" ]

# 2. Re-run without --overwrite refused; with it, runs. (Its phases are cut
# by the step limit of 300 (the in-situ phase has the ramp's steps + 300):
# not_equilibrated, exit 3, the phase and the limit named. The in-situ
# stress is reached all the same: the whole model follows the in-situ
# strain during the ramp, however short; a far-field ramp of 300 steps
# left the region unloaded, in_situ_not_reached.)
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$out" \
  > "$work/rerun.log" 2>&1
rc=$?
check "re-run: refused without --overwrite (exit $rc)" [ "$rc" -ne 0 ]
check "re-run: message names --overwrite" grep -q -- "--overwrite" "$work/rerun.log"
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$out" --overwrite \
  > "$work/overwrite.log" 2>&1
rc=$?
check "re-run: --overwrite runs, not equilibrated (exit $rc)" [ "$rc" -eq 3 ]
check "re-run: manifest status not_equilibrated" \
  grep -q '"status": "not_equilibrated"' "$out/manifest.json"
check "re-run: a short ramp installs the in-situ stress" \
  bash -c "! grep -q in_situ_not_reached '$out/summary.json'"
check "re-run: summary names the phase and the step limit" \
  grep -Eq "phase '[^']+' ended at its step limit \([0-9]+ steps, Coupling/step limit\)" \
  "$out/summary.json"

# 3. Corrupted checkpoint: 16 bytes in the middle of the file and, apart,
# one byte of the stored .prm text.
ck="$out/checkpoint.h5"
check "checkpoint written" [ -f "$ck" ]
cp "$ck" "$work/mid.h5"
size=$(stat -c %s "$work/mid.h5")
printf '\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff' |
  dd of="$work/mid.h5" bs=1 seek=$((size / 2)) conv=notrunc status=none
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$work/from_mid" \
  --restart "$work/mid.h5" > "$work/mid.log" 2>&1
rc=$?
check "corrupt (middle): refused (exit $rc)" [ "$rc" -eq 1 ]
check "corrupt (middle): names the file" grep -q "$work/mid.h5" "$work/mid.log"
check "corrupt (middle): nothing written" [ ! -e "$work/from_mid" ]

cp "$ck" "$work/text.h5"
/usr/bin/python3 - "$work/text.h5" <<'PY'
import sys
p = sys.argv[1]
b = bytearray(open(p, 'rb').read())
k = b.find(b'slaved-layer')
assert k >= 0
b[k] ^= 0x20
open(p, 'wb').write(b)
PY
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$work/from_text" \
  --restart "$work/text.h5" > "$work/text.log" 2>&1
rc=$?
check "corrupt (prm text): refused (exit $rc)" [ "$rc" -eq 1 ]
check "corrupt (prm text): Fletcher32 named" grep -q "Fletcher32" "$work/text.log"

# 5. Outcome checks. Phases that cannot reach an equilibrium ratio of 1e-12
# within 2000 steps (the in-situ state is reached: 4 % off sigma0, measured):
# not_equilibrated, exit 3; with --accept, exit 0 and the status kept.
unreachable=(--set "Coupling/equilibrium ratio=1e-12" --set "Coupling/step limit=2000")
"$exe" tunnel "$prm" "${small[@]}" "${unreachable[@]}" \
  --set "Problem/output directory=$work/unequilibrated" > "$work/unequilibrated.log" 2>&1
rc=$?
check "not equilibrated: exit 3 (exit $rc)" [ "$rc" -eq 3 ]
check "not equilibrated: summary status" \
  grep -q '"status": "not_equilibrated"' "$work/unequilibrated/summary.json"
"$exe" tunnel "$prm" "${small[@]}" "${unreachable[@]}" \
  --set "Problem/output directory=$work/accepted" \
  --accept not_equilibrated,region_too_small > "$work/accepted.log" 2>&1
rc=$?
check "accept: not_equilibrated accepted (exit $rc)" [ "$rc" -eq 0 ]
check "accept: summary and manifest still say not_equilibrated" \
  grep -q '"status": "not_equilibrated"' "$work/accepted/summary.json" "$work/accepted/manifest.json"
# A DEM 10^4 times stiffer than the continuum: in_situ_not_reached, exit 4,
# even with --accept not_equilibrated. Before the in-situ servo the grains
# could not hold the in-situ state (error 93 %); the servo fits the
# region's stiffness (9 754 / 9 584 times the continuum's) and needs an
# interface strain of 99.99 % of the in-situ strain, beyond its 50 % limit
# (measured, its phases cut by the step limit: error 23.6 % as well).
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$work/stiff" \
  --set "DEM region/emod=2e14" --set "DEM region/lnm emod=2e14" \
  --accept not_equilibrated > "$work/stiff.log" 2>&1
rc=$?
check "absurd stiffness: in_situ_not_reached (exit $rc)" [ "$rc" -eq 4 ]
check "absurd stiffness: summary and manifest name it" \
  grep -q '"status": "in_situ_not_reached"' "$work/stiff/summary.json" "$work/stiff/manifest.json"
check "absurd stiffness: message names the tolerance key" \
  grep -q "Tunnel/in situ tolerance" "$work/stiff.log"
# A modulus beyond any material (1e300 Pa): the packing's forces overflow;
# an error naming the keys, not a silent run or a "ratio nan".
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$work/overflow" \
  --set "DEM region/emod=1e300" --set "DEM region/lnm emod=1e300" > "$work/overflow.log" 2>&1
rc=$?
check "overflowing modulus: error (exit $rc)" [ "$rc" -eq 1 ]
check "overflowing modulus: message names the keys" \
  grep -q "the packing diverged (non-finite forces).*DEM region/emod" "$work/overflow.log"
"$exe" tunnel "$prm" "${small[@]}" --set "Problem/output directory=$work/bad_accept" \
  --accept diverged > "$work/bad_accept.log" 2>&1
rc=$?
check "accept: diverged cannot be accepted (exit $rc)" [ "$rc" -eq 1 ]

# 4. Disk full (a 300 KiB tmpfs; only where mounting is allowed, e.g. as
# root): one error naming the file, exit 1, no crash, and the files written
# before are complete (replaced atomically).
total=27
tiny="$work/tiny"
mkdir -p "$tiny"
if mount -t tmpfs -o size=300k tmpfs "$tiny" 2>/dev/null; then
  trap 'umount "$tiny" 2>/dev/null; rm -rf "$work"' EXIT
  "$exe" tunnel "$prm" "${small[@]}" --set "Output/interval=200" \
    --set "Problem/output directory=$tiny/run" > "$work/full.log" 2>&1
  rc=$?
  total=$((total + 4))
  check "disk full: exit 1 (exit $rc)" [ "$rc" -eq 1 ]
  check "disk full: one error naming the file and the reason" \
    [ "$(grep -c 'error:' "$work/full.log")" -eq 1 -a \
      "$(grep -c "error: .*$tiny/run/.*No space left on device" "$work/full.log")" -eq 1 ]
  check "disk full: no temporary file left over as a result" \
    [ -z "$(find "$tiny/run" -name '*.pvd' -size 0)" ]
  check "disk full: history.csv complete (every row ends a line)" \
    [ ! -s "$tiny/run/history.csv" -o "$(tail -c 1 "$tiny/run/history.csv" | od -An -c | tr -d ' ')" = '\n' ]
  umount "$tiny"
else
  echo "skipped: disk-full probe (cannot mount a tmpfs here)"
fi

for f in "$work"/*.log; do echo "--- $f"; tail -n 3 "$f"; done
echo "$((total - failed)) passed, $failed failed"
[ "$failed" -eq 0 ]
