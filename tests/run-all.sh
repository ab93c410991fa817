#!/usr/bin/env bash
# Runs every check and test of tessera, installing what a fresh machine lacks first:
# the thumbv7em-none-eabihf target (the core is cross-built for a Cortex-M4F) and
# qemu-system-arm (the firmware tests run under emulation).
set -euo pipefail
cd "$(dirname "$0")/.."

say() { printf '\n== %s\n' "$*"; }

say "toolchain: $(rustc --version)"
if ! rustup target list --installed | grep -qx thumbv7em-none-eabihf; then
  say "installing the thumbv7em-none-eabihf target"
  rustup target add thumbv7em-none-eabihf
fi
rustup component list --installed | grep -q '^clippy' || rustup component add clippy
rustup component list --installed | grep -q '^rustfmt' || rustup component add rustfmt
if ! command -v qemu-system-arm >/dev/null 2>&1; then
  say "installing qemu-system-arm"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq qemu-system-arm >/dev/null
fi
qemu-system-arm --version | head -n 1

say "format"
cargo fmt --all -- --check

say "clippy (exact and fast-math backends)"
cargo clippy --workspace --all-targets -- -D warnings
cargo clippy -p tessera --all-targets --features fast-math -- -D warnings

say "firmware test image (tests/firmware): format and clippy, both backends"
cargo fmt --manifest-path tests/firmware/Cargo.toml -- --check
cargo clippy --manifest-path tests/firmware/Cargo.toml --target thumbv7em-none-eabihf -- -D warnings
cargo clippy --manifest-path tests/firmware/Cargo.toml --target thumbv7em-none-eabihf --features fast-math -- -D warnings

say "no-panic proof (tests/nopanic): format and clippy, both backends"
cargo fmt --manifest-path tests/nopanic/Cargo.toml -- --check
cargo clippy --manifest-path tests/nopanic/Cargo.toml --target thumbv7em-none-eabihf -- -D warnings
cargo clippy --manifest-path tests/nopanic/Cargo.toml --target thumbv7em-none-eabihf --features fast-math -- -D warnings

say "core for the Cortex-M4F (thumbv7em-none-eabihf), both backends"
cargo build -p tessera --target thumbv7em-none-eabihf --release
cargo build -p tessera --target thumbv7em-none-eabihf --release --features fast-math

# The image renders every built-in scene through the tile API and its panic handler
# calls an undefined symbol: the link fails ("undefined symbol:
# tessera_nopanic__a_panic_is_reachable_from_the_render_path") if any panic is
# reachable from the render path. Then one run under qemu: every render returned Ok.
say "no panic reachable on the Cortex-M4F (tests/nopanic links), both backends"
for backend in exact fast-math; do
  features=()
  [ "$backend" = fast-math ] && features=(--features fast-math)
  cargo build --release --manifest-path tests/nopanic/Cargo.toml --target thumbv7em-none-eabihf "${features[@]}"
  cargo run -q --release --manifest-path tests/nopanic/Cargo.toml --target thumbv7em-none-eabihf "${features[@]}"
  echo "tests/nopanic ($backend): links, renders every built-in scene under qemu"
done

log=$(mktemp)
trap 'rm -f "$log"' EXIT
failed_runs=()
# Runs one test command, its output also appended to the log of the summary; a
# failure is remembered, and the other runs and the summary still happen.
run_tests() {
  "$@" 2>&1 | tee -a "$log" || failed_runs+=("$*")
}

say "tests"
run_tests cargo test --workspace

# The same tests with the micromath backend: the core's own (math, texture
# coordinates) and the host's (the f64 reference against the core, also where
# fast-math approximates). Not tessera-tests, which has no fast-math feature and
# holds the long runs (qemu, golden images).
say "tests with the fast-math backend (core, host)"
run_tests cargo test -p tessera --features fast-math
run_tests cargo test -p tessera-host --features fast-math

# One closing line for every run above (cargo prints one per test binary, the last
# of which is often an empty doc-test binary).
awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($i ~ /^passed;?$/) p += $(i-1); if ($i ~ /^failed;?$/) f += $(i-1) } }
     END { printf "tests: %d passed, %d failed\n", p, f }' "$log"
if [ "${#failed_runs[@]}" -ne 0 ]; then
  printf 'failed: %s\n' "${failed_runs[@]}" >&2
  exit 1
fi
