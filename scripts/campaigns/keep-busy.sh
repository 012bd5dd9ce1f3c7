#!/bin/bash
# keep-busy.sh DIR SECONDS MIXLOAD CAMPAIGN:JOBS[:WARM...] ...: keeps the machine's cores on the
# listed campaigns, in order, until SECONDS from now. Whenever fewer solvers run than cores (seen
# twice a minute apart), it starts `campaign run` (nice 19, --snapshots, --max-hours up to the end)
# on the first listed campaign with open points and no driver, with at most JOBS solvers and no
# more than the idle cores. When no campaign can be started, the running drivers' --jobs add up to
# fewer than the cores, and a driver has fewer solvers than its JOBS and its open points, it stops
# that driver (SIGTERM: the driver keeps the progress
# of its points) so that the next round restarts it on the idle cores too; a campaign whose
# neighbour ran dry thus gets the freed core. WARM is passed through with its colons turned into
# spaces, e.g. v2-holdout:1:--warm-from-campaign:v2. Drivers stop themselves at the end (their
# --max-hours), keeping the progress of the points they stop.
set -uo pipefail
[ $# -ge 4 ] || { echo "usage: $0 DIR SECONDS MIXLOAD CAMPAIGN:JOBS[:WARM...] ..." >&2; exit 2; }
dir=$1; end=$(( $(date +%s) + $2 )); mixload=$3; shift 3
cores=$(nproc)
idle=0

open_points() {
  "$mixload" campaign status "$1" --dir "$dir" --json 2>/dev/null |
    python3 -c "import json,sys; n=json.load(sys.stdin)['counts']; print(n['queued']+n['running'])" 2>/dev/null || echo 0
}
driver_jobs() {  # the --jobs of the running driver of campaign $1 (empty when none runs)
  pgrep -fa "campaign run $1 " | head -1 | sed -n 's/.*--jobs \([0-9]*\).*/\1/p'
}
all_driver_jobs() {  # the --jobs of every running driver, summed: the solvers they may still start
  pgrep -fa "mixload campaign run" | sed -n 's/.*--jobs \([0-9]*\).*/\1/p' | awk '{s += $1} END {print s + 0}'
}

while [ "$(date +%s)" -lt $((end - 120)) ]; do
  solvers=$(pgrep -fc "mixloadInterFoam" || true)
  if [ "$solvers" -lt "$cores" ]; then idle=$((idle + 1)); else idle=0; fi
  if [ $idle -ge 2 ] || ! pgrep -f "mixload campaign run" >/dev/null; then
    started=0
    for spec in "$@"; do
      IFS=: read -r name jobs warm <<< "$spec"
      pgrep -f "campaign run $name " >/dev/null && continue
      open=$(open_points "$name")
      [ "$open" -gt 0 ] || continue
      free=$((cores - solvers)); [ $free -ge 1 ] || free=1
      n=$jobs; [ $n -le $free ] || n=$free; [ $n -le "$open" ] || n=$open
      hours=$(python3 -c "print(max(0.0, ($end - $(date +%s)) / 3600))")
      echo "$(date +%T) start $name ($open open, $n of $jobs jobs, $hours h, $solvers solvers)"
      (nice -n 19 "$mixload" campaign run "$name" --dir "$dir" --snapshots --jobs "$n" ${warm//:/ } \
         --max-hours "$hours" >> "$dir/$name.driver.log" 2>&1 &)
      idle=0; started=1
      sleep 20
      break
    done
    if [ $started -eq 0 ] && [ $idle -ge 2 ] && [ "$(all_driver_jobs)" -lt "$cores" ]; then
      for spec in "$@"; do
        IFS=: read -r name jobs warm <<< "$spec"
        running=$(driver_jobs "$name"); [ -n "$running" ] || continue
        open=$(open_points "$name")
        if [ "$running" -lt "$jobs" ] && [ "$running" -lt "$open" ]; then
          echo "$(date +%T) stop $name (driver on $running of $jobs jobs, $open open, $solvers solvers) to restart it wider"
          pkill -TERM -f "campaign run $name " || true
          for _ in $(seq 60); do pgrep -f "campaign run $name " >/dev/null || break; sleep 10; done
          idle=2
          break
        fi
      done
    fi
  fi
  sleep 60
done
echo "$(date +%T) keep-busy ends"
