#!/usr/bin/env bash
# Runs every check and test of tessera, installing what a fresh machine lacks first:
# the targets of the firmware test image's cores (thumbv7em-none-eabihf: Cortex-M4F
# and M7; thumbv8m.main-none-eabihf: Cortex-M33 and M55; riscv32imafc-unknown-none-elf;
# without an FPU thumbv6m-none-eabi and riscv32imc-unknown-none-elf),
# qemu-system-arm and qemu-system-misc (qemu-system-riscv32: the firmware tests run
# under emulation) and the minimum supported Rust (Cargo.toml's rust-version, checked
# with a minimal toolchain).
#
# The workspace commands are the cargo aliases of .cargo/config.toml (`cargo lint`,
# `cargo lint-fast`, `cargo fw-core`, `cargo test-all`): they are defined there only.
# Every step runs even when one before it failed; the failed steps, if any, are
# listed (`failed: <command>`, exit 1) before the last line, which is always the
# summary `tests: N passed, M failed`, also when the script stops early.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each step's heading says when it started (seconds since the script did).
say() { printf '\n== %s (at %d s)\n' "$*" "$SECONDS"; }

log=$(mktemp)
failed=()
# Runs one step, its output also appended to the log of the summary; a failure is
# remembered, and the other steps and the summary still happen.
run() {
  "$@" 2>&1 | tee -a "$log" || failed+=("$*")
}
# The closing lines, also when the script stops early (an installation that fails):
# what failed, then one count for every test run (cargo prints one line per test
# binary, the last of which is often an empty doc-test binary).
finish() {
  local status=$?
  if [ "${#failed[@]}" -ne 0 ]; then
    printf 'failed: %s\n' "${failed[@]}"
    [ "$status" -ne 0 ] || status=1
  fi
  awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($i ~ /^passed;?$/) p += $(i-1); if ($i ~ /^failed;?$/) f += $(i-1) } }
       END { printf "tests: %d passed, %d failed\n", p, f }' "$log"
  rm -f "$log"
  exit "$status"
}
trap finish EXIT

say "toolchain: $(rustc --version)"
# A CI run starts from a fresh clone and keeps nothing: incremental compilation
# would only write caches no later build reads (about a tenth more time for the
# test binaries' build, measured from an empty target folder). A developer's run
# keeps cargo's default.
if [ -n "${CI:-}" ] && [ -z "${CARGO_INCREMENTAL:-}" ]; then
  export CARGO_INCREMENTAL=0
fi
targets=(thumbv7em-none-eabihf thumbv8m.main-none-eabihf riscv32imafc-unknown-none-elf
  thumbv6m-none-eabi riscv32imc-unknown-none-elf)
for target in "${targets[@]}"; do
  if ! rustup target list --installed | grep -qx "$target"; then
    say "installing the $target target"
    rustup target add "$target"
  fi
done
rustup component list --installed | grep -q '^clippy' || rustup component add clippy
rustup component list --installed | grep -q '^rustfmt' || rustup component add rustfmt
# qemu: tests/install-qemu.sh checks its install plan by simulation on every run
# (a conflict fails this step, qemu present or not) and installs what is missing.
say "qemu-system-arm and qemu-system-misc (qemu-system-riscv32): the install plan, checked, and the install"
run bash tests/install-qemu.sh
if ! command -v qemu-system-arm >/dev/null 2>&1 || ! command -v qemu-system-riscv32 >/dev/null 2>&1; then
  echo "qemu is missing and could not be installed: the firmware tests cannot run (the message above says what to do)" >&2
  exit 1
fi
qemu-system-arm --version | head -n 1
qemu-system-riscv32 --version | head -n 1
msrv=$(sed -n 's/^rust-version = "\([0-9.]*\)"$/\1/p' Cargo.toml)
if ! rustup toolchain list | grep -q "^$msrv-"; then
  say "installing Rust $msrv (the minimum supported version), minimal profile"
  rustup toolchain install "$msrv" --profile minimal
fi

