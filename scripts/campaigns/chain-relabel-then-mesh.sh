#!/bin/bash
# chain-relabel-then-mesh.sh DEADLINE_EPOCH [MIXLOAD]: one core on the full runs, in order, until the
# deadline: issue 64's relabel (v3, v3-holdout), then issue 65's mesh study of one impeller (mesh-1cm,
# mesh-7.5mm, mesh-5mm; created as docs/mixer.md says). Each campaign runs resumable slices; a
# finished one passes straight to the next. MIXLOAD defaults to a copy of the build, so that a
# rebuild does not replace the binary under a running driver.
set -u
[ $# -ge 1 ] || { echo "usage: $0 DEADLINE_EPOCH [MIXLOAD]" >&2; exit 2; }
deadline=$1; mixload=${2:-/var/tmp/mixload/mixload-runner}
dir=/var/tmp/mixload/campaigns
for c in v3 v3-holdout mesh-1cm mesh-7.5mm mesh-5mm; do
  [ -d "$dir/$c" ] || continue
  left=$(python3 -c "print(max(0.0, ($deadline - $(date +%s)) / 3600))")
  python3 -c "import sys; sys.exit(0 if $left > 0.05 else 1)" || break
  nice -n 19 "$mixload" campaign run "$c" --dir "$dir" --jobs 1 --snapshots --max-hours "$left" --json \
    > "/var/tmp/mixload/run-$c.json" 2> "/var/tmp/mixload/run-$c.err"
done
