#!/usr/bin/env bash
# Diagnoses every shipped recording (assets/recordings/**/recording.toml) and prints one row per
# recording: its verdict, or the error, and the seconds it took. Usage:
#   scripts/diagnose_shipped.sh [extra diagnose options, e.g. --model lattice] > table.md
# ONLY=ecoflex runs those whose path contains it.
set -uo pipefail
cd "$(dirname "$0")/.."
bin=${SOFTGRIP:-target/release/softgrip}
out=${OUT:-target/diagnose-shipped}
mkdir -p "$out"
echo "| recording | verdict | effects | alternatives | seconds |"
echo "|---|---|---|---|---|"
find assets/recordings -name recording.toml | sort | grep -- "${ONLY:-}" | while read -r rec; do
  name=$(dirname "${rec#assets/recordings/}" | tr / _)
  start=$(date +%s)
  if "$bin" diagnose "$rec" --no-report --json "$out/$name.json" "$@" > "$out/$name.txt" 2>&1; then
    seconds=$(( $(date +%s) - start ))
    python3 - "$out/$name.json" "$rec" "$seconds" <<'PY'
import json, sys
v = json.load(open(sys.argv[1]))["verdict"]
alt = ", ".join(a["effect"] + (f" ({a['variant']})" if a["variant"] else "") for a in v.get("alternatives", []))
print(f"| {sys.argv[2]} | {v['effect']} | {' + '.join(v['effects'])} | {alt or '-'} | {sys.argv[3]} |")
PY
  else
    seconds=$(( $(date +%s) - start ))
    echo "| $rec | ERROR: $(tail -1 "$out/$name.txt" | cut -c1-120) | | | $seconds |"
  fi
done
