#!/usr/bin/env bash
# The test suite, as CI runs it: everything (the default features: the core and the wgpu
# runtime, GPU tests on whatever adapter wgpu finds), then the core alone with the runtime
# feature off, which is what an engine with its own wgpu builds, then the Bevy plugin
# (crates/clothbake_bevy, on the core alone, with Bevy's wgpu). Release mode: the direct
# evaluation is too slow unoptimised.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --release --locked
cargo test --release --locked --no-default-features
cargo test --release --locked -p clothbake_bevy
