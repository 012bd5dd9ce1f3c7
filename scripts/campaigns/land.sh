#!/bin/bash
# land.sh DIR NAME [MIXLOAD]: copies a live campaign DIR/NAME into data/campaigns/mixer-NAME
# (ledger by SQLite's online backup, kept final fields, kept progress) and its export
# data/campaigns/mixer-NAME.csv, ready to commit, checks the shipped kriging model against it and,
# for v2-holdout and its 1.5 cm twin v2m-holdout, redraws docs/studies/rom/pareto-mixer-1cm.
# Safe while its driver runs.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 DIR NAME [MIXLOAD]" >&2; exit 2; }
here=$(cd "$(dirname "$0")/../.." && pwd)
dir=$1; name=$2; mixload=${3:-$here/build/app/mixload}
dst=$here/data/campaigns/mixer-$name
mkdir -p "$dst"
sqlite3 "$dir/$name/ledger.sqlite" ".backup $dst/ledger.sqlite"
for f in fields.h5 fields.xmf progress.h5 progress.xmf; do
  rm -f "$dst/$f.new"
  if [ -f "$dir/$name/$f" ]; then cp "$dir/$name/$f" "$dst/$f.new" && mv "$dst/$f.new" "$dst/$f"; else rm -f "$dst/$f"; fi
done
"$mixload" campaign export "$name" --dir "$dir" -o "$dst.csv"
# Every run that lands is checked against the shipped model (recorded in its check history when
# the runs are of the model's own scene; another scene's are shown, not recorded). Runs already
# checked (by the driver's --check, or an earlier landing) give the same figures and are not
# recorded again.
model=$here/data/models/mixer-loading-kriging.json
# Its parity plot (each run's M against the model's answer) goes to docs/studies/surrogates/check-NAME.
[ -f "$model" ] && { "$mixload" check --model "$model" --table "$dst.csv" --plot "$here/docs/studies/surrogates/check-$name" || true; }
# The hold-out's time-against-error table on 1 cm (issue 19) is redrawn with every landing of the
# hold-out or of its 1.5 cm twin, when the training campaign and the 2 cm twin are in DIR as well
# (scripts/campaigns/restore.sh); the 1.5 cm twin joins when it is there.
if { [ "$name" = v2-holdout ] || [ "$name" = v2m-holdout ]; } && [ -d "$dir/v2" ] && [ -d "$dir/v2-holdout" ] \
   && [ -d "$dir/v2c-holdout" ]; then
  coarse=(--coarse v2c-holdout)
  [ -d "$dir/v2m-holdout" ] && coarse+=(--coarse v2m-holdout)
  "$mixload" bench pareto-mixer --campaign v2 --holdout v2-holdout "${coarse[@]}" --dir "$dir" \
    --out "$here/docs/studies/rom/pareto-mixer-1cm" > /dev/null
fi
"$mixload" campaign status "$name" --dir "$dir"
