#!/usr/bin/env bash
# Regenerates every generated report of docs/ (never edit those by hand), one
# report binary of the test crate after another, in release; stops at the first
# that fails. The chip's reports need qemu (`bash tests/install-qemu.sh`), the
# profiles gcc (and valgrind for the host's). `bvh-report` prints where a BVH
# pays; it writes no page (docs/bvh.md quotes it by hand).
set -euo pipefail
cd "$(dirname "$0")/.."
report() { cargo run -q -p tessera-tests --release --bin "$@"; }
report chip-report       # docs/chip-cost.md
report chip-profile      # docs/chip-profile.md
report nofpu-report      # docs/chip-nofpu.md
report trade-report      # docs/trade.md, trade.svg, trade-chip.svg, interference.png
report extremes-report   # docs/extremes.md
report dither-report     # docs/dither.md, docs/images/dither-crops.png
report math-report > docs/math-report.md
