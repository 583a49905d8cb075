#!/usr/bin/env bash
# One network decomposed over MPI ranks (docs/scaling.md), on localhost:
#  - mpirun -np 1, 2 and 4 write every file of the one-process run byte for byte (all but
#    timings.csv and manifest.json, whose file hashes and summary must match too), for
#    direct guidance (with paths, SWC and SONATA), the analytic field with growth-rate
#    modulation, the imposed field in physical units, the particle field (Brownian with
#    the estimate; ballistic with collisions; the gathers of source_vector_sum) and the grid
#    field (implicit absorbing, explicit reflecting); the manifest records the blocks, and
#    the messaging layer (ob1 when every rank is on this node, unless the user chose one);
#  - a signal to one rank stops every rank at the same step with a checkpoint (exit 143),
#    and a kill -9 of one rank ends the job; either run resumes on another rank count to the
#    one-process bytes; so do particle and grid runs whose rank was killed;
#  - what cannot proceed exits 2 or 3 with one message, from rank 0, and no rank hangs: too
#    many ranks for the scene's halo (a step's reach, the particles' sensing radius, the
#    grid's slabs), --backend emulated (the accelerator), an arbour scene (designed in
#    docs/scaling.md, not built), placement too dense (the folder is
#    left as it was), a folder that holds another run, a checkpoint of another scene, and
#    a launcher that is not this build's MPI's, and an MPI that fails inside MPI_Init (exit
#    3, naming the library).
# Usage: check_mpi_run.sh AXONGUIDE MPIEXEC SOURCE_DIR
set -euo pipefail
exe=$1
mpi=("$2" --allow-run-as-root --oversubscribe)
src=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
# same DIR_A DIR_B: every file but timings.csv and manifest.json byte-identical, the same
# file list, and the manifests' file hashes (timings aside) and summaries equal.
same() {
  diff <(cd "$1" && find . -type f ! -name timings.csv ! -name manifest.json | sort) \
       <(cd "$2" && find . -type f ! -name timings.csv ! -name manifest.json | sort) > /dev/null ||
    fail "$2 holds other files than $1"
  (cd "$1" && find . -type f ! -name timings.csv ! -name manifest.json) | while read -r f; do
    cmp -s "$1/$f" "$2/$f" || fail "$2/$f differs from $1/$f"
  done
  /usr/bin/python3 - "$1" "$2" <<'PY' || fail "$2/manifest.json: hashes or summary differ from $1's"
import json, sys
a, b = (json.load(open(d + "/manifest.json")) for d in sys.argv[1:3])
strip = lambda m: {k: v for k, v in m["files"].items() if k != "timings.csv"}
assert strip(a) == strip(b) and a["summary"] == b["summary"] and a["scene"] == b["scene"], "differ"
assert a["status"] == b["status"] == "complete"
PY
}
run1() { "$exe" run "$@" -q; }
runk() { local k=$1; shift; timeout 300 "${mpi[@]}" -np "$k" "$exe" run "$@" -q; }

/usr/bin/python3 - "$src" <<'PY'
import json, sys
src = sys.argv[1]
direct = json.load(open(src + "/scenes/paper-direct-1000.json"))
direct["output"] = dict(direct.get("output", {}), paths=True, swc=True, sonata=True)
json.dump(direct, open("direct.json", "w"))
analytic = json.load(open(src + "/data/golden/analytic-snr/scene.json"))
analytic.setdefault("axons", {})["growth_modulation"] = 0.5
analytic.setdefault("neurons", {})["count"] = 600
json.dump(analytic, open("analytic.json", "w"))
PY
cp "$src/data/golden/imposed-explant-units/scene.json" imposed.json
for g in particles-brownian-snr particles-ballistic-collisions-vector-sum particles-source-vector-sum \
         grid-implicit-absorbing-snr grid-explicit-reflecting-vector-sum; do
  /usr/bin/python3 -c "import json,sys; s=json.load(open(sys.argv[1])); s['neurons']['count']=200; s['steps']=30; \
json.dump(s, open(sys.argv[2], 'w'))" "$src/data/golden/$g/scene.json" $g.json
done
for scene in direct analytic imposed particles-brownian-snr particles-ballistic-collisions-vector-sum \
             particles-source-vector-sum grid-implicit-absorbing-snr grid-explicit-reflecting-vector-sum; do
  run1 $scene.json --out one-$scene
  for k in 1 2 4; do
    runk $k $scene.json --out np$k-$scene || fail "mpirun -np $k run $scene exited $?"
    same one-$scene np$k-$scene
    /usr/bin/python3 -c "import json,sys; d=json.load(open('np$k-$scene/manifest.json'))['decomposition']; \
assert d['ranks']==$k and d['blocks'][0]*d['blocks'][1]*d['blocks'][2]==$k, d" || fail "np$k-$scene: no decomposition facts"
    "$exe" verify np$k-$scene > /dev/null || fail "np$k-$scene does not verify"
  done
  echo "$scene: mpirun -np 1, 2, 4 wrote the one-process files byte for byte"
