#!/usr/bin/env bash
# The test suite, as CI runs it: everything (the core with its default features, the wgpu
# runtime, GPU tests on whatever adapter wgpu finds; the Bevy plugin, with Bevy's wgpu), then
# the CLI with the runtime feature off, as an engine with its own wgpu builds the core.
# The `ci` profile (Cargo.toml): our crates optimised as in release (the direct evaluation is
# too slow unoptimised), the dependencies the tests do not wait on left unoptimised.
set -euo pipefail
cd "$(dirname "$0")/.."
# The core and the Bevy plugin in one build graph: the dependencies they share build once,
# and cargo schedules both packages' crates together on CI's two cores (1.94 busy on
# average in a `--timings` run of this build). Features unify across the workspace (the
# plugin links the core with its runtime here; tests/repository/feature_split.rs keeps the
# plugin off the runtime's modules); the CLI without the runtime is built and tested below.
# The plugin's headless comparison runs the `clothbake` binary of this same build
# (CLOTHBAKE_BIN) rather than building it again with the core's own feature set.
CLOTHBAKE_BIN="$PWD/target/ci/clothbake" cargo test --profile ci --locked --workspace
# The Python package (crates/clothbake_py) against the binary built above (with
# the runtime: the Mitsuba comparison renders with it; the next step replaces it), and inside
# Mitsuba 3: rebuilt first in case the sources changed since scripts/setup.sh installed it.
scripts/python-package.sh
CLOTHBAKE_BIN="$PWD/target/ci/clothbake" .venv/bin/python -m pytest -q crates/clothbake_py/tests
# Without the runtime: the CLI without `render`/`view`/`report` (its own test binary, `cli`,
# tests/cli/, against that binary; `eval --evaluator` there exercises the evaluators without
# their GPU forms). Nothing else needs running again: the feature only changes lib.rs's list
# of modules, the CLI's commands and the evaluators' GPU forms
# (tests/repository/feature_split.rs keeps it so), and the other core modules build the same
# either way. The workspace's feature
# unification differs here, so some dependencies build a second time.
cargo test --profile ci --locked --no-default-features --bins --test cli
