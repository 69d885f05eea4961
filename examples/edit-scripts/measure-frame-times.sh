#!/usr/bin/env bash
# Editor frame times, side by side in one run (docs/notebook/2026-12-07-editor.md), from the
# repository root after `cargo build --profile ci` and the default bake.
set -u
X=(xvfb-run -a -s "-screen 0 1280x1024x24")
for env in none default; do
  echo "== --env $env: editor, resonant (the default)"
  "${X[@]}" target/ci/clothbake view --env $env --edit polyester_satin_charmeuse --script examples/edit-scripts/frame-times.txt 2>&1 | grep "frame" | grep -v keys
  echo "== --env $env: editor, --evaluator paper"
  "${X[@]}" target/ci/clothbake view --env $env --evaluator paper --edit polyester_satin_charmeuse --script examples/edit-scripts/frame-times.txt 2>&1 | grep "frame" | grep -v keys
  echo "== --env $env: view, table only"
  "${X[@]}" target/ci/clothbake view --env $env --fabric polyester_satin_charmeuse --frames 60 2>&1 | grep "drew"
done
