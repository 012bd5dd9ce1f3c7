#!/bin/bash
# The third row of numerics.csv: MRF's steady case at 39 rpm x 45 kg/h (sm-compare, run
# f923c662912de6a2, 85.59 s) run on with the sliding mesh's alpha settings (explicit MULES, one
# alpha corrector, Courant 0.5; fullcfd/cases/mixer3d.cpp), its loading monitor's state cleared so
# that its windows start afresh. Usage: make-case.sh SM_COMPARE_RUNS_DIR OUT BUILD_DIR
set -euo pipefail
src=$1/f923c662912de6a2; build=$3
out=$2
mkdir -p "$out"
cp -r "$src/constant" "$src/system" "$src/85.59241639471" "$out/"
rm -rf "$out/85.59241639471/uniform/functionObjects"
sed -i 's|nAlphaCorr 2;|nAlphaCorr 1;|; s|MULESCorr yes;|MULESCorr no;|' "$out/system/fvSolution"
sed -i "s|^maxCo 1;|maxCo 0.5;|; s|^maxAlphaCo 1;|maxAlphaCo 0.5;|; s|^endTime 1200;|endTime 200;|; s|^libs .*|libs (\"$build/fullcfd/rheology/libmixloadRheology.so\" \"$build/fullcfd/monitors/libmixloadMonitors.so\");|" "$out/system/controlDict"
cd "$out" && WM_PROJECT_DIR=/usr/share/openfoam FOAM_ETC=/usr/share/openfoam/etc \
  "$build/fullcfd/solver/mixloadInterFoam" -case . > log.interFoam 2>&1
grep "loading steady" log.interFoam
