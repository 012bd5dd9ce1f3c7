#!/bin/bash
# keep-busy.sh DIR SECONDS MIXLOAD SPEC ...: keeps the machine's cores on the listed campaigns and
# studies, in order, until SECONDS from now. A SPEC is either
#   CAMPAIGN:JOBS[:WARM...]           a campaign of DIR, e.g. v2-holdout:1:--warm-from-campaign:v2
#   study:OUT:JOBS:KIND[:ARGS...]     `mixload study KIND ARGS --out OUT`, e.g.
#                                     study:/var/tmp/mixload/sm-compare:1:mixer:--scene:gcm250-v3:...
# (colons in WARM and ARGS turn into spaces). Whenever fewer solvers run than cores (seen twice a
# minute apart), it starts the first listed one with open work and no driver (nice 19,
# --max-hours up to the end; campaigns with --snapshots), on at most JOBS solvers and no more than
# the idle cores. A campaign has open work while it has queued or running points, a study until its
# study.json says no run is unfinished. When nothing can be started, the running drivers' --jobs
# add up to fewer than the cores, and a campaign's driver has fewer solvers than its JOBS and its
# open points, it stops that driver (SIGTERM: the driver keeps the progress of its points) so that
# the next round restarts it on the idle cores too. Drivers stop themselves at the end (their
# --max-hours), keeping the progress of what they stop.
set -uo pipefail
[ $# -ge 4 ] || { echo "usage: $0 DIR SECONDS MIXLOAD SPEC ..." >&2; exit 2; }
dir=$1; end=$(( $(date +%s) + $2 )); mixload=$3; shift 3
cores=$(nproc)
idle=0

open_points() {
  "$mixload" campaign status "$1" --dir "$dir" --json 2>/dev/null |
    python3 -c "import json,sys; n=json.load(sys.stdin)['counts']; print(n['queued']+n['running'])" 2>/dev/null || echo 0
}
study_open() {  # 1 while the study in $1 has never run or has unfinished runs
  [ -f "$1/study.json" ] || { echo 1; return; }
  python3 -c "import json,sys; print(1 if json.load(open(sys.argv[1]))['unfinished'] else 0)" "$1/study.json" 2>/dev/null || echo 1
}
driver_jobs() {  # the --jobs of the running driver of campaign $1 (empty when none runs)
  pgrep -fa "campaign run $1 " | head -1 | sed -n 's/.*--jobs \([0-9]*\).*/\1/p'
}
all_driver_jobs() {  # the --jobs of every running driver, summed: the solvers they may still start
  pgrep -fa "mixload (campaign run|study )" | sed -n 's/.*--jobs \([0-9]*\).*/\1/p' | awk '{s += $1} END {print s + 0}'
}
hours_left() { python3 -c "print(max(0.0, ($end - $(date +%s)) / 3600))"; }

while [ "$(date +%s)" -lt $((end - 120)) ]; do
  # The solver processes alone: a compiler building mixloadInterFoam names it in its arguments too.
  solvers=$(pgrep -fc '^[^ ]*mixloadInterFoam( |$)' || true)
  if [ "$solvers" -lt "$cores" ]; then idle=$((idle + 1)); else idle=0; fi
  if [ $idle -ge 2 ] || ! pgrep -f "mixload (campaign run|study )" >/dev/null; then
    started=0
    free=$((cores - solvers)); [ $free -ge 1 ] || free=1
    for spec in "$@"; do
      if [[ $spec == study:* ]]; then
        IFS=: read -r _ out jobs kind args <<< "$spec"
        pgrep -f "study $kind .*--out $out --max-hours" >/dev/null && continue
        [ "$(study_open "$out")" = 1 ] || continue
        n=$jobs; [ $n -le $free ] || n=$free
        echo "$(date +%T) start study $kind in $out ($n of $jobs jobs, $(hours_left) h, $solvers solvers)"
        (nice -n 19 "$mixload" study "$kind" ${args//:/ } --jobs "$n" --out "$out" --max-hours "$(hours_left)" \
           >> "$out.out" 2>> "$out.err" &)
      else
        IFS=: read -r name jobs warm <<< "$spec"
        pgrep -f "campaign run $name " >/dev/null && continue
        open=$(open_points "$name")
        [ "$open" -gt 0 ] || continue
        n=$jobs; [ $n -le $free ] || n=$free; [ $n -le "$open" ] || n=$open
        echo "$(date +%T) start $name ($open open, $n of $jobs jobs, $(hours_left) h, $solvers solvers)"
        (nice -n 19 "$mixload" campaign run "$name" --dir "$dir" --snapshots --jobs "$n" ${warm//:/ } \
           --max-hours "$(hours_left)" >> "$dir/$name.driver.log" 2>&1 &)
      fi
      idle=0; started=1
      sleep 20
      break
    done
    if [ $started -eq 0 ] && [ $idle -ge 2 ] && [ "$(all_driver_jobs)" -lt "$cores" ]; then
      for spec in "$@"; do
        [[ $spec == study:* ]] && continue
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