# The firmware images' and examples' steps (their own workspaces and target
# folders) run in the background beside the workspace's format, lint, rustdoc,
# package and minimum-Rust steps: many of both are single-threaded for long
# stretches (a crate's own compile, a fat-LTO link, qemu), so the two cores are
# busier together. Their output is held in a file and shown when they end, and
# their failures join the list.
own_workspaces() {
  say "firmware test image (tests/firmware): format and clippy, both backends, every core's target and board"
  run cargo fmt --manifest-path tests/firmware/Cargo.toml -- --check
  run cargo clippy --manifest-path tests/firmware/Cargo.toml --target thumbv7em-none-eabihf -- -D warnings
  run cargo clippy --manifest-path tests/firmware/Cargo.toml --target thumbv7em-none-eabihf --features fast-math -- -D warnings
  run cargo clippy --manifest-path tests/firmware/Cargo.toml --target thumbv7em-none-eabihf --features mps2-an500 -- -D warnings
  run cargo clippy --manifest-path tests/firmware/Cargo.toml --target thumbv8m.main-none-eabihf -- -D warnings
  run cargo clippy --manifest-path tests/firmware/Cargo.toml --target thumbv8m.main-none-eabihf --features mps3-an547 -- -D warnings
  run cargo clippy --manifest-path tests/firmware/Cargo.toml --target riscv32imafc-unknown-none-elf -- -D warnings
  run cargo clippy --manifest-path tests/firmware/Cargo.toml --target thumbv6m-none-eabi -- -D warnings
  run cargo clippy --manifest-path tests/firmware/Cargo.toml --target riscv32imc-unknown-none-elf -- -D warnings

  # Both Cortex-M33 of qemu's mps2-an521 sharing a frame's tiles: its own workspace;
  # the tests `dualcore::...` in `cargo test-all` build it and run it under qemu.
  say "dual-core firmware image (tests/dualcore): format and clippy"
  run cargo fmt --manifest-path tests/dualcore/Cargo.toml -- --check
  run cargo clippy --manifest-path tests/dualcore/Cargo.toml --target thumbv8m.main-none-eabihf -- -D warnings

  # The three examples are linted in the release profile, the one their tests
  # build them in (in the target folders their tests use): the build scripts and
  # their build-dependencies (the scene baker, tessera-host) are then compiled
  # once, for both.

  # The Raspberry Pi Pico 2 example (an RP2350, both cores, and a Waveshare
  # Pico-LCD-1.3 fed by DMA): its own workspace, for the Cortex-M33, linted and
  # built in the qemu example's target folder (its test `examples::pico2::...`
  # in `cargo test-all` links it there and checks the sizes its README states):
  # the scene baker the three examples' build scripts use is compiled once.
  say "Pico 2 example (examples/pico2-st7789): format and clippy"
  run cargo fmt --manifest-path examples/pico2-st7789/Cargo.toml -- --check
  run env CARGO_TARGET_DIR=examples/qemu-m4f/target cargo clippy --release --manifest-path examples/pico2-st7789/Cargo.toml --target thumbv8m.main-none-eabihf -- -D warnings
  # Its bench (docs/bench.md), linted with the flash-only layout (everything
  # run from flash, without ram.x) and linked with the default one: the bench
  # and the teapot fit the Pico 2.
  run env CARGO_TARGET_DIR=examples/qemu-m4f/target cargo clippy --release --manifest-path examples/pico2-st7789/Cargo.toml --target thumbv8m.main-none-eabihf --features bench,flash-only -- -D warnings
  run env CARGO_TARGET_DIR=examples/qemu-m4f/target cargo build --release --manifest-path examples/pico2-st7789/Cargo.toml --target thumbv8m.main-none-eabihf --features bench

  # The firmware to copy (a scene file on qemu's Cortex-M4F): its own workspace; the
  # tests `examples::qemu::...` in `cargo test-all` build it in its folder, as a user
  # does, and run it.
  say "qemu example (examples/qemu-m4f): format and clippy"
  run cargo fmt --manifest-path examples/qemu-m4f/Cargo.toml -- --check
  run cargo clippy --release --manifest-path examples/qemu-m4f/Cargo.toml --target thumbv7em-none-eabihf -- -D warnings
  # The bench for any Cortex-M (docs/bench.md), beside it; the test
  # `examples::qemu::the_bench_...` builds it in the example's target folder.
  say "the bench (examples/qemu-m4f/bench): format and clippy"
  run cargo fmt --manifest-path examples/qemu-m4f/bench/Cargo.toml -- --check
  run env CARGO_TARGET_DIR=examples/qemu-m4f/target cargo clippy --release --manifest-path examples/qemu-m4f/bench/Cargo.toml --target thumbv7em-none-eabihf -- -D warnings

  # The board example (an STM32F411 Black Pill and an ST7789 panel): its own
  # workspace, linted and built in the qemu example's target folder (its test
  # `examples::board::...` in `cargo test-all` links it there for a textured scene
  # file and for its default, the teapot, and checks the sizes its README states):
  # the scene baker both examples' build scripts use is compiled once.
  say "board example (examples/blackpill-st7789): format and clippy"
  run cargo fmt --manifest-path examples/blackpill-st7789/Cargo.toml -- --check
  run env CARGO_TARGET_DIR=examples/qemu-m4f/target cargo clippy --release --manifest-path examples/blackpill-st7789/Cargo.toml --target thumbv7em-none-eabihf -- -D warnings
  # Its bench, linted and linked (the bench and the teapot fit the F411).
  run env CARGO_TARGET_DIR=examples/qemu-m4f/target cargo clippy --release --manifest-path examples/blackpill-st7789/Cargo.toml --target thumbv7em-none-eabihf --features bench -- -D warnings
  run env CARGO_TARGET_DIR=examples/qemu-m4f/target cargo build --release --manifest-path examples/blackpill-st7789/Cargo.toml --target thumbv7em-none-eabihf --features bench

  say "no-panic proof (tests/nopanic): format and clippy, both backends"
  run cargo fmt --manifest-path tests/nopanic/Cargo.toml -- --check
  run cargo clippy --manifest-path tests/nopanic/Cargo.toml --target thumbv7em-none-eabihf -- -D warnings
  run cargo clippy --manifest-path tests/nopanic/Cargo.toml --target thumbv7em-none-eabihf --features fast-math -- -D warnings

  # The other targets' builds of the core are the firmware tests' (`cores::...`,
  # `nofpu::...` in `cargo test-all`: the test image, the core in it, for each
  # core's target, with the teapot).
  say "core for the Cortex-M4F (thumbv7em-none-eabihf), both backends"
  run cargo fw-core
  run cargo fw-core --features fast-math

  # The image renders every built-in scene through the tile API and its panic handler
  # calls an undefined symbol: the link fails ("undefined symbol:
  # tessera_nopanic__a_panic_is_reachable_from_the_render_path") if any panic is
  # reachable from the render path. Then one run under qemu: every render returned Ok.
  say "no panic reachable on the Cortex-M4F (tests/nopanic links): exact, fast-math, and with the BVH search, the optional kinds, image textures, the sun and the instances linked"
  for backend in exact fast-math bvh; do
    features=()
    [ "$backend" = fast-math ] && features=(--features fast-math)
    [ "$backend" = bvh ] && features=(--features bvh,all-kinds,image,sun,instances)
    run cargo build --release --manifest-path tests/nopanic/Cargo.toml --target thumbv7em-none-eabihf "${features[@]}"
    run cargo run -q --release --manifest-path tests/nopanic/Cargo.toml --target thumbv7em-none-eabihf "${features[@]}"
  done
}
own_log=$(mktemp)
own_failed=$(mktemp)
(
  # This subshell's own `run` and `say`: output to the held file, a failure
  # to the list file (the parent's list is not this process's).
  run() { "$@" >>"$own_log" 2>&1 || printf '%s\n' "$*" >>"$own_failed"; }
  say() { printf '\n== %s (at %d s)\n' "$*" "$SECONDS" >>"$own_log"; }
  own_workspaces
) &
own_pid=$!

