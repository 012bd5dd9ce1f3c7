#!/bin/bash
# land.sh OUT DEST.tar.xz: packs a stopped `mixload study mixer` directory OUT (its tables, plots
# and every run's resumable state) into DEST.tar.xz, to be committed, so that a study run in
# resumable slices (--max-hours) survives a machine that comes back without /var/tmp. Per run it
# keeps the top-level records (scene, mesh, start, slices, result), system/, constant/ without
# the meshing surfaces, the latest whole time directory (what the solver resumes from, its
# monitor's state included) and postProcessing/ with each history thinned evenly to at most 5 000
# lines (first and last kept; the steady test reads the monitor's own samples, not these). Logs,
# earlier times and loading_history.dat (the run's plot data, rewritten from postProcessing/ when
# the run finishes: a fifth of the pack) stay behind. Land only a stopped study: a running solver
# may be writing.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 OUT DEST.tar.xz" >&2; exit 2; }
out=$(cd "$1" && pwd); dest=$2
[ -d "$out/runs" ] || { echo "land: $out holds no runs/ (not a study directory)" >&2; exit 2; }
solver_in_out() {  # a solver runs in a case below $out (its command line names no case: its cwd does)
  local pid
  for pid in $(pgrep -f '^[^ ]*mixloadInterFoam( |$)'); do
    case "$(readlink "/proc/$pid/cwd")" in "$out"/*) return 0 ;; esac
  done
  return 1
}
if solver_in_out || pgrep -af "study " | grep -q -- "--out $1"; then
  echo "land: the study in $out is running; stop it first (its --max-hours, or SIGTERM)" >&2; exit 2
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
stage=$tmp/study; mkdir -p "$stage/runs"
find "$out" -maxdepth 1 -type f -exec cp {} "$stage/" \;
for run in "$out"/runs/*/; do
  run=${run%/}; d=$stage/runs/$(basename "$run"); mkdir -p "$d"
  find "$run" -maxdepth 1 -type f ! -name 'log.*' ! -name 'loading_history.dat' -exec cp {} "$d/" \;
  [ -d "$run/system" ] && cp -r "$run/system" "$d/"
  if [ -d "$run/constant" ]; then
    mkdir -p "$d/constant"
    find "$run/constant" -mindepth 1 -maxdepth 1 ! -name triSurface -exec cp -r {} "$d/constant/" \;
  fi
  latest=$(find "$run" -mindepth 1 -maxdepth 1 -type d -regex '.*/[0-9.e+-]+' -printf '%f\n' | sort -g | tail -1)
  [ -n "$latest" ] && cp -r "$run/$latest" "$d/"
  if [ -d "$run/postProcessing" ]; then
    (cd "$run" && find postProcessing -type d) | while read -r p; do mkdir -p "$d/$p"; done
    (cd "$run" && find postProcessing -type f) | while read -r f; do
      n=$(wc -l < "$run/$f")
      k=$(( (n + 4999) / 5000 ))
      awk -v k="$k" -v n="$n" '/^#/ || NR == n || (NR % k) == 1 || k <= 1' "$run/$f" > "$d/$f"
    done
  fi
done
mkdir -p "$(dirname "$dest")"
tar -C "$tmp" -cJf "$dest.new" study && mv "$dest.new" "$dest"
echo "land: $(basename "$out") -> $dest ($(du -h "$dest" | cut -f1), $(ls "$out/runs" | wc -l) runs)"
