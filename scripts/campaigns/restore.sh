#!/bin/bash
# restore.sh DIR NAME...: lays the landed campaigns data/campaigns/mixer-NAME (ledger, kept final
# fields, kept progress) into DIR/NAME, for a machine that came back without its campaign stores.
# A campaign already in DIR is left alone.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 DIR NAME..." >&2; exit 2; }
here=$(cd "$(dirname "$0")/../.." && pwd)
dir=$1; shift
for name in "$@"; do
  src=$here/data/campaigns/mixer-$name
  [ -f "$src/ledger.sqlite" ] || { echo "restore: no landed campaign $src" >&2; exit 2; }
  if [ -f "$dir/$name/ledger.sqlite" ]; then echo "restore: $dir/$name exists, left alone"; continue; fi
  mkdir -p "$dir/$name"
  sqlite3 "$src/ledger.sqlite" ".backup $dir/$name/ledger.sqlite"
  for f in fields.h5 fields.xmf progress.h5 progress.xmf; do
    if [ -f "$src/$f" ]; then cp "$src/$f" "$dir/$name/"; fi
  done
  echo "restore: $name -> $dir/$name"
done
