#!/usr/bin/env bash
# Installs what clothbake needs on a fresh Debian machine, then runs the given command:
#   scripts/setup.sh cargo run --release -- bake
#   scripts/setup.sh scripts/test.sh
#
# - Rust (rustup, minimal profile) when cargo is missing or older than the workspace needs;
# - Mesa's lavapipe Vulkan driver (mesa-vulkan-drivers, libvulkan1) so that wgpu finds an
#   adapter without a GPU; installing it also upgrades the Mesa packages already present,
#   which must match;
# - Xvfb, an X server without a display, for the window tests (`clothbake view` and the Bevy
#   plugin's `drape` example), and the X client libraries winit loads at run time (it links
#   none of them);
# - glslang-tools (Khronos' glslangValidator), which the tests use to compile the GLSL and
#   HLSL translations of the lookup (`clothbake wgsl --lang`) and to run the GLSL through
#   Vulkan;
# - python3-venv, and libllvm15 for Mitsuba 3's LLVM back end (Dr.Jit loads it at run time);
# - Debian's Chromium, which tools/export-check/render-gltf.mjs drives headless (playwright-core)
#   to render `clothbake export`'s glTF with three.js on SwiftShader; it is large (about 80 MB to
#   download, 290 MB installed with its libraries), but npm's Playwright brings no browser and
#   none can be downloaded here;
# - the npm packages of tools/export-check (gltf-validator, three, playwright-core), by
#   `npm ci` from its package-lock.json when node_modules is missing or older than the lock;
#   Debian's nodejs and npm only where npm is missing (playwright-core needs Node.js 20 or
#   newer, and Debian 12's nodejs is 18: then only the glTF validation works);
# - the Python package `clothbake` (crates/clothbake_py, docs/python.md), built by maturin and
#   installed with its tools (pytest, Mitsuba 3.6.4, and MaterialX 1.39.5 for
#   tools/export-check/validate-mtlx.py) into the virtual environment .venv.
# Packages already installed are left alone, so a second run costs nothing.
set -euo pipefail

packages=(mesa-vulkan-drivers libvulkan1 xvfb xauth ca-certificates curl
    libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0 glslang-tools
    python3-venv libllvm15 chromium)
sudo=()
[[ $(id -u) -ne 0 ]] && sudo=(sudo)
missing=()
for package in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" ||
        missing+=("$package")
done
if ((${#missing[@]})); then
    echo "setup: installing ${missing[*]}" >&2
    "${sudo[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends \
        "${missing[@]}" >&2
fi

# The newest rust-version among the workspace's crates (the Bevy plugin's), which an older
# cargo already on the machine (Debian's own, say) cannot build: then rustup's stable.
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
need=$(sed -n 's/^rust-version = "\(.*\)"/\1/p' "$root/Cargo.toml" "$root"/crates/*/Cargo.toml |
    sort -V | tail -n 1)
cargo_is_new_enough() {
    local have
    have=$(cargo --version 2>/dev/null | awk '{print $2}' || true)
    [[ -n $have && $(printf '%s\n%s\n' "$need" "$have" | sort -V | head -n 1) == "$need" ]]
}
# rustup's cargo may be installed but not yet on PATH: look there before installing.
cargo_is_new_enough || export PATH="$HOME/.cargo/bin:$PATH"
if ! cargo_is_new_enough; then
    if [[ ! -x $HOME/.cargo/bin/rustup ]]; then
        echo "setup: installing Rust $need or newer with rustup" >&2
        curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs |
            sh -s -- -y --profile minimal --no-modify-path >&2
    else
        echo "setup: installing rustup's stable Rust (need $need or newer)" >&2
        rustup toolchain install stable --profile minimal >&2
        export RUSTUP_TOOLCHAIN=stable
    fi
fi

# The outside checks of `clothbake export` (tools/export-check/README.md): `npm ci` when their
# node_modules is missing or older than package-lock.json (npm rewrites
# node_modules/.package-lock.json at each install, so that file's time tells).
if ! command -v npm >/dev/null; then
    echo "setup: installing Debian's nodejs and npm" >&2
    "${sudo[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends \
        nodejs npm >&2
fi
export_check=$root/tools/export-check
if [[ ! -f $export_check/node_modules/.package-lock.json ||
    $export_check/package-lock.json -nt $export_check/node_modules/.package-lock.json ]]; then
    echo "setup: installing tools/export-check's npm packages" >&2
    (cd "$export_check" && npm ci --no-audit --no-fund >&2)
fi
node -e 'process.exit(Number(process.versions.node.split(".")[0]) >= 20 ? 0 : 1)' ||
    echo "setup: warning: Node.js $(node --version) is older than 20, which playwright-core" \
        "needs: tools/export-check/render-gltf.mjs will not run" >&2

# The Python package and its tools in .venv. Mitsuba is pinned: 3.6.4 runs on Debian 12's
# LLVM 15, newer releases' JIT aborts there (docs/python.md#versions). MaterialX is pinned to
# the release tools/export-check/validate-mtlx.py was tested with.
if [[ ! -x $root/.venv/bin/python ]]; then
    echo "setup: creating the Python virtual environment .venv" >&2
    python3 -m venv "$root/.venv" >&2
fi
"$root/.venv/bin/pip" install -q --disable-pip-version-check \
    "maturin>=1.9.4,<2" "numpy>=1.22" pytest "mitsuba==3.6.4" "materialx==1.39.5" >&2
"$root/scripts/python-package.sh" >&2

# Vulkan loaders warn without a runtime directory; the value does not matter headless.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
exec "$@"