done

# Messages cut into pieces (AXG_TEST_MPI_CHUNK bytes each, as messages of 1 GiB or more are
# in a large run): the same bytes, a particle scene (migrants, halo, the save's gather) and
# a grid scene (ghost planes, the pipelined sweep).
for scene in particles-source-vector-sum grid-implicit-absorbing-snr; do
  timeout 300 "${mpi[@]}" -x AXG_TEST_MPI_CHUNK=1000 -np 2 "$exe" run $scene.json --out chunk-$scene -q ||
    fail "mpirun -np 2 run $scene with 1000-byte pieces exited $?"
  same one-$scene chunk-$scene
done
echo "messages cut into 1000-byte pieces: the same bytes"

# Every rank on one node and no messaging layer chosen: Open MPI's shared-memory path (pml
# ob1), said in the facts; a layer the user chose stands, and gives the same bytes.
pml() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['decomposition']['mpi_pml'])" "$1"; }
[ "$(pml np2-direct/manifest.json)" = "ob1 (every rank on one node)" ] || fail "np2-direct: mpi_pml is $(pml np2-direct/manifest.json)"
timeout 300 "${mpi[@]}" --mca pml ob1 --mca btl self,vader -np 2 "$exe" run direct.json --out np2-chosen -q ||
  fail "mpirun --mca pml ob1 exited $?"
same one-direct np2-chosen
case "$(pml np2-chosen/manifest.json)" in "ob1 (OMPI_MCA_pml or --mca pml)") ;; *) fail "np2-chosen: mpi_pml is $(pml np2-chosen/manifest.json)";; esac
echo "messaging layer: ob1 on one node unless chosen; a chosen one stands"

# Interrupted on one rank: all stop after the same step, with a checkpoint; resumed on 4.
echo '{"neurons": {"count": 3000, "region": {"radius": 9}}, "guidance": {"model": "direct"}, "steps": 60,
       "output": {"checkpoint_every": 5, "paths": true}}' > long.json
run1 long.json --out one-long
set +e
AXG_FAULT_KILL_AT="step 17" AXG_FAULT_SIGNAL=TERM AXG_FAULT_RANK=1 runk 2 long.json --out stopped 2> stopped.log
rc=$?
set -e
[ $rc -eq 143 ] || fail "SIGTERM to rank 1: mpirun exited $rc, expected 143 ($(cat stopped.log))"
grep -q 'interrupted by SIGTERM after step 17' stopped.log || fail "no message from rank 0: $(cat stopped.log)"
[ "$(grep -c 'interrupted by' stopped.log)" = 1 ] || fail "more than one rank spoke: $(cat stopped.log)"
grep -q '"status": "interrupted"' stopped/manifest.json || fail "stopped/manifest.json does not say interrupted"
runk 4 --resume stopped || fail "the resume on 4 ranks exited $?"
same one-long stopped
echo "SIGTERM to one of 2 ranks: every rank stopped after step 17; resumed on 4 ranks to the same bytes"

