#!/usr/bin/env bash
# Builds the Python package `clothbake` (crates/clothbake_py) and installs it into .venv
# (made by scripts/setup.sh), in the `ci` profile that the tests build: our crates
# optimised as in release. Quick when nothing changed.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
VIRTUAL_ENV="$root/.venv" "$root/.venv/bin/maturin" develop --quiet --locked --profile ci \
    --manifest-path "$root/crates/clothbake_py/Cargo.toml"
