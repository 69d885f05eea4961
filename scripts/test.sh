#!/usr/bin/env bash
# The test suite, as CI runs it: everything (the default features: the core and the wgpu
# runtime, GPU tests on whatever adapter wgpu finds), then the core alone with the runtime
# feature off, which is what an engine with its own wgpu builds, then the Bevy plugin
# (crates/clothbake_bevy, with Bevy's wgpu). Release mode: the direct evaluation is too
# slow unoptimised.
set -euo pipefail
cd "$(dirname "$0")/.."
# The core and the Bevy plugin in one build graph, so that each package's long serial
# compiles (clothbake, bevy_render, bevy_pbr) overlap on CI's two cores instead of leaving
# one idle. Features unify across the workspace (the plugin links the core with its
# runtime here); the core without the runtime is built and tested below. The plugin's
# headless comparison runs the `clothbake` binary of this same build (CLOTHBAKE_BIN) rather
# than building it again with the core's own feature set.
CLOTHBAKE_BIN="$PWD/target/release/clothbake" cargo test --release --locked --workspace
# Without the runtime: every test target must still build, and what the feature changes
# runs again (the library's own tests, the CLI without `render`/`view`/`report`, the WGSL
# translations). The numerical suites (accuracy, resonant, sampling, stability, table)
# run the same core code as above and are not repeated: about 4 minutes on 2 cores.
cargo test --release --locked --no-default-features --no-run
cargo test --release --locked --no-default-features --lib --bins \
    --test cli --test bake_cli --test shader_language --test fabric_file --test environment
