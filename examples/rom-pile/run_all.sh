#!/bin/sh
# The whole study: training runs (w = 3, 4, 5, 6), the model, the test at w = 4.5 resolved (two
# seeds: the chaotic noise floor of the comparison) and reduced, timings repeated back to back.
# Everything it writes (logs log.<tag>, fields cg.<tag>.txt, the model) goes to work/, beside
# and never over the committed logs.
#   LMP=/path/to/lmp ./run_all.sh
set -e
LMP=${LMP:-../../build/lmp}
case $LMP in /*) ;; */*) LMP=$(pwd)/$LMP ;; esac
mkdir -p work
cd work
for w in 3 4 5 6; do
  $LMP -in ../in.rom-pile -var w $w -var steps 30000 -log log.w$w.resolved -echo none > /dev/null
done
/usr/bin/python3 ../train_rom.py rom.model cg.w3.resolved.txt:3 cg.w4.resolved.txt:4 \
  cg.w5.resolved.txt:5 cg.w6.resolved.txt:6 | tail -2
$LMP -in ../in.rom-pile -var w 4.5 -var steps 30000 -var seed 3391 -var tag w4.5.resolved.seed2 \
  -log log.w4.5.resolved.seed2 -echo none > /dev/null
for rep in 1 2; do
  $LMP -in ../in.rom-pile -var w 4.5 -var steps 30000 -log log.w4.5.resolved -echo none > /dev/null
  $LMP -in ../in.rom-pile -var w 4.5 -var steps 30000 -var mode rom -var eps 0.1 -var every 10 \
    -log log.w4.5.rom -echo none > /dev/null
  echo "== repeat $rep: reduced (eps 0.1, every 10) against resolved"
  /usr/bin/python3 ../compare.py w4.5.resolved w4.5.rom
done
echo "== noise floor: resolved (seed 2) against resolved"
/usr/bin/python3 ../compare.py w4.5.resolved w4.5.resolved.seed2