# kill -9 of one rank: mpirun ends the job; the checkpoint resumes on one process.
set +e
AXG_FAULT_KILL_AT="step 23" AXG_FAULT_RANK=2 runk 3 long.json --out killed > killed.log 2>&1
rc=$?
set -e
[ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "a rank killed: mpirun exited $rc"
"$exe" run --resume killed -q || fail "the resume in one process exited $?"
same one-long killed
echo "kill -9 of one of 3 ranks: the job ended (exit $rc); resumed in one process to the same bytes"

# A particle run and a grid run, one rank killed: resumed on another rank count and in one
# process to the one-process bytes (the checkpoints hold the particles and the grid).
/usr/bin/python3 - "$src" <<'PY'
import json, sys
src = sys.argv[1]
for name, out in (("particles-ballistic-collisions-vector-sum", "plong.json"), ("grid-implicit-absorbing-snr", "glong.json")):
    s = json.load(open(src + "/data/golden/" + name + "/scene.json"))
    s["neurons"]["count"] = 400
    s["steps"] = 40
    s["output"] = dict(s.get("output", {}), checkpoint_every=4)
    json.dump(s, open(out, "w"))
PY
for scene in plong glong; do
  run1 $scene.json --out one-$scene
  set +e
  AXG_FAULT_KILL_AT="step 9" AXG_FAULT_RANK=1 runk 2 $scene.json --out killed-$scene > killed-$scene.log 2>&1
  rc=$?
  set -e
  [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "$scene: a rank killed: mpirun exited $rc"
  cp -r killed-$scene killed1-$scene
  cp -r killed-$scene swap-$scene
  runk 4 --resume killed-$scene || fail "$scene: the resume on 4 ranks exited $?"
  same one-$scene killed-$scene
  "$exe" run --resume killed1-$scene -q || fail "$scene: the resume in one process exited $?"
  same one-$scene killed1-$scene
done
echo "kill -9 of one of 2 ranks in a particle and a grid run: resumed on 4 ranks and in one process to the same bytes"

# SIGTERM to one rank of a particle run: every rank stops after the same step; resumed on 3.
set +e
AXG_FAULT_KILL_AT="step 10" AXG_FAULT_SIGNAL=TERM AXG_FAULT_RANK=1 runk 2 plong.json --out pstopped 2> pstopped.log
rc=$?
set -e
[ $rc -eq 143 ] || fail "SIGTERM to rank 1 of a particle run: mpirun exited $rc, expected 143 ($(cat pstopped.log))"
grep -q 'interrupted by SIGTERM after step 10' pstopped.log || fail "no message from rank 0: $(cat pstopped.log)"
runk 3 --resume pstopped || fail "the particle run's resume on 3 ranks exited $?"
same one-plong pstopped
echo "SIGTERM to one of 2 ranks of a particle run: stopped after step 10; resumed on 3 ranks to the same bytes"

# What cannot proceed: exit 2 or 3, one message from rank 0, no hang, no folder.
refuse() {  # refuse CODE PATTERN NP ARGS...: exit CODE, one error line matching PATTERN
  local code=$1 pattern=$2 k=$3; shift 3
  set +e
  timeout 120 "${mpi[@]}" -np "$k" "$exe" run "$@" -q > refuse.log 2>&1
  local rc=$?
  set -e
  [ $rc -eq "$code" ] || fail "run $* on $k ranks exited $rc, expected $code: $(cat refuse.log)"
  [ "$(grep -c 'axonguide: ' refuse.log)" = 1 ] || fail "expected one message from rank 0: $(cat refuse.log)"
  grep -q "$pattern" refuse.log || fail "message without '$pattern': $(cat refuse.log)"
}
# One rank refuses its scene (a file the others see, it does not): rank 0 says so, and
# every rank, so mpirun, ends with the same code.
set +e
timeout 120 "${mpi[@]}" -np 1 "$exe" run direct.json --out split -q : -np 1 "$exe" run nowhere.json --out split -q \
  > refuse.log 2>&1
rc=$?
set -e
[ $rc -eq 2 ] || fail "a scene one rank cannot read: exit $rc, expected 2: $(cat refuse.log)"
grep -q 'another rank could not start the run (exit 2)' refuse.log || fail "rank 0 did not say why: $(cat refuse.log)"
[ ! -e split ] || fail "a refused run made its folder"
echo '{"neurons": {"count": 20, "region": {"radius": 1.2}}, "guidance": {"model": "direct"}}' > small.json
refuse 2 'narrower than the halo' 5 small.json --out small
[ ! -e small ] || fail "a refused run made its folder"
# The particles' sensing radius sets the halo of source_vector_sum's gathers; a grid scene
# is cut in slabs along z, each at least as thick as its ghost planes (the sensing ball
# and half a step beyond it).
/usr/bin/python3 -c "import json; s=json.load(open('particles-source-vector-sum.json')); \
s['guidance']['sensing_radius']=4.0; json.dump(s, open('wide.json', 'w'))"
refuse 2 'the particles within the sensing radius.*at most 1 rank)' 2 wide.json --out wide
refuse 2 'at most 7 slabs along z' 12 grid-implicit-absorbing-snr.json --out slabs
# A checkpoint of another scene in the folder: exit 2, and the folder is left as it was.
cp swap-plong/checkpoint.axg swap-glong/checkpoint.axg
files() { (cd "$1" && find . -type f ! -name .axonguide.lock -exec sha256sum {} + | sort); }  # the dead run's lock goes
before=$(files swap-glong)
refuse 2 'written for another scene' 2 --resume swap-glong
[ "$(files swap-glong)" = "$before" ] || fail "the refused resume changed its folder"
refuse 3 'one block per GPU is designed' 2 direct.json --backend emulated --out emulated
refuse 3 'arbour scenes over ranks are designed' 2 "$src/scenes/culture.json" --out arbours
[ ! -e arbours ] || fail "a refused arbour run made its folder"
echo '{"neurons": {"count": 2300, "region": {"radius": 5}, "soma_radius": 0.3, "max_attempts": 40},
       "guidance": {"model": "direct"}}' > dense.json
refuse 3 'still overlaps an earlier soma' 3 dense.json --out dense
[ ! -e dense ] || fail "a run whose placement failed left its folder"
run1 direct.json --out taken && refuse 2 'holds another run' 2 direct.json --out taken
same one-direct taken
# Another MPI's launcher (its variables say 2 ranks, this build's MPI sees one): exit 3,
# naming this build's MPI, and no folder (K copies would each run the whole network).
set +e
OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 PMI_SIZE=2 PMI_RANK=0 timeout 60 "$exe" run direct.json --out foreign -q \
  > foreign.log 2>&1
rc=$?
set -e
[ $rc -eq 3 ] || fail "a foreign launcher: exited $rc, expected 3: $(cat foreign.log)"
grep -q "this build's MPI (Open MPI" foreign.log || fail "the message does not name the MPI: $(cat foreign.log)"
[ ! -e foreign ] || fail "a run under a foreign launcher made its folder"
# An MPI that cannot start: Open MPI fails inside MPI_Init (a messaging component that does
# not exist; pml ucx, which cannot be selected on a machine without its transports, is the
# same path) and ends the job through PMIx_Abort, which the command defines: exit 3, the
# command's message naming this build's MPI beside Open MPI's own, and no folder.
set +e
OMPI_MCA_pml=nonexistent timeout 60 "${mpi[@]}" -np 2 "$exe" run direct.json --out nostart -q > nostart.log 2>&1
rc=$?
set -e
[ $rc -eq 3 ] || fail "an MPI that cannot start: mpirun exited $rc, expected 3: $(cat nostart.log)"
grep -q "axonguide: error: MPI could not start (Open MPI" nostart.log ||
  fail "the message does not say that MPI could not start, naming it: $(cat nostart.log)"
[ ! -e nostart ] || fail "a run whose MPI could not start made its folder"
echo "refusals: exit 2 or 3, one message from rank 0, no hang, no folder"
