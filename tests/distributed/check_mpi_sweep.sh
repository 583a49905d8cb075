#!/usr/bin/env bash
# Sweeps over MPI ranks (docs/guide.md §3.1), on localhost:
#  - mpirun -np 1, 2 and 3 write sweep.csv, summary.csv and sweep.json with the bytes of the
#    one-process sweep;
#  - a rank killed while it runs a member (AXG_FAULT_KILL_AT) costs that member: with
#    --enable-recovery the sweep goes on and reports it failed, without it mpirun ends the
#    job; either way the records of the finished members are kept, and a re-run finishes
#    the sweep with the one-process bytes;
#  - a bad sweep file exits 2 with one message, from rank 0, and no rank hangs.
# Usage: check_mpi_sweep.sh AXONGUIDE MPIEXEC
set -euo pipefail
exe=$1
mpi=("$2" --allow-run-as-root --oversubscribe)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
echo '{"neurons": {"count": 150}, "steps": 40}' > base.json
cat > sweep.json <<'JSON'
{"scene": "base.json", "parameters": [{"key": "guidance.gain", "values": [100, 250, 500]}], "seeds": [1, 2, 3]}
JSON
fail() { echo "FAIL: $*"; exit 1; }
same() {  # same DIR_A DIR_B: the gathered files are byte-identical
  for f in sweep.csv summary.csv sweep.json; do cmp -s "$1/$f" "$2/$f" || fail "$2/$f differs from $1/$f"; done
}
"$exe" sweep sweep.json --out one -q
for k in 1 2 3; do
  timeout 120 "${mpi[@]}" -np $k "$exe" sweep sweep.json --out np$k -q || fail "mpirun -np $k exited $?"
  same one np$k
  echo "mpirun -np $k: sweep.csv, summary.csv, sweep.json identical to the one-process sweep"
done

# Rank death, the job kept alive (--enable-recovery): member 4 is reported, the rest done.
set +e
AXG_FAULT_KILL_AT="sweep member 4" AXG_MPI_DEAD_AFTER=3 timeout 120 "${mpi[@]}" --enable-recovery -np 3 \
  "$exe" sweep sweep.json --out dead > dead.log 2>&1
rc=$?
set -e
[ $rc -ne 124 ] || fail "the sweep with a dead rank hung"
grep -q '^4,1,250,2,failed,3,.*rank [12] died while running it' dead/sweep.csv || fail "member 4 not reported: $(cat dead.log)"
[ "$(grep -c ',ok,' dead/sweep.csv)" = 8 ] || fail "the other 8 members did not all finish"
grep -q 'member 4 failed (exit 3): rank' dead.log || fail "rank 0 did not report the dead rank"
timeout 120 "${mpi[@]}" -np 2 "$exe" sweep sweep.json --out dead -q
same one dead
echo "a rank killed with --enable-recovery: only its member lost and reported; the re-run matches"

# Rank death, default mpirun: the job ends; finished members' records are kept.
set +e
AXG_FAULT_KILL_AT="sweep member 4" timeout 120 "${mpi[@]}" -np 3 "$exe" sweep sweep.json --out killed > killed.log 2>&1
rc=$?
set -e
[ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "mpirun exited $rc after a rank was killed"
[ ! -e killed/members/m0000004.json ] || fail "a record for the member whose rank died"
kept=$(ls killed/members | wc -l)
timeout 120 "${mpi[@]}" -np 3 "$exe" sweep sweep.json --out killed > rerun.log
same one killed
ran=$(sed -n 's/.*ran \([0-9]*\), reused.*/\1/p' rerun.log)
[ "$ran" = $((9 - kept)) ] || fail "the re-run ran $ran members, expected the $((9 - kept)) without records"
echo "a rank killed under default mpirun: $kept records kept, the re-run ran $ran and matches"

# Bad input: exit 2 from every rank, one message, no hang.
echo '{"scene": "base.json", "seeds": "many"}' > bad.json
set +e
timeout 60 "${mpi[@]}" -np 3 "$exe" sweep bad.json --out bad > bad.log 2>&1
rc=$?
set -e
[ $rc -eq 2 ] || fail "a bad sweep file: mpirun exited $rc, expected 2 ($(cat bad.log))"
[ "$(grep -c 'error' bad.log)" = 1 ] || fail "expected one error line from rank 0: $(cat bad.log)"
echo "a bad sweep file: exit 2, one message, no hang"
