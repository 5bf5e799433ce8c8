#!/bin/sh
# The whole study: training runs (w = 3, 4, 5, 6), the model, the test at w = 4.5 resolved (two
# seeds: the chaotic noise floor of the comparison) and reduced, timings repeated back to back,
# and a sweep of the reduced run's eps and every.
# Everything it writes (logs, fields cg.<tag>.txt, the model) goes to work/, beside and never
# over the committed logs; each run's log is log.DATE.rom-pile.<tag>.1 (today's date, LAMMPS's
# naming; an older log of the same run in work/ goes).
#   LMP=/path/to/lmp ./run_all.sh
set -e
LMP=${LMP:-../../build/lmp}
case $LMP in /*) ;; */*) LMP=$(pwd)/$LMP ;; esac
DATE=$(LC_ALL=C date +%-d%b%y)
LOG="log.$DATE.rom-pile.{}.1"
mkdir -p work
cd work

# run TAG [-var ...]: in.rom-pile for 30000 steps on one process
run() {
  tag=$1
  shift
  rm -f log.*.rom-pile.$tag.1
  $LMP -in ../in.rom-pile -var steps 30000 -var tag $tag "$@" -log log.$DATE.rom-pile.$tag.1 > /dev/null
}

for w in 3 4 5 6; do
  run w$w.resolved -var w $w
done
/usr/bin/python3 ../train_rom.py rom.model cg.w3.resolved.txt:3 cg.w4.resolved.txt:4 \
  cg.w5.resolved.txt:5 cg.w6.resolved.txt:6 | tail -2
run w4.5.resolved.seed2 -var w 4.5 -var seed 3391
for rep in 1 2; do
  run w4.5.resolved -var w 4.5
  run w4.5.rom -var w 4.5 -var mode rom -var eps 0.1 -var every 10
  echo "== repeat $rep: reduced (eps 0.1, every 10) against resolved"
  /usr/bin/python3 ../compare.py --log "$LOG" w4.5.resolved w4.5.rom
done
echo "== noise floor: resolved (seed 2) against resolved"
/usr/bin/python3 ../compare.py --log "$LOG" w4.5.resolved w4.5.resolved.seed2
for setting in "0.05 10" "0.1 50" "0.2 10" "0.3 10"; do
  set -- $setting
  run w4.5.rom.e$1.n$2 -var w 4.5 -var mode rom -var eps $1 -var every $2
  echo "== sweep: reduced (eps $1, every $2) against resolved"
  /usr/bin/python3 ../compare.py --log "$LOG" w4.5.resolved w4.5.rom.e$1.n$2
done