say "format"
run cargo fmt --all -- --check

say "clippy (exact and fast-math backends, and each approximation alone)"
run cargo lint
run cargo lint-fast
for feature in fast-rsqrt fast-recip fast-pow; do
  run cargo clippy -p tessera-core --all-targets --features "$feature" -- -D warnings
done
# The host library without its command (a firmware's build-dependency: scene
# reader and baker; tests/lite_deps.rs checks its dependencies).
run cargo clippy -p tessera-host --no-default-features --all-targets -- -D warnings
# The core's `defmt` feature (defmt::Format for the errors and value types), for
# the Cortex-M4F (the board examples build it too).
run cargo clippy -p tessera-core --target thumbv7em-none-eabihf --features defmt -- -D warnings

say "rustdoc: no warnings (broken or private links, unclosed HTML tags)"
run env RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps
# The core alone, with its default features (what a firmware's docs build sees):
# the workspace build unifies the host's features (bvh, teapot) into it.
run env RUSTDOCFLAGS="-D warnings" cargo doc -p tessera-core --no-deps
# What the online documentation builds ([package.metadata.docs.rs]): every feature
# of the core, for the Cortex-M4F (the host library's, with its command's
# features, is the workspace's above).
run env RUSTDOCFLAGS="-D warnings" cargo doc -p tessera-core --no-deps --all-features --target thumbv7em-none-eabihf

wait "$own_pid" || true
say "the firmware images' and examples' steps, run beside the steps above:"
cat "$own_log"
cat "$own_log" >>"$log"
while IFS= read -r step; do failed+=("$step"); done <"$own_failed"
rm -f "$own_log" "$own_failed"

