#!/bin/bash
# keep-busy.sh DIR SECONDS MIXLOAD CAMPAIGN:JOBS[:WARM...] ...: keeps the machine's cores on the
# listed campaigns, in order, until SECONDS from now: whenever fewer solvers run than cores (seen
# twice a minute apart), it starts `campaign run` (nice 19, --snapshots, --max-hours up to the end)
# on the first listed campaign with open points and no driver. WARM is passed through with its
# colons turned into spaces, e.g. v2-holdout:1:--warm-from-campaign:v2. Drivers stop themselves at
# the end (their --max-hours), keeping the progress of the points they stop.
set -uo pipefail
[ $# -ge 4 ] || { echo "usage: $0 DIR SECONDS MIXLOAD CAMPAIGN:JOBS[:WARM...] ..." >&2; exit 2; }
dir=$1; end=$(( $(date +%s) + $2 )); mixload=$3; shift 3
cores=$(nproc)
idle=0
while [ "$(date +%s)" -lt $((end - 120)) ]; do
  solvers=$(pgrep -fc "mixloadInterFoam" || true)
  if [ "$solvers" -lt "$cores" ]; then idle=$((idle + 1)); else idle=0; fi
  if [ $idle -ge 2 ] || ! pgrep -f "mixload campaign run" >/dev/null; then
    for spec in "$@"; do
      IFS=: read -r name jobs warm <<< "$spec"
      pgrep -f "campaign run $name " >/dev/null && continue
      open=$("$mixload" campaign status "$name" --dir "$dir" --json 2>/dev/null |
             python3 -c "import json,sys; n=json.load(sys.stdin)['counts']; print(n['queued']+n['running'])" 2>/dev/null || echo 0)
      [ "$open" -gt 0 ] || continue
      hours=$(python3 -c "print(max(0.0, ($end - $(date +%s)) / 3600))")
      echo "$(date +%T) start $name ($open open, $hours h, $solvers solvers)"
      (nice -n 19 "$mixload" campaign run "$name" --dir "$dir" --snapshots --jobs "$jobs" ${warm//:/ } \
         --max-hours "$hours" >> "$dir/$name.driver.log" 2>&1 &)
      idle=0
      sleep 20
      break
    done
  fi
  sleep 60
done
echo "$(date +%T) keep-busy ends"
