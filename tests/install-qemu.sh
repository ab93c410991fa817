#!/usr/bin/env bash
# Installs the emulators the firmware tests run under, qemu-system-arm and
# qemu-system-misc (qemu-system-riscv32), from the distribution's packages with
# apt-get, and checks the install plan even when they are present.
#
#   bash tests/install-qemu.sh           plan, check the plan, install what is missing
#   bash tests/install-qemu.sh --check   plan and check the plan only (changes nothing)
#
# The plan is `apt-get install --no-install-recommends qemu-system-arm
# qemu-system-misc`, with `qemu-utils=<the same version>` added when qemu-utils is
# installed at another version: the qemu packages of one version go together, and
# a machine can carry a newer qemu-utils (a backport) whose `Breaks:` refuses the
# distribution's qemu-system-common. Such a qemu-utils is downgraded to the
# version of the qemu it goes with (apt would otherwise remove it); no package
# source is added. The plan is first run by `apt-get install -s` (simulation):
# it is refused, with the command to run by hand, when apt cannot make it, when it
# removes a package, or when it downgrades one the plan does not name. The
# packages it changes are printed, a downgrade named as one.
#
# The blessed instruction counts (tests/chip-baseline*.txt) were counted under
# qemu 7.2 (QEMU_SERIES in tests/src/firmware.rs, which the firmware tests check);
# the distribution here (Debian 12) has 7.2.
#
# Exit status: 0 when qemu is there (installed now or before) and the plan is
# sound; 1 when the plan is refused or the install fails; 2 on a bad argument.
# tests/tests/install.rs runs it against a stand-in apt-get, apt-cache and
# dpkg-query (first on PATH) in each machine state it has to handle.
set -euo pipefail

check_only=false
case "${1:-}" in
  "") ;;
  --check) check_only=true ;;
  *)
    echo "install-qemu.sh: unknown argument '$1' (expected nothing or --check)" >&2
    exit 2
    ;;
esac


# qemu counts as present when both emulators run.
present=true
for emulator in qemu-system-arm qemu-system-riscv32; do
  command -v "$emulator" >/dev/null 2>&1 || present=false
done

if ! command -v apt-get >/dev/null 2>&1; then
  if $present; then
    echo "install-qemu: no apt-get on this machine: the install plan is not checked; qemu is present"
    exit 0
  fi
  echo "install-qemu: qemu-system-arm and qemu-system-riscv32 are missing and this machine has no apt-get:" >&2
  echo "  install qemu 7.2 (the system emulators for Arm and RISC-V) with its package manager, then run 'bash tests/run-all.sh' again" >&2
  exit 1
fi

# Root, or sudo when there is one; without either, only the simulation runs.
sudo_cmd=()
can_change=true
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
  else
    can_change=false
  fi
fi
as_root() { "${sudo_cmd[@]}" "$@"; }

# The package lists: refreshed when the lists may change something (an install),
# and by root on every run, so that the plan is checked against what a fresh
# machine would fetch; a user without root checks against the lists there are.
if ! $present || [ "$(id -u)" -eq 0 ]; then
  if $can_change; then
    if ! as_root env DEBIAN_FRONTEND=noninteractive apt-get update -qq >/dev/null 2>&1; then
      echo "install-qemu: 'apt-get update' failed; the plan is checked against the package lists already on this machine" >&2
    fi
  fi
fi

# The version of a package apt would install, and the one installed (empty when none).
# (dpkg-query fails on a package it does not know: that is "none", not an error.)
candidate() { { apt-cache policy "$1" 2>/dev/null || true; } | awk '$1 == "Candidate:" { print $2; exit }'; }
installed() {
  { dpkg-query -W -f='${Status} ${Version}\n' "$1" 2>/dev/null || true; } |
    awk '$1 == "install" && $3 == "installed" { print $4; exit }'
}

version=$(candidate qemu-system-common)
if [ -z "$version" ] || [ "$version" = "(none)" ]; then
  echo "install-qemu: the package lists offer no qemu-system-common: apt cannot install qemu-system-arm here." >&2
  echo "  Run 'sudo apt-get update', then 'bash tests/run-all.sh' again; or install qemu 7.2 (qemu-system-arm, qemu-system-misc) by hand." >&2
  exit 1
fi

packages=(qemu-system-arm qemu-system-misc)
pinned=()
utils=$(installed qemu-utils)
if [ -n "$utils" ] && [ "$utils" != "$version" ]; then
  packages+=("qemu-utils=$version")
  pinned+=(qemu-utils)
