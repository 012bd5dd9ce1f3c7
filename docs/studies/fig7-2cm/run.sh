#!/bin/sh
# Issue 18's Fig. 7 on 2 cm: the reference to its verdict, then the 23 fig7-similar runs (mu_d x 0.7 falls below mu_s) warm from it.
# Resumable: both commands pick up what they ran. Usage: run.sh HOURS (the study's slice).
# On a machine without /var/tmp/mixload: mkdir -p /var/tmp/mixload/fig7-2cm && cp docs/studies/fig7-2cm/run.sh /var/tmp/mixload/fig7-2cm/
#   && bash scripts/studies/restore.sh data/studies/fig7-2cm.tar.xz /var/tmp/mixload/fig7-2cm/study
# Land after a slice: bash scripts/studies/land.sh --leaves /var/tmp/mixload/fig7-2cm/study data/studies/fig7-2cm.tar.xz
M=/work/main/build/app/mixload
D=/var/tmp/mixload/fig7-2cm
$M mixer --scene gcm250-v2 --cell-size 0.02 --courant-alpha-min 0 --out $D/study/runs/reference --json > $D/reference.json || exit 1
$M study formulation --scene gcm250-v2 --cell-size 0.02 --courant-alpha-min 0 --preset fig7-similar \
   --warm-from $D/study/runs/reference --model /work/main/data/models/mixer-loading-kriging.json \
   --out $D/study --max-hours "$1"
