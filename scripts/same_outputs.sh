#!/usr/bin/env bash
# Writes the outputs that a refactor must leave byte-identical (issue 58): every shipped scene's
# `run --out` (0.2 simulated s), every shipped recording's `compare --json`, a `diagnose` with its
# report and JSON, and the reports and JSON of `compare`, `sweep`, `fit` and `modulus`.
# Usage: scripts/same_outputs.sh BINARY OUTDIR [OUTDIR_BEFORE]; with OUTDIR_BEFORE it then
# compares the two and exits 1 on any difference. Every byte is compared, and each command's exit
# code, except the wall-clock time `run --json` reports ("wall_s") and the printed logs
# (OUTDIR/logs), which hold timings.
set -uo pipefail
cd "$(dirname "$0")/.."
bin=$1
out=$2
before=${3:-}
mkdir -p "$out/logs" "$out/exit"
# go NAME ARGS...: runs the binary with ARGS, its output to logs/NAME.txt, its exit code to exit/NAME.
go() {
  local name=$1
  shift
  "$bin" "$@" > "$out/logs/$name.txt" 2>&1
  echo $? > "$out/exit/$name"
}
for scene in assets/scenes/*.toml; do
  name=$(basename "$scene" .toml)
  go "run_$name" run "$scene" --duration 0.2 --out "$out/run_$name" --json "$out/run_$name.json"
done
while read -r rec; do
  name=$(dirname "${rec#assets/recordings/}" | tr / _)
  go "compare_$name" compare "$rec" --no-report --json "$out/compare_$name.json"
done < <(find assets/recordings -name recording.toml | sort)
thesis=assets/recordings/synthetic/thesis_7_loads/recording.toml
go diagnose diagnose $thesis --report "$out/diagnose_thesis_7_loads" \
  --json "$out/diagnose_thesis_7_loads.json"
go compare_report compare assets/recordings/beam_ds10/gravity_a/recording.toml \
  --report "$out/compare_report_gravity_a"
go sweep sweep $thesis --param young_modulus=60e3:120e3:4 --report "$out/sweep_thesis" \
  --json "$out/sweep_thesis.json"
go fit fit assets/recordings/synthetic/tomato_press/recording.toml --params young_modulus \
  --report "$out/fit_tomato" --json "$out/fit_tomato.json"
go modulus modulus assets/recordings/ecoflex_compression/EF30_0T_A1/recording.toml \
  --report "$out/modulus_ef30" --json "$out/modulus_ef30.json"
# What holds wall-clock time is taken out before comparing: `run --json`'s "wall_s", the
# diagnosis report's "## Time" table, the sweep report's seconds, and the diagnosis's fit
# checkpoint (its key names the build, its rows their seconds; the fits' results are in the JSON).
if [ -n "$before" ]; then
  for d in "$before" "$out"; do
    rm -f "$d"/diagnose_thesis_7_loads/fits.checkpoint
    sed -i '/^## Time$/,$d' "$d"/diagnose_thesis_7_loads/diagnosis.md
    sed -i 's/), [0-9]* s; /), _ s; /' "$d"/sweep_thesis/sweep.md
  done
  diff -r -x logs -I '^  "wall_s": ' "$before" "$out" && echo "identical: $out and $before"
fi