fi
args=(-y --no-install-recommends)
[ "${#pinned[@]}" -ne 0 ] && args+=(--allow-downgrades)
args+=("${packages[@]}")
command_line="apt-get install ${args[*]}"

# The simulation: apt's plan as `Inst NAME [OLD] (NEW ...)` and `Remv NAME [OLD]` lines.
plan_file=$(mktemp)
trap 'rm -f "$plan_file"' EXIT
refuse() {
  echo "install-qemu: refused: $1" >&2
  echo "  the plan checked: $command_line" >&2
  echo "  install qemu 7.2 by hand (qemu-system-arm, qemu-system-misc and qemu-system-common of one version," >&2
  echo "  and qemu-utils of that version or none), for example:" >&2
  echo "    sudo apt-get install --no-install-recommends --allow-downgrades qemu-system-arm=$version qemu-system-misc=$version qemu-system-common=$version qemu-utils=$version" >&2
  echo "  then run 'bash tests/run-all.sh' again" >&2
  exit 1
}
if ! LC_ALL=C DEBIAN_FRONTEND=noninteractive apt-get install -s "${args[@]}" >"$plan_file" 2>&1; then
  # apt's own words are its resolver's; the first line naming a package says which.
  reason=$(grep -m1 -E '^ [^ ].* : |^E: Unable to locate|^E: Version' "$plan_file" | sed 's/^ *//' || true)
  refuse "apt cannot make the plan${reason:+ ($reason)}"
fi

removed=$(awk '$1 == "Remv" { print $2 " " $3 }' "$plan_file" | tr -d '[]')
if [ -n "$removed" ]; then
  refuse "the plan removes $(echo "$removed" | awk '{ print $1 " " $2 }' | paste -sd, - | sed 's/,/, /g')"
fi

# Each change: "NAME OLD NEW" (OLD "-" for a new package).
changes=$(awk '$1 == "Inst" {
    name = $2; old = "-"; new = "";
    if ($3 ~ /^\[/) { old = $3; gsub(/[][]/, "", old); new = $4 } else { new = $3 }
    gsub(/[()]/, "", new); print name, old, new }' "$plan_file")
downgrades=()
installs=()
upgrades=()
while read -r name old new; do
  [ -n "$name" ] || continue
  if [ "$old" = "-" ]; then
    installs+=("$name $new")
  elif dpkg --compare-versions "$new" lt "$old"; then
    allowed=false
    for p in "${pinned[@]}"; do [ "$p" = "$name" ] && allowed=true; done
    $allowed || refuse "the plan downgrades $name ($old to $new), which it does not name"
    downgrades+=("$name $old -> $new")
  else
    upgrades+=("$name $old -> $new")
  fi
done <<<"$changes"

describe() {
  local verb=$1
  shift
  [ "$#" -eq 0 ] && return 0
  printf '%s (%d): %s\n' "$verb" "$#" "$(printf '%s, ' "$@" | sed 's/, $//')"
}
echo "install-qemu: plan checked (apt-get install -s): $command_line"
if [ -z "$changes" ]; then
  echo "install-qemu: nothing to change: qemu $version is installed"
fi

if $present || $check_only; then
  if [ -n "$changes" ]; then
    describe "  the plan would install" "${installs[@]}"
    describe "  the plan would upgrade" "${upgrades[@]}"
    describe "  the plan would downgrade" "${downgrades[@]}"
    $present && echo "install-qemu: qemu is present; nothing is changed"
  fi
  exit 0
fi

if ! $can_change; then
  echo "install-qemu: qemu is missing and this user can neither act as root nor use sudo; run as root:" >&2
  echo "  $command_line" >&2
  exit 1
fi

echo "install-qemu: installing qemu $version"
if ! as_root env DEBIAN_FRONTEND=noninteractive apt-get install -qq "${args[@]}" >"$plan_file" 2>&1; then
  echo "install-qemu: 'apt-get install' failed (its output follows); run by hand: sudo $command_line" >&2
  tail -n 20 "$plan_file" >&2
  exit 1
fi
describe "  installed" "${installs[@]}"
describe "  upgraded" "${upgrades[@]}"
describe "  downgraded" "${downgrades[@]}"
for emulator in qemu-system-arm qemu-system-riscv32; do
  if ! command -v "$emulator" >/dev/null 2>&1; then
    echo "install-qemu: apt-get installed the packages but $emulator is not on PATH" >&2
    exit 1
  fi
done
