#!/bin/bash
# land.sh [--leaves] OUT DEST.tar.xz: packs a stopped `mixload study` directory OUT (its tables,
# plots and every run's resumable state) into DEST.tar.xz, to be committed, so that a study run in
# resumable slices (--max-hours) survives a machine that comes back without /var/tmp. Per run it
# keeps the top-level records (scene, mesh, start, slices, result), system/, constant/ without
# the meshing surfaces, and postProcessing/ with each history (*.dat) thinned to the steady test's
# own sampling (a line where 1/50 of the test's shortest window, steady_window_revs revolutions, has
# passed since the last kept one: what `mixload study verdict` reads, so its replay is unchanged
# but at the ends of slices). The latest whole time directory (what a run resumes from, its monitor's
# state included) is kept for every run: a study checks each warm source again when it resumes.
# --leaves leaves it out for finished warm-started runs, for a study whose warm runs are no one's
# source (study formulation's variants, all started from one reference run that is kept). Logs,
# earlier times and loading_history.dat (rewritten from postProcessing/ when a run finishes) stay
# behind. Land only a stopped study: a running solver may be writing.
set -euo pipefail
leaves=0
[ "${1:-}" = --leaves ] && { leaves=1; shift; }
[ $# -eq 2 ] || { echo "usage: $0 [--leaves] OUT DEST.tar.xz" >&2; exit 2; }
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
scene_value() {  # scene_value RUN KEY: a number of the scene's top level in RUN/scene.json
  awk -F': ' -v k="\"$2\"" '$1 == "    " k { sub(/,$/, "", $2); print $2 }' "$1/scene.json"
}
kept=0; left=0
for run in "$out"/runs/*/; do
  run=${run%/}; d=$stage/runs/$(basename "$run"); mkdir -p "$d"
  find "$run" -maxdepth 1 -type f ! -name 'log.*' ! -name 'loading_history.dat' -exec cp {} "$d/" \;
  [ -d "$run/system" ] && cp -r "$run/system" "$d/"
  if [ -d "$run/constant" ]; then
    mkdir -p "$d/constant"
    find "$run/constant" -mindepth 1 -maxdepth 1 ! -name triSurface -exec cp -r {} "$d/constant/" \;
  fi
  fields=1
  [ $leaves -eq 1 ] && [ -f "$run/result.json" ] && [ -f "$run/start.json" ] && fields=0
  latest=$(find "$run" -mindepth 1 -maxdepth 1 -type d -regex '.*/[0-9.e+-]+' -printf '%f\n' | sort -g | tail -1)
  if [ -n "$latest" ] && [ $fields -eq 1 ]; then cp -r "$run/$latest" "$d/"; kept=$((kept + 1)); else left=$((left + 1)); fi
  if [ -d "$run/postProcessing" ]; then
    rpm=$(scene_value "$run" rpm); revs=$(scene_value "$run" steady_window_revs)
    step=$(awk -v r="${rpm:-0}" -v n="${revs:-3}" 'BEGIN { print (r > 0 ? n * 60 / r : n) / 50 }')
    (cd "$run" && find postProcessing -type d) | while read -r p; do mkdir -p "$d/$p"; done
    (cd "$run" && find postProcessing -type f) | while read -r f; do
      case "$f" in
        *.dat) awk -v dt="$step" '{ kept = /^#/ || !have || $1 - last >= dt; line = $0 }
                                  kept { print; if (!/^#/) { last = $1; have = 1 } }
                                  END { if (NR && !kept) print line }' "$run/$f" > "$d/$f" ;;
        *) cp "$run/$f" "$d/$f" ;;  # the monitor's verdict and other records, whole
      esac
    done
  fi
done
mkdir -p "$(dirname "$dest")"
tar -C "$tmp" -cJf "$dest.new" study && mv "$dest.new" "$dest"
echo "land: $(basename "$out") -> $dest ($(du -h "$dest" | cut -f1), $(ls "$out/runs" | wc -l) runs, fields of $kept kept, of $left left out)"
