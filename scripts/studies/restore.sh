#!/bin/bash
# restore.sh SRC.tar.xz OUT: lays a landed study (land.sh) into OUT for a machine that came back
# without it; a run directory already in OUT is left alone. Then the study's own command, with
# --out OUT, resumes every unfinished run from its landed latest time and reuses the finished ones.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 SRC.tar.xz OUT" >&2; exit 2; }
src=$1; out=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
tar -C "$tmp" -xJf "$src"
mkdir -p "$out/runs"
for f in "$tmp"/study/*; do [ -f "$f" ] && [ ! -e "$out/$(basename "$f")" ] && cp "$f" "$out/"; done
n=0
for run in "$tmp"/study/runs/*/; do
  name=$(basename "$run")
  if [ -e "$out/runs/$name" ]; then echo "restore: $out/runs/$name exists, left alone"; continue; fi
  cp -r "$run" "$out/runs/$name"; n=$((n + 1))
done
echo "restore: $n runs -> $out/runs"