# The two crates users depend on, as the crate registry would take them, and
# the minimum supported Rust: both compile from scratch in target folders of
# their own, so they run in the background beside the tests (which spend most
# of their time in qemu, one core at a time).
packages_and_msrv() {
  # The two crates users depend on, as the crate registry would take them: each
  # packaged from its own files (the host against the packaged core) and its
  # manifest checked as an upload would be, then the upload skipped.
  # --allow-dirty: the steps before may have refreshed a lock file. The packages
  # are not built here (--no-verify) but checked below, from their files alone,
  # with the minimum supported Rust.
  say "packages: cargo publish --dry-run (tessera-core, tessera-host)"
  # Cargo unpacks the packaged crates into its registry folder (one folder per
  # local overlay, named by a hash) and reuses a folder of the same name and
  # version: an earlier run's tessera-core 0.1.0 would be read instead of this
  # one's. Neither crate comes from the crate registry, so those folders are only
  # ever this check's.
  rm -rf "${CARGO_HOME:-$HOME/.cargo}"/registry/src/-*/tessera-core-* \
    "${CARGO_HOME:-$HOME/.cargo}"/registry/src/-*/tessera-host-*
  run cargo publish --dry-run --no-verify --allow-dirty -p tessera-core -p tessera-host --target-dir target/package-check

  # rust-version is what the dependencies need (flip-rs 1.88, criterion 1.86).
  # First the two packages as a user gets them, unpacked into a workspace of
  # their own (the host's dependency on the core patched to the unpacked core,
  # the repository's lock file): every target they hold (the library, the
  # command, their unit tests) type-checks with that toolchain from the
  # packaged files alone (a file the package lacks fails here), and cargo
  # refuses a dependency whose own rust-version is newer. Then the crates'
  # other targets in the repository (integration tests, the benchmark), in the
  # same target folder, which has the dependencies checked already. (The test
  # crate is the repository's own, never built by a user.)
  say "the packages from their files alone, and every target, with the minimum supported Rust: cargo +$msrv check (Cargo.toml's rust-version)"
  run check_packages
  run cargo "+$msrv" check -p tessera-core -p tessera-host --all-targets --target-dir target/msrv
}

# Packages both crates (`cargo package`: the files `cargo publish` sends, into
# target/package-check/package), unpacks them into a workspace of their own and
# type-checks every target of both with the minimum supported Rust.
check_packages() {
  local dir=target/package-check/unpacked crates=target/package-check/package
  rm -f "$crates"/tessera-*.crate
  cargo package --no-verify --allow-dirty -p tessera-core -p tessera-host --target-dir target/package-check || return 1
  rm -rf "$dir" && mkdir -p "$dir" || return 1
  local core host
  core=$(cd "$crates" && ls tessera-core-*.crate) || return 1
  host=$(cd "$crates" && ls tessera-host-*.crate) || return 1
  tar -xzf "$crates/$core" -C "$dir" && tar -xzf "$crates/$host" -C "$dir" || return 1
  core=${core%.crate} host=${host%.crate}
  # The repository's profiles (its manifest's last tables), so that the check
  # of the repository's other targets after this one finds the dependencies
  # checked in the same profile and checks only the two crates again.
  {
    printf '[workspace]\nmembers = ["%s", "%s"]\nresolver = "2"\n\n[patch.crates-io]\ntessera-core = { path = "%s" }\n\n' \
      "$core" "$host" "$core"
    sed -n '/^\[profile/,$p' Cargo.toml
  } >"$dir/Cargo.toml"
  cp Cargo.lock "$dir/Cargo.lock"
  cargo "+$msrv" check --workspace --all-targets --manifest-path "$dir/Cargo.toml" --target-dir target/msrv
}

say "tests"
# The test binaries are built first; while they run (the long part: the firmware
# under qemu, mostly one core at a time), the same tests with the approximations
# on build and run beside them: the core's unit tests (math: each approximation's
# error bound; not its doc examples or its layers test, which no approximation
# changes) and the host library's (the f64 reference against the core), with
# fast-math (every approximation; each alone is linted above). Not the command's
# integration tests (messages, outputs, files: nothing an approximation changes),
# nor tessera-tests, which holds the long runs (qemu, golden images: exact
# images). Their output is held and shown after the tests, and their failures
# join the list.
run cargo test-all --no-run
fast_log=$(mktemp)
fast_failed=$(mktemp)
(
  run() { "$@" >>"$fast_log" 2>&1 || printf '%s\n' "$*" >>"$fast_failed"; }
  say() { printf '\n== %s (at %d s)\n' "$*" "$SECONDS" >>"$fast_log"; }
  say "tests with the approximations (fast-math: the core's unit tests, the host library's)"
  run cargo test -p tessera-core --features fast-math --lib
  run cargo test -p tessera-host --features fast-math --lib
  packages_and_msrv
) &
fast_pid=$!
# Three test threads on each test binary unless RUST_TEST_THREADS says otherwise:
# the examples' tests build in one shared target folder, so one of them often
# waits on cargo's lock of it, and a third thread keeps both cores busy then.
run env RUST_TEST_THREADS="${RUST_TEST_THREADS:-3}" cargo test-all
wait "$fast_pid" || true
say "the tests with the approximations, the packages and the minimum Rust, run beside the tests above:"
cat "$fast_log"
cat "$fast_log" >>"$log"
while IFS= read -r step; do failed+=("$step"); done <"$fast_failed"
rm -f "$fast_log" "$fast_failed"
